# The layering test (ctest "layering"): every #include in host/<layer>/ must name the
# layer itself or a layer it links (directly or through others), and a layer that does
# not link gpu must not include Vulkan or GLFW headers, which include roots cannot hide.
# Usage: cmake -DSOURCE_DIR=<repo> -DGRAPH="scene=core|bvh=|..." -P cmake/CheckLayers.cmake
# (GRAPH comes from penumbra_layer_graph in cmake/Layers.cmake, i.e. from the targets.)
cmake_minimum_required(VERSION 3.25)

string(REPLACE "|" ";" entries "${GRAPH}")
set(layers "")
foreach(entry IN LISTS entries)
  string(REGEX MATCH "^([^=]+)=(.*)$" _ "${entry}")
  list(APPEND layers ${CMAKE_MATCH_1})
  string(REPLACE "," ";" uses_${CMAKE_MATCH_1} "${CMAKE_MATCH_2}")
endforeach()

# reach_<layer>: the layer and everything it links, transitively.
foreach(layer IN LISTS layers)
  set(reach ${layer})
  set(todo ${uses_${layer}})
  while(todo)
    list(POP_FRONT todo next)
    if(NOT next IN_LIST reach)
      list(APPEND reach ${next})
      list(APPEND todo ${uses_${next}})
    endif()
  endwhile()
  set(reach_${layer} ${reach})
endforeach()

set(problems "")
foreach(layer IN LISTS layers)
  file(GLOB_RECURSE files ${SOURCE_DIR}/host/${layer}/*.h ${SOURCE_DIR}/host/${layer}/*.hpp
                          ${SOURCE_DIR}/host/${layer}/*.cpp)
  string(REPLACE ";" ", " allowed "${reach_${layer}}")
  foreach(file IN LISTS files)
    file(RELATIVE_PATH rel ${SOURCE_DIR} ${file})
    file(STRINGS ${file} lines REGEX "^[ \t]*#[ \t]*include")
    foreach(line IN LISTS lines)
      if(NOT line MATCHES "^[ \t]*#[ \t]*include[ \t]*[<\"]([^>\"]+)[>\"]")
        continue()
      endif()
      set(header ${CMAKE_MATCH_1})
      string(REGEX MATCH "^[^/]+" top "${header}")
      string(TOLOWER "${header}" lower)
      if(header MATCHES "^\\.\\./|/\\.\\./")
        list(APPEND problems "${rel}: includes \"${header}\": name headers from the layer root")
      elseif(top IN_LIST layers AND NOT top IN_LIST reach_${layer})
        list(APPEND problems
             "${rel}: includes \"${header}\", but ${layer} may only use ${allowed}")
      elseif(NOT gpu IN_LIST reach_${layer}
             AND (lower MATCHES "(^|/)vulkan|^glfw/|(^|/)volk\\.h"))
        list(APPEND problems
             "${rel}: includes <${header}>, but ${layer} does not use the GPU (only ${allowed})")
      endif()
    endforeach()
  endforeach()
endforeach()

if(problems)
  string(REPLACE ";" "\n" problems "${problems}")
  message(FATAL_ERROR "layering violations:\n${problems}")
endif()
list(LENGTH layers count)
message(STATUS "layering: ${count} layers, every include follows the targets' links")
