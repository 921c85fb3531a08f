#include "parallaxes/profiling/measurement/work.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "parallaxes/render/surface_capture.h"

namespace px::profiling {

namespace {

constexpr double kWorkScale = 65536.0;  // surface_main.glsl: px_work / 65536.0 in place of the uv

double nearest_rank(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) return 0.0;
    const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
    return sorted[std::min(sorted.size() - 1, rank > 0 ? rank - 1 : 0)];
}

}  // namespace

std::size_t work_bucket(double iterations) {
    std::size_t b = 0;
    for (double top = 2.0; iterations >= top && b + 1 < WorkStats{}.histogram.size(); top *= 2.0) ++b;
    return b;
}

namespace {

// Pixel i's counts, or an error where they are not whole numbers.
Status read_counts(const SurfaceImage& surfaces, std::size_t i, double& n, double& f) {
    const SurfaceSample& s = surfaces.samples[i];
    n = s.uv.x * kWorkScale;
    f = s.uv.y * kWorkScale;
    if (!(std::fabs(n - std::round(n)) < 1e-3 && std::fabs(f - std::round(f)) < 1e-3 && n >= 0.0 && f >= 0.0)) {
        const auto width = static_cast<std::size_t>(std::max(1, surfaces.width));
        return make_error("work counts: pixel " + std::to_string(i % width) + "," + std::to_string(i / width) +
                          " reads " + std::to_string(n) + " iterations and " + std::to_string(f) +
                          " fetches, not whole numbers: was the renderer made with RendererOptions::count_work?");
    }
    n = std::round(n);
    f = std::round(f);
    return {};
}

}  // namespace

std::vector<double> work_iterations(const SurfaceImage& surfaces) {
    std::vector<double> out(surfaces.samples.size(), -1.0);
    for (std::size_t i = 0; i < surfaces.samples.size(); ++i) {
        if (!surfaces.samples[i].covered) continue;
        double n = 0.0, f = 0.0;
        out[i] = read_counts(surfaces, i, n, f) ? n : std::numeric_limits<double>::quiet_NaN();
    }
    return out;
}

Result<WorkStats> measure_work(Renderer& renderer, int width, int height) {
    Result<SurfaceImage> surfaces = capture_surfaces(renderer, width, height);
    if (!surfaces) return surfaces.error();
    std::vector<double> iterations, fetches;
    for (std::size_t i = 0; i < surfaces->samples.size(); ++i) {
        if (!surfaces->samples[i].covered) continue;
        double n = 0.0, f = 0.0;
        if (Status s = read_counts(*surfaces, i, n, f); !s) return s.error();
        iterations.push_back(n);
        fetches.push_back(f);
    }
    WorkStats w;
    w.pixels = iterations.size();
    for (double n : iterations) ++w.histogram[work_bucket(n)];
    std::sort(iterations.begin(), iterations.end());
    std::sort(fetches.begin(), fetches.end());
    w.iterations_median = nearest_rank(iterations, 0.5);
    w.iterations_p90 = nearest_rank(iterations, 0.9);
    w.iterations_p99 = nearest_rank(iterations, 0.99);
    w.iterations_max = iterations.empty() ? 0.0 : iterations.back();
    w.fetches_median = nearest_rank(fetches, 0.5);
    w.fetches_p99 = nearest_rank(fetches, 0.99);
    return w;
}

}  // namespace px::profiling
