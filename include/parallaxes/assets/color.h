// sRGB colour (IEC 61966-2-1): the transfer functions the shaders, the
// exact reference and the CPU mip chains share, and an sRGB-correct
// halving of an RGBA8 image.
#pragma once

#include "parallaxes/assets/image.h"

namespace px {

// Encoded [0, 1] to linear light and back: the piecewise sRGB curve (a
// linear toe below 0.04045 encoded, 0.0031308 linear; exponent 2.4 above).
// Clamped to [0, 1].
double srgb_to_linear(double encoded);
double linear_to_srgb(double linear);
// The byte an sRGB display shows for a linear value (rounded).
std::uint8_t linear_to_srgb8(double linear);

// The next mip level of an RGBA8 image: each side halved (at least 1,
// odd sides folding their last texel into the last output texel), every
// output texel the mean of its 2x2 (or 2x1, 1x2) sources, colour averaged in
// linear light and encoded back (srgb), or averaged as stored; alpha as stored.
Image next_mip_level(const Image& rgba, bool srgb);

}  // namespace px
