#include "parallaxes/profiling/measurement/showcase.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <set>

#include "parallaxes/core/files.h"
#include "parallaxes/gl/gl.h"
#include "parallaxes/profiling/measurement/interleaved.h"
#include "parallaxes/profiling/measurement/work.h"
#include "parallaxes/reference/metrics.h"
#include "parallaxes/reference/reference_image.h"
#include "parallaxes/render/surface_capture.h"

namespace px::profiling {

namespace {

std::string now_iso8601() {
    const std::time_t t = std::time(nullptr);
    char buffer[32];
    std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buffer;
}

std::string g(double x, const char* format = "%.3g") {
    if (x < 0.0) return "-";
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, format, x);
    return buffer;
}

// One object's row: its plan, and its hit and shadow errors under the plan
// and under every effect, against the references by shadow mode.
Result<ShowcaseObject> measure_object(const SceneDesc& scene, size_t i, const DrawReport& planned_report,
                                      const DrawReport& all_report, const SurfaceImage& planned_surfaces,
                                      const SurfaceImage& all_surfaces,
                                      const std::map<ShadowMode, reference::ReferenceImage>& references) {
    const auto reference_for = [&](ShadowMode mode) -> const reference::ReferenceImage& {
        auto it = references.find(mode);
        return it != references.end() ? it->second : references.begin()->second;
    };
    ShowcaseObject o;
    o.object = scene.objects[i].name;
    o.material = scene.objects[i].material;
    const ObjectPlan& plan = planned_report.plan;
    o.planned = plan.planned;
    o.planned_variant = plan.key.describe();
    o.all_variant = all_report.variant.describe();
    o.predicted = plan.predicted_error;
    const MaterialDesc* m = scene.find_material(o.material);
    if (m && m->effects) {
        o.target = m->effects->parallax ? m->effects->max_error_texels : -1.0;
        o.shadow = m->effects->shadow;
        if (o.shadow != ShadowMode::none) o.shadow_target = m->effects->shadow_max_error;
    }
    const int index = static_cast<int>(i);
    Result<reference::ObjectError> ep = reference::compare_object(planned_surfaces, reference_for(ShadowMode::none), index);
    Result<reference::ObjectError> ea = reference::compare_object(all_surfaces, reference_for(ShadowMode::none), index);
    if (!ep) return ep.error();
    if (!ea) return ea.error();
    o.pixels = ep->pixels;
    if (ep->pixels > 0) {
        o.error_planned = ep->level_error_p95;
        o.base_error_planned = ep->base_error_p95;
    }
    if (ea->pixels > 0) {
        o.error_all = ea->level_error_p95;
        o.base_error_all = ea->base_error_p95;
    }
    if (o.shadow != ShadowMode::none) {
        const reference::ReferenceImage& shadow_truth = reference_for(o.shadow);
        Result<reference::ObjectError> sp = reference::compare_object(planned_surfaces, shadow_truth, index);
        Result<reference::ObjectError> sa = reference::compare_object(all_surfaces, shadow_truth, index);
        if (!sp) return sp.error();
        if (!sa) return sa.error();
        // A shadow the planner dropped (no light reaches the surface):
        // the horizon alone, which the reference agrees with.
        o.shadow_planned = sp->visibility_error_mean;
        o.shadow_all = sa->visibility_error_mean;
    }
    o.meets = (o.target < 0.0 || o.error_planned <= o.target) && (o.shadow_target < 0.0 || o.shadow_planned <= o.shadow_target);
    return o;
}

}  // namespace

SceneDesc all_effects_scene(const SceneDesc& scene) {
    SceneDesc s = scene;
    for (MaterialDesc& m : s.materials) {
        const ShadowMode asked = m.effects ? m.effects->shadow : m.technique.shadow;
        m.effects.reset();
        TechniqueOptions o;
        o.technique = Technique::relief;
        o.min_samples = o.max_samples = 64;
        o.refine_steps = 5;
        o.shadow = asked == ShadowMode::none ? ShadowMode::soft : asked;
        o.shadow_samples = 32;
        o.depth_write = true;
        o.exact_view = true;
        o.lod = false;
        m.technique = o;
    }
    return s;
}

Result<ShowcaseRun> run_showcase(const SceneDesc& scene, const RendererOptions& given_options, int frames,
                                 const RenderTarget& target, const std::string& command,
                                 const std::function<void(const std::string&)>& progress,
                                 const std::function<std::string(const std::vector<ObjectPlan>&)>& explain,
                                 bool count_work) {
    if (frames < 1) return make_error("showcase: frames must be at least 1");
    auto say = [&](const std::string& what) {
        if (progress) progress(what);
    };
    ShowcaseRun run;
    run.date = now_iso8601();
    run.renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    run.version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    run.command = command;
    run.scene = scene.name;
    run.width = target.width;
    run.height = target.height;
    run.frames = frames;

    const SceneDesc all_scene = all_effects_scene(scene);
    RendererOptions options = given_options;
    options.effect_planner = effect_planner;
    options.texture_files = texture_files();
    Result<std::unique_ptr<Renderer>> planned = Renderer::create(options);
    if (!planned) return planned.error();
    Result<std::unique_ptr<Renderer>> all = Renderer::create(options);
    if (!all) return all.error();
    // One preparation (validation, images, meshes): the all-effects scene is
    // the same scene with each material's technique replaced, its images
    // shared; the references trace the same prepared scene.
    Result<std::shared_ptr<const PreparedScene>> prepared = prepare_scene(scene, (*planned)->prepare_options());
    if (!prepared) return prepared.error();
    std::shared_ptr<const PreparedScene> all_prepared = *prepared;
    for (const MaterialDesc& m : all_scene.materials) {
        Result<std::shared_ptr<const PreparedScene>> next = replace_material(*all_prepared, m);
        if (!next) return with_context("the all-effects scene", next.error());
        all_prepared = std::move(*next);
    }
    Status loaded = (*planned)->load(*prepared);
    if (!loaded) return loaded.error();
    loaded = (*all)->load(all_prepared);
    if (!loaded) return with_context("the all-effects scene", loaded.error());
    Result<int> viewed = (*planned)->set_view(scene.camera, target.width, target.height);
    if (!viewed) return viewed.error();
    viewed = (*all)->set_view(all_scene.camera, target.width, target.height);
    if (!viewed) return viewed.error();
    std::vector<ObjectPlan> plans;
    for (const DrawReport& r : (*planned)->reports()) plans.push_back(r.plan);
    if (explain) run.plan_text = explain(plans);

    // Time: both warm, then interleaved rounds on the same machine state.
    say("timing");
    Result<InterleavedTimes> timed = time_interleaved([&] { return (*planned)->draw(target); },
                                                      [&] { return (*all)->draw(target); }, frames);
    if (!timed) return timed.error();
    run.planned_ms = timed->first_median_ms;
    run.all_ms = timed->second_median_ms;
    run.speedup = timed->ratio_median;
    run.planned_programs = static_cast<int>((*planned)->program_count());
    run.all_programs = static_cast<int>((*all)->program_count());

    // Error: what each shader computed against the depth-composited exact
    // reference, one reference per shadow mode asked for.
    say("capturing");
    Result<SurfaceImage> planned_surfaces = capture_surfaces(**planned, target.width, target.height);
    if (!planned_surfaces) return planned_surfaces.error();
    Result<SurfaceImage> all_surfaces = capture_surfaces(**all, target.width, target.height);
    if (!all_surfaces) return all_surfaces.error();
    std::set<ShadowMode> modes = {ShadowMode::none};
    for (const MaterialDesc& m : scene.materials)
        if (m.effects) modes.insert(m.effects->shadow);
    std::map<ShadowMode, reference::ReferenceImage> references;
    for (ShadowMode mode : modes) {
        say(std::string("reference (shadow ") + shadow_mode_name(mode) + ")");
        reference::ReferenceOptions ro;
        ro.shadow = mode;
        ro.depth_composite = true;
        Result<reference::ReferenceImage> truth = reference::render_reference(**prepared, target.width, target.height, ro);
        if (!truth) return truth.error();
        references.emplace(mode, std::move(*truth));
    }
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        Result<ShowcaseObject> o = measure_object(scene, i, (*planned)->reports()[i], (*all)->reports()[i],
                                                  *planned_surfaces, *all_surfaces, references);
        if (!o) return o.error();
        run.objects.push_back(std::move(*o));
    }
    if (!count_work) return run;
    // Each object's loop passes: both scenes drawn again with the work
    // counters; the reference says which object each pixel shows.
    const std::vector<int>& owner = references.at(ShadowMode::none).object_index;
    for (const bool planned_side : {true, false}) {
        say(planned_side ? "counting work (planner)" : "counting work (every effect)");
        RendererOptions counting = options;
        counting.count_work = true;
        Result<std::unique_ptr<Renderer>> counter = Renderer::create(counting);
        if (!counter) return counter.error();
        if (Status s = (*counter)->load(planned_side ? *prepared : all_prepared); !s) return s.error();
        Result<int> counted_view =
            (*counter)->set_view(planned_side ? scene.camera : all_scene.camera, target.width, target.height);
        if (!counted_view) return counted_view.error();
        Result<SurfaceImage> counts = capture_surfaces(**counter, target.width, target.height);
        if (!counts) return counts.error();
        const std::vector<double> iterations = work_iterations(*counts);
        // Only the searches count (VariantKey::count_work): an object drawn
        // otherwise runs no loop, one pass.
        std::vector<bool> counts_work;
        for (const DrawReport& r : (*counter)->reports())
            counts_work.push_back((technique_info(r.variant.technique).options & (kOptSamples | kOptSteps)) != 0);
        std::vector<double> passes(scene.objects.size(), 0.0), pixels(scene.objects.size(), 0.0);
        for (size_t p = 0; p < iterations.size() && p < owner.size(); ++p) {
            const int object = owner[p];
            if (object < 0 || static_cast<size_t>(object) >= passes.size() || iterations[p] < 0.0) continue;
            const size_t o = static_cast<size_t>(object);
            const bool counted = o < counts_work.size() && counts_work[o];
            if (counted && std::isnan(iterations[p]))
                return make_error("work counts of object '" + scene.objects[o].name + "' at pixel " +
                                  std::to_string(p % static_cast<size_t>(target.width)) + "," +
                                  std::to_string(p / static_cast<size_t>(target.width)) + " are not whole numbers");
            passes[o] += counted ? std::max(1.0, iterations[p]) : 1.0;
            pixels[o] += 1.0;
        }
        for (size_t i = 0; i < run.objects.size(); ++i) {
            if (!(pixels[i] > 0.0)) continue;
            (planned_side ? run.objects[i].passes_planned : run.objects[i].passes_all) = passes[i] / pixels[i];
        }
    }
    return run;
}

Status write_showcase_md(const ShowcaseRun& run, const std::string& path) {
    std::string md;
    md += "Scene `" + run.scene + "` at " + std::to_string(run.width) + "x" + std::to_string(run.height) + " on " +
          run.renderer + " (" + run.version + "), " + run.date + ".\n";
    md += "Command: `" + run.command + "`.\n\n";
    md += "| | planner | every effect |\n|---|---|---|\n";
    md += "| frame time, median of " + std::to_string(run.frames) + " interleaved rounds | " + g(run.planned_ms, "%.2f") +
          " ms | " + g(run.all_ms, "%.2f") + " ms |\n";
    md += "| programs | " + std::to_string(run.planned_programs) + " | " + std::to_string(run.all_programs) + " |\n";
    md += "\n**The planner is " + g(run.speedup, "%.2f") +
          " times faster** (median over the rounds of every-effect time / planner time).\n\n";
    if (!run.prices.empty()) md += "The planner priced its candidates as: " + run.prices + ".\n\n";
    if (!run.gpu.empty()) {
        md += "**On " + run.gpu + "**, fragment cycles per frame (the compiler's estimate per pixel of each object's "
              "variant compiled for this scene's " + std::to_string(run.lights) + " light(s), with a kept loop's "
              "share of it taken once per counted pass, times its pixels): planner " +
              g(run.gpu_planned / 1e3, "%.1f") + " thousand, every effect " + g(run.gpu_all / 1e3, "%.1f") +
              " thousand";
        if (run.gpu_planned > 0.0 && run.gpu_all > 0.0) md += ": **" + g(run.gpu_all / run.gpu_planned, "%.2f") + " times fewer**";
        md += ".\n\n| object | pixels | planner: cycles per pixel | loop passes | every effect: cycles per pixel | loop passes |\n"
              "|---|---:|---:|---:|---:|---:|\n";
        for (const ShowcaseObject& o : run.objects)
            md += "| " + o.object + " | " + std::to_string(o.pixels) + " | " + g(o.gpu_cycles_planned) + " | " +
                  g(o.passes_planned) + " | " + g(o.gpu_cycles_all) + " | " + g(o.passes_all) + " |\n";
        md += "\n";
    }
    md += "Per object: hit error as the 95th percentile over its pixels in texels of the mip level sampled "
          "(the target's unit; base-level texels in brackets), against the exact reference composited by depth; "
          "shadow as the mean visibility difference against the reference of the shadow mode asked for.\n\n";
    md += "| object | planner's variant | target | predicted | planner | every effect | shadow target | shadow: planner | shadow: every effect | meets |\n";
    md += "|---|---|---|---|---|---|---|---|---|---|\n";
    for (const ShowcaseObject& o : run.objects) {
        md += "| " + o.object + " | `" + o.planned_variant + "` | " + g(o.target) + " | " + g(o.predicted) + " | " +
              g(o.error_planned) + " (" + g(o.base_error_planned) + ") | " + g(o.error_all) + " (" + g(o.base_error_all) +
              ") | " + g(o.shadow_target) + " | " + g(o.shadow_planned) + " | " + g(o.shadow_all) + " | " +
              (o.meets ? "yes" : "**no**") + " |\n";
    }
    md += "\nEvery effect: ";
    std::set<std::string> variants;
    for (const ShowcaseObject& o : run.objects) variants.insert("`" + o.all_variant + "`");
    bool first = true;
    for (const std::string& v : variants) {
        md += (first ? "" : ", ") + v;
        first = false;
    }
    md += ".\n\nThe plan:\n\n```\n" + run.plan_text + "```\n";
    return write_file_atomically(path, md);
}

}  // namespace px::profiling
