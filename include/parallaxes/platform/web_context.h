// The browser's platform (the web build, docs/web.md): a WebGL 2 context
// (OpenGL ES 3.0: the ES 3.0 paths) or a WebGL 1 context with its extensions
// (OpenGL ES 2.0: the ES 2.0 paths) on a page's canvas, made current. The
// sibling of HeadlessContext (surfaceless EGL); the library's layers do not
// know which one they run on. Defined only in a build for the browser
// (Emscripten); the declaration is plain C++ so that every build checks it.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "parallaxes/core/result.h"

namespace px::platform {

struct WebContextOptions {
    std::string canvas = "#canvas";  // CSS selector of the page's <canvas>
    int webgl_version = 2;           // 2: WebGL 2 (ES 3.0); 1: WebGL 1 (ES 2.0)
    // Where WebGL 2 cannot be had, take WebGL 1 (the ES 2.0 paths) and say so
    // in fallback_note() instead of failing.
    bool fall_back = true;
    bool antialias = false;  // the canvas's own multisampling (the library's images are compared without it)
};

class WebContext {
public:
    // Errors: no canvas matches the selector, or the browser gives neither
    // WebGL version asked for (the message names both and the selector).
    static Result<std::unique_ptr<WebContext>> create(const WebContextOptions& options = {});
    ~WebContext();
    WebContext(const WebContext&) = delete;
    WebContext& operator=(const WebContext&) = delete;

    int webgl_version() const { return webgl_version_; }
    int es_major() const { return webgl_version_ == 2 ? 3 : 2; }
    // Why this is WebGL 1 when WebGL 2 was asked for; empty otherwise.
    const std::string& fallback_note() const { return fallback_note_; }
    // The WebGL extensions enabled at creation (browser names, without "GL_").
    const std::string& enabled_extensions() const { return enabled_extensions_; }
    // For RendererOptions::current_context: the context current now.
    static std::function<const void*()> current_context();
    Status make_current() const;

private:
    WebContext() = default;
    long handle_ = 0;  // EMSCRIPTEN_WEBGL_CONTEXT_HANDLE
    int webgl_version_ = 0;
    std::string fallback_note_;
    std::string enabled_extensions_;
};

}  // namespace px::platform
