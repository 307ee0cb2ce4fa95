# `cmake --install build [--prefix DIR]`: tesserad and tessera (their own folders' rules), the
# gRPC client library with its headers and a CMake package (find_package(tessera CONFIG)
# gives tessera::client), the systemd unit, an example configuration, and the Python package
# (client/python).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(TESSERA_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/tessera)

# Headers under include/tessera, laid out as in the build (client/client.hpp,
# tessera/v1/render.grpc.pb.h), so code includes them the same way in and out of this tree.
install(TARGETS tessera_client tessera_proto EXPORT tesseraTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(FILES ${PROJECT_SOURCE_DIR}/client/client.hpp ${PROJECT_SOURCE_DIR}/client/client_error.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tessera/client)
install(DIRECTORY ${PROJECT_BINARY_DIR}/proto/generated/tessera
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tessera FILES_MATCHING PATTERN "*.h")
install(EXPORT tesseraTargets NAMESPACE tessera:: DESTINATION ${TESSERA_INSTALL_CMAKEDIR})

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/tesseraConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/tesseraConfig.cmake
                              INSTALL_DESTINATION ${TESSERA_INSTALL_CMAKEDIR}
                              PATH_VARS CMAKE_INSTALL_BINDIR)
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/tesseraConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/tesseraConfig.cmake
              ${PROJECT_BINARY_DIR}/tesseraConfigVersion.cmake
        DESTINATION ${TESSERA_INSTALL_CMAKEDIR})

# The systemd unit with ExecStart at this prefix's tesserad, written when installing so that
# `--prefix` holds; PREFIX/lib/systemd/system is on systemd's unit path for /usr/local and /usr.
install(CODE "
  file(READ \"${PROJECT_SOURCE_DIR}/deploy/tesserad.service\" unit)
  string(REPLACE \"/usr/local/bin/tesserad\" \"\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}/tesserad\" unit \"\${unit}\")
  file(WRITE \"${PROJECT_BINARY_DIR}/install/tesserad.service\" \"\${unit}\")")
install(FILES ${PROJECT_BINARY_DIR}/install/tesserad.service DESTINATION lib/systemd/system)
install(FILES ${PROJECT_SOURCE_DIR}/deploy/tesserad.yaml
        DESTINATION ${CMAKE_INSTALL_DATADIR}/tessera)
