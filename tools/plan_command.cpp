// parallax plan [SCENE] [--size WxH] [--es 2|3] [--format table|json] [--calibrate]
//               [--calibration-cache DIR|off] [--verify]
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>

#include "cli_common.h"
#include "draw_surface.h"
#include "commands.h"
#include "parallaxes/core/files.h"
#include "plan_report.h"
#include "parallaxes/platform/headless_context.h"
#include "parallaxes/profiling/measurement/planner_table.h"
#include "parallaxes/render/offscreen_target.h"
#include "parallaxes/render/renderer.h"
#include "parallaxes/scene/material_images.h"

namespace px::tools {

namespace {

struct PlanArgs {
    std::string scene;
    std::string size = "512x512";
    int es = 3;
    bool no_fragment_highp = false;  // --no-fragment-highp (ES 2.0 only)
    std::string format = "table";
    bool calibrate = false;
    bool candidates = false;
    std::string calibration_cache;  // "": the default folder
    int frames = 0;
    bool verify = false;
    std::string cost_target;  // --cost-target: price candidates in this GPU's cycles (its carried table)
    std::string cost_table;   // --cost-table: price candidates from this table file
    std::string command;
};

// The table angles that bracket [lo, hi].
std::vector<double> bracketing_angles(const std::vector<double>& grid, double lo, double hi) {
    double from = grid.front(), to = grid.back();
    for (double a : grid)
        if (a <= lo) from = a;
    for (auto it = grid.rbegin(); it != grid.rend(); ++it)
        if (*it >= hi) to = *it;
    std::vector<double> out;
    for (double a : grid)
        if (a >= from && a <= to) out.push_back(a);
    return out;
}

// Measures every planned material's own relief at the angles its objects
// are seen from, on an ES 3.0 context, and stores each in the cache.
int calibrate(const PlanArgs& a, const SceneDesc& scene, const std::string& dir, int width, int height) {
    if (dir.empty() || dir == "off") return fail("--calibrate needs a cache folder (--calibration-cache DIR)");
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) return fail("cannot create the calibration cache '" + dir + "': " + ec.message());
    platform::ContextOptions options;
    options.es_major = 3;  // float debug captures; every technique
    auto context = platform::HeadlessContext::create(options);
    if (!context) return fail(context.error().message);
    RendererOptions renderer_options = program_renderer_options();
    auto renderer = Renderer::create(renderer_options);
    if (!renderer) return fail(renderer.error().message);
    Status loaded = (*renderer)->load(scene);
    if (!loaded) return fail(in_scene_file(scene.source, loaded.error().message));
    Result<std::vector<ObjectPlan>> plans = (*renderer)->plan_view(scene.camera, width, height);
    if (!plans) return fail(in_scene_file(scene.source, plans.error().message));
    // Per material, the range of view angles over its visible objects.
    std::map<std::string, std::pair<double, double>> angles;
    for (const ObjectPlan& p : *plans) {
        if (!p.planned || !p.view.visible || !p.request.parallax) continue;
        auto it = angles.find(p.material);
        if (it == angles.end())
            angles[p.material] = {p.view.angle_min_deg, p.view.angle_max_deg};
        else
            it->second = {std::min(it->second.first, p.view.angle_min_deg), std::max(it->second.second, p.view.angle_max_deg)};
    }
    profiling::TableGrid grid;
    grid.frames = a.frames;
    auto target = OffscreenTarget::create(grid.width, grid.height);
    if (!target) return fail(target.error().message);
    for (const auto& [name, range] : angles) {
        const MaterialDesc* m = scene.find_material(name);
        if (!m || !(m->height_scale > 0.0f)) continue;
        Result<MaterialImages> images = build_material_images(*m, scene.base_dir);
        if (!images) return fail(images.error().message);
        const ReliefFeatures features = measure_relief(images->traced, m->height_scale);
        if (!(features.range > 0.0)) continue;
        std::vector<double> at = bracketing_angles(grid.angles, range.first, std::min(range.second, 89.0));
        Result<CostTable> table = profiling::calibrate_material(
            *m, scene.base_dir, at, grid, a.command, target->target(), [&target]() { return target->read_pixels(); },
            [label = "calibrating '" + name + "'"](int done, int total, const std::string& what) {
                show_progress(label.c_str(), done, total, what);
            });
        if (!table) return fail("calibrating material '" + name + "': " + table.error().message);
        const std::string file = calibration_file(dir, features);
        Status written = write_file_atomically(file, cost_table_json(*table));
        if (!written) return fail(written.error().message);
        std::fprintf(stderr, "calibrated material '%s' (%s) at %zu angles: %s\n", name.c_str(), describe(features).c_str(),
                     at.size(), file.c_str());
    }
    return 0;
}

int run_plan(const PlanArgs& a) {
    int width = 0, height = 0;
    if (!parse_size(a.size, width, height))
        return fail("--size '" + a.size + "': expected WIDTHxHEIGHT with integers in 1..16384, e.g. 512x512");
    if (a.format != "table" && a.format != "json") return fail("--format must be table or json, got '" + a.format + "'");
    if (a.frames < 0 || a.frames > 100) return fail("--frames must be within 0..100, got " + std::to_string(a.frames));
    if (a.no_fragment_highp && a.es >= 3)
        return fail("--no-fragment-highp is for --es 2: OpenGL ES 3.0 guarantees fragment highp");
    Result<std::shared_ptr<const CostTable>> prices = chosen_cost_table(a.cost_target, a.cost_table);
    if (!prices) return fail(prices.error().message);
    Result<SceneDesc> scene = load_scene(a.scene.empty() ? "default" : a.scene);
    if (!scene) return fail(scene.error().message);
    const std::string dir = a.calibration_cache.empty() ? default_calibration_dir() : a.calibration_cache;
    if (a.calibrate) {
        const int status = calibrate(a, *scene, dir, width, height);
        if (status != 0) return status;
    }

    platform::ContextOptions options;
    options.es_major = a.es;
    auto context = platform::HeadlessContext::create(options);
    if (!context) return fail(context.error().message);
    RendererOptions renderer_options = program_renderer_options();
    renderer_options.planner.find_calibration = calibration_finder(dir);
    renderer_options.emulate_no_fragment_highp = a.no_fragment_highp;
    renderer_options.planner.table = prices->get();
    auto renderer = Renderer::create(renderer_options);
    if (!renderer) return fail(renderer.error().message);
    Status loaded = (*renderer)->load(*scene);
    if (!loaded) return fail(in_scene_file(scene->source, loaded.error().message));
    Result<std::vector<ObjectPlan>> plans = (*renderer)->plan_view(scene->camera, width, height);
    if (!plans) return fail(in_scene_file(scene->source, plans.error().message));
    const Caps& caps = (*renderer)->caps();
    const std::string context_line = caps.version + " | " + caps.renderer;
    if (a.format == "json") {
        std::fputs(plans_json(*plans, scene->name, context_line, prices_line(prices->get())).c_str(), stdout);
    } else {
        std::printf("scene      %s, planned for %dx%d\ncontext    %s\nprices     %s\n", scene->name.c_str(), width,
                    height, context_line.c_str(), prices_line(prices->get()).c_str());
        std::fputs(plans_table(*plans).c_str(), stdout);
    }
    if (a.verify || a.candidates) return verify_plan(**renderer, *scene, width, height, a.candidates);
    return 0;
}

}  // namespace

void add_plan_command(CLI::App& app, int argc, char** argv) {
    auto args = std::make_shared<PlanArgs>();
    for (int i = 0; i < argc; ++i) args->command += (i ? " " : "") + std::string(i == 0 ? "parallax" : argv[i]);
    CLI::App* cmd = app.add_subcommand("plan", "Print the effect planner's choice per object, without rendering");
    cmd->add_option("scene", args->scene, "A scene file (.json) or the name of a built-in scene (default: default)");
    cmd->add_option("--size", args->size, "Image size the plan is for (texels per pixel)")->capture_default_str();
    cmd->add_option("--es", args->es, "OpenGL ES major version: 2 or 3")->check(CLI::IsMember({2, 3}))->capture_default_str();
    cmd->add_flag("--no-fragment-highp", args->no_fragment_highp,
                  "With --es 2: plan and draw as a GPU without fragment highp (no GL_FRAGMENT_PRECISION_HIGH, "
                  "Mali-400 class) would");
    cmd->add_option("--format", args->format, "table or json")->capture_default_str();
    cmd->add_flag("--calibrate", args->calibrate,
                  "Measure each planned material's own relief (exact reference and GPU timing, at the angles the "
                  "camera sees) and cache it by the field's hash; plans then use it");
    cmd->add_option("--calibration-cache", args->calibration_cache,
                    "Folder of calibrations (default $XDG_CACHE_HOME/parallaxes/calibration; off: none)");
    cmd->add_option("--frames", args->frames,
                    "--calibrate: timed rounds per setting on this GPU; 0 measures errors only and prices each "
                    "candidate from the built-in table (deterministic, about 5 times faster)")
        ->capture_default_str();
    cmd->add_option("--cost-target", args->cost_target,
                    "Price every candidate in this GPU's cycles (a real compiler's estimate per pixel: the table the "
                    "program carries for it; see docs/gpu-compilers.md) instead of this machine's frame times");
    cmd->add_option("--cost-table", args->cost_table,
                    "Price every candidate from this cost table (parallax bench --planner-table FILE [--gpu NAME])");
    cmd->add_flag("--verify", args->verify,
                  "Draw the plan and measure each object's hit and shadow error against the exact reference, beside "
                  "the prediction and the target; exit 1 when a target is missed");
    cmd->add_flag("--candidates", args->candidates,
                  "With --verify: also draw every technique and sample count the context runs in each planned "
                  "object's place, and print the cheapest that measures within the targets against the plan's time");
    cmd->callback([args]() { set_exit_status(run_plan(*args)); });
}

}  // namespace px::tools
