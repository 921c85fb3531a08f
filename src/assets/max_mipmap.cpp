#include "parallaxes/assets/max_mipmap.h"

#include "parallaxes/core/numeric.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace px {

namespace {

Image level_image(int width, int height, int channels) {
    Image img;
    img.width = width;
    img.height = height;
    img.channels = channels;
    img.pixels.assign(static_cast<size_t>(width) * height * channels, 0);
    return img;
}

}  // namespace

int MaxMipmap::max_value(int level, long long x, long long y) const {
    const Image& img = levels[static_cast<size_t>(level)];
    const std::uint8_t* t = img.texel(wrap_index(x, img.width), wrap_index(y, img.height));
    return bits == 11 ? t[0] * 256 + t[1] : t[0];
}

std::uint8_t MaxMipmap::max_byte(int level, long long x, long long y) const {
    return static_cast<std::uint8_t>(std::min(max_value(level, x, y), 255));
}

float MaxMipmap::max_height(int level, long long x, long long y) const {
    return static_cast<float>(max_value(level, x, y)) / (bits == 11 ? 2047.0f : 255.0f);
}

Result<MaxMipmap> build_max_mipmap(const HeightField& field, int bits) {
    if (bits != 8 && bits != 11) return make_error("max mipmap: " + std::to_string(bits) + "-bit heights (8 or 11)");
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
    const double scale = bits == 11 ? 2047.0 : 255.0;
    std::vector<int> q(field.texels.size());
    for (size_t i = 0; i < q.size(); ++i) {
        const double v = field.texels[i];
        q[i] = !(v > 0.0) ? 0 : static_cast<int>(std::lround(std::min(v, 1.0) * scale));
    }
    const auto texel = [&](int x, int y) { return q[static_cast<size_t>(y % h) * w + x % w]; };
    const int channels = bits == 11 ? 2 : 1;
    // 11-bit maxima in two 8-bit channels (R = v >> 8, G = v & 255): the
    // shader reads each exactly, as it does 8-bit ones.
    const auto store = [&](Image& img, int x, int y, int v) {
        std::uint8_t* t = img.texel(x, y);
        if (channels == 1) {
            t[0] = static_cast<std::uint8_t>(v);
        } else {
            t[0] = static_cast<std::uint8_t>(v >> 8);
            t[1] = static_cast<std::uint8_t>(v & 255);
        }
    };
    const auto load = [&](const Image& img, int x, int y) {
        const std::uint8_t* t = img.texel(x, y);
        return channels == 1 ? int{t[0]} : t[0] * 256 + t[1];
    };

    MaxMipmap m;
    m.width = w;
    m.height = h;
    m.bits = bits;
    // Level 0: the max of each cell's four corners bounds its bilinear patch.
    Image base = level_image(w, h, channels);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            store(base, x, y, std::max({texel(x, y), texel(x + 1, y), texel(x, y + 1), texel(x + 1, y + 1)}));
    m.levels.push_back(std::move(base));

    // Level k: the max of its children (two of them per axis until that axis is 1).
    while (m.levels.back().width > 1 || m.levels.back().height > 1) {
        const Image& prev = m.levels.back();
        const int cw = std::max(1, prev.width / 2);
        const int ch = std::max(1, prev.height / 2);
        const int fx = prev.width > 1 ? 2 : 1;
        const int fy = prev.height > 1 ? 2 : 1;
        Image next = level_image(cw, ch, channels);
        for (int y = 0; y < ch; ++y)
            for (int x = 0; x < cw; ++x) {
                int v = 0;
                for (int dy = 0; dy < fy; ++dy)
                    for (int dx = 0; dx < fx; ++dx) v = std::max(v, load(prev, x * fx + dx, y * fy + dy));
                store(next, x, y, v);
            }
        m.levels.push_back(std::move(next));
    }
    return m;
}

AtlasOrigin max_atlas_origin(int width, int height, int level) {
    AtlasOrigin o;
    o.x = width;
    for (int j = 1; j < level; ++j) o.y += std::max(1, height >> j);
    return o;
}

Result<MaxAtlas> build_max_atlas(const HeightField& field) {
    Result<MaxMipmap> pyramid = build_max_mipmap(field, 8);
    if (!pyramid) return pyramid.error();
    const int w = pyramid->width, h = pyramid->height;
    const int top = pyramid->level_count() - 1;
    const AtlasOrigin last = max_atlas_origin(w, h, top);
    MaxAtlas atlas;
    atlas.levels = pyramid->level_count();
    atlas.image = level_image(w + std::max(1, w / 2), std::max(h, top >= 1 ? last.y + 1 : 1), 4);
    const auto byte = [&](int x, int y) {
        const double v = field.texels[static_cast<size_t>(wrap_index(y, h)) * w + wrap_index(x, w)];
        return static_cast<std::uint8_t>(!(v > 0.0) ? 0 : std::lround(std::min(v, 1.0) * 255.0));
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::uint8_t* t = atlas.image.texel(x, y);
            t[0] = byte(x, y);
            t[1] = byte(x + 1, y);
            t[2] = byte(x, y + 1);
            t[3] = byte(x + 1, y + 1);
        }
    for (int level = 1; level <= top; ++level) {
        const Image& src = pyramid->levels[static_cast<size_t>(level)];
        const AtlasOrigin o = max_atlas_origin(w, h, level);
        for (int y = 0; y < src.height; ++y)
            for (int x = 0; x < src.width; ++x) atlas.image.texel(o.x + x, o.y + y)[0] = src.texel(x, y)[0];
    }
    return atlas;
}

}  // namespace px
