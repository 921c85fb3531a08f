#include "parallaxes/core/text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace px {

std::string echo(const std::string& value, std::size_t max_bytes) {
    std::string out;
    const std::size_t shown = std::min(value.size(), max_bytes);
    for (std::size_t i = 0; i < shown; ++i) {
        const auto c = static_cast<unsigned char>(value[i]);
        if (c < 0x20 || c == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02x", c);
            out += buf;
        } else {
            out += static_cast<char>(c);
        }
    }
    if (shown < value.size()) out += "... (" + std::to_string(value.size()) + " bytes)";
    return out;
}

std::string fixed_text(double v, int decimals) {
    if (!std::isfinite(v)) return "n/a";
    char b[64];
    std::snprintf(b, sizeof b, "%.*f", decimals, v);
    return b;
}

std::string significant_text(double v, int digits) {
    if (!std::isfinite(v)) return "n/a";
    char b[64];
    std::snprintf(b, sizeof b, "%.*g", digits, v);
    return b;
}

}  // namespace px
