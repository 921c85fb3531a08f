// The CPU codecs, one family each, on one 2D image (one level, layer, face).
// Every decoder takes the image's bytes exactly as a container holds them
// (`size` must be image_bytes(format, width, height); anything else is an
// error, never a read past the end) and writes row 0 first, as the data is
// laid out (row 0 = t = 0 = px::Image row 0). Partial blocks at the right
// and top edges decode only the texels inside the image.
//
// Two outputs:
//   rgba8:   width * height * 4 bytes, missing channels as GL returns them
//            (G = B = 0, A = 255 for one channel; B = 0, A = 255 for two).
//   unorm16: width * height * channels values for the one- and two-channel
//            formats (EAC R11/RG11, BC4/BC5, r8/rg8), each channel's value
//            widened by bit replication (11-bit v -> v << 5 | v >> 6;
//            8-bit v -> v * 257), so v / 65535 is the texel GL returns
//            to within 1/65535.
// Encoders take rgba8 (colour formats) or unorm16 (EAC, BC4/BC5) pixels in
// the same layout and return image_bytes(format, width, height) bytes; they
// pad partial blocks by repeating the edge texels.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/texture/format.h"

namespace px {

// ETC1, ETC2 RGB / RGB A1 / RGBA, EAC R11 / RG11 (texture/etc.cpp).
// Khronos Data Format Specification 1.3, chapter 21 (ETC1) and 22 (ETC2/EAC).
Status decode_etc_rgba8(TextureFormat format, std::uint32_t width, std::uint32_t height, const std::uint8_t* data,
                        std::size_t size, std::uint8_t* rgba);
Status decode_eac_unorm16(TextureFormat format, std::uint32_t width, std::uint32_t height,
                          const std::uint8_t* data, std::size_t size, std::uint16_t* values);
// etc1_rgb8, etc2_rgb8, etc2_rgba8, etc2_rgb8a1 from rgba8.
Result<std::vector<std::uint8_t>> encode_etc_rgba8(TextureFormat format, std::uint32_t width,
                                                   std::uint32_t height, const std::uint8_t* rgba);
// eac_r11, eac_rg11 from unorm16 (1 or 2 channels).
Result<std::vector<std::uint8_t>> encode_eac_unorm16(TextureFormat format, std::uint32_t width,
                                                     std::uint32_t height, const std::uint16_t* values);

// BC1..BC5 (texture/bc.cpp).
Status decode_bc_rgba8(TextureFormat format, std::uint32_t width, std::uint32_t height, const std::uint8_t* data,
                       std::size_t size, std::uint8_t* rgba);
Status decode_bc_unorm16(TextureFormat format, std::uint32_t width, std::uint32_t height, const std::uint8_t* data,
                         std::size_t size, std::uint16_t* values);
// bc1_rgb, bc3 from rgba8; bc4, bc5 from unorm16.
Result<std::vector<std::uint8_t>> encode_bc_rgba8(TextureFormat format, std::uint32_t width, std::uint32_t height,
                                                  const std::uint8_t* rgba);
Result<std::vector<std::uint8_t>> encode_bc_unorm16(TextureFormat format, std::uint32_t width,
                                                    std::uint32_t height, const std::uint16_t* values);

// PVRTC1 2 and 4 bpp (texture/pvrtc.cpp): power-of-two sizes only.
Status decode_pvrtc_rgba8(TextureFormat format, std::uint32_t width, std::uint32_t height,
                          const std::uint8_t* data, std::size_t size, std::uint8_t* rgba);
Result<std::vector<std::uint8_t>> encode_pvrtc_rgba8(TextureFormat format, std::uint32_t width,
                                                     std::uint32_t height, const std::uint8_t* rgba);
// PVRTC1 levels smaller than 2 x 2 blocks. IMG_texture_compression_pvrtc
// sizes every level as at least 8x8 texels (4 bpp) or 16x8 (2 bpp): 2 x 2
// blocks, and glCompressedTexImage2D takes nothing less. Some tools (basisu
// 1.15's -unpack) store only the blocks the level covers (one 8-byte block
// for 4x4 and below). Decoding wraps, so a level of bx x by blocks decodes
// exactly as the 2 x 2 (or wider) grid that repeats them: this returns the
// bytes of a short level, `stored` blocks, and the padded bytes otherwise.
std::uint64_t pvrtc_stored_bytes(TextureFormat format, std::uint32_t width, std::uint32_t height);
std::vector<std::uint8_t> pvrtc_pad_level(TextureFormat format, std::uint32_t width, std::uint32_t height,
                                          const std::uint8_t* stored);

// ASTC LDR through libastcenc (texture/astc.cpp), linear (not sRGB) profile.
Status decode_astc_rgba8(TextureFormat format, std::uint32_t width, std::uint32_t height,
                         const std::uint8_t* data, std::size_t size, std::uint8_t* rgba);
// quality: astcenc's 0 (fastest) .. 100 (exhaustive); 60 is "thorough".
Result<std::vector<std::uint8_t>> encode_astc_rgba8(TextureFormat format, std::uint32_t width,
                                                    std::uint32_t height, const std::uint8_t* rgba,
                                                    float quality = 60.0f);

}  // namespace px
