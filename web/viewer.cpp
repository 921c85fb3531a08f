// The viewer page's program (docs/web.md): the library on a WebGL 2 or
// WebGL 1 canvas, driven by web/viewer.js through the C functions below
// (Module.ccall). Like tools/, it is a thin layer: scenes are prepared,
// planned and drawn by the library; the page only moves the camera and
// shows what the library reports. Files dropped onto the page arrive in
// Emscripten's in-memory file system (MEMFS) before a scene names them.
//
// Every function returns 0 / null / a negative time on failure and leaves
// the message for pxv_error(); strings returned stay valid until the next
// call of the same function.
#include <emscripten/emscripten.h>
#include <emscripten/html5.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "parallaxes/assets/image.h"
#include "parallaxes/effects/variant.h"
#include "parallaxes/gl/program.h"
#include "parallaxes/planner/planner.h"
#include "parallaxes/platform/web_context.h"
#include "parallaxes/reference/metrics.h"
#include "parallaxes/reference/reference_image.h"
#include "parallaxes/render/offscreen_target.h"
#include "parallaxes/render/renderer.h"
#include "parallaxes/render/surface_capture.h"
#include "parallaxes/scene/scene.h"
#include "parallaxes/texture/format.h"

namespace {

using json = nlohmann::json;

struct Viewer {
    std::unique_ptr<px::platform::WebContext> context;
    std::unique_ptr<px::Renderer> renderer;
    px::SceneDesc scene;           // as loaded (before any override)
    std::string technique;         // override; empty: as the scene says
    int max_samples = 0;           // override of max_samples; 0: as the scene says
    px::CameraDesc camera;         // the page's camera (orbit, pan, dolly)
    bool loaded = false;
};

Viewer g_viewer;
std::string g_error;
std::string g_text;  // the last string handed to the page

const char* give(std::string text) {
    g_text = std::move(text);
    return g_text.c_str();
}

int fail(const std::string& message) {
    g_error = message;
    return 0;
}

bool ready(const char* what) {
    if (!g_viewer.renderer) {
        g_error = std::string(what) + ": no WebGL context yet (pxv_start)";
        return false;
    }
    if (!g_viewer.loaded) {
        g_error = std::string(what) + ": no scene loaded";
        return false;
    }
    return true;
}

// The scene with the page's overrides, prepared and loaded.
int load_current() {
    px::SceneDesc s = g_viewer.scene;
    if (!g_viewer.technique.empty()) {
        px::Result<px::Technique> t = px::parse_technique(g_viewer.technique);
        if (!t) return fail(t.error().message);
        (void)px::force_technique(s, *t);
        if (g_viewer.max_samples > 0) {
            const int limit = px::technique_info(*t).max_samples_limit;
            for (px::MaterialDesc& m : s.materials) {
                m.technique.max_samples = std::min(g_viewer.max_samples, limit);
                m.technique.min_samples = std::min(m.technique.min_samples, m.technique.max_samples);
                if (*t == px::Technique::maxmip) m.technique.max_steps = std::min(g_viewer.max_samples, limit);
            }
        }
    }
    px::Status loaded = g_viewer.renderer->load(s);
    g_viewer.loaded = loaded.ok();
    if (!loaded) return fail(loaded.error().message);
    return 1;
}

px::HostFrame frame_for(int width, int height) {
    px::HostFrame f = px::HostFrame::from_camera(g_viewer.camera, px::RenderTarget{0, width, height});
    f.clear_color = true;
    f.clear_depth = true;
    return f;
}

// Orbits keep the camera's distance to its target and its up axis.
void orbit(float yaw_deg, float pitch_deg) {
    px::CameraDesc& c = g_viewer.camera;
    const glm::vec3 up = glm::normalize(c.up);
    glm::vec3 offset = c.position - c.target;
    const float distance = glm::length(offset);
    if (distance <= 0.0f) return;
    offset = glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(-yaw_deg), up) * glm::vec4(offset, 0.0f));
    // Pitch about the horizontal axis, kept short of the poles.
    const glm::vec3 dir = offset / distance;
    const float elevation = std::asin(std::clamp(glm::dot(dir, up), -1.0f, 1.0f));
    const float wanted = std::clamp(elevation + glm::radians(pitch_deg), glm::radians(-85.0f), glm::radians(85.0f));
    const glm::vec3 flat = dir - up * glm::dot(dir, up);
    const float flat_length = glm::length(flat);
    if (flat_length > 1e-6f) {
        const glm::vec3 horizontal = flat / flat_length;
        offset = distance * (horizontal * std::cos(wanted) + up * std::sin(wanted));
    }
    c.position = c.target + offset;
}

json precision_json(const px::PrecisionInfo& p) {
    return json{{"range_min", p.range_min}, {"range_max", p.range_max}, {"bits", p.precision}};
}

}  // namespace

extern "C" {

EMSCRIPTEN_KEEPALIVE const char* pxv_error() { return g_error.c_str(); }

// Creates the context (WebGL 2, or 1; WebGL 2 falls back to 1) and the
// renderer. Returns the OpenGL ES major version (3 or 2), 0 on failure.
EMSCRIPTEN_KEEPALIVE int pxv_start(int webgl_version) {
    g_viewer = Viewer{};
    px::platform::WebContextOptions options;
    options.webgl_version = webgl_version;
    auto context = px::platform::WebContext::create(options);
    if (!context) return fail(context.error().message);
    g_viewer.context = std::move(*context);
    px::RendererOptions ro;
    ro.effect_planner = px::effect_planner;
    ro.texture_files = px::texture_files();
    ro.current_context = px::platform::WebContext::current_context();
    auto renderer = px::Renderer::create(ro);
    if (!renderer) return fail(renderer.error().message);
    g_viewer.renderer = std::move(*renderer);
    return g_viewer.context->es_major();
}

// What the context offers: versions, extensions, compressed formats, precisions.
EMSCRIPTEN_KEEPALIVE const char* pxv_context_json() {
    if (!g_viewer.renderer) return give("{}");
    const px::Caps& c = g_viewer.renderer->caps();
    json formats = json::array();
    for (std::uint32_t f : c.compressed_formats) {
        char hex[16];
        std::snprintf(hex, sizeof hex, "0x%04X", f);
        px::Result<px::TextureFormat> known = px::format_from_gl(f, 0, 0);
        std::string srgb = px::srgb_gl_name(f);
        formats.push_back(known ? std::string(px::format_name(*known)) : !srgb.empty() ? srgb : std::string(hex));
    }
    json j{{"webgl", g_viewer.context->webgl_version()},
           {"es_major", c.es_major},
           {"fallback", g_viewer.context->fallback_note()},
           {"version", c.version},
           {"glsl_version", c.glsl_version},
           {"renderer", c.renderer},
           {"vendor", c.vendor},
           {"max_texture_size", c.max_texture_size},
           {"max_varying_vectors", c.max_varying_vectors},
           {"fragment_highp", c.fragment_highp},
           {"fragment_mediump_float", precision_json(c.fragment_mediump_float)},
           {"fragment_highp_float", precision_json(c.fragment_highp_float)},
           {"float_capture", px::captures_floats(c)},
           {"extensions", std::vector<std::string>(c.extensions.begin(), c.extensions.end())},
           {"compressed_formats", formats}};
    return give(j.dump());
}

EMSCRIPTEN_KEEPALIVE const char* pxv_builtin_scenes() { return give(json(px::builtin_scene_names()).dump()); }

EMSCRIPTEN_KEEPALIVE const char* pxv_techniques() {
    json list = json::array();
    for (const px::TechniqueInfo& t : px::technique_table())
        list.push_back({{"name", t.name}, {"summary", t.summary}, {"min_es", t.min_es_major},
                        {"max_samples", t.max_samples_limit}, {"default_samples", px::TechniqueOptions{}.max_samples}});
    return give(list.dump());
}

// A built-in scene, or a scene file (in the page's file system, its textures
// beside it): loaded with the current overrides, the camera reset to its own.
EMSCRIPTEN_KEEPALIVE int pxv_load_builtin(const char* name) {
    if (!g_viewer.renderer) return fail("no WebGL context yet (pxv_start)");
    px::Result<px::SceneDesc> s = px::builtin_scene(name ? name : "");
    if (!s) return fail(s.error().message);
    g_viewer.scene = std::move(*s);
    g_viewer.camera = g_viewer.scene.camera;
    return load_current();
}

EMSCRIPTEN_KEEPALIVE int pxv_load_file(const char* path) {
    if (!g_viewer.renderer) return fail("no WebGL context yet (pxv_start)");
    px::Result<px::SceneDesc> s = px::load_scene_file(path ? path : "");
    if (!s) return fail(s.error().message);
    // Keep the scene the page had if this one cannot be drawn here.
    px::SceneDesc before = g_viewer.scene;
    const px::CameraDesc camera_before = g_viewer.camera;
    g_viewer.scene = std::move(*s);
    g_viewer.camera = g_viewer.scene.camera;
    if (load_current()) return 1;
    const std::string message = g_error;
    g_viewer.scene = std::move(before);
    g_viewer.camera = camera_before;
    if (!g_viewer.scene.objects.empty()) (void)load_current();
    return fail(message);
}

// Draws every material with `technique` ("" or "scene": as the scene says)
// at up to `max_samples` samples (0: the technique's own default).
EMSCRIPTEN_KEEPALIVE int pxv_set_technique(const char* technique, int max_samples) {
    if (!ready("pxv_set_technique")) return 0;
    std::string t = technique ? technique : "";
    if (t == "scene") t.clear();
    if (!t.empty()) {
        px::Result<px::Technique> parsed = px::parse_technique(t);
        if (!parsed) return fail(parsed.error().message);
    }
    if (max_samples < 0) return fail("sample count " + std::to_string(max_samples) + ": 0 (default) or more");
    const std::string old_t = g_viewer.technique;
    const int old_n = g_viewer.max_samples;
    g_viewer.technique = t;
    g_viewer.max_samples = max_samples;
    if (load_current()) return 1;
    const std::string message = g_error;
    g_viewer.technique = old_t;
    g_viewer.max_samples = old_n;
    (void)load_current();
    return fail(message);
}

EMSCRIPTEN_KEEPALIVE void pxv_orbit(float yaw_deg, float pitch_deg) { orbit(yaw_deg, pitch_deg); }

// Moves camera and target across the view, by fractions of the view's height
// at the target's distance.
EMSCRIPTEN_KEEPALIVE void pxv_pan(float dx, float dy) {
    px::CameraDesc& c = g_viewer.camera;
    const glm::vec3 forward = c.target - c.position;
    const float distance = glm::length(forward);
    if (distance <= 0.0f) return;
    const glm::vec3 right = glm::normalize(glm::cross(forward, c.up));
    const glm::vec3 up = glm::normalize(glm::cross(right, forward));
    const float span = 2.0f * distance * std::tan(glm::radians(c.fov_y_deg) * 0.5f);
    const glm::vec3 move = (-dx * right + dy * up) * span;
    c.position += move;
    c.target += move;
}

// Moves the camera toward its target: factor < 1 closer, > 1 away.
EMSCRIPTEN_KEEPALIVE void pxv_dolly(float factor) {
    px::CameraDesc& c = g_viewer.camera;
    const glm::vec3 offset = c.position - c.target;
    const float distance = glm::length(offset);
    const float wanted = std::clamp(distance * factor, c.near_plane * 4.0f, c.far_plane * 0.5f);
    if (distance > 0.0f) c.position = c.target + offset * (wanted / distance);
}

EMSCRIPTEN_KEEPALIVE void pxv_reset_view() { g_viewer.camera = g_viewer.scene.camera; }

EMSCRIPTEN_KEEPALIVE const char* pxv_camera_json() {
    const px::CameraDesc& c = g_viewer.camera;
    return give(json{{"position", {c.position.x, c.position.y, c.position.z}},
                     {"target", {c.target.x, c.target.y, c.target.z}}}
                    .dump());
}

// Draws the scene into the canvas (width x height pixels). `wait`: 0 returns
// when the calls are made; 1 calls glFinish (in a browser a round trip to
// its GPU process, which need not wait for the rasteriser: the viewer's
// interactive frames); 2 reads one pixel back, which waits for the frame's
// pixels (frame-time measurements; the browser notes a synchronous read as
// a stall in its console, once per context). Returns the milliseconds from
// the draw call to that point, or -1 on failure.
EMSCRIPTEN_KEEPALIVE double pxv_draw(int width, int height, int wait) {
    if (!ready("pxv_draw")) return -1.0;
    if (width < 1 || height < 1 || width > 8192 || height > 8192) {
        g_error = "canvas size " + std::to_string(width) + "x" + std::to_string(height) + " (1 to 8192 per side)";
        return -1.0;
    }
    const double start = emscripten_get_now();
    px::Status drawn = g_viewer.renderer->draw(frame_for(width, height));
    if (!drawn) {
        g_error = drawn.error().message;
        return -1.0;
    }
    if (wait == 1) glFinish();
    if (wait == 2) {
        unsigned char pixel[4];
        glReadPixels(width / 2, height / 2, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel);
    }
    return emscripten_get_now() - start;
}

// What the planner chose per object and why (the last draw's reports).
EMSCRIPTEN_KEEPALIVE const char* pxv_report_json() {
    if (!g_viewer.renderer) return give("[]");
    json list = json::array();
    for (const px::DrawReport& r : g_viewer.renderer->reports()) {
        json o{{"object", r.object},
               {"material", r.material},
               {"requested", px::technique_name(r.requested)},
               {"variant", r.variant.describe()},
               {"technique", px::technique_name(r.variant.technique)},
               {"planned", r.plan.planned},
               {"notes", r.notes},
               {"plan_notes", r.plan.notes}};
        if (r.plan.predicted_error >= 0.0) o["predicted_error"] = r.plan.predicted_error;
        if (r.plan.predicted_cost >= 0.0) o["predicted_cost"] = r.plan.predicted_cost;
        if (!r.plan.prediction_source.empty()) o["prediction_source"] = r.plan.prediction_source;
        list.push_back(std::move(o));
    }
    return give(list.dump());
}

// Compiles and links every variant the library can build for this context's
// ES version (the shader-validation set), each with its typed interface
// checked. Returns [{variant, ok, ms, error}].
EMSCRIPTEN_KEEPALIVE const char* pxv_compile_all_json() {
    if (!g_viewer.renderer) return give("[]");
    json list = json::array();
    for (const px::VariantKey& key : px::enumerate_variants(g_viewer.renderer->caps().es_major)) {
        const double start = emscripten_get_now();
        px::Result<px::VariantSources> sources = px::assemble_variant(key);
        std::string error;
        if (!sources) {
            error = sources.error().message;
        } else {
            auto program = px::build_program(*sources, key);
            if (!program) error = program.error().message;
        }
        list.push_back({{"variant", key.describe()}, {"ok", error.empty()}, {"ms", emscripten_get_now() - start},
                        {"error", error}});
    }
    return give(list.dump());
}

// Renders the scene from its own camera into an offscreen target (as the
// golden tests do: one sample per pixel) and writes it as PNG to `path` in
// the page's file system.
EMSCRIPTEN_KEEPALIVE int pxv_render_png(const char* path, int width, int height) {
    if (!ready("pxv_render_png")) return 0;
    auto target = px::OffscreenTarget::create(width, height);
    if (!target) return fail(target.error().message);
    px::Result<int> viewed = g_viewer.renderer->set_view(g_viewer.scene.camera, width, height);
    if (!viewed) return fail(viewed.error().message);
    px::Status drawn = g_viewer.renderer->draw(target->target());
    if (!drawn) return fail(drawn.error().message);
    px::Result<px::Image> image = target->read_pixels();
    if (!image) return fail(image.error().message);
    px::Status written = px::write_png(path ? path : "", *image);
    if (!written) return fail(written.error().message);
    return 1;
}

// The per-pixel hit error of the page's view against the exact reference,
// at width x height: the GPU's hit uv (the surface capture) against the
// reference tracer's, in texels of the base level, drawn as a colour map
// into a PNG at `path` (transparent where neither shows a relief). Returns
// {pixels, mean, p95, max, capture_ms, reference_ms} or null.
EMSCRIPTEN_KEEPALIVE const char* pxv_error_overlay(const char* path, int width, int height) {
    if (!ready("pxv_error_overlay")) return nullptr;
    if (width < 1 || height < 1 || width > 1024 || height > 1024) {
        g_error = "overlay size " + std::to_string(width) + "x" + std::to_string(height) + " (1 to 1024 per side)";
        return nullptr;
    }
    px::Renderer& r = *g_viewer.renderer;
    double start = emscripten_get_now();
    px::Result<int> viewed = r.set_view(g_viewer.camera, width, height);
    if (!viewed) {
        g_error = viewed.error().message;
        return nullptr;
    }
    px::Result<px::SurfaceImage> measured = px::capture_surfaces(r, width, height);
    if (!measured) {
        g_error = measured.error().message;
        return nullptr;
    }
    const double capture_ms = emscripten_get_now() - start;
    start = emscripten_get_now();
    px::PreparedScene seen = *r.prepared();
    seen.desc.camera = g_viewer.camera;
    px::reference::ReferenceOptions ro;
    ro.images = r.material_image_options();
    px::Result<px::reference::ReferenceImage> truth = px::reference::render_reference(seen, width, height, ro);
    if (!truth) {
        g_error = truth.error().message;
        return nullptr;
    }
    const double reference_ms = emscripten_get_now() - start;
    const double tw = std::max(1, truth->texture_width), th = std::max(1, truth->texture_height);
    px::Image map;
    map.width = width;
    map.height = height;
    map.channels = 4;
    map.pixels.assign(static_cast<size_t>(width) * height * 4, 0);
    std::vector<double> errors;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const px::SurfaceSample& m = measured->at(x, y);
            const px::SurfaceSample& t = truth->surface.at(x, y);
            if (!m.covered || !t.covered) continue;
            // Modulo the tile, the shorter way round (as compare_surfaces).
            glm::dvec2 d = m.uv - t.uv;
            d -= glm::round(d);
            const double texels = std::hypot(d.x * tw, d.y * th);
            errors.push_back(texels);
            // 0 texels: transparent green; 1: yellow; 4 and over: red.
            const double s = std::clamp(std::log2(1.0 + texels) / std::log2(5.0), 0.0, 1.0);
            std::uint8_t* p = &map.pixels[(static_cast<size_t>(y) * width + x) * 4];  // row 0 = bottom
            p[0] = static_cast<std::uint8_t>(255.0 * std::min(1.0, 2.0 * s));
            p[1] = static_cast<std::uint8_t>(255.0 * std::min(1.0, 2.0 * (1.0 - s)));
            p[2] = 0;
            p[3] = static_cast<std::uint8_t>(60.0 + 195.0 * s);
        }
    px::Status written = px::write_png(path ? path : "", map);
    if (!written) {
        g_error = written.error().message;
        return nullptr;
    }
    double mean = 0.0, max = 0.0;
    for (double e : errors) {
        mean += e;
        max = std::max(max, e);
    }
    if (!errors.empty()) mean /= static_cast<double>(errors.size());
    const double p95 = px::reference::nearest_rank_p95(errors);
    // The canvas draws from the page's camera again at its own size.
    return give(json{{"pixels", errors.size()}, {"mean", mean}, {"p95", p95}, {"max", max},
                     {"width", width}, {"height", height}, {"capture_ms", capture_ms}, {"reference_ms", reference_ms}}
                    .dump());
}

}  // extern "C"

// The module starts nothing by itself: the page calls pxv_start. Emscripten's
// file system starts with a umask of 0777, under which every file the library
// writes (render.png, overlay.png) would have no permissions and could not be
// read back: the usual 022, as a shell would set.
int main() {
    umask(022);
    return 0;
}
