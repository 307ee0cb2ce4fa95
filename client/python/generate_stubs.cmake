# Generates the Python stubs of the public API into the tessera_client package, run by the
# custom command in CMakeLists.txt (cmake -P). protoc and grpc_python_plugin rather than
# Debian's grpc_tools, which is too old for proto3 `optional`. The generated modules import
# each other as `tessera.v1`; that import is rewritten to `tessera_client._proto`, so the
# package brings no top-level `tessera` module into a user's Python.
#
# Variables: PROTOC, PLUGIN, PROTO_ROOT (the folder holding tessera/v1/*.proto), WORK_DIR
# (scratch), OUTPUT_DIR (the package's _proto folder), PROTOS (comma-separated file names).
foreach(var PROTOC PLUGIN PROTO_ROOT WORK_DIR OUTPUT_DIR PROTOS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "generate_stubs.cmake: ${var} is not set")
  endif()
endforeach()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR} ${OUTPUT_DIR})
string(REPLACE "," ";" protos "${PROTOS}")
set(proto_paths)
foreach(proto ${protos})
  list(APPEND proto_paths ${PROTO_ROOT}/tessera/v1/${proto})
endforeach()
execute_process(
  COMMAND ${PROTOC} --proto_path=${PROTO_ROOT} --python_out=${WORK_DIR}
          --grpc_python_out=${WORK_DIR} --plugin=protoc-gen-grpc_python=${PLUGIN} ${proto_paths}
  RESULT_VARIABLE status
  ERROR_VARIABLE errors)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "protoc failed (${status}): ${errors}")
endif()

file(GLOB generated ${WORK_DIR}/tessera/v1/*.py)
if(NOT generated)
  message(FATAL_ERROR "protoc wrote no Python modules into ${WORK_DIR}/tessera/v1")
endif()
foreach(module ${generated})
  get_filename_component(name ${module} NAME)
  file(READ ${module} text)
  string(REGEX REPLACE "(^|\n)from tessera\\.v1 import " "\\1from tessera_client._proto import "
                       text "${text}")
  file(WRITE ${OUTPUT_DIR}/${name} "${text}")
endforeach()
file(WRITE ${OUTPUT_DIR}/__init__.py "# Generated from proto/tessera/v1 at build time.\n")
file(REMOVE_RECURSE ${WORK_DIR})
