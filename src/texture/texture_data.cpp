#include "texture/texture_data.h"

#include "core/limits.h"

namespace px {

const char* container_name(ContainerKind kind) {
    switch (kind) {
    case ContainerKind::ktx1: return "KTX 1.1";
    case ContainerKind::ktx2: return "KTX 2.0";
    case ContainerKind::pvr3: return "PVR v3";
    case ContainerKind::image: return "image";
    }
    return "image";
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
    if (layers == 0 || layers > 2048) return make_error(std::to_string(layers) + " array layers (1..2048)");
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
