# The web build's dependencies (emcmake; docs/web.md). Emscripten's toolchain
# searches only its own sysroot, so Debian's header-only libraries (glm,
# nlohmann-json, stb) are reached through a folder of links to exactly those
# three, never /usr/include itself (whose C library headers are not
# Emscripten's). libjpeg, libzstd and libastcenc have no WebAssembly build in
# Debian: the web build goes without them, and their files are refused by
# name (PX_NO_JPEG, PX_NO_ZSTD, PX_NO_ASTCENC).
set(PX_WEB_HOST_HEADERS ${CMAKE_BINARY_DIR}/web_host_headers)
file(MAKE_DIRECTORY ${PX_WEB_HOST_HEADERS})
foreach(dir glm nlohmann stb)
  if(NOT EXISTS /usr/include/${dir})
    message(FATAL_ERROR "the web build needs Debian's /usr/include/${dir}: apt-get install libglm-dev nlohmann-json3-dev libstb-dev")
  endif()
  if(NOT EXISTS ${PX_WEB_HOST_HEADERS}/${dir})
    file(CREATE_LINK /usr/include/${dir} ${PX_WEB_HOST_HEADERS}/${dir} SYMBOLIC)
  endif()
endforeach()
add_library(glm::glm INTERFACE IMPORTED)
set_target_properties(glm::glm PROPERTIES INTERFACE_INCLUDE_DIRECTORIES ${PX_WEB_HOST_HEADERS})
add_library(nlohmann_json::nlohmann_json INTERFACE IMPORTED)
set_target_properties(nlohmann_json::nlohmann_json PROPERTIES INTERFACE_INCLUDE_DIRECTORIES ${PX_WEB_HOST_HEADERS})
set(STB_INCLUDE_DIR ${PX_WEB_HOST_HEADERS})
set(JPEG_INCLUDE_DIRS "")
set(ZSTD_INCLUDE_DIR "")
set(GLES_LIBRARY "")
add_compile_definitions(PX_NO_JPEG PX_NO_ZSTD PX_NO_ASTCENC)
# The scene reader reports JSON errors through exceptions (nlohmann-json).
add_compile_options(-fexceptions)
add_link_options(-fexceptions)
