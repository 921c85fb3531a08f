#include "parallaxes/assets/color.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace px {

double srgb_to_linear(double e) {
    e = std::clamp(e, 0.0, 1.0);
    return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
}

double linear_to_srgb(double l) {
    l = std::clamp(l, 0.0, 1.0);
    return l <= 0.0031308 ? l * 12.92 : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
}

std::uint8_t linear_to_srgb8(double l) {
    return static_cast<std::uint8_t>(std::lround(linear_to_srgb(l) * 255.0));
}

namespace {

const std::array<double, 256>& decoded_bytes() {
    static const std::array<double, 256> table = [] {
        std::array<double, 256> t{};
        for (int i = 0; i < 256; ++i) t[static_cast<std::size_t>(i)] = srgb_to_linear(i / 255.0);
        return t;
    }();
    return table;
}

}  // namespace

Image next_mip_level(const Image& rgba, bool srgb) {
    Image out;
    out.width = std::max(1, rgba.width / 2);
    out.height = std::max(1, rgba.height / 2);
    out.channels = rgba.channels;
    out.pixels.resize(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height) *
                      static_cast<std::size_t>(out.channels));
    const auto& decoded = decoded_bytes();
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            // The sources: 2x2, widened to take an odd side's last texel.
            const int x0 = 2 * x, y0 = 2 * y;
            const int x1 = std::min(rgba.width - 1, x == out.width - 1 ? rgba.width - 1 : x0 + 1);
            const int y1 = std::min(rgba.height - 1, y == out.height - 1 ? rgba.height - 1 : y0 + 1);
            for (int c = 0; c < rgba.channels; ++c) {
                double sum = 0.0;
                int n = 0;
                for (int sy = y0; sy <= y1; ++sy)
                    for (int sx = x0; sx <= x1; ++sx) {
                        const std::uint8_t v = rgba.texel(sx, sy)[c];
                        sum += srgb && c < 3 ? decoded[v] : v / 255.0;
                        ++n;
                    }
                const double mean = sum / n;
                out.texel(x, y)[c] = srgb && c < 3 ? linear_to_srgb8(mean)
                                                   : static_cast<std::uint8_t>(std::lround(mean * 255.0));
            }
        }
    return out;
}

}  // namespace px
