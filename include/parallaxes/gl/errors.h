// GL error checks at well-defined points (after each upload, build and draw,
// not after every call), and KHR_debug messages where the context has them.
#pragma once

#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/gl/gl.h"

namespace px {

const char* gl_enum_name(GLenum e);

// Drains glGetError; an error names `where` and every pending error code.
Status check_gl(const std::string& where);

// Reads and discards errors the host left pending (GL keeps no way to put
// them back), so that the library's checks report only its own; called on
// entry to each call of the library that checks for errors.
void discard_pending_errors();

// The program's info log (the driver's link messages), without its NUL.
std::string program_info_log(GLuint program);

// Names a framebuffer completeness status.
const char* framebuffer_status_name(GLenum status);

// Loader for extension entry points (eglGetProcAddress in platform/, or the
// host app's own loader): the library never includes EGL.
using GetProcAddress = void* (*)(const char* name);

// Installs a KHR_debug callback that collects the driver's messages, if the
// context exposes GL_KHR_debug, `get_proc` finds its entry points and the
// host has no callback of its own: a host's callback and its user
// parameter are left alone (the context holds one; the library's errors
// then carry glGetError's codes only).
enum class DebugMessages { none, installed, host_callback };
DebugMessages install_debug_messages(GetProcAddress get_proc, bool has_khr_debug);
// Takes the library's callback out again (context current), leaving none;
// a callback the host installed since is left alone.
void remove_debug_messages(GetProcAddress get_proc);
// Messages of high and medium severity since the last call (cleared).
std::vector<std::string> take_debug_messages();

}  // namespace px
