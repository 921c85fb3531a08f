# Layers the build enforces (docs: README "Layout", ../shared/DESIGN.md).
#
# Every source folder is its own include root: build/views/<folder>/ holds one
# link, <folder> -> the folder itself, and that view is the only include
# directory a folder's target publishes. A target sees its own folder and the
# folders of the targets it links, nothing else, so `#include "gl/caps.h"`
# from a core file fails with "No such file or directory": a backward include
# does not build. tests/layers/ checks this with a deliberate one.

set(PX_VIEW_ROOT ${CMAKE_BINARY_DIR}/views)

# px_folder_view(FOLDER PATH): makes build/views/FOLDER/FOLDER -> PATH and
# returns the include root in PX_VIEW_<FOLDER>.
function(px_folder_view folder path)
  set(view ${PX_VIEW_ROOT}/${folder})
  file(MAKE_DIRECTORY ${view})
  if(NOT EXISTS ${view}/${folder})
    file(CREATE_LINK ${path} ${view}/${folder} SYMBOLIC)
  endif()
  set(PX_VIEW_${folder} ${view} PARENT_SCOPE)
endfunction()

# px_layer_objects(NAME FOLDER PATH DEPS ...): an object library of every .cpp
# in PATH, publishing only FOLDER's view, linking the object libraries DEPS
# (which bring their own views). Extra sources may be added by the caller.
function(px_layer_objects name folder path)
  cmake_parse_arguments(ARG "" "" "DEPS;SOURCES" ${ARGN})
  px_folder_view(${folder} ${path})
  file(GLOB sources CONFIGURE_DEPENDS ${path}/*.cpp)
  add_library(${name} OBJECT ${sources} ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC $<BUILD_INTERFACE:${PX_VIEW_${folder}}>)
  target_compile_options(${name} PRIVATE ${PX_WARNINGS})
  # Unused functions and data stay out of a host's binary when it links with
  # --gc-sections (examples/host_app does).
  target_compile_options(${name} PRIVATE -ffunction-sections -fdata-sections)
  set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  if(ARG_DEPS)
    target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  endif()
  set(PX_VIEW_${folder} ${PX_VIEW_${folder}} PARENT_SCOPE)
endfunction()
