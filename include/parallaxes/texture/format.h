// Texture formats as data: what a container's format code means, the block
// arithmetic every level size is checked against, and the codes each
// container and OpenGL ES use for it. GL-free (the GL enums are numbers).
//
// Byte layout everywhere in texture/: a 2D image is stored as the file and
// glTexImage2D / glCompressedTexImage2D take it, first row (or row of
// blocks) = t = 0, which is row 0 of px::Image (bottom, v = 0).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "parallaxes/core/caps.h"
#include "parallaxes/core/result.h"

namespace px {

enum class TextureFormat : std::uint8_t {
    // Uncompressed, 8 bits per channel, unsigned normalised.
    r8,
    rg8,
    rgb8,
    rgba8,
    // ETC (Khronos Data Format Specification 1.3, chapters 21 and 22).
    etc1_rgb8,
    etc2_rgb8,
    etc2_rgb8a1,  // punch-through alpha
    etc2_rgba8,   // ETC2 colour + EAC alpha
    eac_r11,
    eac_rg11,
    // ASTC LDR, every 2D block size (KHR_texture_compression_astc_ldr).
    astc_4x4,
    astc_5x4,
    astc_5x5,
    astc_6x5,
    astc_6x6,
    astc_8x5,
    astc_8x6,
    astc_8x8,
    astc_10x5,
    astc_10x6,
    astc_10x8,
    astc_10x10,
    astc_12x10,
    astc_12x12,
    // PVRTC1 (IMG_texture_compression_pvrtc).
    pvrtc1_rgb_2bpp,
    pvrtc1_rgb_4bpp,
    pvrtc1_rgba_2bpp,
    pvrtc1_rgba_4bpp,
    // S3TC and RGTC (EXT_texture_compression_s3tc, _rgtc).
    bc1_rgb,
    bc1_rgba,
    bc2,
    bc3,
    bc4,
    bc5,
};

enum class FormatFamily : std::uint8_t { uncompressed, etc1, etc2, eac, astc, pvrtc, s3tc, rgtc };

struct FormatInfo {
    TextureFormat format;
    const char* name;       // as texinfo prints it and --format takes it: "eac_r11"
    FormatFamily family;
    int block_width;        // texels per block (1 for uncompressed)
    int block_height;
    int block_bytes;        // bytes per block (per texel when uncompressed)
    int min_blocks_x;       // PVRTC1: a level is at least 2 x 2 blocks
    int min_blocks_y;
    int channels;           // meaningful channels: 1 (R), 2 (RG), 3 (RGB), 4 (RGBA)
    int channel_bits;       // precision of a decoded channel: 8, or 11 for EAC
    std::uint32_t gl_internal_format;  // sized (uncompressed) or compressed enum
    std::uint32_t gl_format;           // uncompressed: GL_RED/RG/RGB/RGBA; else 0
    std::uint32_t vk_format;           // KTX 2.0 vkFormat; 0: none
    std::uint32_t pvr_format;          // PVR v3 pixel format (compressed: low word); 0xFFFFFFFF: none
    bool compressed() const { return family != FormatFamily::uncompressed; }
};

const FormatInfo& format_info(TextureFormat format);
const std::vector<FormatInfo>& all_formats();
const char* format_name(TextureFormat format);
// By name (case-insensitive); errors list the names.
Result<TextureFormat> parse_format(const std::string& name);

// Container codes to formats. A code that names a known but unsupported
// format (sRGB, signed, BC6H/BC7, PVRTC2, float) is an error naming it; an
// unknown code is an error giving the number.
Result<TextureFormat> format_from_gl(std::uint32_t gl_internal_format, std::uint32_t gl_format,
                                     std::uint32_t gl_type);
Result<TextureFormat> format_from_vk(std::uint32_t vk_format);
Result<TextureFormat> format_from_pvr(std::uint64_t pvr_pixel_format, std::uint32_t channel_type);

// sRGB container codes: the linear code of the same bits (0 where `code`
// is not an sRGB format this library reads). GL: ETC2, ASTC, S3TC
// (EXT_texture_sRGB), PVRTC1 (EXT_pvrtc_sRGB), GL_SRGB8(_ALPHA8) and ES
// 2.0's unsized GL_SRGB(_ALPHA)_EXT. Vulkan: R8..RGBA8, BC1 to BC3, ETC2,
// ASTC and PVRTC1 *_SRGB. BC7 sRGB and PVRTC2 stay unsupported.
std::uint32_t linear_gl_of_srgb(std::uint32_t gl_internal_format);
std::uint32_t linear_vk_of_srgb(std::uint32_t vk_format);
// The GL name of an sRGB code, for messages ("GL_COMPRESSED_SRGB8_ALPHA8_ETC2_EAC").
std::string srgb_gl_name(std::uint32_t gl_internal_format);
// The other way, for the writers: the sRGB code of a linear one (0: none;
// EAC, BC4, BC5 and ETC1 in KTX 1.1 have no sRGB form).
std::uint32_t srgb_gl_of_linear(std::uint32_t linear_internal);
std::uint32_t srgb_vk_of_linear(std::uint32_t linear_vk);

// Bytes of one w x h image of `format` (w, h >= 1), from the block
// arithmetic, or nullopt where it would not fit in 63 bits (never wraps).
std::optional<std::uint64_t> image_bytes(TextureFormat format, std::uint64_t width, std::uint64_t height);

// Size of mip level `level` of a w x h base: max(1, w >> level) each way.
inline std::uint32_t mip_extent(std::uint32_t base, int level) {
    const std::uint32_t e = level >= 32 ? 0u : base >> level;
    return e ? e : 1u;
}
// Levels of a full chain down to 1 x 1: floor(log2(max(w, h))) + 1.
int full_mip_count(std::uint32_t width, std::uint32_t height);

// Whether the context samples `format` directly (glCompressedTexImage2D):
// an ES version or extension that defines it, and the format listed in
// GL_COMPRESSED_TEXTURE_FORMATS (Caps::compressed_formats) where the
// context lists any. ETC1 data also goes up as ETC2 RGB on ES 3.0 (ETC2
// decodes ETC1 blocks identically). Uncompressed formats: always.
bool context_samples(const Caps& caps, TextureFormat format);
// The GL internal format the upload uses for `format` on this context
// (ETC1 as GL_COMPRESSED_RGB8_ETC2 where OES_compressed_ETC1_RGB8_texture is
// missing on ES 3.0).
std::uint32_t upload_internal_format(const Caps& caps, TextureFormat format);
// What a context without it would need ("GL_KHR_texture_compression_astc_ldr").
const char* format_requirement(TextureFormat format);
// sRGB sampling of `format` (its sRGB twin) on this context: the internal
// format glCompressedTexImage2D takes (0: none), and whether the context
// samples it. Uncompressed RGBA8 and RGB8 go up as GL_SRGB8_ALPHA8 and
// GL_SRGB8 on ES 3.0 (context_samples_srgb: true); R8 and RG8 colour, and
// every format on ES 2.0, are decoded on the CPU or in the shader.
std::uint32_t srgb_internal_format(const Caps& caps, TextureFormat format);
bool context_samples_srgb(const Caps& caps, TextureFormat format);

// GL enum values used above (GL-free code needs the numbers).
namespace glenum {
inline constexpr std::uint32_t kRed = 0x1903, kRg = 0x8227, kRgb = 0x1907, kRgba = 0x1908;
inline constexpr std::uint32_t kLuminance = 0x1909, kLuminanceAlpha = 0x190A, kAlpha = 0x1906;
inline constexpr std::uint32_t kUnsignedByte = 0x1401;
inline constexpr std::uint32_t kR8 = 0x8229, kRg8 = 0x822B, kRgb8 = 0x8051, kRgba8 = 0x8058;
inline constexpr std::uint32_t kEtc1Rgb8 = 0x8D64;
inline constexpr std::uint32_t kR11Eac = 0x9270, kSignedR11Eac = 0x9271, kRg11Eac = 0x9272,
                               kSignedRg11Eac = 0x9273, kRgb8Etc2 = 0x9274, kSrgb8Etc2 = 0x9275,
                               kRgb8A1Etc2 = 0x9276, kSrgb8A1Etc2 = 0x9277, kRgba8Etc2Eac = 0x9278,
                               kSrgb8Alpha8Etc2Eac = 0x9279;
inline constexpr std::uint32_t kAstc4x4 = 0x93B0;       // .. 0x93BD in block-size order
inline constexpr std::uint32_t kSrgbAstc4x4 = 0x93D0;   // .. 0x93DD
inline constexpr std::uint32_t kPvrtcRgb4 = 0x8C00, kPvrtcRgb2 = 0x8C01, kPvrtcRgba4 = 0x8C02,
                               kPvrtcRgba2 = 0x8C03;
inline constexpr std::uint32_t kDxt1Rgb = 0x83F0, kDxt1Rgba = 0x83F1, kDxt3 = 0x83F2, kDxt5 = 0x83F3;
inline constexpr std::uint32_t kRgtc1 = 0x8DBB, kSignedRgtc1 = 0x8DBC, kRgtc2 = 0x8DBD, kSignedRgtc2 = 0x8DBE;
}  // namespace glenum

}  // namespace px
