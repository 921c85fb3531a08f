#include "parallaxes/profiling/measurement/bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <memory>

#include "parallaxes/gl/gl.h"
#include "parallaxes/profiling/measurement/interleaved.h"
#include "parallaxes/profiling/measurement/work.h"
#include "parallaxes/reference/reference_image.h"
#include "parallaxes/reference/tracer.h"
#include "parallaxes/render/renderer.h"
#include "parallaxes/render/surface_capture.h"
#include "parallaxes/scene/material_images.h"

namespace px::profiling {

namespace {

struct SceneSpec {
    const char* name;
    FieldKind kind;
    int size;
    float height_scale;
    ShadowMode shadow;
};

// Smooth, stepped, thin and shadowed reliefs: where the techniques part ways.
const std::vector<SceneSpec>& scene_specs() {
    static const std::vector<SceneSpec> specs = {
        {"sine", FieldKind::sine, 256, 0.08f, ShadowMode::none},
        {"bricks", FieldKind::bricks, 256, 0.06f, ShadowMode::none},
        {"text", FieldKind::text, 512, 0.05f, ShadowMode::none},
        {"hemispheres", FieldKind::hemispheres, 256, 0.1f, ShadowMode::none},
        // 1-texel lines: the thinnest feature a field can have.
        {"lines", FieldKind::lines, 256, 0.05f, ShadowMode::none},
        {"bricks_shadowed", FieldKind::bricks, 256, 0.06f, ShadowMode::hard},
        {"bricks_soft", FieldKind::bricks, 256, 0.06f, ShadowMode::soft},
        // Thin, steep glyphs cast many shadow edges: the planner's shadow
        // rows for reliefs unlike bricks.
        {"text_shadowed", FieldKind::text, 512, 0.05f, ShadowMode::hard},
        {"text_soft", FieldKind::text, 512, 0.05f, ShadowMode::soft},
    };
    return specs;
}

const SceneSpec* find_spec(const std::string& name) {
    for (const SceneSpec& s : scene_specs())
        if (name == s.name) return &s;
    return nullptr;
}

struct Setting {
    std::string technique;  // catalogue name or kDisplacedMesh
    int samples = 0;
    int shadow_samples = 0;  // 0: the material's default
};

std::string now_iso8601() {
    const std::time_t t = std::time(nullptr);
    char buffer[32];
    std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buffer;
}

Result<std::unique_ptr<Renderer>> make_renderer(const RendererOptions& given) {
    RendererOptions options = given;
    options.effect_planner = effect_planner;
    options.texture_files = texture_files();
    return Renderer::create(options);
}

// A renderer drawing a prepared scene: every renderer of a setting (the
// draw, the ray capture, the work count) uploads the same preparation.
Result<std::unique_ptr<Renderer>> load_renderer(std::shared_ptr<const PreparedScene> scene,
                                                const RendererOptions& given = {}) {
    Result<std::unique_ptr<Renderer>> r = make_renderer(given);
    if (!r) return r.error();
    Status loaded = (*r)->load(std::move(scene));
    if (!loaded) return loaded.error();
    return r;
}

SceneDesc with_setting(const SceneDesc& base, const Setting& setting, ShadowMode shadow, bool exact_view) {
    SceneDesc s = base;
    MaterialDesc& m = s.materials[0];
    if (setting.technique == kDisplacedMesh) {
        m.technique.technique = Technique::normal;
        s.objects[0].mesh.displaced = true;
        return s;
    }
    m.technique.technique = parse_technique(setting.technique).value();
    if (setting.samples > 0) m.technique.min_samples = m.technique.max_samples = setting.samples;
    m.technique.shadow = shadow;
    if (setting.shadow_samples > 0) m.technique.shadow_samples = setting.shadow_samples;
    m.technique.exact_view = exact_view;
    return s;
}

}  // namespace

LightDesc sun_light(double elevation_deg, double azimuth_deg) {
    const double az = azimuth_deg * M_PI / 180.0, el = elevation_deg * M_PI / 180.0;
    LightDesc light;
    light.direction = -glm::vec3(static_cast<float>(std::cos(el) * std::cos(az)),
                                 static_cast<float>(std::cos(el) * std::sin(az)), static_cast<float>(std::sin(el)));
    light.angular_radius_deg = 2.0f;
    return light;
}

std::vector<std::string> bench_scene_names() {
    std::vector<std::string> names;
    for (const SceneSpec& s : scene_specs()) names.push_back(s.name);
    return names;
}

ShadowMode bench_scene_shadow(const std::string& name) {
    const SceneSpec* spec = find_spec(name);
    return spec ? spec->shadow : ShadowMode::none;
}

std::vector<std::string> bench_technique_names(int es_major) {
    std::vector<std::string> names;
    for (const TechniqueInfo& info : technique_table())
        if (info.benched && info.min_es_major <= es_major) names.push_back(info.name);
    names.push_back(kDisplacedMesh);
    return names;
}

Result<SceneDesc> bench_scene(const std::string& name, double angle_deg, int segments, double light_elevation_deg) {
    const SceneSpec* spec = find_spec(name);
    if (!spec) {
        std::string known;
        for (const std::string& n : bench_scene_names()) known += (known.empty() ? "" : ", ") + n;
        return make_error("unknown bench scene '" + name + "' (known: " + known + ")");
    }
    MaterialDesc m;
    m.name = "surface";
    m.albedo.kind = TextureSource::Kind::color;
    m.albedo.color = glm::vec3(0.75f, 0.7f, 0.65f);
    m.height.kind = TextureSource::Kind::procedural;
    m.height.field.kind = spec->kind;
    m.height.field.size = spec->size;
    if (spec->kind == FieldKind::text) m.height.field.text = "PARALLAX";
    if (spec->kind == FieldKind::lines) m.height.field.count = 16;
    m.height_scale = spec->height_scale;
    return bench_scene_of(spec->name, m, "", angle_deg, segments, light_elevation_deg);
}

Result<SceneDesc> bench_scene_of(const std::string& name, const MaterialDesc& material, const std::string& base_dir,
                                 double angle_deg, int segments, double light_elevation_deg) {
    if (!(angle_deg >= 0.0 && angle_deg < 90.0))
        return make_error("view angle " + std::to_string(angle_deg) + " is outside [0, 90) degrees");
    SceneDesc s;
    s.name = name;
    s.base_dir = base_dir;
    const double a = angle_deg * M_PI / 180.0;
    const float distance = 2.2f;
    s.camera.position = glm::vec3(0.0f, static_cast<float>(-distance * std::sin(a)),
                                  static_cast<float>(distance * std::cos(a)));
    s.camera.target = glm::vec3(0.0f);
    s.camera.up = angle_deg < 1.0 ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f);
    s.camera.fov_y_deg = 45.0f;
    s.lights = {sun_light(light_elevation_deg, 30.0)};

    MaterialDesc m = material;
    m.name = "surface";
    m.effects.reset();
    m.uv = UvTransform{};  // one tile over the plane: texels per pixel as the bench's
    m.technique = TechniqueOptions{};
    m.technique.technique = Technique::pom;  // marks the plane as relief for the reference
    s.materials = {m};
    ObjectDesc o;
    o.name = "plane";
    o.mesh.kind = MeshKind::plane;
    o.mesh.size = 2.4f;
    // 64 x 64 quads: with the opt-in per-vertex view vector (the PowerVR
    // whitepaper's saving, --per-vertex-view) one big quad alone costs POM
    // about a texel of hit error at 30 degrees (docs/accuracy.md).
    o.mesh.segments = segments;
    o.material = "surface";
    s.objects = {o};
    return s;
}

double own_ray_error(const HeightField& field, const glm::dvec2& hit_uv, const SurfaceSample& ray,
                     double polygon_height) {
    const glm::dvec2 size(field.width, field.height);
    // height and visibility carry the parallax vector (uv shift per unit of
    // normalised height): view_ray's with a height scale of 1.
    const reference::ReliefHit exact =
        reference::trace_view(field, ray.uv, glm::dvec3(ray.height, ray.visibility, 1.0), 1.0, polygon_height);
    const glm::dvec2 d = (hit_uv - exact.uv) * size;
    return glm::length(d - glm::floor(d / size + 0.5) * size);  // modulo the tile, as compare_surfaces
}

Result<std::vector<double>> own_ray_errors(const HeightField& field, const SurfaceImage& hits, const SurfaceImage& rays,
                                           double polygon_height) {
    if (hits.width != rays.width || hits.height != rays.height || hits.samples.size() != rays.samples.size())
        return make_error("own_ray_errors: the hits and the rays are images of different sizes");
    std::vector<double> errors;
    for (size_t i = 0; i < hits.samples.size(); ++i) {
        const SurfaceSample& hit = hits.samples[i];
        const SurfaceSample& ray = rays.samples[i];
        if (hit.covered && ray.covered) errors.push_back(own_ray_error(field, hit.uv, ray, polygon_height));
    }
    return errors;
}

namespace {

// Every (technique, samples) the options ask for, checked.
Result<std::vector<Setting>> bench_settings(const BenchOptions& options, const std::vector<std::string>& techniques) {
    std::vector<Setting> settings;
    for (const std::string& name : techniques) {
        if (name == kDisplacedMesh) {
            settings.push_back({name, 0});
            continue;
        }
        Result<Technique> t = parse_technique(name);
        if (!t) return make_error("--techniques: " + t.error().message + ", " + kDisplacedMesh);
        const TechniqueInfo& info = technique_info(*t);
        if (info.min_es_major > options.es_major)
            return make_error("--techniques: " + std::string(info.name) + " needs OpenGL ES " +
                              std::to_string(info.min_es_major) + ".0; this sweep runs on OpenGL ES " +
                              std::to_string(options.es_major) + ".0");
        if (!(info.options & kOptSamples)) {
            settings.push_back({name, 0});
            continue;
        }
        for (int samples : options.samples) {
            if (samples < 1 || samples > info.max_samples_limit)
                return make_error("--samples: " + std::to_string(samples) + " is outside 1.." +
                                  std::to_string(info.max_samples_limit) + " for " + info.name);
            settings.push_back({name, samples});
        }
    }
    return settings;
}

// One scene at one angle: its exact reference, its field and the normal-
// mapping baseline every setting is timed against.
struct AngleContext {
    SceneDesc base;
    // `base` prepared once (validated, images and mesh built): every setting
    // at this angle, the baseline and the reference draw from it.
    std::shared_ptr<const PreparedScene> prepared;
    ShadowMode shadow = ShadowMode::none;
    double angle = 0.0;
    reference::ReferenceImage truth;
    HeightField field;
    double input_floor_p95 = 0.0;  // reference::fp32_input_floor's p95 over the covered pixels
    std::unique_ptr<Renderer> normal;  // null when untimed
};

// The setting's own_ray_errors p95: NaN where it cannot be read (no float
// read-back, a technique that traces nothing).
Result<double> own_ray_error_p95(const BenchOptions& options, const AngleContext& at, const Setting& setting,
                                 const std::shared_ptr<const PreparedScene>& scene, const RenderTarget& target,
                                 const SurfaceImage& hits) {
    constexpr double kNotMeasured = std::numeric_limits<double>::quiet_NaN();
    if (setting.technique == kDisplacedMesh) return kNotMeasured;
    if (!(technique_info(*parse_technique(setting.technique)).options & kOptHeight)) return kNotMeasured;
    // A rewritten variant (the PowerVR ladder's steps) may have no capture.
    if (options.renderer.variant_transform) return kNotMeasured;
    RendererOptions capturing = options.renderer;
    capturing.capture_ray = true;
    Result<std::unique_ptr<Renderer>> renderer = load_renderer(scene, capturing);
    if (!renderer) return with_context(setting.technique + " (capturing rays)", renderer.error());
    if (!captures_floats((*renderer)->caps())) return kNotMeasured;
    Result<SurfaceImage> rays = capture_surfaces(**renderer, target.width, target.height);
    if (!rays) return with_context(setting.technique + " (capturing rays)", rays.error());
    Result<std::vector<double>> errors = own_ray_errors(at.field, hits, *rays, at.truth.polygon_height);
    if (!errors) return errors.error();
    return reference::nearest_rank_p95(std::move(*errors));
}

// What one setting measures at one scene and angle, as a row.
// The setting's scene from the angle's preparation: a material replaced
// (its images kept: only the technique and its options differ), or for the
// displaced mesh, whose object changes, prepared afresh.
Result<std::shared_ptr<const PreparedScene>> setting_scene(const BenchOptions& options, const AngleContext& at,
                                                           const Setting& setting) {
    const SceneDesc scene = with_setting(at.base, setting, at.shadow, options.exact_view);
    if (setting.technique == kDisplacedMesh) return prepare_scene(scene, at.prepared->options);
    return replace_material(*at.prepared, scene.materials[0]);
}

Result<BenchRow> measure_setting(const BenchOptions& options, const AngleContext& at, const Setting& setting,
                                 const std::string& scene_name, const RenderTarget& target,
                                 const std::function<Result<Image>()>& read_color) {
    Result<std::shared_ptr<const PreparedScene>> prepared = setting_scene(options, at, setting);
    if (!prepared) return with_context(setting.technique, prepared.error());
    const std::shared_ptr<const PreparedScene>& scene = *prepared;
    Result<std::unique_ptr<Renderer>> renderer = load_renderer(scene, options.renderer);
    if (!renderer) return with_context(setting.technique, renderer.error());

    // What the shader computed, against the reference.
    Result<SurfaceImage> surfaces = capture_surfaces(**renderer, target.width, target.height);
    if (!surfaces) return surfaces.error();
    if (setting.technique == kDisplacedMesh) {
        // Normal mapping reports the polygon's height; the mesh's is the field's at its uv.
        for (SurfaceSample& s : surfaces->samples)
            if (s.covered) s.height = at.field.sample_bilinear(s.uv.x, s.uv.y);
    }
    Result<reference::ErrorMetrics> error =
        reference::compare_surfaces(*surfaces, at.truth.surface, at.truth.texture_width, at.truth.texture_height);
    if (!error) return error.error();
    // The same in texels of the level sampled (GL's mip selection at each
    // pixel): what the planner's targets are in.
    Result<reference::ObjectError> level = reference::compare_object(*surfaces, at.truth, 0);
    if (!level) return level.error();

    BenchRow row;
    // Colour, then time: both programs warm, then normal mapping and the
    // setting interleaved so both see the same machine.
    std::vector<double> times{0.0}, ratios{0.0};
    if (options.timed) {
        Status drawn = (*renderer)->draw(target);
        if (!drawn) return drawn.error();
        Result<Image> color = read_color();
        if (!color) return color.error();
        row.color_psnr_db = reference::color_psnr(*color, at.truth.color, at.truth.surface);
        Status warm = at.normal->draw(target);
        if (!warm) return warm.error();
        Result<InterleavedTimes> timed = time_interleaved(
            [&] { return at.normal->draw(target); }, [&] { return (*renderer)->draw(target); }, options.frames, false);
        if (!timed) return timed.error();
        times = timed->second_ms;
        ratios = timed->ratios;
    }
    row.scene = scene_name;
    row.angle_deg = at.angle;
    row.technique = setting.technique;
    row.samples = setting.samples;
    if (!(*renderer)->reports().empty() && setting.technique != kDisplacedMesh)
        row.variant = (*renderer)->reports()[0].variant.describe();
    row.shadow = at.shadow;
    row.light_elevation_deg = options.light_elevation_deg;
    row.shadow_samples = at.shadow == ShadowMode::none ? 0 : scene->desc.materials[0].technique.shadow_samples;
    row.pixels = error->pixels;
    row.uv_error_mean = error->uv_error_mean;
    row.uv_error_p95 = error->uv_error_p95;
    row.uv_error_max = error->uv_error_max;
    row.level_error_p95 = level->level_error_p95;
    row.input_floor_p95 = at.input_floor_p95;
    Result<double> own = own_ray_error_p95(options, at, setting, scene, target, *surfaces);
    if (!own) return own.error();
    row.own_ray_error_p95 = *own;
    row.wrong_surface_share = error->wrong_surface_share;
    row.depth_error_mean = error->depth_error_mean;
    row.depth_error_max = error->depth_error_max;
    row.shadow_disagreement = error->shadow_disagreement;
    row.frame_ms_median = median_of(times);
    row.frame_ms_min = *std::min_element(times.begin(), times.end());
    row.frame_ms_max = *std::max_element(times.begin(), times.end());
    row.ns_per_pixel = error->pixels > 0 ? row.frame_ms_median * 1e6 / static_cast<double>(error->pixels) : 0.0;
    row.ratio_to_normal = median_of(ratios);
    // The exact walk's work per pixel, counted by the shader (a second,
    // untimed program with PX_COUNT_WORK).
    const unsigned searches = options.count_every_search ? (kOptSteps | kOptSamples) : kOptSteps;
    const bool walks = setting.technique != kDisplacedMesh &&
                       (technique_info(*parse_technique(setting.technique)).options & searches) != 0;
    if (walks) {
        RendererOptions counting = options.renderer;
        counting.count_work = true;
        Result<std::unique_ptr<Renderer>> counter = load_renderer(scene, counting);
        if (!counter) return with_context(setting.technique + " (counting work)", counter.error());
        Result<WorkStats> work = measure_work(**counter, target.width, target.height);
        if (!work) return with_context(setting.technique, work.error());
        row.iterations_median = work->iterations_median;
        row.iterations_p90 = work->iterations_p90;
        row.iterations_p99 = work->iterations_p99;
        row.iterations_max = work->iterations_max;
        row.fetches_median = work->fetches_median;
        row.iteration_histogram.assign(work->histogram.begin(), work->histogram.end());
    }
    return row;
}

// The settings a scene is measured with: each at every shadow sample count
// where the scene is shadowed (the displaced mesh has no shadow).
std::vector<Setting> scene_settings(const std::vector<Setting>& settings, ShadowMode shadow,
                                    const std::vector<int>& shadow_samples) {
    std::vector<Setting> out;
    for (const Setting& setting : settings) {
        if (shadow == ShadowMode::none || setting.technique == kDisplacedMesh) {
            out.push_back(setting);
            continue;
        }
        for (int k : shadow_samples) {
            Setting with_shadow = setting;
            with_shadow.shadow_samples = k;
            out.push_back(with_shadow);
        }
    }
    return out;
}

// One scene at one angle: its scene, the exact reference, the traced height
// field and (timed) normal mapping loaded as the baseline.
Status prepare_angle(const BenchOptions& options, SceneDesc base, const std::string& scene_name, double angle,
                     const RenderTarget& target, AngleContext& at) {
    at.base = std::move(base);
    at.angle = angle;
    // One preparation, for this context's texture rules (what its renderers
    // would prepare): the reference traces the same images.
    Result<std::unique_ptr<Renderer>> context = make_renderer(options.renderer);
    if (!context) return context.error();
    Result<std::shared_ptr<const PreparedScene>> prepared = prepare_scene(at.base, (*context)->prepare_options());
    if (!prepared) return with_context(scene_name, prepared.error());
    at.prepared = std::move(*prepared);
    reference::ReferenceOptions reference_options;
    reference_options.shadow = at.shadow;
    reference_options.images = at.prepared->options.images;
    Result<reference::ReferenceImage> truth =
        reference::render_reference(*at.prepared, target.width, target.height, reference_options);
    if (!truth) return with_context("reference for " + scene_name, truth.error());
    at.truth = std::move(*truth);
    at.field = at.prepared->materials[0]->images.traced;
    // What an fp32 tracer cannot be asked to beat: how far the exact hit
    // moves for one float ulp of its inputs, per covered pixel.
    std::vector<double> floors;
    for (size_t i = 0; i < at.truth.surface.samples.size(); ++i)
        if (at.truth.surface.samples[i].covered)
            floors.push_back(reference::fp32_input_floor(at.field, at.truth.entry_uv[i], at.truth.view_ts[i],
                                                         at.truth.height_scale, at.truth.polygon_height));
    at.input_floor_p95 = reference::nearest_rank_p95(std::move(floors));
    at.normal.reset();
    if (!options.timed) return {};
    MaterialDesc normal = at.base.materials[0];
    normal.technique.technique = Technique::normal;
    Result<std::shared_ptr<const PreparedScene>> normal_scene = replace_material(*at.prepared, normal);
    if (!normal_scene) return normal_scene.error();
    RendererOptions baseline_options = options.renderer;
    baseline_options.variant_transform = nullptr;
    Result<std::unique_ptr<Renderer>> loaded = load_renderer(std::move(*normal_scene), baseline_options);
    if (!loaded) return loaded.error();
    at.normal = std::move(*loaded);
    return {};
}

// The run's header: when, what, on which renderer, at what size.
BenchRun run_header(const BenchOptions& options, const RenderTarget& target) {
    BenchRun run;
    run.date = now_iso8601();
    run.command = options.command;
    run.gl_renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    run.gl_version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    run.threads = options.threads;
    run.width = target.width;
    run.height = target.height;
    run.frames = options.frames;
    return run;
}

Status check_bench_options(const BenchOptions& options, const std::vector<std::string>& scenes) {
    if (options.frames < 1) return make_error("frames must be at least 1");
    if (options.segments < 1 || options.segments > 1024) return make_error("segments must be within 1..1024");
    for (const std::string& s : scenes)
        if (!find_spec(s)) return bench_scene(s, 0.0).error();
    if (options.shadow_samples.empty()) return make_error("shadow_samples: needs at least one count");
    for (int k : options.shadow_samples)
        if (k < 1 || k > 128) return make_error("shadow_samples: " + std::to_string(k) + " is outside 1..128");
    return {};
}

}  // namespace

Result<BenchRun> run_bench(const BenchOptions& options, const RenderTarget& target,
                           const std::function<Result<Image>()>& read_color, const Progress& progress) {
    std::vector<std::string> scenes = options.scenes.empty() && options.materials.empty() ? bench_scene_names() : options.scenes;
    const std::vector<std::string> techniques =
        options.techniques.empty() ? bench_technique_names() : options.techniques;
    if (Status s = check_bench_options(options, scenes); !s) return s.error();
    for (const BenchMaterial& m : options.materials) scenes.push_back(m.name);
    auto scene_at = [&](const std::string& name, double angle) -> Result<SceneDesc> {
        for (const BenchMaterial& m : options.materials)
            if (m.name == name)
                return bench_scene_of(name, m.material, m.base_dir, angle, options.segments, options.light_elevation_deg);
        return bench_scene(name, angle, options.segments, options.light_elevation_deg);
    };
    auto shadow_of = [&](const std::string& name) {
        for (const BenchMaterial& m : options.materials)
            if (m.name == name) return m.shadow;
        return bench_scene_shadow(name);
    };
    Result<std::vector<Setting>> settings = bench_settings(options, techniques);
    if (!settings) return settings.error();
    BenchRun run = run_header(options, target);
    int total = 0, done = 0;
    for (const std::string& scene_name : scenes)
        total += static_cast<int>(options.angles.size() *
                                  scene_settings(*settings, shadow_of(scene_name), options.shadow_samples).size());
    for (const std::string& scene_name : scenes) {
        AngleContext at;
        at.shadow = shadow_of(scene_name);
        for (double angle : options.angles) {
            Result<SceneDesc> base = scene_at(scene_name, angle);
            if (!base) return base.error();
            if (Status s = prepare_angle(options, std::move(*base), scene_name, angle, target, at); !s) return s.error();
            for (const Setting& setting : scene_settings(*settings, at.shadow, options.shadow_samples)) {
                Result<BenchRow> row = measure_setting(options, at, setting, scene_name, target, read_color);
                if (!row) return row.error();
                run.rows.push_back(std::move(*row));
                ++done;
                if (!progress) continue;
                std::string what = scene_name + " " + std::to_string(static_cast<int>(angle)) + "deg " + setting.technique;
                if (setting.samples) what += " " + std::to_string(setting.samples);
                progress(done, total, what);
            }
        }
    }
    return run;
}

}  // namespace px::profiling
