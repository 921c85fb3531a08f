// The accuracy/time benchmark's results and the report writers: one row per
// scene, view angle, technique and sample setting.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/effects/technique.h"

namespace px::profiling {

// "displaced_mesh": the real-geometry baseline (one vertex per texel).
inline constexpr const char* kDisplacedMesh = "displaced_mesh";

struct BenchRow {
    std::string scene;        // bench scene name
    double angle_deg = 0.0;   // view angle from the normal
    std::string technique;    // catalogue name, or "displaced_mesh" for the real-geometry baseline
    int samples = 0;          // max_samples (0 where the technique has none)
    std::string variant;      // the drawn shader variant (VariantKey::describe); empty for the mesh baseline
    ShadowMode shadow = ShadowMode::none;
    int shadow_samples = 0;   // shadowed scenes: samples along the shadow ray
    double light_elevation_deg = 35.0;  // the light, above the plane
    // Error against the exact reference (see include/parallaxes/reference/metrics.h).
    long pixels = 0;
    double uv_error_mean = 0.0;  // texels
    double uv_error_p95 = 0.0;
    double uv_error_max = 0.0;
    double level_error_p95 = 0.0;  // the same in texels of the level sampled (divided by texels per pixel where > 1)
    // p95 over the same pixels of how far the exact hit moves for one fp32
    // ulp of the ray's inputs (reference::fp32_input_floor): the error an
    // fp32 tracer reading a rounded uv and view vector cannot be held below.
    double input_floor_p95 = 0.0;
    // p95 of the hit error against the exact reference of the ray each
    // pixel's trace was handed (its own fp32 uv and parallax vector, read
    // back): the tracer's error alone. NaN where not measured (a technique
    // that traces nothing, or no float read-back: ES 2.0): empty in the
    // CSV, null in the JSON.
    double own_ray_error_p95 = std::numeric_limits<double>::quiet_NaN();
    double wrong_surface_share = 0.0;
    double depth_error_mean = 0.0;
    double depth_error_max = 0.0;
    double shadow_disagreement = 0.0;
    double color_psnr_db = 0.0;
    // Time: wall clock around glFinish after a warm-up, over repeated frames.
    double frame_ms_median = 0.0;
    double frame_ms_min = 0.0;
    double frame_ms_max = 0.0;
    double ns_per_pixel = 0.0;   // median frame time / pixels drawn
    double ratio_to_normal = 0.0;  // median of per-round (this / normal mapping), interleaved
    // The exact walk's work per drawn pixel, counted by the shader
    // (include/parallaxes/profiling/measurement/work.h); 0 for the techniques not counted.
    double iterations_median = 0.0;
    double iterations_p90 = 0.0;
    double iterations_p99 = 0.0;
    double iterations_max = 0.0;
    double fetches_median = 0.0;
    // Pixels per iteration count in powers of two (work.h); empty where not counted.
    std::vector<std::size_t> iteration_histogram;
    // `bench --gpu NAME`: the variant's fragment shader as that GPU's real
    // compiler estimates it (profile --gpu, docs/gpu-compilers.md). NaN where
    // not asked for, or where the compiler gives no cycle estimate.
    double gpu_cycles = std::numeric_limits<double>::quiet_NaN();  // its static figure; a kept loop counts one pass
    double gpu_loops = std::numeric_limits<double>::quiet_NaN();   // loops it kept after unrolling
    // Per pixel: gpu_cycles where it kept no loop; where it kept one and the
    // shader's own work counters read the iterations back (the exact walk),
    // gpu_cycles times the median iterations (an upper bound: the code
    // outside the loop is counted each time); NaN otherwise.
    double gpu_cycles_per_pixel = std::numeric_limits<double>::quiet_NaN();
};

struct BenchRun {
    std::string date;           // ISO 8601
    std::string command;        // the command line that made it
    std::string gl_renderer;    // GL_RENDERER
    std::string gl_version;     // GL_VERSION
    int threads = 0;            // llvmpipe threads (LP_NUM_THREADS or the CPU count)
    int width = 0, height = 0;  // image size
    int frames = 0;             // timed frames per setting
    std::string gpu;            // bench --gpu: "Mali-G57 (Valhall): Panfrost of ..."; empty when not asked for
    std::vector<BenchRow> rows;
};

Status write_csv(const BenchRun& run, const std::string& path);
Status write_json(const BenchRun& run, const std::string& path);
// Error (mean texels, log scale) against time (ratio to normal mapping) per
// technique, one panel per angle class, the Pareto frontier marked.
Status write_pareto_svg(const BenchRun& run, const std::string& path);
// The same plot with the real GPU compiler's cost (bench --gpu: cycles per
// pixel over normal mapping's) on the cost axis. Error: a run without GPU figures.
Status write_pareto_gpu_svg(const BenchRun& run, const std::string& path);
// Per scene and angle: the cheapest setting reaching 1, 0.5 and 0.25 texel
// mean error and its cost relative to normal mapping; says where a technique
// never gets there.
Status write_report_md(const BenchRun& run, const std::string& path);

}  // namespace px::profiling
