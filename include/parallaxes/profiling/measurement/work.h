// Work per pixel of a search: its loop iterations and texture fetches,
// counted by the shader itself (VariantKey::count_work, PX_COUNT_WORK in
// shaders_es/chunks/surface_common.glsl) and read back through the debug
// outputs (px_work / 65536 in place of the hit uv: exact in the float pass
// and in the 24-bit packing), so the
// counts are those of the shipped walk, not of a CPU model of it. For
// `parallax bench`'s work columns (why the exact walk costs what it does).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/core/surface_image.h"
#include "parallaxes/render/renderer.h"

namespace px::profiling {

struct WorkStats {
    std::size_t pixels = 0;  // drawn
    // Percentiles over drawn pixels (nearest rank).
    double iterations_median = 0.0, iterations_p90 = 0.0, iterations_p99 = 0.0, iterations_max = 0.0;
    double fetches_median = 0.0, fetches_p99 = 0.0;
    // Pixels per iteration count in powers of two: [0] 0-1, [1] 2-3, [2] 4-7, ... [12] 4096+.
    std::array<std::size_t, 13> histogram{};
};

// Draws the loaded scene (whose renderer was made with
// RendererOptions::count_work) and counts. Errors: a count that is not a
// whole number (the renderer was made without count_work, or the read-back
// lost it).
Result<WorkStats> measure_work(Renderer& renderer, int width, int height);

// Each pixel's counted loop iterations from a capture of a count_work
// renderer (row 0 = bottom), -1 where nothing was drawn, NaN where the
// pixel holds no whole counts (its variant counts no work: only the
// searches do, VariantKey::count_work).
std::vector<double> work_iterations(const SurfaceImage& surfaces);

// The bucket of `iterations` in WorkStats::histogram.
std::size_t work_bucket(double iterations);

}  // namespace px::profiling
