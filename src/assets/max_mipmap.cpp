#include "assets/max_mipmap.h"

#include "core/numeric.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace px {

namespace {

Image single_channel(int width, int height) {
    Image img;
    img.width = width;
    img.height = height;
    img.channels = 1;
    img.pixels.assign(static_cast<size_t>(width) * height, 0);
    return img;
}

}  // namespace

std::uint8_t MaxMipmap::max_byte(int level, long long x, long long y) const {
    const Image& img = levels[static_cast<size_t>(level)];
    return img.texel(wrap_index(x, img.width), wrap_index(y, img.height))[0];
}

float MaxMipmap::max_height(int level, long long x, long long y) const {
    return static_cast<float>(max_byte(level, x, y)) / 255.0f;
}

Result<MaxMipmap> build_max_mipmap(const HeightField& field) {
    const std::string size = std::to_string(field.width) + "x" + std::to_string(field.height);
    if (field.width < 1 || field.height < 1) return make_error("max mipmap: empty height field (" + size + ")");
    if (!is_power_of_two(field.width) || !is_power_of_two(field.height))
        return make_error("max mipmap: height field size " + size +
                          " is not a power of two in both width and height (the quadtree halves every "
                          "level exactly); resize the field");
    if (field.texels.size() != static_cast<size_t>(field.width) * field.height)
        return make_error("max mipmap: height field " + size + " holds " + std::to_string(field.texels.size()) +
                          " texels");

    const int w = field.width;
    const int h = field.height;
    std::vector<std::uint8_t> q(field.texels.size());
    for (size_t i = 0; i < q.size(); ++i) q[i] = to_unorm8(field.texels[i]);
    const auto texel = [&](int x, int y) { return q[static_cast<size_t>(y % h) * w + x % w]; };

    MaxMipmap m;
    m.width = w;
    m.height = h;
    // Level 0: the max of each cell's four corners bounds its bilinear patch.
    Image base = single_channel(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            base.texel(x, y)[0] = std::max({texel(x, y), texel(x + 1, y), texel(x, y + 1), texel(x + 1, y + 1)});
    m.levels.push_back(std::move(base));

    // Level k: the max of its children (two of them per axis until that axis is 1).
    while (m.levels.back().width > 1 || m.levels.back().height > 1) {
        const Image& prev = m.levels.back();
        const int cw = std::max(1, prev.width / 2);
        const int ch = std::max(1, prev.height / 2);
        const int fx = prev.width > 1 ? 2 : 1;
        const int fy = prev.height > 1 ? 2 : 1;
        Image next = single_channel(cw, ch);
        for (int y = 0; y < ch; ++y)
            for (int x = 0; x < cw; ++x) {
                std::uint8_t v = 0;
                for (int dy = 0; dy < fy; ++dy)
                    for (int dx = 0; dx < fx; ++dx) v = std::max(v, prev.texel(x * fx + dx, y * fy + dy)[0]);
                next.texel(x, y)[0] = v;
            }
        m.levels.push_back(std::move(next));
    }
    return m;
}

}  // namespace px
