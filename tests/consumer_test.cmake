# Installs an osdmra build tree into a scratch prefix, then configures, builds and
# runs tests/consumer against that prefix alone: checks the install rules, the
# exported target and osdmraConfig.cmake the way a user's project meets them.
#
#   cmake -DOSDMRA_BUILD_DIR=<build tree> -DCONSUMER_SOURCE_DIR=<tests/consumer>
#         -DWORK_DIR=<scratch dir> [-DCXX_COMPILER=...] [-DBUILD_TYPE=...]
#         [-DSANITIZE=address,undefined] -P consumer_test.cmake
cmake_minimum_required(VERSION 3.20)
foreach(var OSDMRA_BUILD_DIR CONSUMER_SOURCE_DIR WORK_DIR)
  if(NOT ${var})
    message(FATAL_ERROR "consumer_test.cmake: ${var} is not set")
  endif()
endforeach()
if(NOT BUILD_TYPE)
  set(BUILD_TYPE Release)
endif()

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " line "${ARGN}")
    message(FATAL_ERROR "consumer_test.cmake: failed (${rc}): ${line}")
  endif()
endfunction()

set(prefix "${WORK_DIR}/prefix")
set(build "${WORK_DIR}/build")
file(REMOVE_RECURSE "${WORK_DIR}")

run(${CMAKE_COMMAND} --install "${OSDMRA_BUILD_DIR}" --config "${BUILD_TYPE}" --prefix "${prefix}")

# The public API only: the top layer's header is there, and no detail/ folder (their
# headers are internal helpers, README, Layout).
set(headers "${prefix}/include/osdmra")
if(NOT EXISTS "${headers}/pipeline.h")
  message(FATAL_ERROR "consumer_test.cmake: ${headers}/pipeline.h is not installed; "
    "the top layer must be part of the installed API")
endif()
file(GLOB_RECURSE installed LIST_DIRECTORIES true RELATIVE "${headers}" "${headers}/*")
set(leaked "")
foreach(entry IN LISTS installed)
  if(entry MATCHES "(^|/)detail(/|$)")
    list(APPEND leaked "${entry}")
  endif()
endforeach()
if(leaked)
  string(REPLACE ";" ", " leaked "${leaked}")
  message(FATAL_ERROR "consumer_test.cmake: detail/ headers are internal and must not be "
    "installed, but ${headers} has: ${leaked}")
endif()

set(configure -S "${CONSUMER_SOURCE_DIR}" -B "${build}"
  "-DCMAKE_BUILD_TYPE=${BUILD_TYPE}"
  "-DCMAKE_PREFIX_PATH=${prefix}"
  "-DOSDMRA_EXPECTED_PREFIX=${prefix}"
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
if(CXX_COMPILER)
  list(APPEND configure "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
endif()
# A sanitized static libosdmra needs the sanitizer runtimes at link time.
if(SANITIZE)
  list(APPEND configure "-DCMAKE_CXX_FLAGS=-fsanitize=${SANITIZE}"
    "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=${SANITIZE}")
endif()
run(${CMAKE_COMMAND} ${configure})
run(${CMAKE_COMMAND} --build "${build}" --config "${BUILD_TYPE}")
run(${CMAKE_CTEST_COMMAND} --test-dir "${build}" -C "${BUILD_TYPE}" --output-on-failure)

file(REMOVE_RECURSE "${WORK_DIR}")
