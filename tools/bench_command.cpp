// parallax bench [--scenes ...] [--techniques ...] [--samples ...] [--angles ...]
//                [--size WxH] [--frames N] [--quick] [--out DIR]
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "parallaxes/core/limits.h"
#include "parallaxes/core/counters.h"
#include "parallaxes/core/files.h"
#include "parallaxes/profiling/measurement/bench.h"
#include "parallaxes/profiling/costs/gpu_compilers.h"
#include "parallaxes/shaders/shader_source.h"
#include "parallaxes/profiling/measurement/planner_table.h"
#include "parallaxes/profiling/measurement/showcase.h"
#include "plan_report.h"
#include "cli_common.h"
#include "draw_surface.h"
#include "commands.h"
#include "parallaxes/platform/headless_context.h"
#include "parallaxes/render/offscreen_target.h"

namespace px::tools {

int run_search_model_bench(const std::string& folder, int width, int height, const std::string& out,
                           const std::string& command);
int run_texture_bench(const std::string& scene_name, int width, int height, int frames, const std::string& out,
                      const std::string& command);

namespace {

struct BenchArgs {
    std::vector<std::string> scenes;
    std::vector<std::string> techniques;
    std::vector<int> samples;
    std::vector<double> angles;
    std::string size = "256x256";
    int frames = 0;
    bool quick = false;
    bool stats = false;
    int segments = 64;
    bool per_vertex_view = false;
    std::string out = "out/bench";
    std::string planner_table;  // write the planner's cost table here instead of the bench report
    std::string showcase;       // a scene: the planner against every effect, instead of the sweep
    bool shadows_only = false;  // --planner-table: measure only the shadow rows, keep the file's others
    std::string calibration_cache = "off";  // --showcase: plan with these calibrations
    std::string command;
    bool textures = false;      // the texture-format table instead of the sweep
    std::string textures_scene; // --textures-scene: its scene (default: the built-in lettering scene)
    std::string search_model;   // a folder of fit_*.json and judge_*.json scenes
    int es = 3;                 // the sweep's OpenGL ES version
    std::string gpu;            // --gpu: one real GPU compiler's cost of each setting's variant
};

// --gpu: each drawn variant compiled with that GPU's real compiler
// (profiling/costs/gpu_compilers.h), its cycles into the rows.
Status add_gpu_costs(profiling::BenchRun& run, const std::string& name, int es) {
    Result<std::vector<profiling::GpuTarget>> targets = profiling::parse_gpu_targets(name);
    if (!targets) return targets.error();
    if (targets->size() != 1) return make_error("--gpu: one GPU at a time for bench");
    const profiling::GpuTarget& t = targets->front();
    Result<profiling::GpuCompilers> tools = profiling::find_gpu_compilers();
    if (!tools) return tools.error();
    // Each row's pixel as the bench draws it: the variant compiled for the
    // bench's one sun, its search truncated to the median steps the
    // shader's own counters read (gpu_pixel_costs).
    std::vector<profiling::GpuPixelCost> requests;
    std::vector<profiling::BenchRow*> rows;
    for (profiling::BenchRow& r : run.rows) {
        if (r.variant.empty()) continue;
        Result<VariantKey> key = VariantKey::parse(r.variant);
        if (!key) return make_error("--gpu: the drawn variant '" + r.variant + "' does not parse: " + key.error().message);
        requests.push_back({*key, profiling::pixel_search_steps(*key, !r.iteration_histogram.empty(), r.iterations_median)});
        rows.push_back(&r);
    }
    std::fprintf(stderr, "bench: compiling %zu setting(s) with %s's compiler (%s, under qemu-aarch64)\n", requests.size(),
                 t.gpu.c_str(), t.driver.c_str());
    std::string context;
    Result<std::vector<profiling::GpuCost>> costs = profiling::gpu_pixel_costs(*tools, t, es, requests, 1, &context);
    if (!costs) return costs.error();
    run.gpu = t.gpu + ": " + t.driver + " of " + context;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        profiling::BenchRow& r = *rows[i];
        const profiling::GpuCost& c = (*costs)[i];
        if (!c.error.empty())
            std::fprintf(stderr, "bench: warning: %s on %s: %s\n", t.gpu.c_str(), r.variant.c_str(), c.error.c_str());
        if (c.variant.cycles < 0.0) continue;
        r.gpu_cycles = c.variant.cycles;
        r.gpu_loops = c.variant.loops;
        const bool searches = requests[i].steps > 0 ||
                              !(technique_info(requests[i].key.technique).options & (kOptSamples | kOptSteps));
        if (searches && c.cycles_per_pixel >= 0.0) r.gpu_cycles_per_pixel = c.cycles_per_pixel;
    }
    return {};
}

// --planner-table with --gpu: each row's cost becomes its variant's cycles
// per pixel on that GPU over normal mapping's on the same relief (the
// unshadowed run's normal-mapping row: a shadowed scene's twin). `normal`
// carries the plain run's baselines to the shadow runs after it.
Status price_rows_on_gpu(profiling::BenchRun& run, const std::string& name, std::map<std::string, double>& normal,
                         std::string& prices) {
    if (Status s = add_gpu_costs(run, name, 3); !s) return s;
    const auto relief_of = [](const std::string& scene) {
        for (const char* suffix : {"_shadowed", "_soft"}) {
            const std::string tail = suffix;
            if (scene.size() > tail.size() && scene.compare(scene.size() - tail.size(), tail.size(), tail) == 0)
                return scene.substr(0, scene.size() - tail.size());
        }
        return scene;
    };
    for (const profiling::BenchRow& r : run.rows)
        if (r.technique == "normal" && r.shadow == ShadowMode::none && r.gpu_cycles_per_pixel > 0.0)
            normal.emplace(relief_of(r.scene), r.gpu_cycles_per_pixel);
    for (profiling::BenchRow& r : run.rows) {
        if (r.technique == profiling::kDisplacedMesh) continue;
        const auto base = normal.find(relief_of(r.scene));
        if (base == normal.end())
            return make_error("--gpu: no normal-mapping row of relief '" + relief_of(r.scene) +
                              "' to price against (the table's unshadowed scenes must include it)");
        if (!(r.gpu_cycles_per_pixel > 0.0))
            return make_error("--gpu: " + r.scene + " at " + std::to_string(static_cast<int>(r.angle_deg)) + " degrees, " +
                              r.variant + ": no cycles per pixel (" +
                              (r.gpu_cycles < 0.0 ? "the compiler gave no estimate" : "a kept loop whose work was not counted") +
                              ")");
        r.ratio_to_normal = r.gpu_cycles_per_pixel / base->second;
    }
    const std::string context = run.gpu.substr(std::min(run.gpu.size(), run.gpu.find(" of ") + 4));
    Result<std::vector<profiling::GpuTarget>> t = profiling::parse_gpu_targets(name);
    if (!t) return t.error();
    prices = t->front().gpu + " cycles per pixel relative to normal mapping's: the static estimate of " +
             t->front().driver + "'s compiler (" + context +
             ", under drm-shim) for the variant compiled for the scene's one light; where it kept a loop, the loop's "
             "share of its instruction listing taken once per search iteration the shader counted";
    return {};
}


// The planner's cost table: the grid of include/parallaxes/profiling/measurement/planner_table.h, or the
// options given (--scenes, --angles, --samples, --frames, --size).
int run_planner_table(const BenchArgs& a, const profiling::BenchOptions& o) {
    profiling::TableGrid grid;
    if (!a.scenes.empty()) grid.scenes = a.scenes;
    if (!a.angles.empty()) grid.angles = a.angles;
    if (!a.samples.empty()) grid.samples = a.samples;
    if (a.frames > 0) grid.frames = a.frames;
    grid.width = o.width;
    grid.height = o.height;
    if (a.quick) {
        grid.scenes = {"bricks", "lines"};
        grid.angles = {30, 85};
        grid.samples = {8, 32};
        grid.shadow_scenes = {"bricks_shadowed"};
        grid.shadow_samples = {8, 16};
        grid.shadow_angles = {30};
        grid.light_elevations = {35};
        grid.frames = 2;
    }
    Result<DrawSurface> surface = make_draw_surface(grid.width, grid.height);
    if (!surface) return fail(surface.error().message);
    OffscreenTarget* target = &*surface->target;
    std::optional<CostTable> keep;
    if (a.shadows_only) {
        Result<std::vector<std::uint8_t>> bytes = read_file_bounded(a.planner_table, 64u << 20, "cost table");
        if (!bytes) return fail(bytes.error().message);
        Result<CostTable> old = parse_cost_table(std::string(bytes->begin(), bytes->end()), a.planner_table);
        if (!old) return fail(old.error().message);
        keep = std::move(*old);
    }
    // --gpu: errors measured here, untimed; every row priced in that GPU's
    // cycles per pixel.
    std::map<std::string, double> normal_cycles;
    profiling::RowPricer price;
    if (!a.gpu.empty()) {
        grid.timed = false;
        grid.count_every_search = true;
        price = [&a, &normal_cycles](profiling::BenchRun& run, std::string& prices) {
            return price_rows_on_gpu(run, a.gpu, normal_cycles, prices);
        };
    }
    Result<CostTable> table = profiling::measure_cost_table(
        grid, a.command, target->target(), [&target]() { return target->read_pixels(); },
        [](int done, int total, const std::string& what) { show_progress("planner table", done, total, what); },
        keep ? &*keep : nullptr, price);
    if (!table) return fail(table.error().message);
    Status written = write_file_atomically(a.planner_table, cost_table_json(*table));
    if (!written) return fail(written.error().message);
    std::printf("planner table: %zu rows over %zu reliefs measured on %s; wrote %s\n", table->rows.size(),
                table->reliefs.size(), table->renderer.c_str(), a.planner_table.c_str());
    return 0;
}

// --showcase --gpu: each object's two variants compiled by that GPU's
// compiler; cycles per pixel with the counted passes, and per frame.
Status add_showcase_gpu_cycles(profiling::ShowcaseRun& run, const std::string& name, int lights) {
    Result<std::vector<profiling::GpuTarget>> targets = profiling::parse_gpu_targets(name);
    if (!targets) return targets.error();
    const profiling::GpuTarget& t = targets->front();
    Result<profiling::GpuCompilers> tools = profiling::find_gpu_compilers();
    if (!tools) return tools.error();
    // Each object's two variants as its pixels run them: compiled for the
    // scene's lights, each search truncated to the object's mean counted steps.
    std::vector<profiling::GpuPixelCost> requests;
    for (const profiling::ShowcaseObject& o : run.objects)
        for (const auto& [variant, passes] : {std::pair{o.planned_variant, o.passes_planned}, std::pair{o.all_variant, o.passes_all}}) {
            Result<VariantKey> key = VariantKey::parse(variant);
            if (!key) return make_error("--gpu: the drawn variant '" + variant + "' does not parse: " + key.error().message);
            requests.push_back({*key, profiling::pixel_search_steps(*key, passes >= 1.0, passes)});
        }
    std::fprintf(stderr, "showcase: compiling %zu variant(s) with %s's compiler (%s, under qemu-aarch64)\n", requests.size(),
                 t.gpu.c_str(), t.driver.c_str());
    std::string context;
    Result<std::vector<profiling::GpuCost>> costs =
        profiling::gpu_pixel_costs(*tools, t, 3, requests, std::clamp(lights, 1, kMaxLights), &context);
    if (!costs) return costs.error();
    run.gpu = t.gpu + " (" + t.driver + " of " + context + ")";
    run.lights = lights;
    const auto per_pixel = [&](std::size_t request, const std::string& variant) {
        const profiling::GpuCost& c = (*costs)[request];
        if (!c.error.empty())
            std::fprintf(stderr, "showcase: warning: %s on %s: %s\n", t.gpu.c_str(), variant.c_str(), c.error.c_str());
        return c.cycles_per_pixel;
    };
    run.gpu_planned = run.gpu_all = 0.0;
    for (std::size_t i = 0; i < run.objects.size(); ++i) {
        profiling::ShowcaseObject& o = run.objects[i];
        if (o.pixels <= 0) continue;
        o.gpu_cycles_planned = per_pixel(2 * i, o.planned_variant);
        o.gpu_cycles_all = per_pixel(2 * i + 1, o.all_variant);
        const double n = static_cast<double>(o.pixels);
        run.gpu_planned = o.gpu_cycles_planned < 0.0 || run.gpu_planned < 0.0 ? -1.0 : run.gpu_planned + n * o.gpu_cycles_planned;
        run.gpu_all = o.gpu_cycles_all < 0.0 || run.gpu_all < 0.0 ? -1.0 : run.gpu_all + n * o.gpu_cycles_all;
    }
    return {};
}

// The planner against every effect on every surface (docs/planner.md).
int run_showcase_bench(const BenchArgs& a, int width, int height) {
    Result<SceneDesc> scene = load_scene(a.showcase);
    if (!scene) return fail(scene.error().message);
    Result<DrawSurface> surface = make_draw_surface(width, height);
    if (!surface) return fail(surface.error().message);
    OffscreenTarget* target = &*surface->target;
    RendererOptions options = program_renderer_options();
    options.planner.find_calibration = calibration_finder(a.calibration_cache);
    // --gpu: the plan priced by that GPU's table, both frames in its cycles.
    const CostTable* gpu_table = nullptr;
    if (!a.gpu.empty()) {
        Result<const CostTable*> t = profiling::gpu_cost_table(a.gpu);
        if (!t) return fail("--gpu: " + t.error().message);
        gpu_table = *t;
        options.planner.table = gpu_table;
    }
    Result<profiling::ShowcaseRun> run = profiling::run_showcase(
        *scene, options, a.frames > 0 ? a.frames : 9, target->target(), a.command,
        [](const std::string& what) { std::fprintf(stderr, "showcase: %s\n", what.c_str()); },
        [](const std::vector<ObjectPlan>& plans) { return plans_table(plans); }, gpu_table != nullptr);
    if (!run) return fail(run.error().message);
    if (gpu_table) {
        run->prices = gpu_table->prices + " (table of " + gpu_table->date + ")";
        if (Status s = add_showcase_gpu_cycles(*run, a.gpu, static_cast<int>(scene->lights.size())); !s)
            return fail(s.error().message);
    }
    std::error_code ec;
    std::filesystem::create_directories(a.out, ec);
    if (ec) return fail("cannot create '" + a.out + "': " + ec.message());
    const std::string path = a.out + "/showcase.md";
    Status written = profiling::write_showcase_md(*run, path);
    if (!written) return fail(written.error().message);
    int missed = 0;
    for (const profiling::ShowcaseObject& o : run->objects) missed += o.meets ? 0 : 1;
    std::printf("showcase: planner %.2f ms, every effect %.2f ms: %.2fx faster; %d of %zu objects miss a target; wrote %s\n",
                run->planned_ms, run->all_ms, run->speedup, missed, run->objects.size(), path.c_str());
    if (!run->gpu.empty() && run->gpu_planned > 0.0 && run->gpu_all > 0.0)
        std::printf("showcase: on %s: planner %.0f, every effect %.0f fragment cycles per frame: %.2fx fewer\n",
                    run->gpu.c_str(), run->gpu_planned, run->gpu_all, run->gpu_all / run->gpu_planned);
    return 0;
}

int run(BenchArgs a) {
    profiling::BenchOptions o;
    if (a.quick) {  // under 2 minutes on 2 cores
        o.scenes = {"bricks", "text"};
        o.angles = {30, 75, 85};
        o.samples = {8, 32, 128};
        o.frames = 3;
        if (a.size == "256x256") a.size = "128x128";
    }
    if (!a.scenes.empty()) o.scenes = a.scenes;
    if (!a.techniques.empty()) o.techniques = a.techniques;
    if (!a.samples.empty()) o.samples = a.samples;
    if (!a.angles.empty()) o.angles = a.angles;
    if (a.frames < 0 || a.frames > 1000) return fail("--frames must be within 1..1000, got " + std::to_string(a.frames));
    if (a.frames > 0) o.frames = a.frames;
    int width = 0, height = 0;
    if (!parse_size(a.size, width, height))
        return fail("--size '" + a.size + "': expected WIDTHxHEIGHT with integers in 1..16384, e.g. 256x256");
    o.width = width;
    o.height = height;
    o.command = a.command;
    o.segments = a.segments;
    o.exact_view = !a.per_vertex_view;
    const char* threads = std::getenv("LP_NUM_THREADS");
    o.threads = threads ? std::atoi(threads) : static_cast<int>(std::thread::hardware_concurrency());

    if (a.es != 3 && (!a.planner_table.empty() || !a.showcase.empty() || !a.search_model.empty() || a.textures))
        return fail("--es 2 is for the sweep only: --planner-table, --showcase, --search-model and --textures run on "
                    "OpenGL ES 3.0");
    if (!a.gpu.empty()) {
        if (!a.search_model.empty() || a.textures)
            return fail("--gpu is for the sweep, --planner-table and --showcase only");
        if (a.shadows_only)
            return fail("--gpu with --shadows-only: the kept rows' prices would come from another source; measure the "
                        "whole table with --gpu");
        // The names and the compilers checked before anything is measured.
        Result<std::vector<profiling::GpuTarget>> t = profiling::parse_gpu_targets(a.gpu);
        if (!t) return fail(t.error().message);
        if (t->size() != 1) return fail("--gpu: one GPU at a time for bench");
        if (t->front().pipes.empty())
            return fail("--gpu " + t->front().name + ": its compiler gives no cycle estimate; bench --gpu needs one "
                        "that does (mali-g52, mali-g57; profile --gpu shows the others' figures)");
        if (a.es > t->front().es_max)
            return fail("--gpu " + t->front().name + ": " + t->front().gpu + " runs OpenGL ES 2.0 only: add --es 2");
        if (Result<profiling::GpuCompilers> c = profiling::find_gpu_compilers(); !c) return fail(c.error().message);
    }
    if (!a.planner_table.empty()) return run_planner_table(a, o);
    // Every other mode writes into --out at the end: refuse a folder that
    // cannot be written before measuring anything.
    if (const std::string unwritable = check_output_folder(a.out); !unwritable.empty()) return fail(unwritable);
    if (!a.showcase.empty()) return run_showcase_bench(a, width, height);
    if (!a.search_model.empty()) return run_search_model_bench(a.search_model, width, height, a.out, a.command);
    if (a.textures) return run_texture_bench(a.textures_scene, width, height, a.frames > 0 ? a.frames : 7, a.out, a.command);
    std::error_code ec;
    std::filesystem::create_directories(a.out, ec);
    if (ec) return fail("cannot create '" + a.out + "': " + ec.message());

    Result<DrawSurface> surface = make_draw_surface(width, height, a.es);
    if (!surface) return fail(surface.error().message);
    OffscreenTarget* target = &*surface->target;
    o.es_major = a.es;
    o.count_every_search = !a.gpu.empty();  // a kept loop's cycles times its counted iterations
    if (a.es < 3 && a.techniques.empty()) o.techniques = profiling::bench_technique_names(a.es);
    const PipelineCounters counters_before = pipeline_counters();
    auto result = profiling::run_bench(o, target->target(), [&target]() { return target->read_pixels(); },
                                       [](int done, int total, const std::string& what) {
                                           show_progress("bench", done, total, what);
                                       });
    if (!result) return fail(result.error().message);
    if (!a.gpu.empty())
        if (Status g = add_gpu_costs(*result, a.gpu, a.es); !g) return fail(g.error().message);

    const std::string base = a.out + "/";
    for (const auto& [writer, name] :
         {std::pair{&profiling::write_csv, "results.csv"}, std::pair{&profiling::write_json, "results.json"},
          std::pair{&profiling::write_pareto_svg, "pareto.svg"}, std::pair{&profiling::write_report_md, "report.md"}}) {
        Status s = writer(*result, base + name);
        if (!s) return fail(s.error().message);
    }
    if (!a.gpu.empty())
        if (Status s = profiling::write_pareto_gpu_svg(*result, base + "pareto_gpu.svg"); !s) return fail(s.error().message);
    std::printf("bench: %zu settings measured on %s; wrote %sresults.csv, results.json, pareto.svg%s, report.md\n",
                result->rows.size(), result->gl_renderer.c_str(), base.c_str(), a.gpu.empty() ? "" : ", pareto_gpu.svg");
    if (a.stats) {
        const PipelineCounters c = pipeline_counters() - counters_before;
        std::printf("pipeline   %llu validation(s), %llu material image build(s), %llu mesh build(s), "
                    "%llu object plan(s), %llu program(s) built, %llu named material plan(s), for %zu setting(s)\n",
                    static_cast<unsigned long long>(c.validations), static_cast<unsigned long long>(c.image_builds),
                    static_cast<unsigned long long>(c.mesh_builds), static_cast<unsigned long long>(c.object_plans),
                    static_cast<unsigned long long>(c.programs_built), static_cast<unsigned long long>(c.material_plans),
                    result->rows.size());
    }
    return 0;
}

}  // namespace

void add_bench_command(CLI::App& app, int argc, char** argv) {
    auto args = std::make_shared<BenchArgs>();
    std::ostringstream command;
    for (int i = 0; i < argc; ++i) command << (i ? " " : "") << (i == 0 ? "parallax" : argv[i]);
    args->command = command.str();
    CLI::App* cmd = app.add_subcommand("bench", "Sweep error against the exact reference beside frame time");
    cmd->add_option("--gpu", args->gpu,
                    "One real mobile GPU compiler (parallax profile --gpu list; mali-g52 or mali-g57 estimate cycles): "
                    "its cost of each setting's variant beside the error, in the report; with --planner-table: the "
                    "table priced in its cycles per pixel (errors measured here, untimed); with --showcase: the plan "
                    "priced by that GPU's table and both frames in its cycles");
    cmd->add_option("--scenes", args->scenes, "Bench scenes (default: all)")->delimiter(',');
    cmd->add_option("--techniques", args->techniques, "Techniques, and displaced_mesh (default: all)")->delimiter(',');
    cmd->add_option("--samples", args->samples, "max_samples settings (default " + sample_grid_text() + ")")->delimiter(',');
    cmd->add_option("--angles", args->angles, "View angles from the normal, degrees (default 0,30,60,75,85,89)")
        ->delimiter(',');
    cmd->add_option("--size", args->size, "Image size")->capture_default_str();
    cmd->add_option("--es", args->es,
                    "OpenGL ES major version of the sweep: 2 (a true ES 2.0 context; techniques that need ES 3.0 are "
                    "left out of the default list and refused when named) or 3")
        ->check(CLI::IsMember({2, 3}))
        ->capture_default_str();
    cmd->add_option("--frames", args->frames, "Timed rounds per setting (default 7; --quick 3)");
    cmd->add_flag("--quick", args->quick, "A small grid that finishes in under 2 minutes");
    cmd->add_flag("--stats", args->stats,
                  "Print how often the sweep validated, built images and meshes, planned and built programs");
    cmd->add_option("--segments", args->segments, "Quads per side of each bench plane")->capture_default_str();
    cmd->add_flag("--per-vertex-view", args->per_vertex_view,
                  "Every technique with the view vector normalised per vertex (\"exact_view\": false) "
                  "instead of the exact one");
    cmd->add_option("--out", args->out, "Output folder")->capture_default_str();
    cmd->add_option("--showcase", args->showcase,
                    "Draw this scene with the planner and with every effect on every surface: time ratio and each "
                    "object's error against its target (writes OUT/showcase.md)");
    cmd->add_option("--planner-table", args->planner_table,
                    "Measure the effect planner's cost table and write it to this file "
                    "(the library's is src/planner/cost_table.json)");
    cmd->add_option("--calibration-cache", args->calibration_cache,
                    "With --showcase: plan with the calibrations in this folder (default off: the generic table)");
    cmd->add_flag("--textures", args->textures,
                  "Texture formats: bytes, frame time and the hit error of each height-map format, per asset variant, "
                  "on the built-in lettering scene (or --textures-scene); writes OUT/textures.md");
    cmd->add_option("--textures-scene", args->textures_scene, "With --textures: the scene (file or built-in name; default lettering)");
    cmd->add_option("--search-model", args->search_model,
                    "The planner's search model against the GPU: every fit_*.json and judge_*.json scene of this folder "
                    "(examples/scenes/relief_family) benched and simulated; writes OUT/search_model.md, .csv, .svg");
    cmd->add_flag("--shadows-only", args->shadows_only,
                  "With --planner-table: measure only the shadow rows, keeping the file's other rows");
    cmd->callback([args]() { set_exit_status(run(*args)); });
}

}  // namespace px::tools
