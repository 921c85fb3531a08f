#include "parallaxes/gl/errors.h"

#include <mutex>

namespace px {

const char* gl_enum_name(GLenum e) {
    switch (e) {
        case GL_NO_ERROR: return "GL_NO_ERROR";
        case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
        default: return "unknown GL enum";
    }
}

const char* framebuffer_status_name(GLenum status) {
    switch (status) {
        case GL_FRAMEBUFFER_COMPLETE: return "GL_FRAMEBUFFER_COMPLETE";
        // ES 3.0: framebuffer 0 of a context with no default framebuffer
        // (surfaceless, or made current with no surface).
        case GL_FRAMEBUFFER_UNDEFINED: return "GL_FRAMEBUFFER_UNDEFINED (framebuffer 0 of a context made current without a surface)";
        case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
        case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
        case GL_FRAMEBUFFER_INCOMPLETE_DIMENSIONS: return "GL_FRAMEBUFFER_INCOMPLETE_DIMENSIONS";
        case GL_FRAMEBUFFER_UNSUPPORTED: return "GL_FRAMEBUFFER_UNSUPPORTED";
        case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE: return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
        case 0: return "no status (glCheckFramebufferStatus failed: is a context current?)";
        default: return "unknown framebuffer status";
    }
}

std::string program_info_log(GLuint program) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(length > 1 ? length : 1), '\0');
    glGetProgramInfoLog(program, length, nullptr, &log[0]);
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

void discard_pending_errors() {
    for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; ++i) {
    }
    (void)take_debug_messages();
}

Status check_gl(const std::string& where) {
    std::string errors;
    // Bounded: a lost context may report errors forever.
    for (int i = 0; i < 16; ++i) {
        const GLenum e = glGetError();
        if (e == GL_NO_ERROR) break;
        if (!errors.empty()) errors += ", ";
        errors += gl_enum_name(e);
    }
    std::vector<std::string> debug = take_debug_messages();
    if (errors.empty()) return {};
    std::string message = "GL error after " + where + ": " + errors;
    for (const std::string& m : debug) message += "\n  driver: " + m;
    return make_error(message);
}

namespace {

std::mutex g_debug_mutex;
std::vector<std::string> g_debug_messages;

void GL_APIENTRY on_debug_message(GLenum /*source*/, GLenum type, GLuint /*id*/, GLenum severity,
                                  GLsizei length, const GLchar* message, const void* /*user*/) {
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION_KHR || severity == GL_DEBUG_SEVERITY_LOW_KHR) return;
    std::lock_guard<std::mutex> lock(g_debug_mutex);
    if (g_debug_messages.size() >= 64) return;
    std::string text = type == GL_DEBUG_TYPE_ERROR_KHR ? "error: " : "";
    text.append(message, length > 0 ? static_cast<size_t>(length) : std::char_traits<char>::length(message));
    g_debug_messages.push_back(text);
}

}  // namespace

DebugMessages install_debug_messages(GetProcAddress get_proc, bool has_khr_debug) {
    if (!get_proc || !has_khr_debug) return DebugMessages::none;
    auto callback = reinterpret_cast<PFNGLDEBUGMESSAGECALLBACKKHRPROC>(get_proc("glDebugMessageCallbackKHR"));
    auto get_pointer = reinterpret_cast<PFNGLGETPOINTERVKHRPROC>(get_proc("glGetPointervKHR"));
    if (!callback || !get_pointer) return DebugMessages::none;
    // The host's own callback (and its user parameter) stays: the context
    // has one callback, and the host's is the host's. The library's errors
    // then carry glGetError's codes without the driver's words.
    void* host = nullptr;
    get_pointer(GL_DEBUG_CALLBACK_FUNCTION_KHR, &host);
    if (host != nullptr) return reinterpret_cast<void*>(&on_debug_message) == host ? DebugMessages::installed
                                                                                    : DebugMessages::host_callback;
    callback(on_debug_message, nullptr);
    return DebugMessages::installed;
}

void remove_debug_messages(GetProcAddress get_proc) {
    if (!get_proc) return;
    auto callback = reinterpret_cast<PFNGLDEBUGMESSAGECALLBACKKHRPROC>(get_proc("glDebugMessageCallbackKHR"));
    auto get_pointer = reinterpret_cast<PFNGLGETPOINTERVKHRPROC>(get_proc("glGetPointervKHR"));
    if (!callback || !get_pointer) return;
    void* current = nullptr;
    get_pointer(GL_DEBUG_CALLBACK_FUNCTION_KHR, &current);
    // Only the library's own: a host that installed one since keeps it.
    if (current == reinterpret_cast<void*>(&on_debug_message)) callback(nullptr, nullptr);
}

std::vector<std::string> take_debug_messages() {
    std::lock_guard<std::mutex> lock(g_debug_mutex);
    std::vector<std::string> out;
    out.swap(g_debug_messages);
    return out;
}

}  // namespace px
