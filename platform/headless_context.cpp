#include "parallaxes/platform/headless_context.h"

#include <dlfcn.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <string>

#include <GLES2/gl2.h>

namespace px::platform {

namespace {

// Live HeadlessContexts per display: eglInitialize on an initialised display
// does nothing, eglTerminate ends it for all, so the last one terminates it.
std::mutex g_display_mutex;
std::map<EGLDisplay, int> g_display_users;

void retain_display(EGLDisplay display) {
    std::lock_guard<std::mutex> lock(g_display_mutex);
    ++g_display_users[display];
}

// Whether this was the display's last user.
bool release_display(EGLDisplay display) {
    std::lock_guard<std::mutex> lock(g_display_mutex);
    auto it = g_display_users.find(display);
    if (it == g_display_users.end()) return true;
    if (--it->second > 0) return false;
    g_display_users.erase(it);
    return true;
}

const char* egl_error_name(EGLint e) {
    switch (e) {
        case EGL_SUCCESS: return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
        case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
        case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
        case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
        case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
        case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
        case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
        case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
        case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
        case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
        default: return "unknown EGL error";
    }
}

bool has_word(const char* list, const char* word) {
    if (!list) return false;
    const size_t n = std::strlen(word);
    for (const char* p = list; (p = std::strstr(p, word)) != nullptr; p += n) {
        const bool starts = p == list || p[-1] == ' ';
        const bool ends = p[n] == '\0' || p[n] == ' ';
        if (starts && ends) return true;
    }
    return false;
}

const char* kInstallHint = "install Mesa's EGL and software rasteriser: apt-get install libegl1 libegl-mesa0 libgles2 libgl1-mesa-dri";

}  // namespace

// EGL entry points, loaded at run time so that a machine without libEGL gets
// a message instead of a loader failure before main().
struct HeadlessContext::Egl {
    void* library = nullptr;
    PFNEGLGETPROCADDRESSPROC GetProcAddress = nullptr;
    PFNEGLGETERRORPROC GetError = nullptr;
    PFNEGLQUERYSTRINGPROC QueryString = nullptr;
    PFNEGLGETDISPLAYPROC GetDisplay = nullptr;
    PFNEGLGETPLATFORMDISPLAYEXTPROC GetPlatformDisplayEXT = nullptr;
    PFNEGLQUERYDEVICESEXTPROC QueryDevicesEXT = nullptr;
    PFNEGLINITIALIZEPROC Initialize = nullptr;
    PFNEGLTERMINATEPROC Terminate = nullptr;
    PFNEGLBINDAPIPROC BindAPI = nullptr;
    PFNEGLCHOOSECONFIGPROC ChooseConfig = nullptr;
    PFNEGLCREATECONTEXTPROC CreateContext = nullptr;
    PFNEGLDESTROYCONTEXTPROC DestroyContext = nullptr;
    PFNEGLMAKECURRENTPROC MakeCurrent = nullptr;
    PFNEGLRELEASETHREADPROC ReleaseThread = nullptr;
    PFNEGLGETCURRENTCONTEXTPROC GetCurrentContext = nullptr;

    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;

    std::string error(const std::string& what) const {
        return what + " failed with " + egl_error_name(GetError());
    }

    ~Egl() {
        if (display != EGL_NO_DISPLAY) {
            // Release only this context: another one of the process may be
            // current. eglTerminate ends every context of the display (one
            // per process for the surfaceless platform), so only the last
            // HeadlessContext on it terminates it.
            if (context != EGL_NO_CONTEXT && (!GetCurrentContext || GetCurrentContext() == context))
                MakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            if (context != EGL_NO_CONTEXT) DestroyContext(display, context);
            if (release_display(display)) {
                Terminate(display);
                ReleaseThread();
            }
        }
        // libEGL stays loaded: Mesa's drivers register exit handlers.
    }
};

static void* g_get_proc_address = nullptr;

HeadlessContext::ProcLoader HeadlessContext::proc_loader() {
    return [](const char* name) -> void* {
        if (!g_get_proc_address) return nullptr;
        return reinterpret_cast<void*>(reinterpret_cast<PFNEGLGETPROCADDRESSPROC>(g_get_proc_address)(name));
    };
}

Result<std::unique_ptr<HeadlessContext>> HeadlessContext::create(const ContextOptions& options) {
    if (options.es_major != 2 && options.es_major != 3)
        return make_error("OpenGL ES " + std::to_string(options.es_major) + " was asked for; use 2 or 3");

    // Mesa 22.3's llvmpipe keys its on-disk shader cache without the SIMD
    // width or CPU features: a shader cached by a default (256-bit) run and
    // loaded by a run with LP_NATIVE_VECTOR_WIDTH=128 corrupts the heap
    // (malloc aborts in 5 runs of 6, found by the golden tests). So a run
    // on such a configuration without a cache folder of its own compiles
    // without the cache. Mesa reads these variables when the driver loads:
    // before dlopen. A value the caller set is never overwritten.
    if ((std::getenv("LP_NATIVE_VECTOR_WIDTH") || std::getenv("GALLIUM_OVERRIDE_CPU_CAPS")) &&
        !std::getenv("MESA_SHADER_CACHE_DIR"))
        ::setenv("MESA_SHADER_CACHE_DISABLE", "true", 0);

    auto egl = std::make_unique<Egl>();
    egl->library = dlopen("libEGL.so.1", RTLD_NOW | RTLD_GLOBAL);
    if (!egl->library) return make_error(std::string("cannot load libEGL.so.1 (") + dlerror() + "): " + kInstallHint);
    egl->GetProcAddress = reinterpret_cast<PFNEGLGETPROCADDRESSPROC>(dlsym(egl->library, "eglGetProcAddress"));
    if (!egl->GetProcAddress) return make_error("libEGL.so.1 has no eglGetProcAddress: a broken EGL install; " + std::string(kInstallHint));
    g_get_proc_address = reinterpret_cast<void*>(egl->GetProcAddress);
    auto load = [&egl](const char* name) { return reinterpret_cast<void*>(egl->GetProcAddress(name)); };
#define PX_LOAD(field, name) egl->field = reinterpret_cast<decltype(egl->field)>(load(name))
    PX_LOAD(GetError, "eglGetError");
    PX_LOAD(QueryString, "eglQueryString");
    PX_LOAD(GetDisplay, "eglGetDisplay");
    PX_LOAD(GetPlatformDisplayEXT, "eglGetPlatformDisplayEXT");
    PX_LOAD(QueryDevicesEXT, "eglQueryDevicesEXT");
    PX_LOAD(Initialize, "eglInitialize");
    PX_LOAD(Terminate, "eglTerminate");
    PX_LOAD(BindAPI, "eglBindAPI");
    PX_LOAD(ChooseConfig, "eglChooseConfig");
    PX_LOAD(CreateContext, "eglCreateContext");
    PX_LOAD(DestroyContext, "eglDestroyContext");
    PX_LOAD(MakeCurrent, "eglMakeCurrent");
    PX_LOAD(ReleaseThread, "eglReleaseThread");
    PX_LOAD(GetCurrentContext, "eglGetCurrentContext");
#undef PX_LOAD
    if (!egl->GetError || !egl->QueryString || !egl->GetDisplay || !egl->Initialize || !egl->Terminate ||
        !egl->BindAPI || !egl->ChooseConfig || !egl->CreateContext || !egl->DestroyContext || !egl->MakeCurrent ||
        !egl->ReleaseThread)
        return make_error(std::string("libEGL.so.1 lacks core EGL 1.4 functions; ") + kInstallHint);

    // Display: surfaceless first (no GPU, no window system), then a device,
    // then whatever the default display is. Checked before asking, as piglit does.
    const char* client_extensions = egl->QueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    std::string description;
    std::string tried;
    if (egl->GetPlatformDisplayEXT && has_word(client_extensions, "EGL_MESA_platform_surfaceless")) {
        egl->display = egl->GetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        description = "surfaceless (EGL_MESA_platform_surfaceless)";
        tried += " EGL_MESA_platform_surfaceless";
    }
    if (egl->display == EGL_NO_DISPLAY && egl->GetPlatformDisplayEXT && egl->QueryDevicesEXT &&
        has_word(client_extensions, "EGL_EXT_platform_device")) {
        EGLDeviceEXT devices[8];
        EGLint count = 0;
        if (egl->QueryDevicesEXT(8, devices, &count) && count > 0) {
            egl->display = egl->GetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[0], nullptr);
            description = "device (EGL_EXT_platform_device)";
        }
        tried += " EGL_EXT_platform_device";
    }
    if (egl->display == EGL_NO_DISPLAY) {
        egl->display = egl->GetDisplay(EGL_DEFAULT_DISPLAY);
        description = "default display";
        tried += " default-display";
    }
    if (egl->display == EGL_NO_DISPLAY)
        return make_error("no EGL display (tried:" + tried + "); " + kInstallHint);
    // Mesa gives an ES 3.2 context whatever version is asked for, unless
    // MESA_GLES_VERSION_OVERRIDE is set before the display is initialised (Mesa reads it then). ES 2.0
    // must mean ES 2.0's shaders, formats and extensions, so ask Mesa for it.
    const char* wanted_override = options.es_major == 2 ? "2.0" : "3.0";
    const char* existing_override = std::getenv("MESA_GLES_VERSION_OVERRIDE");
    if (existing_override && std::strcmp(existing_override, wanted_override) != 0)
        return make_error(std::string("MESA_GLES_VERSION_OVERRIDE=") + existing_override + " contradicts the OpenGL ES " +
                          std::to_string(options.es_major) + ".0 context asked for; unset it or set it to " +
                          wanted_override);
    setenv("MESA_GLES_VERSION_OVERRIDE", wanted_override, 1);
    // Put the environment back once the context exists, so the host process
    // (and a later context of the other version) sees what it had before.
    struct RestoreOverride {
        bool had;
        ~RestoreOverride() {
            if (!had) unsetenv("MESA_GLES_VERSION_OVERRIDE");
        }
    } restore{existing_override != nullptr};

    EGLint egl_major = 0, egl_minor = 0;
    if (!egl->Initialize(egl->display, &egl_major, &egl_minor)) {
        const std::string message = egl->error("eglInitialize on the " + description);
        egl->display = EGL_NO_DISPLAY;
        return make_error(message + "; " + kInstallHint);
    }
    retain_display(egl->display);
    description += ", EGL " + std::to_string(egl_major) + "." + std::to_string(egl_minor);
    const char* display_extensions = egl->QueryString(egl->display, EGL_EXTENSIONS);
    if (!has_word(display_extensions, "EGL_KHR_surfaceless_context"))
        return make_error("the EGL display (" + description +
                          ") lacks EGL_KHR_surfaceless_context, so no context can be current without a window; "
                          "use Mesa 17 or newer");

    if (!egl->BindAPI(EGL_OPENGL_ES_API)) return make_error(egl->error("eglBindAPI(EGL_OPENGL_ES_API)"));

    const EGLint renderable = options.es_major >= 3 ? EGL_OPENGL_ES3_BIT_KHR : EGL_OPENGL_ES2_BIT;
    // EGL_SURFACE_TYPE 0: no surface is ever made (its default, EGL_WINDOW_BIT,
    // matches no config on the surfaceless platform).
    const EGLint config_attributes[] = {EGL_SURFACE_TYPE, 0, EGL_RENDERABLE_TYPE, renderable, EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8,
                                        EGL_BLUE_SIZE, 8, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint config_count = 0;
    if (!egl->ChooseConfig(egl->display, config_attributes, &config, 1, &config_count) || config_count < 1)
        return make_error("no EGL config renders OpenGL ES " + std::to_string(options.es_major) + ".0 on the " +
                          description + " (" + egl_error_name(egl->GetError()) + "); " + kInstallHint);
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, options.es_major, EGL_CONTEXT_MINOR_VERSION, 0,
                                         EGL_CONTEXT_OPENGL_DEBUG, options.debug ? EGL_TRUE : EGL_FALSE, EGL_NONE};
    egl->context = egl->CreateContext(egl->display, config, EGL_NO_CONTEXT, context_attributes);
    if (egl->context == EGL_NO_CONTEXT)
        return make_error(egl->error("creating an OpenGL ES " + std::to_string(options.es_major) + ".0 context") +
                          " on the " + description +
                          (options.es_major >= 3 ? "; the driver may only offer ES 2.0: try --es 2" : ""));
    if (!egl->MakeCurrent(egl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl->context))
        return make_error(egl->error("eglMakeCurrent with no surface"));

    // A context is only what it says it is.
    const GLubyte* version = glGetString(GL_VERSION);
    int got_major = 0, got_minor = 0;
    if (!version || std::sscanf(reinterpret_cast<const char*>(version), "OpenGL ES %d.%d", &got_major, &got_minor) != 2)
        return make_error(std::string("the new context reports GL_VERSION '") +
                          (version ? reinterpret_cast<const char*>(version) : "(null)") +
                          "', not OpenGL ES; check that libGLESv2 comes from the same vendor as libEGL");
    if (got_major != options.es_major)
        return make_error("asked for OpenGL ES " + std::to_string(options.es_major) + ".0 but the driver made '" +
                          reinterpret_cast<const char*>(version) + "'; on Mesa, set MESA_GLES_VERSION_OVERRIDE=" +
                          wanted_override + " before the context is made");

    std::unique_ptr<HeadlessContext> context(new HeadlessContext());
    context->egl_ = std::move(egl);
    context->es_major_ = options.es_major;
    context->display_description_ = description;
    return context;
}

HeadlessContext::~HeadlessContext() = default;

Status HeadlessContext::make_current() {
    if (!egl_->MakeCurrent(egl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_->context))
        return make_error(egl_->error("eglMakeCurrent"));
    return {};
}

}  // namespace px::platform
