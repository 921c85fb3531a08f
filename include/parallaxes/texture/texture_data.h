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

// astc: astcenc's own .astc file (a 16-byte header, then the blocks).
enum class ContainerKind : std::uint8_t { ktx1, ktx2, pvr3, image, astc };

const char* container_name(ContainerKind kind);  // "KTX 1.1", "KTX 2.0", "PVR v3", "image", ".astc"

// What a container's header says (texture/containers.h read_texture_shape).
struct TextureShape {
    ContainerKind container = ContainerKind::image;
    TextureFormat format{};
    std::uint32_t width = 0, height = 0, layers = 1, faces = 1, levels = 1;
    std::uint64_t bytes = 0;  // decoded: every level, layer and face
};

// Which stored row is the top of the image. The field's tools store the top
// row first (PVRTexToolCLI and crunch declare KTXorientation "S=r,T=d", KTX
// 2.0 files "rd", PVR v3 metadata "y down"; astcenc and basisu declare
// nothing, and their own decoders show the first row at the top), and so
// does this library's writer. OpenGL samples the first stored row at t = 0,
// the bottom of the uv square: the renderer flips v for top-first data
// (docs/textures.md).
enum class RowOrder : std::uint8_t { top_first, bottom_first };

const char* row_order_name(RowOrder rows);  // "top row first", "bottom row first"

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
    RowOrder rows = RowOrder::top_first;
    // Where `rows` came from: "KTXorientation \"S=r,T=d\"", "PVR v3 orientation
    // metadata (y down)", "no KTXorientation: the tools' default", "the scene's
    // first_row", ...
    std::string rows_source = "default";
    // Whether the texels are sRGB-encoded colour, as the file declares it: a
    // KTX 1.1 sRGB glInternalFormat, KTX 2.0's sRGB vkFormat or its data
    // format descriptor's sRGB transfer function, PVR v3's colour space 1.
    // `format` is then the linear format of the same bits (sampled through
    // its sRGB twin, or decoded and converted). .astc files declare nothing.
    bool srgb = false;
    // What said so, for texinfo and the render log: "glInternalFormat
    // 0x9279 (GL_COMPRESSED_SRGB8_ALPHA8_ETC2_EAC)", "PVR v3 colour space 1",
    // "DFD transfer function 2 (sRGB)"; empty: the file declares nothing (or linear).
    std::string color_space_source;
    // What the reader repaired on the way, for texinfo and the render log
    // ("level [4] 4x4: one stored PVRTC block, repeated to the 2x2 blocks ...").
    std::vector<std::string> notes;
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
