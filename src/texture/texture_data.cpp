#include "parallaxes/texture/texture_data.h"

#include "parallaxes/core/limits.h"

namespace px {

const char* row_order_name(RowOrder rows) {
    return rows == RowOrder::top_first ? "top row first" : "bottom row first";
}

const char* container_name(ContainerKind kind) {
    switch (kind) {
    case ContainerKind::ktx1: return "KTX 1.1";
    case ContainerKind::ktx2: return "KTX 2.0";
    case ContainerKind::pvr3: return "PVR v3";
    case ContainerKind::image: return "image";
    case ContainerKind::astc: return ".astc";
    }
    return "image";
}

std::string hex_code(std::uint64_t v) {
    static const char* digits = "0123456789ABCDEF";
    std::string s;
    do {
        s.insert(s.begin(), digits[v & 15]);
        v >>= 4;
    } while (v);
    return "0x" + s;
}

Status check_texture_layout(const TextureData& t) {
    const auto num = [](std::uint64_t v) { return std::to_string(v); };
    if (t.levels.empty()) return make_error("the texture has no levels");
    const std::uint32_t max = static_cast<std::uint32_t>(kMaxTextureSize);
    if (t.width == 0 || t.height == 0 || t.width > max || t.height > max)
        return make_error("size " + num(t.width) + "x" + num(t.height) + " is outside 1.." + num(max));
    if (t.levels.size() > static_cast<std::size_t>(full_mip_count(t.width, t.height)))
        return make_error(num(t.levels.size()) + " levels is more than the full chain");
    if (t.layers == 0 || t.layers > kMaxTextureLayers) return make_error(num(t.layers) + " layers");
    if (t.faces != 1 && t.faces != 6) return make_error(num(t.faces) + " faces (1 or 6)");
    std::uint64_t offset = 0;
    for (std::size_t i = 0; i < t.levels.size(); ++i) {
        const TextureLevel& l = t.levels[i];
        const int li = static_cast<int>(i);
        const auto one = image_bytes(t.format, l.width, l.height);
        if (l.width != mip_extent(t.width, li) || l.height != mip_extent(t.height, li) || !one ||
            *one != l.image_bytes || l.offset != offset)
            return make_error("level " + num(i) + " (" + num(l.width) + "x" + num(l.height) + ", " +
                              num(l.image_bytes) + " bytes at " + num(l.offset) +
                              ") does not match the layout of the format and base size");
        offset += *one * t.layers * t.faces;
    }
    if (offset != t.bytes.size())
        return make_error("the texture holds " + num(t.bytes.size()) + " bytes; its levels need " + num(offset));
    return {};
}

Result<TextureData> allocate_texture(TextureFormat format, std::uint32_t width, std::uint32_t height,
                                     int level_count, std::uint32_t layers, std::uint32_t faces,
                                     std::uint64_t max_bytes) {
    if (width == 0 || height == 0)
        return make_error("size " + std::to_string(width) + "x" + std::to_string(height) + " has a zero side");
    if (width > static_cast<std::uint32_t>(kMaxTextureSize) || height > static_cast<std::uint32_t>(kMaxTextureSize))
        return make_error("size " + std::to_string(width) + "x" + std::to_string(height) + " is larger than " +
                          std::to_string(kMaxTextureSize) + " texels per side");
    const int chain = full_mip_count(width, height);
    if (level_count < 1 || level_count > chain)
        return make_error(std::to_string(level_count) + " mip levels for a " + std::to_string(width) + "x" +
                          std::to_string(height) + " texture (a full chain has " + std::to_string(chain) + ")");
    if (layers == 0 || layers > kMaxTextureLayers)
        return make_error(std::to_string(layers) + " array layers (1.." + std::to_string(kMaxTextureLayers) + ")");
    if (faces != 1 && faces != 6) return make_error(std::to_string(faces) + " faces (1 or 6)");
    TextureData t;
    t.format = format;
    t.width = width;
    t.height = height;
    t.layers = layers;
    t.faces = faces;
    std::uint64_t total = 0;
    for (int i = 0; i < level_count; ++i) {
        TextureLevel l;
        l.width = mip_extent(width, i);
        l.height = mip_extent(height, i);
        const auto one = image_bytes(format, l.width, l.height);
        if (!one) return make_error("level " + std::to_string(i) + " size does not fit");
        l.image_bytes = static_cast<std::size_t>(*one);
        l.offset = static_cast<std::size_t>(total);
        // one <= 2^28 (4096^2 * 16), layers * faces <= 12288: no overflow.
        total += *one * layers * faces;
        if (total > max_bytes)
            return make_error("the texture needs " + std::to_string(total) + "+ bytes, more than the " +
                              std::to_string(max_bytes) + " allowed");
        t.levels.push_back(l);
    }
    t.bytes.assign(static_cast<std::size_t>(total), 0);
    return t;
}

}  // namespace px
