// The browser platform: WebGL through Emscripten's html5 API.
#include "parallaxes/platform/web_context.h"

#include <emscripten/html5.h>

#include <string>

namespace px::platform {

namespace {

// What the library's ES 2.0 paths use on WebGL 1 (derivatives for the
// normal-from-height path and the LOD, frag depth for depth_write, 32-bit
// indices, float targets for the surface capture), and the compressed
// formats the texture loader uploads as they are. Each is asked for by name:
// a browser without one leaves it out, and the renderer's caps see it
// missing (GL_EXTENSIONS lists only what is enabled).
const char* const kExtensions[] = {
    "OES_standard_derivatives", "EXT_frag_depth", "OES_element_index_uint", "EXT_shader_texture_lod",
    "OES_texture_float", "OES_texture_half_float", "WEBGL_color_buffer_float", "EXT_color_buffer_float",
    "EXT_color_buffer_half_float", "EXT_sRGB", "WEBGL_compressed_texture_etc", "WEBGL_compressed_texture_etc1",
    "WEBGL_compressed_texture_astc", "WEBGL_compressed_texture_s3tc", "WEBGL_compressed_texture_s3tc_srgb",
    "WEBGL_compressed_texture_pvrtc", "EXT_texture_filter_anisotropic",
};

const char* html5_result_name(EMSCRIPTEN_RESULT r) {
    switch (r) {
        case EMSCRIPTEN_RESULT_NOT_SUPPORTED: return "not supported";
        case EMSCRIPTEN_RESULT_UNKNOWN_TARGET: return "no element matches the selector";
        case EMSCRIPTEN_RESULT_INVALID_TARGET: return "the element is not a canvas";
        case EMSCRIPTEN_RESULT_INVALID_PARAM: return "invalid parameter";
        case EMSCRIPTEN_RESULT_FAILED: return "the browser refused";
        default: return "error";
    }
}

// emscripten_webgl_create_context gives 0 where the browser returns no
// context (no WebGL of that version here), a negative code otherwise.
std::string why_not(EMSCRIPTEN_WEBGL_CONTEXT_HANDLE h, int version) {
    const std::string what = "WebGL " + std::to_string(version);
    if (h == 0) return "this browser gives no " + what + " context";
    return what + ": " + html5_result_name(static_cast<EMSCRIPTEN_RESULT>(h));
}

EMSCRIPTEN_WEBGL_CONTEXT_HANDLE try_create(const WebContextOptions& o, int version) {
    EmscriptenWebGLContextAttributes a;
    emscripten_webgl_init_context_attributes(&a);
    a.alpha = false;
    a.depth = true;
    a.stencil = false;
    a.antialias = o.antialias;
    a.premultipliedAlpha = false;
    // The page reads its pixels back (tests, screenshots) after the frame.
    a.preserveDrawingBuffer = true;
    a.majorVersion = version;
    a.minorVersion = 0;
    // Only the extensions named above, so that what the caps list is what
    // this code asked for.
    a.enableExtensionsByDefault = false;
    return emscripten_webgl_create_context(o.canvas.c_str(), &a);
}

}  // namespace

Result<std::unique_ptr<WebContext>> WebContext::create(const WebContextOptions& options) {
    if (options.webgl_version != 1 && options.webgl_version != 2)
        return make_error("WebGL version " + std::to_string(options.webgl_version) + ": 1 or 2");
    std::unique_ptr<WebContext> c(new WebContext());
    EMSCRIPTEN_WEBGL_CONTEXT_HANDLE h = try_create(options, options.webgl_version);
    c->webgl_version_ = options.webgl_version;
    if (h <= 0 && options.webgl_version == 2 && options.fall_back) {
        const std::string why = why_not(h, 2);
        h = try_create(options, 1);
        c->webgl_version_ = 1;
        if (h > 0) c->fallback_note_ = why + ": WebGL 1, the OpenGL ES 2.0 paths";
    }
    if (h <= 0)
        return make_error("cannot draw on '" + options.canvas + "': " + why_not(h, c->webgl_version_) +
                          (options.webgl_version == 2 && options.fall_back ? ", nor WebGL 1" : ""));
    c->handle_ = h;
    if (emscripten_webgl_make_context_current(h) != EMSCRIPTEN_RESULT_SUCCESS)
        return make_error("cannot make the WebGL context on '" + options.canvas + "' current");
    for (const char* e : kExtensions) {
        if (emscripten_webgl_enable_extension(h, e)) {
            if (!c->enabled_extensions_.empty()) c->enabled_extensions_ += ' ';
            c->enabled_extensions_ += e;
        }
    }
    return c;
}

WebContext::~WebContext() {
    if (handle_ > 0) emscripten_webgl_destroy_context(static_cast<EMSCRIPTEN_WEBGL_CONTEXT_HANDLE>(handle_));
}

Status WebContext::make_current() const {
    if (emscripten_webgl_make_context_current(static_cast<EMSCRIPTEN_WEBGL_CONTEXT_HANDLE>(handle_)) !=
        EMSCRIPTEN_RESULT_SUCCESS)
        return make_error("cannot make the WebGL context current");
    return {};
}

std::function<const void*()> WebContext::current_context() {
    return [] { return reinterpret_cast<const void*>(emscripten_webgl_get_current_context()); };
}

}  // namespace px::platform
