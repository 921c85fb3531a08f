// A texture as a file holds it: one format, every mip level as given (never
// regenerated), array layers and cube faces where the container has them.
// The bytes of each image are exactly what glCompressedTexImage2D (or
// glTexImage2D, rows tightly packed) takes for it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/texture/format.h"

namespace px {

// Array layers a texture may have (allocate_texture, the readers, the writers).
inline constexpr std::uint32_t kMaxTextureLayers = 2048;

enum class ContainerKind : std::uint8_t { ktx1, ktx2, pvr3, image };

const char* container_name(ContainerKind kind);  // "KTX 1.1", "KTX 2.0", "PVR v3", "image"

struct TextureLevel {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::size_t image_bytes = 0;  // one image (one layer, one face) of this level
    std::size_t offset = 0;       // of (layer 0, face 0) in TextureData::bytes
};

struct TextureData {
    ContainerKind container = ContainerKind::image;
    TextureFormat format = TextureFormat::rgba8;
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::uint32_t layers = 1;  // array layers (1: not an array)
    std::uint32_t faces = 1;   // 6: a cube map
    std::string supercompression;  // KTX 2.0: "none" or "zstd"; empty elsewhere
    std::vector<TextureLevel> levels;
    // Per level: layers * faces images of levels[i].image_bytes, layer-major
    // (layer 0 faces 0..5, layer 1 ...).
    std::vector<std::uint8_t> bytes;

    std::size_t total_bytes() const { return bytes.size(); }
    const std::uint8_t* image(std::size_t level, std::uint32_t layer = 0, std::uint32_t face = 0) const {
        const TextureLevel& l = levels[level];
        return bytes.data() + l.offset + (static_cast<std::size_t>(layer) * faces + face) * l.image_bytes;
    }
};

// Lays out levels and sizes `bytes` for a format and base size: `level_count`
// levels of the chain (1..full_mip_count), each image sized by the block
// arithmetic. Errors: zero or oversized extents, more levels than the chain,
// or a total past max_bytes (all checked before the allocation).
// Whether `t` is laid out exactly as above (what the writers take): levels
// of the chain with the block arithmetic's sizes, contiguous, and bytes
// their sum. Errors say what differs.
Status check_texture_layout(const TextureData& t);

// "0x1A2B": format codes in messages.
std::string hex_code(std::uint64_t v);

Result<TextureData> allocate_texture(TextureFormat format, std::uint32_t width, std::uint32_t height,
                                     int level_count, std::uint32_t layers, std::uint32_t faces,
                                     std::uint64_t max_bytes);

}  // namespace px
