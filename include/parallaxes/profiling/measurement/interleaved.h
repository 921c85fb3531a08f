// Interleaved timing: two draws compared on the same machine state. Both are
// drawn once to warm them (llvmpipe compiles a shader at its first draw),
// then `rounds` rounds of the first then the second, each timed around
// glFinish. The medians and the median of the per-round ratios (second over
// first) are what bench, showcase and `plan --verify --candidates` report:
// a shared machine's drift moves both draws of a round alike.
#pragma once

#include <functional>
#include <vector>

#include "parallaxes/core/result.h"

namespace px::profiling {

struct InterleavedTimes {
    std::vector<double> first_ms, second_ms, ratios;  // per round
    double first_median_ms = 0.0;
    double second_median_ms = 0.0;
    double ratio_median = 0.0;  // median over the rounds of second / first
};

// Needs a current context. `rounds` >= 1. A draw's error ends the timing.
// `warm`: false where the caller has just drawn both.
Result<InterleavedTimes> time_interleaved(const std::function<Status()>& first, const std::function<Status()>& second,
                                          int rounds, bool warm = true);

// The same for any number of draws: each round draws every one once, in
// order; the result holds each draw's time per round (milliseconds).
Result<std::vector<std::vector<double>>> time_in_rounds(const std::vector<std::function<Status()>>& draws, int rounds,
                                                        bool warm = true);

// The median (the upper one of an even count); 0 for none.
double median_of(std::vector<double> values);

}  // namespace px::profiling
