// The asset step's encoding: a material's height field, normal map and
// albedo made into textures of a chosen format, every level of the full
// mip chain computed here (box-filtered) and encoded, in the layout that
// suits compression: height alone in one channel (grey in colour formats),
// normals in two channels where the format has two (EAC RG11, BC5; the
// shader reconstructs z), or three. Used by `parallax convert` and
// `parallax render --textures`.
#pragma once

#include <string>
#include <vector>

#include "parallaxes/assets/heightfield.h"
#include "parallaxes/assets/image.h"
#include "parallaxes/core/result.h"
#include "parallaxes/texture/texture_data.h"

namespace px {

// The formats of one asset variant, by slot.
struct AssetFormats {
    std::string variant;  // "etc2"
    TextureFormat height = TextureFormat::r8;
    TextureFormat normal = TextureFormat::rgb8;
    TextureFormat albedo = TextureFormat::rgb8;
};

// raw (r8, rgb8, rgb8), etc1 (etc1 x 3), etc2 (eac_r11, eac_rg11,
// etc2_rgb), astc or astc_WxH (that block size x 3), pvrtc (pvrtc1_rgb_4bpp
// x 3), bc (bc4, bc5, bc1_rgb). Errors list the names.
Result<AssetFormats> asset_formats(const std::string& variant);
std::vector<std::string> asset_variant_names();

// Encodes one image of `format` from RGBA8 pixels (w * h * 4, row 0 =
// t = 0): one- and two-channel formats take R (and G).
Result<std::vector<std::uint8_t>> encode_image(TextureFormat format, std::uint32_t width, std::uint32_t height,
                                               const std::uint8_t* rgba);
// The same from unorm16 values (w * h * channels, 1 or 2 channels): EAC and
// BC4/BC5 keep their extra precision; other formats round to 8 bits.
Result<std::vector<std::uint8_t>> encode_image_unorm16(TextureFormat format, std::uint32_t width,
                                                       std::uint32_t height, int channels,
                                                       const std::uint16_t* values);

// Full chains (mipmaps = false: the base level alone). Errors: a format
// that cannot hold the slot (a normal map in one channel), PVRTC1 at a
// non-power-of-two size, an encoder's error.
Result<TextureData> encode_height_texture(const HeightField& field, TextureFormat format, bool mipmaps = true);
Result<TextureData> encode_normal_texture(const Image& normal, TextureFormat format, bool mipmaps = true);
// srgb: the colour is sRGB-encoded, and each mip level averages linear
// light (assets/color.h next_mip_level) instead of code values.
Result<TextureData> encode_color_texture(const Image& rgba, TextureFormat format, bool mipmaps = true,
                                         bool srgb = false);

}  // namespace px
