// A host app that owns its context: it makes its own EGL context (not
// through the library's platform/), its own framebuffer and its own GL state,
// builds a scene in code, draws it with ParallaxES into that framebuffer, and
// checks that every piece of its state survived and that the scene was drawn.
//   host_app [--es 2|3]     exit 0: drawn, state intact; 1: a check failed;
//                           2: no EGL context could be made (the message says why)
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "parallaxes/render/renderer.h"

namespace {

int fail_egl(const char* what) {
    std::fprintf(stderr, "host_app: %s failed (EGL error 0x%04x)\n", what, eglGetError());
    return 2;
}

// The app's own state, as (name, value) pairs read back with glGet.
using HostState = std::vector<std::pair<const char*, double>>;

HostState read_state(bool es3) {
    HostState s;
    auto integers = [&s](const char* name, GLenum pname, int count) {
        GLint v[4] = {0, 0, 0, 0};
        glGetIntegerv(pname, v);
        for (int i = 0; i < count; ++i) s.emplace_back(name, v[i]);
    };
    integers("framebuffer binding", GL_FRAMEBUFFER_BINDING, 1);
    integers("viewport", GL_VIEWPORT, 4);
    integers("scissor box", GL_SCISSOR_BOX, 4);
    integers("current program", GL_CURRENT_PROGRAM, 1);
    integers("active texture", GL_ACTIVE_TEXTURE, 1);
    integers("texture binding", GL_TEXTURE_BINDING_2D, 1);
    integers("array buffer binding", GL_ARRAY_BUFFER_BINDING, 1);
    integers("unpack alignment", GL_UNPACK_ALIGNMENT, 1);
    if (es3) integers("vertex array binding", GL_VERTEX_ARRAY_BINDING, 1);
    s.emplace_back("scissor test", glIsEnabled(GL_SCISSOR_TEST));
    s.emplace_back("blend", glIsEnabled(GL_BLEND));
    s.emplace_back("depth test", glIsEnabled(GL_DEPTH_TEST));
    s.emplace_back("cull face", glIsEnabled(GL_CULL_FACE));
    GLfloat clear[4] = {0, 0, 0, 0};
    glGetFloatv(GL_COLOR_CLEAR_VALUE, clear);
    for (GLfloat c : clear) s.emplace_back("clear colour", c);
    return s;
}

// The scene, in code: a brick floor with parallax occlusion mapping and soft
// self-shadowing under one low light.
px::SceneDesc make_scene() {
    px::SceneDesc scene;
    scene.name = "host app bricks";
    scene.camera.position = {0.0f, -2.2f, 1.6f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    px::LightDesc sun;
    sun.direction = {-0.5f, 0.3f, -0.8f};
    scene.lights.push_back(sun);
    px::MaterialDesc bricks;
    bricks.name = "bricks";
    bricks.height.kind = px::TextureSource::Kind::procedural;
    bricks.height.field.kind = px::FieldKind::bricks;
    bricks.height.field.size = 128;
    bricks.albedo.kind = px::TextureSource::Kind::color;
    bricks.albedo.color = {0.7f, 0.35f, 0.25f};
    bricks.height_scale = 0.06f;
    bricks.technique.technique = px::Technique::pom;
    bricks.technique.shadow = px::ShadowMode::soft;
    scene.materials.push_back(bricks);
    px::ObjectDesc floor;
    floor.name = "floor";
    floor.material = "bricks";
    floor.mesh.size = 2.0f;
    scene.objects.push_back(floor);
    return scene;
}

}  // namespace

int main(int argc, char** argv) {
    int es = 3;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--es") == 0 && i + 1 < argc) es = std::atoi(argv[++i]);
        else {
            std::fprintf(stderr, "usage: host_app [--es 2|3]\n");
            return 2;
        }
    }
    if (es != 2 && es != 3) {
        std::fprintf(stderr, "host_app: --es must be 2 or 3\n");
        return 2;
    }
    // Mesa gives a true ES 2.0 context only when told before eglInitialize.
    if (es == 2) setenv("MESA_GLES_VERSION_OVERRIDE", "2.0", 1);

    // --- The app's own EGL context: surfaceless where Mesa offers it.
    EGLDisplay display = EGL_NO_DISPLAY;
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (client && std::strstr(client, "EGL_MESA_platform_surfaceless") && get_platform_display)
        display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY) display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (display == EGL_NO_DISPLAY || !eglInitialize(display, nullptr, nullptr)) return fail_egl("eglInitialize");
    if (!eglBindAPI(EGL_OPENGL_ES_API)) return fail_egl("eglBindAPI");
    // EGL_SURFACE_TYPE 0: the app renders to its own framebuffer object only
    // (the default, EGL_WINDOW_BIT, matches no surfaceless config).
    const EGLint config_attributes[] = {EGL_SURFACE_TYPE, 0, EGL_RENDERABLE_TYPE,
                                        es == 3 ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_ES2_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (!eglChooseConfig(display, config_attributes, &config, 1, &configs) || configs < 1)
        return fail_egl("eglChooseConfig");
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, es, EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
    if (context == EGL_NO_CONTEXT) return fail_egl("eglCreateContext");
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) return fail_egl("eglMakeCurrent");

    // --- The app's own framebuffer and state.
    const int size = 128;
    GLuint color = 0, depth = 0, framebuffer = 0, other = 0, texture = 0, buffer = 0, vertex_array = 0;
    glGenTextures(1, &color);
    glBindTexture(GL_TEXTURE_2D, color);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, size, size, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT16, size, size);
    glGenFramebuffers(1, &framebuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        std::fprintf(stderr, "host_app: its framebuffer is incomplete\n");
        return 1;
    }
    glClearColor(0.0f, 0.0f, 1.0f, 1.0f);  // blue: whatever the renderer does not draw
    glClear(GL_COLOR_BUFFER_BIT);
    glGenFramebuffers(1, &other);  // the app has another framebuffer bound when it calls draw
    glBindFramebuffer(GL_FRAMEBUFFER, other);
    glGenTextures(1, &texture);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, texture);
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    if (es == 3) {
        glGenVertexArrays(1, &vertex_array);
        glBindVertexArray(vertex_array);
    }
    glViewport(7, 7, 50, 50);
    glEnable(GL_SCISSOR_TEST);
    glScissor(1, 2, 3, 4);
    glEnable(GL_BLEND);
    glClearColor(0.25f, 0.5f, 0.75f, 1.0f);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 8);
    const HostState before = read_state(es == 3);

    // --- ParallaxES draws into the app's framebuffer.
    px::RendererOptions options;
    options.get_proc_address = reinterpret_cast<px::GetProcAddress>(eglGetProcAddress);
    auto renderer = px::Renderer::create(options);
    if (!renderer) {
        std::fprintf(stderr, "host_app: %s\n", renderer.error().message.c_str());
        return 1;
    }
    px::Status loaded = (*renderer)->load(make_scene());
    if (!loaded) {
        std::fprintf(stderr, "host_app: %s\n", loaded.error().message.c_str());
        return 1;
    }
    px::Status drawn = (*renderer)->draw({framebuffer, size, size});
    if (!drawn) {
        std::fprintf(stderr, "host_app: %s\n", drawn.error().message.c_str());
        return 1;
    }
    const HostState after = read_state(es == 3);

    // --- Checks: the app's state, then what was drawn.
    int failures = 0;
    for (size_t i = 0; i < before.size(); ++i)
        if (before[i].second != after[i].second) {
            std::fprintf(stderr, "host_app: FAIL: the renderer changed the app's %s: %g -> %g\n", before[i].first,
                         before[i].second, after[i].second);
            ++failures;
        }
    std::vector<unsigned char> pixels(static_cast<size_t>(size) * size * 4);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, size, size, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    const unsigned char* centre = &pixels[(static_cast<size_t>(size / 2) * size + size / 2) * 4];
    if (centre[2] > 200 && centre[0] < 50) {
        std::fprintf(stderr, "host_app: FAIL: nothing drawn at the centre of the app's framebuffer\n");
        ++failures;
    }
    const px::DrawReport& report = (*renderer)->reports().at(0);
    std::printf("host_app: OpenGL ES %d: drew '%s' with %s into framebuffer %u; centre rgb %d %d %d; %s\n", es,
                report.object.c_str(), report.variant.describe().c_str(), framebuffer, centre[0], centre[1],
                centre[2], failures ? "FAILED" : "the app's state is intact");

    renderer->reset();  // release the library's GL objects while the context is current
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, context);
    eglTerminate(display);
    return failures ? 1 : 0;
}
