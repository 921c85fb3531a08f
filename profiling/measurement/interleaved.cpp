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

Result<std::vector<std::vector<double>>> time_in_rounds(const std::vector<std::function<Status()>>& draws, int rounds,
                                                        bool warm) {
    if (rounds < 1) return make_error("timing needs at least one round");
    for (const auto& draw : draws) {
        if (!warm) break;
        Status drawn = draw();
        if (!drawn) return drawn.error();
    }
    glFinish();
    using clock = std::chrono::steady_clock;
    std::vector<std::vector<double>> times(draws.size());
    for (int i = 0; i < rounds; ++i) {
        for (std::size_t d = 0; d < draws.size(); ++d) {
            const auto start = clock::now();
            Status drawn = draws[d]();
            glFinish();
            times[d].push_back(std::chrono::duration<double, std::milli>(clock::now() - start).count());
            if (!drawn) return drawn.error();
        }
    }
    return times;
}

Result<InterleavedTimes> time_interleaved(const std::function<Status()>& first, const std::function<Status()>& second,
                                          int rounds, bool warm) {
    Result<std::vector<std::vector<double>>> times = time_in_rounds({first, second}, rounds, warm);
    if (!times) return times.error();
    InterleavedTimes out;
    out.first_ms = (*times)[0];
    out.second_ms = (*times)[1];
    for (std::size_t i = 0; i < out.first_ms.size(); ++i) out.ratios.push_back(out.second_ms[i] / std::max(out.first_ms[i], 1e-6));
    out.first_median_ms = median_of(out.first_ms);
    out.second_median_ms = median_of(out.second_ms);
    out.ratio_median = median_of(out.ratios);
    return out;
}

}  // namespace px::profiling
