// Decoding a TextureData's images on the CPU, whatever the format: the
// upload's fallback where the context cannot sample a format, the exact
// reference's height field, and `parallax texinfo`. Formats dispatch to the
// codecs of texture/codecs.h.
#pragma once

#include <cstdint>
#include <vector>

#include "parallaxes/assets/heightfield.h"
#include "parallaxes/assets/image.h"
#include "parallaxes/core/result.h"
#include "parallaxes/texture/texture_data.h"

namespace px {

// One image (level, layer, face) as RGBA8 (channels = 4), row 0 = t = 0.
Result<Image> decode_rgba8(const TextureData& texture, std::size_t level = 0, std::uint32_t layer = 0,
                           std::uint32_t face = 0);

// The same image's first `channels` channels (1 or 2) as unorm16, widened
// as texture/codecs.h says; for 8-bit formats v * 257.
Result<std::vector<std::uint16_t>> decode_unorm16(const TextureData& texture, int channels, std::size_t level = 0);

// The height field the GPU samples from level 0's red channel: EAC R11 and
// RG11 texels as v / 2047 (their 11 bits), every other format's as
// byte / 255, converted from `convention`.
Result<HeightField> height_field_from_texture(const TextureData& texture, HeightConvention convention);

// Bits per texel of the red channel as sampled: 11 (EAC) or 8.
int height_bits(TextureFormat format);

// Any CPU image wrapped as a one-level TextureData of r8 / rg8 / rgb8 /
// rgba8 (by channel count), for code that takes either.
TextureData texture_from_image(const Image& image);

}  // namespace px
