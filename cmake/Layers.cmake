# One static library per folder of host/ ("layer"), so the layering is a build fact.
# Each layer gets its own include root (build/include-roots/<layer>/<layer> links to
# host/<layer>) and sees only the roots of the layers it links: scene/ cannot even find
# gpu/ headers. cmake/CheckLayers.cmake checks what include roots cannot (system headers).
include_guard(GLOBAL)

set(PENUMBRA_INCLUDE_ROOTS ${PROJECT_BINARY_DIR}/include-roots)

# An include root <root>/<name>/<name> -> <dir>, so sources keep writing "<name>/x.h".
function(penumbra_include_root name dir)
  file(MAKE_DIRECTORY ${PENUMBRA_INCLUDE_ROOTS}/${name})
  file(CREATE_LINK ${dir} ${PENUMBRA_INCLUDE_ROOTS}/${name}/${name} SYMBOLIC)
endfunction()

# penumbra_add_layer(<layer> [TARGET name] [PUBLIC deps...] [PRIVATE deps...]) builds every
# .cpp under host/<layer>/ (new files join automatically) into a static library, named
# penumbra_<layer> unless TARGET says otherwise. Dependencies that are layers are recorded
# for the layering check, so they must be added first.
function(penumbra_add_layer layer)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "TARGET" "PUBLIC;PRIVATE")
  if(NOT arg_TARGET)
    set(arg_TARGET penumbra_${layer})
  endif()
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/host/${layer}/*.cpp)
  penumbra_include_root(${layer} ${PROJECT_SOURCE_DIR}/host/${layer})
  add_library(${arg_TARGET} STATIC ${sources})
  if(PENUMBRA_PYTHON)  # linked into the Python module, a shared object (cmake/Python.cmake)
    set_target_properties(${arg_TARGET} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  endif()
  target_include_directories(${arg_TARGET} PUBLIC ${PENUMBRA_INCLUDE_ROOTS}/${layer})
  target_link_libraries(${arg_TARGET} PUBLIC penumbra_options ${arg_PUBLIC}
                                      PRIVATE ${arg_PRIVATE})
  set(uses "")
  foreach(dep IN LISTS arg_PUBLIC arg_PRIVATE)
    get_property(dep_layer GLOBAL PROPERTY PENUMBRA_LAYER_OF_${dep})
    if(dep_layer)
      list(APPEND uses ${dep_layer})
    endif()
  endforeach()
  set_property(GLOBAL PROPERTY PENUMBRA_LAYER_OF_${arg_TARGET} ${layer})
  set_property(GLOBAL APPEND PROPERTY PENUMBRA_LAYERS ${layer})
  set_property(GLOBAL PROPERTY PENUMBRA_LAYER_USES_${layer} "${uses}")
endfunction()

# "layer=dep,dep;layer=..." for cmake/CheckLayers.cmake: each layer and the layers it links.
function(penumbra_layer_graph out)
  get_property(layers GLOBAL PROPERTY PENUMBRA_LAYERS)
  set(graph "")
  foreach(layer IN LISTS layers)
    get_property(uses GLOBAL PROPERTY PENUMBRA_LAYER_USES_${layer})
    string(REPLACE ";" "," uses "${uses}")
    list(APPEND graph "${layer}=${uses}")
  endforeach()
  set(${out} "${graph}" PARENT_SCOPE)
endfunction()

# Every folder of host/ must be a layer: a new folder would otherwise not be built at all.
function(penumbra_check_every_folder_is_a_layer)
  get_property(layers GLOBAL PROPERTY PENUMBRA_LAYERS)
  file(GLOB entries LIST_DIRECTORIES true ${PROJECT_SOURCE_DIR}/host/*)
  foreach(entry IN LISTS entries)
    get_filename_component(name ${entry} NAME)
    if(IS_DIRECTORY ${entry} AND NOT name IN_LIST layers)
      message(FATAL_ERROR "host/${name}/ is not a layer: add penumbra_add_layer(${name} ...) "
                          "to CMakeLists.txt")
    endif()
  endforeach()
endfunction()
