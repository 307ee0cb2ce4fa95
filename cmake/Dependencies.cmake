# Finds every external package through its CMake config (or CMake's own module
# where Debian ships no config) and papers over known packaging defects.

find_package(Threads REQUIRED)
find_package(glm CONFIG REQUIRED)
find_package(yaml-cpp CONFIG REQUIRED)
find_package(spdlog CONFIG REQUIRED)
find_package(OpenImageIO CONFIG REQUIRED)
find_package(Protobuf REQUIRED)
find_package(gRPC CONFIG REQUIRED)
find_package(assimp CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(TBB CONFIG REQUIRED)
# tesserad's JSON log lines (Debian: nlohmann-json3-dev).
find_package(nlohmann_json 3 CONFIG REQUIRED)
# tesserad's /metrics endpoint (Debian: libcpp-httplib-dev), through pkg-config: Debian ships
# no CMake config, and the .pc file carries the CPPHTTPLIB_*_SUPPORT definitions the library
# was built with, which every includer of the header must share.
find_package(PkgConfig REQUIRED)
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)

# Debian's OpenImageIO config lists /usr/include/opencv4 among its include
# directories although OpenCV is not a dependency; CMake refuses to generate when
# that directory is missing, so drop it from the imported target.
foreach(_oiio_target OpenImageIO::OpenImageIO OpenImageIO::OpenImageIO_Util)
  if(TARGET ${_oiio_target})
    foreach(_prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
      get_target_property(_dirs ${_oiio_target} ${_prop})
      if(_dirs)
        list(FILTER _dirs EXCLUDE REGEX "opencv4")
        set_target_properties(${_oiio_target} PROPERTIES ${_prop} "${_dirs}")
      endif()
    endforeach()
  endif()
endforeach()

# yaml-cpp 0.7 on Debian exports the target under its bare name.
if(TARGET yaml-cpp AND NOT TARGET yaml-cpp::yaml-cpp)
  add_library(yaml-cpp::yaml-cpp ALIAS yaml-cpp)
endif()

if(TARGET glm::glm)
  set(TESSERA_GLM_TARGET glm::glm)
else()
  set(TESSERA_GLM_TARGET glm)
endif()

if(TESSERA_BUILD_TESTS)
  find_package(GTest CONFIG REQUIRED)
endif()
if(TESSERA_BUILD_BENCH)
  find_package(benchmark CONFIG QUIET)
  find_package(embree 3 CONFIG QUIET)
endif()

# SHA-256 of bearer tokens and the checks of the TLS files in tesserad, and
# `tessera token hash`. Debian: libssl-dev (OpenSSL, as gRPC's own TLS).
find_package(OpenSSL REQUIRED COMPONENTS Crypto)
