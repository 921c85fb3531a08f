// Maximum mip-maps (Tevs, Ihrke & Seidel 2008; Drobot 2010's quadtree) over
// the BILINEARLY FILTERED height field, for the "maxmip" technique.
//
// Cone maps and max pyramids built over texel samples are not conservative
// once the GPU filters bilinearly (Bán, Valasek et al., EGSR 2024): the
// filtered surface between texel centres is not bounded by the sample at any
// one centre. So level 0 holds one value per CELL, the square between four
// neighbouring texel centres (the domain of one bilinear patch): cell (i, j)
// spans texel space [i + 0.5, i + 1.5] x [j + 0.5, j + 1.5], has corner
// texels (i, j), (i+1, j), (i, j+1), (i+1, j+1) (wrapping, GL_REPEAT), and
// stores the max of those four. A bilinear patch is a convex combination of
// its corners, so that max bounds the filtered surface over the cell exactly.
// Level k stores the max over 2x2 of level k-1 (2x1 or 1x2 once one side is
// down to 1), like the GL mip chain's sizes: max(1, w >> k) x max(1, h >> k).
//
// Values are the 8-bit heights the GPU samples (round(h * 255)), so the
// pyramid is exact in an 8-bit texture and in a mediump sampler.
#pragma once

#include <cstdint>
#include <vector>

#include "parallaxes/assets/heightfield.h"
#include "parallaxes/assets/image.h"
#include "parallaxes/core/result.h"

namespace px {

struct MaxMipmap {
    int width = 0;   // level 0 cells across = field width in texels (a power of two)
    int height = 0;  // level 0 cells down = field height in texels (a power of two)
    // levels[k]: max(1, width >> k) x max(1, height >> k), one channel
    // (R = max height * 255), row 0 = v = 0; levels.back() is 1 x 1. Ready to
    // upload as mip level k of a texture read with texelFetch.
    std::vector<Image> levels;
    // 8: one channel per level (byte = max * 255). 11: two (R * 256 + G =
    // max * 2047), for 11-bit height maps (EAC R11).
    int bits = 8;

    int level_count() const { return static_cast<int>(levels.size()); }
    // The max of node (x, y) of `level` in texel steps (0..255 or 0..2047);
    // x and y wrap (any integer).
    int max_value(int level, long long x, long long y) const;
    // The same clamped to a byte (8-bit pyramids: the value itself).
    std::uint8_t max_byte(int level, long long x, long long y) const;
    // The same as a normalised height (value / 255 or / 2047), as the shader reads it.
    float max_height(int level, long long x, long long y) const;
};

// Builds the pyramid from the field quantised to 8 bits (round(h * 255), h
// clamped to [0, 1]). Errors: an empty field, a width or height that is not a
// power of two (the message names the size), texel count not width * height.
// `bits`: 8 (heights quantised to byte / 255) or 11 (v / 2047).
Result<MaxMipmap> build_max_mipmap(const HeightField& field, int bits = 8);

// The same pyramid for GLSL ES 1.00, which has no texelFetch and no lod reads
// in the fragment stage: one RGBA8 image without mips (read with NEAREST at
// texel centres; NPOT is core ES 2.0 with CLAMP_TO_EDGE). Layout:
// - a width x height block at (0, 0): texel (i, j) holds cell (i, j)'s four
//   corner heights (RGBA = texels (i, j), (i+1, j), (i, j+1), (i+1, j+1),
//   wrapping), so one read gives the bilinear patch (and its max, level 0);
// - level k >= 1 (R = its max, byte / 255) at max_atlas_origin(k).
// 8-bit heights only. Errors as build_max_mipmap's.
struct MaxAtlas {
    Image image;     // (width + max(1, width / 2)) x max(height, rows the levels need), 4 channels
    int levels = 0;  // pyramid levels, as MaxMipmap::level_count()
};
Result<MaxAtlas> build_max_atlas(const HeightField& field);
// Where level k >= 1 of a width x height field's pyramid starts in its atlas:
// x = width, y = the rows of levels 1..k-1 (max(1, height >> j) each).
// maxmip.frag's px_node_max computes the same in closed form.
struct AtlasOrigin {
    int x = 0;
    int y = 0;
};
AtlasOrigin max_atlas_origin(int width, int height, int level);

}  // namespace px
