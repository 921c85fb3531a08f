// A host app as an integrator writes one, from the README alone: it owns its
// EGL context, its framebuffer (colour and depth), its own mesh and shader
// and its camera, and draws a scene of its own. ParallaxES draws a parallax
// floor and wall between the app's own draws, into a sub-viewport of the
// app's framebuffer, with the app's camera, depth-tested against the app's
// pillar. Each frame the app checks what it can see: its own pixels outside
// the viewport untouched, its pillar in front where it stands before the
// wall, the floor and wall drawn, and every piece of its GL state intact.
//   host_app [--es 2|3] [--frames N] [--out DIR]
//     exit 0: every frame drawn and checked; 1: a check failed;
//     2: bad arguments, or no EGL context could be made (the message says why)
//   --out DIR writes each frame as DIR/frame_K.ppm.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES2/gl2.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "parallaxes/render/renderer.h"
#include "parallaxes/version.h"

namespace {

int fail_egl(const char* what) {
    std::fprintf(stderr, "host_app: %s failed (EGL error 0x%04x)\n", what, static_cast<unsigned>(eglGetError()));
    return 2;
}

// --- The app's own state, read back with glGet to check it survived.
using HostState = std::vector<std::pair<const char*, double>>;

HostState read_state() {
    HostState s;
    auto integers = [&s](const char* name, GLenum pname, int count) {
        GLint v[4] = {0, 0, 0, 0};
        glGetIntegerv(pname, v);
        for (int i = 0; i < count; ++i) s.emplace_back(name, v[i]);
    };
    integers("framebuffer binding", GL_FRAMEBUFFER_BINDING, 1);
    integers("viewport", GL_VIEWPORT, 4);
    integers("current program", GL_CURRENT_PROGRAM, 1);
    integers("array buffer binding", GL_ARRAY_BUFFER_BINDING, 1);
    integers("active texture", GL_ACTIVE_TEXTURE, 1);
    integers("depth func", GL_DEPTH_FUNC, 1);
    s.emplace_back("depth test", glIsEnabled(GL_DEPTH_TEST));
    s.emplace_back("cull face", glIsEnabled(GL_CULL_FACE));
    s.emplace_back("blend", glIsEnabled(GL_BLEND));
    GLfloat clear[4] = {0, 0, 0, 0};
    glGetFloatv(GL_COLOR_CLEAR_VALUE, clear);
    for (GLfloat c : clear) s.emplace_back("clear colour", c);
    return s;
}

// --- The app's own mesh and shader: a lit box (the pillar).
const char* kVertexShader =
    "attribute vec3 a_position;\n"
    "attribute vec3 a_normal;\n"
    "uniform mat4 u_view_projection;\n"
    "uniform mat4 u_model;\n"
    "varying vec3 v_normal;\n"
    "void main() {\n"
    "    v_normal = mat3(u_model) * a_normal;\n"
    "    gl_Position = u_view_projection * u_model * vec4(a_position, 1.0);\n"
    "}\n";
const char* kFragmentShader =
    "precision mediump float;\n"
    "varying vec3 v_normal;\n"
    "void main() {\n"
    "    float light = 0.35 + 0.65 * max(dot(normalize(v_normal), normalize(vec3(-0.4, -0.6, 0.7))), 0.0);\n"
    "    gl_FragColor = vec4(vec3(0.95, 0.85, 0.2) * light, 1.0);\n"
    "}\n";

GLuint compile(GLenum type, const char* source) {
    const GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) std::fprintf(stderr, "host_app: its own shader did not compile\n");
    return shader;
}

// A box from -half to +half, 36 vertices of position and normal.
std::vector<float> box(glm::vec3 half) {
    std::vector<float> v;
    const glm::vec3 n[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const glm::vec3& normal : n) {
        const glm::vec3 u = std::fabs(normal.z) > 0.5f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
        const glm::vec3 w = glm::cross(normal, u);
        const glm::vec3 corners[4] = {normal - u - w, normal + u - w, normal + u + w, normal - u + w};
        const int order[6] = {0, 1, 2, 0, 2, 3};
        for (int i : order) {
            const glm::vec3 p = corners[i] * half;
            v.insert(v.end(), {p.x, p.y, p.z, normal.x, normal.y, normal.z});
        }
    }
    return v;
}

// --- The parallax part, a scene built in code: a brick floor and a stone
// wall behind it, relief written to depth so the app's pillar stands in it.
px::SceneDesc make_scene() {
    px::SceneDesc scene;
    scene.name = "host app yard";
    px::LightDesc sun;
    sun.direction = {0.4f, 0.6f, -0.7f};
    scene.lights.push_back(sun);

    px::MaterialDesc bricks;
    bricks.name = "bricks";
    bricks.height.kind = px::TextureSource::Kind::procedural;
    bricks.height.field.kind = px::FieldKind::bricks;
    bricks.height.field.size = 128;
    bricks.albedo.kind = px::TextureSource::Kind::color;
    bricks.albedo.color = {0.7f, 0.35f, 0.25f};
    bricks.height_scale = 0.05f;
    bricks.technique.technique = px::Technique::pom;
    bricks.technique.depth_write = true;
    scene.materials.push_back(bricks);

    px::MaterialDesc stones = bricks;
    stones.name = "stones";
    stones.height.field.kind = px::FieldKind::hemispheres;
    stones.albedo.color = {0.55f, 0.55f, 0.6f};
    stones.technique.shadow = px::ShadowMode::hard;
    scene.materials.push_back(stones);

    px::ObjectDesc floor;
    floor.name = "floor";
    floor.material = "bricks";
    floor.mesh.size = 4.0f;
    scene.objects.push_back(floor);
    px::ObjectDesc wall;
    wall.name = "wall";
    wall.material = "stones";
    wall.mesh.size = 4.0f;
    wall.transform.rotate_deg = {90.0f, 0.0f, 0.0f};  // upright, facing -y
    wall.transform.translate = {0.0f, 2.0f, 2.0f};
    scene.objects.push_back(wall);
    return scene;
}

void write_ppm(const std::string& path, const std::vector<unsigned char>& rgba, int width, int height) {
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) {
        std::fprintf(stderr, "host_app: cannot write %s\n", path.c_str());
        return;
    }
    std::fprintf(f, "P6\n%d %d\n255\n", width, height);
    for (int y = height - 1; y >= 0; --y)
        for (int x = 0; x < width; ++x) std::fwrite(&rgba[(static_cast<size_t>(y) * width + x) * 4], 1, 3, f);
    std::fclose(f);
}

}  // namespace

int main(int argc, char** argv) {
    int es = 3, frames = 4;
    std::string out_dir;
    for (int i = 1; i < argc; ++i) {
        const bool more = i + 1 < argc;
        if (std::strcmp(argv[i], "--es") == 0 && more) es = std::atoi(argv[++i]);
        else if (std::strcmp(argv[i], "--frames") == 0 && more) frames = std::atoi(argv[++i]);
        else if (std::strcmp(argv[i], "--out") == 0 && more) out_dir = argv[++i];
        else {
            std::fprintf(stderr, "usage: host_app [--es 2|3] [--frames N] [--out DIR]\n");
            return 2;
        }
    }
    if ((es != 2 && es != 3) || frames < 1 || frames > 1000) {
        std::fprintf(stderr, "host_app: --es must be 2 or 3, --frames 1..1000\n");
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

    // --- The app's framebuffer: colour texture and depth renderbuffer.
    const int width = 256, height = 192;
    GLuint color = 0, depth = 0, framebuffer = 0;
    glGenTextures(1, &color);
    glBindTexture(GL_TEXTURE_2D, color);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT16, width, height);
    glGenFramebuffers(1, &framebuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        std::fprintf(stderr, "host_app: its framebuffer is incomplete\n");
        return 1;
    }

    // --- The app's pillar: its own program and vertex buffer.
    const GLuint program = glCreateProgram();
    const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader), fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glBindAttribLocation(program, 0, "a_position");
    glBindAttribLocation(program, 1, "a_normal");
    glLinkProgram(program);
    const std::vector<float> pillar = box({0.25f, 0.25f, 0.6f});
    GLuint pillar_buffer = 0;
    glGenBuffers(1, &pillar_buffer);
    glBindBuffer(GL_ARRAY_BUFFER, pillar_buffer);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(pillar.size() * sizeof(float)), pillar.data(), GL_STATIC_DRAW);
    const glm::mat4 pillar_model = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.5f, 0.55f));

    // --- ParallaxES: one renderer in the app's context, the scene loaded once.
    px::RendererOptions options;
    options.get_proc_address = reinterpret_cast<px::GetProcAddress>(eglGetProcAddress);
    options.current_context = [] { return static_cast<const void*>(eglGetCurrentContext()); };
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

    // The parallax view sits in a sub-viewport; the rest is the app's own.
    const px::Viewport view_rect{16, 16, 224, 136};
    const unsigned char app_grey[3] = {64, 64, 64};
    int failures = 0;
    std::vector<unsigned char> pixels(static_cast<size_t>(width) * height * 4);
    for (int frame = 0; frame < frames; ++frame) {
        // The app's camera on its path: a slow arc in front of the wall.
        const float t = frames > 1 ? static_cast<float>(frame) / static_cast<float>(frames - 1) : 0.0f;
        const float angle = glm::radians(-25.0f + 50.0f * t);
        const glm::vec3 eye(3.2f * std::sin(angle), -3.2f * std::cos(angle), 1.6f);
        const glm::mat4 view = glm::lookAt(eye, glm::vec3(0.0f, 0.6f, 0.5f), glm::vec3(0.0f, 0.0f, 1.0f));
        const float aspect = static_cast<float>(view_rect.width) / static_cast<float>(view_rect.height);
        const glm::mat4 projection = glm::perspective(glm::radians(45.0f), aspect, 0.1f, 20.0f);

        // The app's frame: its background, then its pillar in the sub-viewport.
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
        glViewport(0, 0, width, height);
        glDisable(GL_SCISSOR_TEST);
        glClearColor(app_grey[0] / 255.0f, app_grey[1] / 255.0f, app_grey[2] / 255.0f, 1.0f);
        glClearDepthf(1.0f);
        glDepthMask(GL_TRUE);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glViewport(view_rect.x, view_rect.y, view_rect.width, view_rect.height);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glEnable(GL_CULL_FACE);
        glUseProgram(program);
        const glm::mat4 view_projection = projection * view;
        glUniformMatrix4fv(glGetUniformLocation(program, "u_view_projection"), 1, GL_FALSE, &view_projection[0][0]);
        glUniformMatrix4fv(glGetUniformLocation(program, "u_model"), 1, GL_FALSE, &pillar_model[0][0]);
        glBindBuffer(GL_ARRAY_BUFFER, pillar_buffer);
        glEnableVertexAttribArray(0);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
        glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(pillar.size() / 6));
        glDisableVertexAttribArray(0);
        glDisableVertexAttribArray(1);

        // ParallaxES between the app's draws: the app's camera and viewport,
        // depth-tested against the pillar, nothing cleared.
        const HostState before = read_state();
        px::HostFrame host_frame(px::RenderTarget{framebuffer, width, height});
        host_frame.viewport = view_rect;
        host_frame.view = view;
        host_frame.projection = projection;
        px::Status drawn = (*renderer)->draw(host_frame);
        if (!drawn) {
            std::fprintf(stderr, "host_app: frame %d: %s\n", frame, drawn.error().message.c_str());
            return 1;
        }
        const HostState after = read_state();
        for (size_t i = 0; i < before.size(); ++i)
            if (before[i].second != after[i].second) {
                std::fprintf(stderr, "host_app: FAIL: frame %d: the library changed the app's %s: %g -> %g\n", frame,
                             before[i].first, before[i].second, after[i].second);
                ++failures;
            }

        // --- What the app can check of its own frame.
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
        auto at = [&](int x, int y) { return &pixels[(static_cast<size_t>(y) * width + x) * 4]; };
        auto is_grey = [&](const unsigned char* p) {
            return p[0] == app_grey[0] && p[1] == app_grey[1] && p[2] == app_grey[2];
        };
        int outside_changed = 0;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const bool inside = x >= view_rect.x && x < view_rect.x + view_rect.width && y >= view_rect.y &&
                                    y < view_rect.y + view_rect.height;
                if (!inside && !is_grey(at(x, y))) ++outside_changed;
            }
        if (outside_changed) {
            std::fprintf(stderr, "host_app: FAIL: frame %d: %d pixels outside the parallax viewport changed\n", frame,
                         outside_changed);
            ++failures;
        }
        // Points of the world, projected into the viewport.
        auto pixel_of = [&](const glm::vec3& world) {
            const glm::vec4 clip = view_projection * glm::vec4(world, 1.0f);
            return std::pair<int, int>(view_rect.x + static_cast<int>((clip.x / clip.w * 0.5f + 0.5f) * view_rect.width),
                                       view_rect.y + static_cast<int>((clip.y / clip.w * 0.5f + 0.5f) * view_rect.height));
        };
        // The pillar's front face: the app's yellow, in front of the wall.
        const auto [pillar_x, pillar_y] = pixel_of(glm::vec3(pillar_model * glm::vec4(0.0f, -0.25f, 0.3f, 1.0f)));
        const unsigned char* p = at(pillar_x, pillar_y);
        if (!(p[0] > 120 && p[1] > 100 && p[2] < 80)) {
            std::fprintf(stderr, "host_app: FAIL: frame %d: the pillar is not in front at (%d, %d): rgb %d %d %d\n",
                         frame, pillar_x, pillar_y, p[0], p[1], p[2]);
            ++failures;
        }
        // The floor before the pillar and the wall above it: drawn by the library.
        const glm::vec3 probes[2] = {{0.6f, -0.9f, 0.0f}, {0.0f, 2.0f, 2.0f}};
        for (const glm::vec3& probe : probes) {
            const auto [x, y] = pixel_of(probe);
            if (is_grey(at(x, y))) {
                std::fprintf(stderr, "host_app: FAIL: frame %d: nothing drawn at (%d, %d)\n", frame, x, y);
                ++failures;
            }
        }
        if (!out_dir.empty()) write_ppm(out_dir + "/frame_" + std::to_string(frame) + ".ppm", pixels, width, height);
    }

    const auto& reports = (*renderer)->reports();
    std::printf("host_app: ParallaxES %s, OpenGL ES %d: %d frame(s) of %s, %s with %s, %s with %s; %s\n",
                PARALLAXES_VERSION_STRING, es, frames, make_scene().name.c_str(), reports.at(0).object.c_str(),
                reports.at(0).variant.describe().c_str(), reports.at(1).object.c_str(),
                reports.at(1).variant.describe().c_str(), failures ? "FAILED" : "every check passed");

    renderer->reset();  // the library's GL objects go while the context is current
    glDeleteBuffers(1, &pillar_buffer);
    glDeleteProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, context);
    eglTerminate(display);
    return failures ? 1 : 0;
}
