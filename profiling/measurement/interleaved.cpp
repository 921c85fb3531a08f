#include "parallaxes/profiling/measurement/interleaved.h"

#include <algorithm>
#include <chrono>

#include "parallaxes/gl/gl.h"

namespace px::profiling {

double median_of(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
    return values[values.size() / 2];
}

Result<InterleavedTimes> time_interleaved(const std::function<Status()>& first, const std::function<Status()>& second,
                                          int rounds, bool warm) {
    if (rounds < 1) return make_error("timing needs at least one round");
    for (const auto* draw : {&first, &second}) {
        if (!warm) break;
        Status drawn = (*draw)();
        if (!drawn) return drawn.error();
    }
    glFinish();
    using clock = std::chrono::steady_clock;
    const auto ms = [](clock::time_point a, clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    };
    InterleavedTimes out;
    for (int i = 0; i < rounds; ++i) {
        const auto t0 = clock::now();
        Status a = first();
        glFinish();
        const auto t1 = clock::now();
        Status b = second();
        glFinish();
        const auto t2 = clock::now();
        if (!a) return a.error();
        if (!b) return b.error();
        out.first_ms.push_back(ms(t0, t1));
        out.second_ms.push_back(ms(t1, t2));
        out.ratios.push_back(ms(t1, t2) / std::max(ms(t0, t1), 1e-6));
    }
    out.first_median_ms = median_of(out.first_ms);
    out.second_median_ms = median_of(out.second_ms);
    out.ratio_median = median_of(out.ratios);
    return out;
}

}  // namespace px::profiling
