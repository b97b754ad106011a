# Checks that the library's folders are layers (README, Layout): a file in a layer
# includes osdmra headers of its own layer and the layers below it only; mra/ and
# remesh/ are siblings that do not include each other; codec/ sits on both; public headers include no
# detail/ header (detail/ is not installed); only subdivision/ talks to OpenSubdiv;
# nothing in the library includes GL, GLFW or Dear ImGui.
#
#   cmake -DSOURCE_DIR=<repository root> -P check_layers.cmake
cmake_minimum_required(VERSION 3.20)
if(NOT SOURCE_DIR)
  message(FATAL_ERROR "check_layers.cmake: SOURCE_DIR is not set")
endif()

# Rank of each layer, lowest first; equal ranks may not include each other.
set(rank_base 0)
set(rank_mesh 1)
set(rank_geometry 2)
set(rank_subdivision 3)
set(rank_mra 4)
set(rank_remesh 4)
set(rank_codec 5)
set(rank_pipeline 6)

function(layer_of path out)
  # osdmra/<layer>/... or osdmra/pipeline.*
  if(path MATCHES "^osdmra/([a-z_]+)/")
    set(${out} "${CMAKE_MATCH_1}" PARENT_SCOPE)
  elseif(path MATCHES "^osdmra/pipeline\\.")
    set(${out} "pipeline" PARENT_SCOPE)
  else()
    set(${out} "" PARENT_SCOPE)
  endif()
endfunction()

set(problems "")
file(GLOB_RECURSE files RELATIVE "${SOURCE_DIR}" "${SOURCE_DIR}/osdmra/*.h"
  "${SOURCE_DIR}/osdmra/*.cpp")
foreach(file IN LISTS files)
  layer_of("${file}" layer)
  if(NOT DEFINED rank_${layer})
    string(APPEND problems "\n  ${file}: not in a known layer folder")
    continue()
  endif()
  file(STRINGS "${SOURCE_DIR}/${file}" includes REGEX "^#include ")
  foreach(line IN LISTS includes)
    if(line MATCHES "[<\"](GL|GLFW|imgui)")
      string(APPEND problems "\n  ${file}: ${line} (no GL in the library)")
    endif()
    if(line MATCHES "<opensubdiv/" AND NOT layer STREQUAL "subdivision")
      string(APPEND problems "\n  ${file}: ${line} (only subdivision/ uses OpenSubdiv)")
    endif()
    if(NOT line MATCHES "\"(osdmra/[^\"]+)\"")
      continue()
    endif()
    set(target "${CMAKE_MATCH_1}")
    layer_of("${target}" used)
    if(NOT DEFINED rank_${used})
      string(APPEND problems "\n  ${file}: ${line} (not in a known layer folder)")
    elseif(NOT used STREQUAL layer AND NOT rank_${used} LESS rank_${layer})
      string(APPEND problems "\n  ${file}: ${line} (${layer} may not use ${used})")
    endif()
    if(target MATCHES "/detail/" AND file MATCHES "\\.h$" AND NOT file MATCHES "/detail/")
      string(APPEND problems "\n  ${file}: ${line} (a public header includes a detail/ one)")
    endif()
  endforeach()
endforeach()

if(problems)
  message(FATAL_ERROR "layering broken:${problems}")
endif()
list(LENGTH files count)
message(STATUS "layering: ${count} files checked")
