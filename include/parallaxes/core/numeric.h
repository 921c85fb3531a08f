// Small numeric helpers that several layers need, one copy each: 8-bit
// quantisation as a unorm8 upload does it, power-of-two tests, index
// wrapping for GL_REPEAT, GL_LINEAR's bilinear taps, and pi.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstddef>
#include <vector>

#include <glm/gtc/constants.hpp>

namespace px {

template <typename T>
constexpr T kPi = glm::pi<T>();

// A value in [0, 1] as the 8-bit unorm texel that an RGBA8 upload stores:
// clamped, then rounded to the nearest of 256 levels (NaN gives 0).
inline std::uint8_t to_unorm8(double unit) {
    if (!(unit > 0.0)) return 0;
    return static_cast<std::uint8_t>(std::lround(std::min(unit, 1.0) * 255.0));
}
// The same level read back as a normalised value (byte / 255).
inline double quantize_unorm8(double unit) { return to_unorm8(unit) / 255.0; }

constexpr bool is_power_of_two(long long v) { return v > 0 && (v & (v - 1)) == 0; }

// Index wrapping for GL_REPEAT: the result is in [0, n) for any i (n > 0).
inline int wrap_index(long long i, int n) {
    const long long r = i % n;
    return static_cast<int>(r < 0 ? r + n : r);
}

// GL_LINEAR with GL_REPEAT on a w x h texture (ES 3.0 spec, 3.8.10): the four
// texels around (u, v) and the weights between them. Texel space minus 0.5
// puts texel centres on integers; the lower index is the floor, the weight
// the fraction, and both indices wrap independently.
struct BilinearTaps {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    double ax = 0.0, ay = 0.0;  // weight of x1 and y1
};
inline BilinearTaps bilinear_taps(double u, double v, int w, int h) {
    BilinearTaps t;
    const double tx = u * w - 0.5;
    const double ty = v * h - 0.5;
    const double fx = std::floor(tx);
    const double fy = std::floor(ty);
    t.ax = tx - fx;
    t.ay = ty - fy;
    // Reduced before converting, so that huge coordinates cannot overflow.
    t.x0 = wrap_index(static_cast<long long>(std::fmod(fx, static_cast<double>(w))), w);
    t.y0 = wrap_index(static_cast<long long>(std::fmod(fy, static_cast<double>(h))), h);
    t.x1 = t.x0 + 1 == w ? 0 : t.x0 + 1;
    t.y1 = t.y0 + 1 == h ? 0 : t.y0 + 1;
    return t;
}

// Reverses the order of the rows of a width x height image of `channels`
// values per texel, in place: top-row-first data to the library's order
// (row 0 at v = 0) and back.
template <typename T>
void reverse_rows(std::vector<T>& texels, std::size_t width, std::size_t height, std::size_t channels) {
    const std::size_t row = width * channels;
    for (std::size_t y = 0; y < height / 2; ++y)
        std::swap_ranges(texels.begin() + static_cast<std::ptrdiff_t>(row * y),
                         texels.begin() + static_cast<std::ptrdiff_t>(row * (y + 1)),
                         texels.begin() + static_cast<std::ptrdiff_t>(row * (height - 1 - y)));
}

}  // namespace px
