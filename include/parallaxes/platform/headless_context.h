// A headless OpenGL ES context on EGL, for the command-line tool, tests and
// benchmarks. The only code in the project that includes EGL, and apart from
// the library's layers: it sees only core/result.h, and libEGL is opened with
// dlopen, never linked, so a missing or broken EGL gets a message, not a
// loader error. Apps that own their context never use this: they hand the
// renderer their framebuffer.
#pragma once

#include <memory>
#include <string>

#include "parallaxes/core/result.h"

namespace px::platform {

struct ContextOptions {
    int es_major = 3;  // 2 or 3: the context is checked to really be that version
    bool debug = false;  // ask for a debug context (KHR_debug messages)
};

class HeadlessContext {
public:
    // Opens libEGL, a display (EGL_PLATFORM_SURFACELESS_MESA, then
    // EGL_EXT_platform_device, then the default display), creates the context
    // and makes it current with no surface. Every failure names the EGL error
    // and what to install or try. With LP_NATIVE_VECTOR_WIDTH or
    // GALLIUM_OVERRIDE_CPU_CAPS set and no MESA_SHADER_CACHE_DIR, it sets
    // MESA_SHADER_CACHE_DISABLE=true first (unless already set): Mesa 22.3
    // corrupts its heap loading a shader cached under another configuration.
    static Result<std::unique_ptr<HeadlessContext>> create(const ContextOptions& options);
    ~HeadlessContext();
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;

    Status make_current();
    int es_major() const { return es_major_; }
    // "surfaceless (EGL_MESA_platform_surfaceless), EGL 1.5"
    const std::string& display_description() const { return display_description_; }
    // eglGetProcAddress, for extension entry points: the type of the
    // renderer's RendererOptions::get_proc_address.
    using ProcLoader = void* (*)(const char* name);
    static ProcLoader proc_loader();

private:
    HeadlessContext() = default;
    struct Egl;
    std::unique_ptr<Egl> egl_;
    int es_major_ = 3;
    std::string display_description_;
};

}  // namespace px::platform
