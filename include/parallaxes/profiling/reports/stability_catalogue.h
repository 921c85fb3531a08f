// The hard-case catalogue behind `parallax stability` and the stability
// tests: grazing and edge-on views, thin features, steps, huge tiled uvs,
// mirrored frames, far and LOD-blended surfaces, each run for every
// technique, and judged on what the shader computed (its debug outputs):
// no NaN or Inf, the uv offset within the bound the technique promises, the
// hit error against the exact reference within the technique's derived
// bound, and continuity along camera sweeps. The cases live in one file
// (tests/stability/catalogue.jsonc, embedded in the program); each bound is
// derived in that file's comments and computed per pixel here.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "parallaxes/core/result.h"
#include "parallaxes/scene/scene.h"

namespace px::profiling {

// How a technique's per-pixel bound is computed from the pixel's exact view
// vector V (unit, texture frame), the relief depth s (tile units), the
// polygon height p (0..1), the texture size and the search's sample count N
// and refinement steps R. P = s |V.xy| / max(V.z, 1/64), in texels: the
// length of the whole parallax vector from the relief's top to its bottom.
enum class BoundKind {
    zero,          // 0
    limited,       // s |V.xy| max(p, 1 - p): offset limiting's promise
    parallax,      // P max(p, 1 - p) for offsets; P for errors
    step,          // P / N: one step of the linear search
    refined_step,  // P / (N 2^R): one step after R halvings
    exact,         // 0: an exact technique (rounding only, covered by the slack)
};

struct TechniqueBounds {
    BoundKind error = BoundKind::parallax;
    BoundKind offset = BoundKind::parallax;
};

struct CatalogueBounds {
    double slack_texels = 0.05;            // absolute, added to every per-pixel bound
    double offset_relative_slack = 0.02;   // relative, on offset bounds
    double violation_share = 0.01;         // share of pixels allowed past a per-pixel bound
    double crest_flip_height = 0.5;        // reference height change that marks a crest flip (continuity)
    std::map<std::string, TechniqueBounds> techniques;  // by technique name
};

struct StabilityCase {
    std::string name;
    std::string why;
    FieldSpec field;
    std::optional<int> image_width, image_height;  // a non-square / NPOT height image (written to a file)
    float height_scale = 0.08f;
    std::optional<float> height_bias;
    std::vector<double> angles{60.0};      // frames: one case per angle unless `sweep`
    bool sweep = false;                    // the angles are one sweep, judged on continuity
    std::vector<double> distances;         // a distance sweep (overrides `distance`), judged on continuity
    double distance = 2.2;
    double azimuth_deg = 0.0;              // the camera's turn about the normal (0: looking along +y)
    std::optional<glm::vec3> camera_position, camera_target;  // explicit camera (overrides angle/distance)
    float fov_deg = 45.0f;
    float plane_size = 2.4f;
    int segments = 16;
    int samples = 32;                      // min = max: the sample axis is exact
    int refine_steps = 5;
    float light_elevation_deg = 35.0f, light_azimuth_deg = 30.0f;
    ShadowMode shadow = ShadowMode::none;
    UvTransform uv;
    glm::vec3 model_scale{1.0f};
    std::optional<glm::vec3> tangent, normal;  // the plane's authored vertex frame (degenerate on purpose)
    bool lod = false;
    float lod_threshold = 3.0f, lod_band = 1.0f;
    std::optional<bool> exact_view;        // unset: the technique's default
    std::vector<std::string> techniques;   // empty: every technique
    std::map<std::string, std::string> limits;  // technique -> the documented limit this case shows
    bool expect_dark = false;              // every covered pixel's first-light visibility must be 0
    bool full_only = false;                // only with --full
    int quick_stride = 1;                  // without --full, every k-th frame of a sweep
};

struct Catalogue {
    CatalogueBounds bounds;
    std::vector<StabilityCase> cases;
};

// The catalogue embedded at build time (tests/stability/catalogue.jsonc).
const std::string& embedded_catalogue_text();
// Parses catalogue text; `origin` names it in errors, which give the JSON
// path of the offending field.
Result<Catalogue> parse_catalogue(const std::string& text, const std::string& origin);

struct StabilityRow {
    std::string case_name;
    std::string technique;
    std::string context;    // "es2" or "es3": the variant's shading language
    std::string precision;  // "native" (the driver, declarations in force) or an emulated profile
    long pixels = 0;        // covered in both the GPU's output and the reference, summed over frames
    long non_finite = 0;    // pixels with NaN or Inf in what the shader computed
    double error_max = 0.0, error_mean = 0.0;  // hit-uv error, texels
    double error_bound_mean = 0.0;             // mean of the per-pixel error bound
    double error_violations = 0.0;             // share of pixels past their error bound
    // The nominal bound: the technique's own promise (P / N for a search),
    // without what its samples allow where a feature lies between two of
    // them. Missing it is the technique's limit: documented in the case, or
    // a failure until it is.
    double nominal_bound_mean = 0.0;
    double nominal_violations = 0.0;
    double offset_ratio_max = 0.0;             // max over pixels of |offset| / its bound (<= 1 holds)
    long offset_violations = 0;                // pixels past their offset bound
    double continuity_max = -1.0;              // sweeps: max |change of error| between neighbours, texels; -1: none
    double continuity_violations = 0.0;        // share of compared pixels past their continuity bound
    long crest_flips = 0;                      // sweep pixels left out: the reference itself jumps there
    double dark_max = -1.0;                    // expect_dark: max visibility seen; -1: not asked
    // The exact tracer where the context reads floats back (ES 3.0, native):
    // its hit error against the exact trace of the ray each pixel was handed
    // (the fragment's fp32 uv and parallax vector, read back), judged in
    // place of the camera-ray figures above, which stay what is shown. The
    // bound's fp32 terms assume the rasteriser's inputs are a few ulps off
    // the camera's exact ray; a GPU's are further off (a fraction of a
    // pixel's footprint), and a ray running along a ridge turns that into
    // texels of hit (docs/exact_tracing.md). The walk's promise is about the
    // ray it is handed. own_error_mean -1: not measured, judged on the
    // camera's rays.
    double own_error_mean = -1.0, own_error_max = 0.0;
    double own_violations = 0.0, own_nominal_violations = 0.0;
    std::string verdict;                       // "pass", "fail", "limit" (a documented limit showed), "n/a"
    std::string reasons;                       // why it failed, or the limit
};

// Judges one row from its measurements (exposed for tests).
void judge(StabilityRow& row, const CatalogueBounds& bounds, const StabilityCase& c);

std::string format_table(const std::vector<StabilityRow>& rows);
std::string format_markdown(const std::vector<StabilityRow>& rows, const std::string& command);
std::string format_json(const std::vector<StabilityRow>& rows);

bool glob_match(const std::string& pattern, const std::string& text);

}  // namespace px::profiling
