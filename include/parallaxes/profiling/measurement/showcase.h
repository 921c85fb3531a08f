// The planner against "every effect on every surface": a scene drawn both
// ways, time as the median of interleaved rounds, and each object's error
// against the exact reference (depth-composited) beside its targets.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/render/renderer.h"
#include "parallaxes/render/target.h"
#include "parallaxes/scene/scene.h"

namespace px::profiling {

struct ShowcaseObject {
    std::string object, material;
    bool planned = false;
    std::string planned_variant, all_variant;
    double target = -1.0;             // texels of the level sampled (planned objects)
    double predicted = -1.0;          // the planner's prediction
    double error_planned = -1.0;      // measured: p95, texels of the level sampled
    double error_all = -1.0;
    double base_error_planned = -1.0; // p95, base texels
    double base_error_all = -1.0;
    long pixels = 0;                  // compared
    ShadowMode shadow = ShadowMode::none;  // asked for
    double shadow_target = -1.0;
    double shadow_planned = -1.0;     // mean |visibility difference|, against the asked mode's reference
    double shadow_all = -1.0;
    bool meets = true;                // the planned draw meets every target
    // count_work runs: the mean over the object's pixels of its counted
    // loop iterations, at least 1 (what a loop the GPU compiler kept runs).
    double passes_planned = -1.0, passes_all = -1.0;
    // With a GPU (bench --showcase --gpu): its compiler's cycles per pixel of
    // each variant (cycles_per_pixel with the passes above).
    double gpu_cycles_planned = -1.0, gpu_cycles_all = -1.0;
};

struct ShowcaseRun {
    std::string date, renderer, version, command, scene;
    int width = 0, height = 0, frames = 0;
    double planned_ms = 0.0, all_ms = 0.0;  // medians
    double speedup = 0.0;                   // median over rounds of all / planned
    int planned_programs = 0, all_programs = 0;
    std::string plan_text;  // the planner's explanation (parallax plan's table)
    std::string prices;     // what the planner's costs were (its table's)
    std::vector<ShowcaseObject> objects;
    // With a GPU: which, and each frame's fragment cycles on it (the sum over
    // objects of pixels x cycles per pixel); -1 where a variant has none.
    std::string gpu;
    double gpu_planned = -1.0, gpu_all = -1.0;
    int lights = 0;  // the scene's: the variants are compiled for this many (profiling::GpuCost)
};

// The "every effect" version of a scene: every material drawn with relief
// mapping at 64 samples and 5 refinements, exact view, depth written, and a
// shadow ray of 32 samples (the mode the material asks for, else soft).
SceneDesc all_effects_scene(const SceneDesc& scene);

// Needs a current ES 3.0 context; `target` of the run's size. `count_work`:
// also draw both with the work counters, for each object's passes.
Result<ShowcaseRun> run_showcase(const SceneDesc& scene, const RendererOptions& options, int frames,
                                 const RenderTarget& target, const std::string& command,
                                 const std::function<void(const std::string&)>& progress,
                                 const std::function<std::string(const std::vector<ObjectPlan>&)>& explain,
                                 bool count_work = false);

Status write_showcase_md(const ShowcaseRun& run, const std::string& path);

}  // namespace px::profiling
