// parallax render [SCENE] [-o OUT.png] [--size WxH] [--technique NAME] [--es 2|3] [--list]
//                 [--program-cache DIR|off] [--golden GOLDEN.png [tolerance options, as compare's]]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_common.h"
#include "draw_surface.h"
#include "commands.h"
#include "compare_command.h"
#include "parallaxes/core/counters.h"
#include "parallaxes/platform/headless_context.h"
#include "program_binary_files.h"
#include "parallaxes/render/offscreen_target.h"
#include "parallaxes/render/renderer.h"
#include "plan_report.h"
#include "texture_assets.h"

#include <glm/glm.hpp>

namespace px::tools {

namespace {

int g_exit_status = 0;

struct RenderArgs {
    std::string scene;
    std::string output;  // default: out/<scene name>.png
    std::string size = "512x512";
    std::string technique;
    int es = 3;
    bool no_fragment_highp = false;  // --no-fragment-highp (ES 2.0 only)
    int frames = 5;
    bool list = false;
    bool explain = false;
    std::string cost_target;  // --cost-target: plan in this GPU's cycles
    std::string cost_table;   // --cost-table: plan from this table
    std::string camera_path;        // "", orbit or dolly
    std::string calibration_cache;  // "": the default folder; off: none
    std::string program_cache;  // empty: default_program_cache_dir(); "off": none
    std::string textures;       // "": the scene's own; else an asset variant (texture/convert.h)
    bool decode_textures = false;
    bool stats = false;
    bool no_state_restore = false;
    bool verify = false;
    std::string golden;            // compare the image with this golden (compare_command.h)
    GoldenOptions golden_options;  // its tolerance entry: the scene's name, this --es
    bool size_given = false;       // --size given; else --golden's size
    int msaa = 0;                  // samples per pixel; 0: the default (4, or 1 with --golden)
    std::string output_color = "srgb";  // srgb: encoded for an sRGB display; linear
};

// Multisampling by default (anti-aliased polygon edges where the context
// offers it); goldens are single-sampled, as the golden tests draw them.
int samples_per_pixel(const RenderArgs& a) { return a.msaa > 0 ? a.msaa : (a.golden.empty() ? 4 : 1); }

// A built-in scene's name, or a scene file's stem: the default output's name
// and the tolerance entry --golden reads.
std::string scene_stem(const RenderArgs& a) {
    return a.scene.empty() ? "default" : std::filesystem::path(a.scene).stem().string();
}

// The camera of frame i of n along a path: orbit turns it around the
// target's vertical axis through 60 degrees (-30 to +30); dolly moves it
// toward the target, to 40 % of its distance.
CameraDesc camera_on_path(const CameraDesc& start, const std::string& path, int i, int n) {
    CameraDesc c = start;
    const double t = n > 1 ? static_cast<double>(i) / (n - 1) : 0.0;
    const glm::vec3 offset = start.position - start.target;
    if (path == "orbit") {
        const double a = glm::radians(-30.0 + 60.0 * t);
        const glm::vec3 axis = glm::length(start.up) > 0.0f ? glm::normalize(start.up) : glm::vec3(0, 0, 1);
        // Rodrigues' rotation of the offset about the up axis.
        const glm::vec3 rotated = offset * static_cast<float>(std::cos(a)) +
                                  glm::cross(axis, offset) * static_cast<float>(std::sin(a)) +
                                  axis * glm::dot(axis, offset) * static_cast<float>(1.0 - std::cos(a));
        c.position = start.target + rotated;
    } else {
        c.position = start.target + offset * static_cast<float>(1.0 - 0.6 * t);
    }
    return c;
}

void list_everything() {
    std::printf("techniques:\n");
    for (const TechniqueInfo& t : technique_table())
        std::printf("  %-15s %s (%s)\n", t.name, t.summary, t.citation);
    std::printf("built-in scenes:\n");
    for (const std::string& name : builtin_scene_names()) std::printf("  %s\n", name.c_str());
}

// `compared`: the --golden comparison's exit status, once it was made.
// The render's size and, with --golden, the tolerance it is compared
// under (the golden's size unless --size is given). Non-zero: the exit status.
int render_size(const RenderArgs& a, std::optional<Tolerance>& tolerance, int& width, int& height) {
    std::string size = a.size;
    std::string golden_size;
    if (!a.golden.empty()) {
        Result<Tolerance> t = resolve_tolerance(a.golden_options);
        if (!t) return bad_input(t.error().message);
        tolerance = *t;
        Result<ImageInfo> info = read_image_info(a.golden);
        if (!info) return bad_input("golden image: " + info.error().message);
        golden_size = std::to_string(info->width) + "x" + std::to_string(info->height);
        if (!a.size_given) size = golden_size;
    }
    if (!parse_size(size, width, height))
        return fail("--size '" + size + "': expected WIDTHxHEIGHT with integers in 1..16384, e.g. 512x512");
    if (tolerance && std::to_string(width) + "x" + std::to_string(height) != golden_size)
        return bad_input("size mismatch: --size " + size + ", golden image " + a.golden + " is " + golden_size);
    return 0;
}

// What the timed frames measured.
struct FrameRun {
    std::vector<double> times_ms;  // sorted
    double longest_ms = 0.0;
    std::vector<double> plan_us;   // per object, sorted
    int plan_changes = 0;
    std::vector<CameraDesc> cameras;  // the path's, or none
    std::vector<DrawReport> first_reports;
};

// With a camera path, every frame's plan is made (and its variants
// compiled) before the first; then one untimed draw (Mesa compiles at first
// use), then the timed frames around glFinish.
Result<FrameRun> run_frames(const RenderArgs& a, Renderer& renderer, const SceneDesc& scene, OffscreenTarget& target,
                            int width, int height) {
    FrameRun run;
    if (!a.camera_path.empty()) {
        std::vector<std::vector<ObjectPlan>> frames;
        for (int i = 0; i < a.frames; ++i) {
            run.cameras.push_back(camera_on_path(scene.camera, a.camera_path, i, a.frames));
            Result<std::vector<ObjectPlan>> plans = renderer.plan_view(run.cameras.back(), width, height);
            if (!plans)
                return make_error("frame " + std::to_string(i) + " of --camera-path " + a.camera_path + ": " +
                                  plans.error().message);
            frames.push_back(std::move(*plans));
        }
        Status compiled = renderer.prepare(frames, target.target());
        if (!compiled) return compiled.error();
        Result<int> first = renderer.set_view(run.cameras.front(), width, height);
        if (!first) return first.error();
        run.first_reports = renderer.reports();
    }
    HostFrame frame = renderer.scene_frame(target.target());
    frame.target_color = a.output_color == "linear" ? HostFrame::TargetColor::linear : HostFrame::TargetColor::srgb_encoded;
    Status drawn = renderer.draw(frame);
    if (!drawn) return drawn.error();
    glFinish();
    if (run.first_reports.empty()) run.first_reports = renderer.reports();
    for (int i = 0; i < a.frames; ++i) {
        const auto start = std::chrono::steady_clock::now();
        if (!run.cameras.empty()) {
            const auto plan_start = std::chrono::steady_clock::now();
            Result<int> changed = renderer.set_view(run.cameras[static_cast<size_t>(i)], width, height);
            const auto plan_end = std::chrono::steady_clock::now();
            if (!changed) return changed.error();
            if (i > 0) run.plan_changes += *changed;
            run.plan_us.push_back(std::chrono::duration<double, std::micro>(plan_end - plan_start).count() /
                                  static_cast<double>(std::max<size_t>(1, scene.objects.size())));
        }
        frame = renderer.scene_frame(target.target());
        frame.target_color =
            a.output_color == "linear" ? HostFrame::TargetColor::linear : HostFrame::TargetColor::srgb_encoded;
        drawn = renderer.draw(frame);
        glFinish();
        const auto end = std::chrono::steady_clock::now();
        if (!drawn) return drawn.error();
        run.times_ms.push_back(std::chrono::duration<double, std::milli>(end - start).count());
    }
    run.longest_ms = *std::max_element(run.times_ms.begin(), run.times_ms.end());
    std::sort(run.times_ms.begin(), run.times_ms.end());
    std::sort(run.plan_us.begin(), run.plan_us.end());
    return run;
}

// The objects' variants (or the plan table with --explain) and the textures.
void print_draws(const RenderArgs& a, Renderer& renderer, const FrameRun& run, int width, int height,
                 const CostTable* prices) {
    if (a.explain) {
        std::vector<ObjectPlan> plans;
        for (const DrawReport& r : run.first_reports) plans.push_back(r.plan);
        std::printf("plan       for %dx%d%s\n", width, height, run.cameras.empty() ? "" : " (the path's first frame)");
        if (!a.cost_target.empty() || !a.cost_table.empty())
            std::printf("prices     %s\n", prices_line(prices).c_str());
        std::fputs(plans_table(plans).c_str(), stdout);
    } else {
        for (const DrawReport& r : run.first_reports) {
            std::printf("object     %-10s material %-10s %s -> %s\n", r.object.c_str(), r.material.c_str(),
                        r.plan.planned ? "effects" : (std::string("technique ") + technique_name(r.requested)).c_str(),
                        r.variant.describe().c_str());
            for (const std::string& note : r.notes) std::printf("             note: %s\n", note.c_str());
        }
    }
    for (const std::string& note : renderer.texture_notes()) std::printf("texture    note: %s\n", note.c_str());
    for (const TextureUpload& u : renderer.texture_uploads()) {
        if (u.container == "image" && a.textures.empty() && !a.decode_textures) continue;
        std::printf("texture    %s: %s %s %ux%u, %d level(s), %llu bytes on the GPU: %s\n", u.what.c_str(),
                    u.container.c_str(), format_name(u.format), u.width, u.height, u.levels,
                    static_cast<unsigned long long>(u.gpu_bytes), u.path.c_str());
        if (!u.rows.empty()) std::printf("             rows: %s\n", u.rows.c_str());
    }
    for (const TextureUpload& u : renderer.texture_uploads())
        if (u.what.find(" albedo (") != std::string::npos)
            std::printf("colour     %s: %s\n", u.what.c_str(), u.color_space.c_str());
    std::printf("output     %s\n", a.output_color == "linear"
                                      ? "linear light (--output-color linear)"
                                      : "lit in linear light, encoded for an sRGB display (--output-color srgb)");
}

// Frame time, the path's planning, the program cache.
void print_timing(const RenderArgs& a, Renderer& renderer, const FrameRun& run, const std::string& cache_dir) {
    const std::vector<double>& times_ms = run.times_ms;
    std::printf("frame      %.3f ms median of %d (min %.3f, max %.3f), %d program(s); wall clock around glFinish\n",
                times_ms[times_ms.size() / 2], a.frames, times_ms.front(), times_ms.back(),
                static_cast<int>(renderer.program_count()));
    if (!run.cameras.empty())
        std::printf("path       %s: %d plan change(s) over %d frames; planning %.1f us per object (median); "
                    "longest frame %.2f ms = %.2fx the median\n",
                    a.camera_path.c_str(), run.plan_changes, a.frames, run.plan_us[run.plan_us.size() / 2],
                    run.longest_ms, run.longest_ms / std::max(1e-9, times_ms[times_ms.size() / 2]));
    const ProgramStats stats = renderer.program_stats();
    const std::string where = cache_dir.empty() || cache_dir == "off" ? std::string("off")
                              : stats.binaries_off.empty()            ? cache_dir
                                                                      : cache_dir + ": " + stats.binaries_off;
    const std::string last = stats.rejected ? " (last: " + stats.last_rejection + ")" : "";
    std::printf("programs   %d compiled, %d from the binary cache (%s), %d stale entries rebuilt%s\n", stats.compiled,
                stats.from_binary, where.c_str(), stats.rejected, last.c_str());
}

// --textures: every material's textures through the asset step into that
// variant (files in a temporary folder, removed at exit), drawn from them.
int convert_textures(const RenderArgs& a, SceneDesc& scene, std::optional<TempFolder>& folder_out) {
    if (a.textures.empty()) return 0;
    Result<AssetFormats> formats = asset_formats(a.textures);
    if (!formats) return fail("--textures: " + formats.error().message);
    Result<TempFolder> folder = make_texture_folder();
    if (!folder) return fail(folder.error().message);
    folder_out.emplace(std::move(*folder));
    ConvertOptions convert;
    convert.formats = *formats;
    Result<std::vector<ConvertedFile>> files = convert_scene_textures(scene, convert, folder_out->path(), show_progress);
    if (!files) return fail(in_scene_file(scene.source, "--textures " + a.textures + ": " + files.error().message));
    return 0;
}

RendererOptions render_options(const RenderArgs& a, const std::string& cache_dir, const CostTable* prices) {
    RendererOptions o = program_renderer_options();
    o.planner.table = prices;
    o.force_texture_decode = a.decode_textures;
    o.preserve_host_state = !a.no_state_restore;
    o.emulate_no_fragment_highp = a.no_fragment_highp;
    o.planner.find_calibration =
        calibration_finder(a.calibration_cache.empty() ? default_calibration_dir() : a.calibration_cache);
    if (!cache_dir.empty() && cache_dir != "off") o.program_binaries = file_program_store(cache_dir);
    return o;
}

// The scene to draw: loaded (validated once, by prepare_scene, unless the
// asset step converts its textures first: it needs a valid scene), with
// --technique's technique for every material.
Result<SceneDesc> render_scene(const RenderArgs& a, std::vector<std::string>& override_notes) {
    if (!a.camera_path.empty() && a.camera_path != "orbit" && a.camera_path != "dolly")
        return make_error("--camera-path must be orbit or dolly, got '" + a.camera_path + "'");
    const SceneChecks checks = a.textures.empty() ? SceneChecks::syntax_only : SceneChecks::validate;
    Result<SceneDesc> scene = load_scene(a.scene.empty() ? "default" : a.scene, checks);
    if (!scene) return scene;
    if (!a.technique.empty()) {
        Result<Technique> t = parse_technique(a.technique);
        if (!t) return make_error("--technique: " + t.error().message);
        // An explicit technique for every material: effect requests give
        // way, and what it cannot draw is dropped with a note in the plan.
        override_notes = force_technique(*scene, *t);
    }
    return scene;
}

// The image written (default: out/<scene>.png, named after the built-in
// scene or file), its folder made.
Result<std::string> write_render(const RenderArgs& a, const Image& image) {
    const std::string output = a.output.empty() ? "out/" + scene_stem(a) + ".png" : a.output;
    const std::filesystem::path out(output);
    if (out.has_parent_path()) {
        std::error_code ec;
        std::filesystem::create_directories(out.parent_path(), ec);
        if (ec) return make_error("cannot create folder '" + out.parent_path().string() + "': " + ec.message());
    }
    Status written = write_png(output, image);
    if (!written) return written.error();
    return output;
}

void print_pipeline_stats(const PipelineCounters& c, const Renderer& renderer) {
    std::printf("pipeline   %llu validation(s), %llu material image build(s), %llu mesh build(s), "
                "%llu object plan(s) over %llu frame(s) drawn, %llu program(s) built, "
                "%llu named material plan(s)\n",
                static_cast<unsigned long long>(c.validations), static_cast<unsigned long long>(c.image_builds),
                static_cast<unsigned long long>(c.mesh_builds), static_cast<unsigned long long>(c.object_plans),
                static_cast<unsigned long long>(renderer.stats().frames), static_cast<unsigned long long>(c.programs_built),
                static_cast<unsigned long long>(c.material_plans));
}

int run_render(const RenderArgs& a, std::optional<int>& compared) {
    if (a.list) {
        list_everything();
        return 0;
    }
    std::optional<Tolerance> tolerance;
    int width = 0, height = 0;
    if (const int status = render_size(a, tolerance, width, height); status != 0) return status;
    if (a.frames < 1 || a.frames > 10000) return fail("--frames must be within 1..10000, got " + std::to_string(a.frames));
    if (a.no_fragment_highp && a.es >= 3)
        return fail("--no-fragment-highp is for --es 2: OpenGL ES 3.0 guarantees fragment highp");
    Result<std::shared_ptr<const CostTable>> prices = chosen_cost_table(a.cost_target, a.cost_table);
    if (!prices) return fail(prices.error().message);
    const PipelineCounters counters_before = pipeline_counters();
    std::vector<std::string> override_notes;
    Result<SceneDesc> scene = render_scene(a, override_notes);
    if (!scene) return fail(scene.error().message);
    std::optional<TempFolder> texture_folder;
    if (const int status = convert_textures(a, *scene, texture_folder); status != 0) return status;

    platform::ContextOptions options;
    options.es_major = a.es;
    Result<std::unique_ptr<platform::HeadlessContext>> context = platform::HeadlessContext::create(options);
    if (!context) return fail(context.error().message);
    const std::string cache_dir = a.program_cache.empty() ? default_program_cache_dir() : a.program_cache;
    Result<std::unique_ptr<Renderer>> renderer = Renderer::create(render_options(a, cache_dir, prices->get()));
    if (!renderer) return fail(renderer.error().message);
    Result<OffscreenTarget> target = OffscreenTarget::create(width, height, samples_per_pixel(a));
    if (!target) return fail(target.error().message);
    // One preparation of the scene, for this context's texture rules.
    Result<std::shared_ptr<const PreparedScene>> prepared = prepare_scene(*scene, (*renderer)->prepare_options());
    if (!prepared) return fail(in_scene_file(scene->source, prepared.error().message));
    Status loaded = (*renderer)->load(*prepared);
    if (!loaded) return fail(in_scene_file(scene->source, loaded.error().message));
    Result<FrameRun> run = run_frames(a, **renderer, *scene, *target, width, height);
    if (!run) return fail(in_scene_file(scene->source, run.error().message));
    Result<Image> image = target->read_pixels();
    if (!image) return fail(image.error().message);
    Result<std::string> output = write_render(a, *image);
    if (!output) return fail(output.error().message);

    if (a.stats) print_pipeline_stats(pipeline_counters() - counters_before, **renderer);
    const Caps& caps = (*renderer)->caps();
    std::printf("scene      %s%s\n", scene->name.c_str(), a.technique.empty() ? "" : (" (every material: " + a.technique + ")").c_str());
    for (const std::string& note : override_notes) std::printf("             note: %s\n", note.c_str());
    std::printf("context    %s | %s | %s\n", caps.version.c_str(), caps.renderer.c_str(),
                (*context)->display_description().c_str());
    // What the driver says its fragment floats are (glGetShaderPrecisionFormat):
    // a desktop GPU may report fp32 for mediump, a mobile one (and llvmpipe
    // with F16C) fp16's 10 bits; without highp the exact tracer is not exact.
    const auto bits = [](const PrecisionInfo& p) {
        return p.precision > 0 ? std::to_string(p.precision) + " bits, range 2^" + std::to_string(p.range_max)
                               : std::string("none");
    };
    std::printf("precision  fragment mediump float %s; highp float %s\n", bits(caps.fragment_mediump_float).c_str(),
                bits(caps.fragment_highp_float).c_str());
    print_draws(a, **renderer, *run, width, height, prices->get());
    std::printf("image      %s (%dx%d, %d sample%s per pixel%s%s)\n", output->c_str(), width, height, target->samples(),
                target->samples() == 1 ? "" : "s", target->sampling_note().empty() ? "" : ": ",
                target->sampling_note().c_str());
    print_timing(a, **renderer, *run, cache_dir);
    if (tolerance) compared = compare_with_golden(*image, *output, a.golden, *tolerance, a.golden_options);
    if (a.verify) return verify_plan(**renderer, *scene, width, height);
    return 0;
}

// With --golden, compare's exit statuses: the comparison's (then --verify's
// miss, 1, after a pass), and kCompareBadInput for a render that failed
// before it could be compared.
int golden_exit_status(const RenderArgs& a, int rendered, const std::optional<int>& compared) {
    if (a.golden.empty() || a.list) return rendered;
    if (!compared) return kCompareBadInput;
    return *compared != 0 ? *compared : rendered;
}

}  // namespace

void set_exit_status(int status) { g_exit_status = status; }
int exit_status() { return g_exit_status; }

void add_render_command(CLI::App& app) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* cmd = app.add_subcommand("render", "Render a scene headless to a PNG");
    cmd->add_option("scene", args->scene, "A scene file (.json) or the name of a built-in scene (default: default)");
    cmd->add_option("-o,--output", args->output, "Output PNG (default: out/<scene>.png)");
    CLI::Option* size = cmd->add_option("--size", args->size, "Image size WIDTHxHEIGHT (with --golden: the golden's)")
                            ->capture_default_str();
    cmd->add_option("--technique", args->technique, "Override every material's technique (and any effects it declares)");
    cmd->add_option("--es", args->es, "OpenGL ES major version: 2 or 3")->check(CLI::IsMember({2, 3}))->capture_default_str();
    cmd->add_flag("--no-fragment-highp", args->no_fragment_highp,
                  "With --es 2: plan and draw as a GPU without fragment highp (no GL_FRAGMENT_PRECISION_HIGH, "
                  "Mali-400 class) would");
    cmd->add_option("--frames", args->frames, "Timed frames after the warm-up frame")->capture_default_str();
    cmd->add_option("--program-cache", args->program_cache,
                     "Folder of cached program binaries, or 'off' (default: $XDG_CACHE_HOME/parallaxes/programs "
                     "or ~/.cache/parallaxes/programs)");
    cmd->add_option("--textures", args->textures,
                    "Draw from this variant of the scene's textures, made by the asset step (raw, etc1, etc2, astc, "
                    "astc_WxH, pvrtc, bc), and print per texture whether it went up directly or was decoded on the CPU");
    cmd->add_flag("--decode-textures", args->decode_textures,
                  "Decode every texture file on the CPU (RGBA8 upload) even where the context samples its format");
    cmd->add_flag("--list", args->list, "List techniques and built-in scenes");
    cmd->add_flag("--no-state-restore", args->no_state_restore,
                  "Draw as a host that manages its own GL state would (RendererOptions::preserve_host_state off): "
                  "compare --frames timings with and without");
    cmd->add_flag("--verify", args->verify,
                  "After rendering, measure each object's hit and shadow error at the scene camera against the "
                  "exact reference, beside the plan's prediction and target; exit 1 when a target is missed");
    cmd->add_flag("--stats", args->stats,
                  "Print how often the pipeline validated, built images and meshes, planned and built programs");
    cmd->add_flag("--explain", args->explain,
                  "Print the plan per object: effects asked for, variant chosen, prediction, what was dropped and why");
    cmd->add_option("--cost-target", args->cost_target,
                    "Plan with candidates priced in this GPU's cycles (the table the program carries for it; "
                    "parallax plan --cost-target)");
    cmd->add_option("--cost-table", args->cost_table, "Plan with candidates priced from this cost table");
    cmd->add_option("--camera-path", args->camera_path,
                    "Move the camera over the --frames (orbit: 60 degrees around the target; dolly: toward it), "
                    "planning every frame");
    cmd->add_option("--calibration-cache", args->calibration_cache,
                    "Folder of `parallax plan --calibrate` results (default $XDG_CACHE_HOME/parallaxes/calibration; off: none)");
    cmd->add_option("--output-color", args->output_color,
                    "What the PNG holds: srgb (lighting in linear light, encoded for an sRGB display) or linear "
                    "(the linear light itself, for further processing)")
        ->check(CLI::IsMember({"srgb", "linear"}))
        ->capture_default_str();
    cmd->add_option("--msaa", args->msaa,
                    "Samples per pixel, 1..64 (default 4, or 1 with --golden: goldens are single-sampled); "
                    "a context that offers fewer gets what it has (OpenGL ES 2.0: 1), and the image line says so")
        ->check(CLI::Range(1, 64));
    CLI::Option* golden = cmd->add_option(
        "--golden", args->golden,
        "Compare the image with this golden as `parallax compare` does (the tolerance file's entry: the scene's "
        "name, this --es); exit 0 within the tolerances, 1 not, 2 when it cannot be compared or rendered");
    add_tolerance_options(cmd, args->golden_options);
    for (const char* name : {"--tolerances", "--threshold", "--max-share", "--max-mean", "--diff"})
        cmd->get_option(name)->needs(golden);
    cmd->callback([args, size]() {
        args->size_given = size->count() > 0;
        if (!args->golden_options.tolerances.empty()) args->golden_options.scene = scene_stem(*args);
        args->golden_options.es = args->es;
        std::optional<int> compared;
        const int rendered = run_render(*args, compared);
        set_exit_status(golden_exit_status(*args, rendered, compared));
    });
}

}  // namespace px::tools
