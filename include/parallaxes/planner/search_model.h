// The planner's error model from the relief itself: every candidate search
// (normal mapping, the single-fetch offsets, the linear searches with their
// endings, the exact walk) simulated on the CPU over the material's own
// height field, as the shaders define them (shaders_es/chunks/march.glsl and
// the technique files), against the exact reference (reference/tracer.h),
// at a grid of view angles over many rays and azimuths. What it cannot know
// (the GPU's rasterisation, texture filtering at the pixel's footprint,
// perspective across an image) is covered by a margin fitted on a family
// of reliefs by `parallax bench --search-model` and judged on reliefs it
// was not fitted on (docs/planner.md, "The search model").
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "parallaxes/core/limits.h"
#include "parallaxes/assets/heightfield.h"
#include "parallaxes/effects/technique.h"

namespace px {

// The shares of rays a curve records its error at (kSearchLevels[k]: the
// error that share of the rays stays within). The planner pools them over
// an object's pixels, each at its own angle, into the object's p95 and p97.
inline constexpr int kSearchLevelCount = 10;
inline constexpr double kSearchLevels[kSearchLevelCount] = {0.5, 0.75, 0.85, 0.9, 0.93, 0.95, 0.97, 0.98, 0.99, 1.0};

struct SearchCurve {
    Technique technique = Technique::normal;
    int samples = 0;            // the linear search's count; 0 for the others
    std::vector<double> error;  // simulated p95 hit error (texels of the field) at each angle
    std::vector<double> upper;  // the p97: where a tail of misses starts just past 5 % of the rays
    // Per angle, the error at each of kSearchLevels, over every azimuth.
    std::vector<std::vector<double>> levels;
    // Per angle, per azimuth sector (search_sector), the error at each of
    // kSearchLevels over that sector's rays: a relief of lines seen along
    // them is stepped over far less than one seen across them.
    std::vector<std::vector<std::vector<double>>> sector_levels;
};

// Azimuth sectors: the view's direction in the field's plane, folded by
// both mirror axes (so that neither the sign of the bitangent nor a flipped
// v can put a pixel in the wrong one) into [0, 90] degrees from the field's
// x axis, then cut into kSearchSectors equal parts. Lines along x are seen
// in sector 0, lines along y in the last.
inline constexpr int kSearchSectors = 6;
int search_sector(double view_x, double view_y);

struct SearchModel {
    std::vector<double> angles;  // view angles from the normal, degrees, increasing
    std::vector<SearchCurve> curves;
    int rays = 0;                // per angle and sector
    // The curve of a candidate, or null.
    const SearchCurve* find(Technique technique, int samples) const;
};

struct SearchModelOptions {
    std::vector<double> angles{0, 20, 40, 55, 65, 72, 78, 82, 85, 87, 89};
    std::vector<int> samples = sample_grid();
    int rays = 128;         // per angle and azimuth sector: stratified over the tile, azimuths spread
    int refine_steps = 5;   // relief's binary search (TechniqueOptions' default)
};

// Simulates every candidate on `field` (as the GPU samples it, 8-bit),
// `height_scale` deep in tile units, polygon at `polygon_height` (units of
// the depth). Deterministic. A field of zero size or a flat one gives zero
// error everywhere.
SearchModel simulate_searches(const HeightField& field, double height_scale, double polygon_height,
                              const SearchModelOptions& options = {});

// One ray to simulate: where the pixel meets the polygon (tile units) and
// the unit vector toward the eye in the texture frame (z along the normal).
struct SearchRay {
    glm::dvec2 uv{0.0};
    glm::dvec3 view{0.0, 0.0, 1.0};
    // Where the ray stands for a pixel: its texels per pixel (GL's mip
    // selection scale). Its errors are divided by it where it exceeds 1,
    // into texels of the level sampled; 1 keeps them in the field's texels.
    double texels_per_pixel = 1.0;
};
// Quantiles over `rays` of each candidate's hit error, in the order of
// search_candidates(samples) (texels of the field).
// `quantiles` (default: the p95) give one vector each, in their order.
std::vector<std::vector<double>> simulate_rays(const HeightField& field, double height_scale, double polygon_height,
                                               const std::vector<SearchRay>& rays, const std::vector<int>& samples,
                                               int refine_steps, const std::vector<double>& quantiles = {0.95});
// The candidates simulate_rays measures, in its order (errors left empty).
std::vector<SearchCurve> search_candidates(const std::vector<int>& samples);

// The margin the planner predicts with, in texels of the level sampled:
// the larger of the simulated p95 times `scale` and the simulated p97, plus
// `floor` (what the GPU's rasterisation and filtering add that the
// simulation has no notion of), per technique, fitted by `parallax bench
// --search-model` on the fit reliefs of examples/scenes/relief_family. The
// p97 is the margin's answer to uncertainty: where a tail of misses (a
// search stepping over crests) starts just past 5 % of the rays, the p95 the
// GPU measures may land well above the simulated one.
struct SearchMargin {
    double scale = 1.0;
    double floor = 0.0;
};
SearchMargin search_margin(Technique technique);
inline double predicted_with_margin(Technique technique, double p95, double p97) {
    const SearchMargin m = search_margin(technique);
    const double scaled = p95 * m.scale;
    return (scaled > p97 ? scaled : p97) + m.floor;
}

}  // namespace px
