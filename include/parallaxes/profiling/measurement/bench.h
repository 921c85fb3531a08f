// The accuracy/time sweep behind `parallax bench`: for every bench scene,
// view angle, technique and sample setting, the error of what the shader
// computed against the exact reference, beside the frame time.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "parallaxes/core/limits.h"
#include "parallaxes/assets/heightfield.h"
#include "parallaxes/assets/image.h"
#include "parallaxes/profiling/reports/bench_results.h"
#include "parallaxes/core/result.h"
#include "parallaxes/core/surface_image.h"
#include "parallaxes/render/renderer.h"
#include "parallaxes/render/target.h"
#include "parallaxes/scene/scene.h"

namespace px::profiling {

// A directional light `elevation_deg` above the horizon, turned `azimuth_deg`
// from +x toward +y, with a 2-degree disc: the bench scenes' and the
// stability catalogue's.
LightDesc sun_light(double elevation_deg, double azimuth_deg);

// Bench scenes: one plane, one material, seen from `angle_deg` off its normal.
std::vector<std::string> bench_scene_names();
// `segments`: quads per side of the plane (see bench.cpp for why 64).
Result<SceneDesc> bench_scene(const std::string& name, double angle_deg, int segments = 64,
                              double light_elevation_deg = 35.0);
// The shadow mode a bench scene measures (and its reference uses).
ShadowMode bench_scene_shadow(const std::string& name);

// The bench's plane and camera with another material (its uv transform and
// technique reset): how `parallax plan --calibrate` measures a relief.
Result<SceneDesc> bench_scene_of(const std::string& name, const MaterialDesc& material, const std::string& base_dir,
                                 double angle_deg, int segments = 64, double light_elevation_deg = 35.0);

// The trace's error on the ray it was handed: each pixel's hit (`hits`,
// capture_surfaces of the technique) against the exact reference of that
// pixel's own fp32 uv and parallax vector (`rays`, capture_surfaces of the
// same scene drawn with RendererOptions::capture_ray), in texels of `field`
// modulo the tile, over pixels covered in both: without what rasterised
// inputs add (compare against render_reference for that). Errors: images
// of different sizes.
Result<std::vector<double>> own_ray_errors(const HeightField& field, const SurfaceImage& hits, const SurfaceImage& rays,
                                           double polygon_height);
// One pixel's: its hit uv against the exact trace of its captured ray
// (`ray`: uv, and the parallax vector in height and visibility).
double own_ray_error(const HeightField& field, const glm::dvec2& hit_uv, const SurfaceSample& ray,
                     double polygon_height);

// A material to bench beside the built-in bench scenes.
struct BenchMaterial {
    std::string name;
    MaterialDesc material;
    std::string base_dir;  // for its texture files
    ShadowMode shadow = ShadowMode::none;
};

// Every benched technique of the catalogue, then kDisplacedMesh.
// The techniques a sweep measures by default on a context of `es_major`
// (those that need a later version left out), and displaced_mesh.
std::vector<std::string> bench_technique_names(int es_major = 3);

struct BenchOptions {
    std::vector<std::string> scenes;      // empty: every bench scene
    std::vector<std::string> techniques;  // empty: every technique and the baseline
    std::vector<int> samples = sample_grid();
    std::vector<double> angles{0, 30, 60, 75, 85, 89};
    int width = 256;
    int height = 256;
    int frames = 7;          // timed rounds per setting (each: normal mapping, then the setting)
    // false: errors only (one debug-output draw per setting): no colour, no
    // timing; the rows' times and ratios are 0 (a calibration without timing).
    bool timed = true;
    int es_major = 3;  // the context's OpenGL ES version: techniques that need a later one are refused
    std::string command;     // recorded in the results
    int threads = 0;         // recorded: llvmpipe's thread count
    int segments = 64;       // quads per side of each bench plane
    bool exact_view = true;  // false: every technique with the per-vertex normalised view vector
    // Shadowed scenes: each setting at each of these shadow-ray sample counts.
    std::vector<int> shadow_samples{16};
    double light_elevation_deg = 35.0;  // the bench's sun, above the plane (azimuth 30 degrees)
    std::vector<BenchMaterial> materials;  // benched after `scenes`
    // Count the work per pixel (loop iterations, fetches: the work columns)
    // of the linear searches too, not only of the exact walk's: what
    // `--gpu` compiles each search truncated to. One more draw per setting.
    bool count_every_search = false;
    // Every setting's renderer is created with these (the normal-mapping
    // baseline's too, less the variant transform): e.g. a variant transform
    // to time another shader form of the same technique.
    RendererOptions renderer;
};

// Called after each setting: done, total, and what was just measured.
using Progress = std::function<void(int done, int total, const std::string& what)>;

// Needs a current context. `target` is an offscreen colour target of the
// options' size and `read_color` reads it back (render/offscreen_target.h provides both).
Result<BenchRun> run_bench(const BenchOptions& options, const RenderTarget& target,
                           const std::function<Result<Image>()>& read_color, const Progress& progress);

}  // namespace px::profiling
