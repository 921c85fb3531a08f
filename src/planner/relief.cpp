#include "parallaxes/planner/relief.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace px {

namespace {

// The shortest run of `above` values along one line of n texels that wraps
// (GL_REPEAT): runs are bounded by changes; a line with no change has none.
int shortest_run(const std::vector<char>& above, int n) {
    int start = -1;
    for (int i = 0; i < n; ++i)
        if (above[static_cast<size_t>(i)] != above[static_cast<size_t>((i + n - 1) % n)]) {
            start = i;
            break;
        }
    if (start < 0) return std::numeric_limits<int>::max();
    int best = std::numeric_limits<int>::max(), run = 0;
    for (int k = 0; k < n; ++k) {
        const int i = (start + k) % n;
        if (k > 0 && above[static_cast<size_t>(i)] != above[static_cast<size_t>((i + n - 1) % n)]) {
            best = std::min(best, run);
            run = 0;
        }
        ++run;
    }
    return std::min(best, run);
}

}  // namespace

ReliefFeatures measure_relief(const HeightField& field, double height_scale) {
    ReliefFeatures f;
    f.width = field.width;
    f.height = field.height;
    if (field.width < 1 || field.height < 1 || field.texels.size() != static_cast<size_t>(field.width) * field.height)
        return f;
    std::uint64_t hash = 1469598103934665603ull;
    auto mix = [&hash](std::uint64_t byte) {
        hash ^= byte;
        hash *= 1099511628211ull;
    };
    for (int shift = 0; shift < 32; shift += 8) mix((static_cast<std::uint32_t>(field.width) >> shift) & 0xFF);
    for (int shift = 0; shift < 32; shift += 8) mix((static_cast<std::uint32_t>(field.height) >> shift) & 0xFF);
    float lo = 1.0f, hi = 0.0f;
    for (float h : field.texels) {
        lo = std::min(lo, h);
        hi = std::max(hi, h);
        mix(static_cast<std::uint64_t>(std::lround(std::clamp(h, 0.0f, 1.0f) * 255.0f)));
    }
    f.field_hash = hash;
    f.range = std::max(0.0, static_cast<double>(hi) - lo);
    f.depth_texels = std::max(0.0, height_scale) * field.width * f.range;
    if (f.range <= 0.0) {
        f.thinnest_texels = std::max(field.width, field.height);
        return f;
    }
    double rise = 0.0;
    for (int y = 0; y < field.height; ++y)
        for (int x = 0; x < field.width; ++x) {
            const float h = field.at(x, y);
            rise = std::max(rise, static_cast<double>(std::fabs(field.at(x + 1, y) - h)));
            rise = std::max(rise, static_cast<double>(std::fabs(field.at(x, y + 1) - h)));
        }
    f.steepness = rise / f.range;
    // Features: runs above and below the mid level, along rows and columns.
    const float mid = 0.5f * (lo + hi);
    int thinnest = std::numeric_limits<int>::max();
    std::vector<char> line(static_cast<size_t>(std::max(field.width, field.height)));
    for (int y = 0; y < field.height; ++y) {
        for (int x = 0; x < field.width; ++x) line[static_cast<size_t>(x)] = field.at(x, y) > mid;
        thinnest = std::min(thinnest, shortest_run(line, field.width));
    }
    for (int x = 0; x < field.width; ++x) {
        for (int y = 0; y < field.height; ++y) line[static_cast<size_t>(y)] = field.at(x, y) > mid;
        thinnest = std::min(thinnest, shortest_run(line, field.height));
    }
    f.thinnest_texels = thinnest == std::numeric_limits<int>::max() ? std::max(field.width, field.height) : thinnest;
    return f;
}

std::string describe(const ReliefFeatures& f) {
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, "depth %.3g texels, steepness %.2f, thinnest %.3g texel%s", f.depth_texels,
                  f.steepness, f.thinnest_texels, f.thinnest_texels == 1.0 ? "" : "s");
    return buffer;
}

std::string hash_hex(std::uint64_t hash) {
    char buffer[20];
    std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(hash));
    return buffer;
}

}  // namespace px
