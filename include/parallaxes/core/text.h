// Quoting values from untrusted input in messages.
#pragma once

#include <cstddef>
#include <string>

#include "parallaxes/core/limits.h"

namespace px {

// A value quoted in a message: at most max_bytes bytes of it, control bytes
// escaped, and "... (N bytes)" when cut, so a hostile 10 MB key or name
// never floods a log. Paths get a longer allowance (echo_path).
std::string echo(const std::string& value, std::size_t max_bytes = kMaxEchoBytes);
inline std::string echo_path(const std::string& path) { return echo(path, kMaxEchoPathBytes); }

// Numbers for reports: `decimals` digits after the point ("0.25"), or
// `digits` significant ones in the shortest form ("0.008031", "1e+06");
// "n/a" for NaN and infinities.
std::string fixed_text(double v, int decimals);
std::string significant_text(double v, int digits);

}  // namespace px
