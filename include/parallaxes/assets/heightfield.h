// Height fields: loaded from images or generated procedurally, and the normal
// maps derived from them.
//
// Conventions. Values are heights in [0, 1]: 1 is the top of the relief, 0 the
// bottom. Files may instead store depth (= 1 - height, as some tools export);
// HeightConvention names which one an image holds and to_height() converts.
// Texel (x, y) covers uv [x/w, (x+1)/w] x [y/h, (y+1)/h]; its value is the
// height at the texel centre, and the surface between centres is the bilinear
// interpolation of the four nearest centres, wrapping at the edges (GL_REPEAT,
// GL_LINEAR), which is the surface the GPU samples.
#pragma once

#include <string>
#include <vector>

#include "parallaxes/assets/image.h"
#include "parallaxes/core/result.h"

namespace px {

enum class HeightConvention {
    height,  // 1 = top of the relief (white is high)
    depth,   // 1 = bottom of the relief (white is deep): height = 1 - depth
};

struct HeightField {
    int width = 0;
    int height = 0;
    std::vector<float> texels;  // width * height, row 0 = v = 0

    float at(int x, int y) const;        // wraps x and y (GL_REPEAT)
    float& ref(int x, int y) { return texels[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)]; }
    // Bilinear filtering as GL_LINEAR with GL_REPEAT does it, in double precision.
    double sample_bilinear(double u, double v) const;
};

// Takes the red channel (or the only channel) of an 8-bit image as height,
// converting from the stated convention.
HeightField height_field_from_image(const Image& image, HeightConvention convention);

// Procedural fields, each defined analytically as h(u, v) on the unit square
// and sampled at texel centres; deterministic for a given FieldSpec.
enum class FieldKind {
    flat,         // h = level everywhere
    bricks,       // running-bond bricks (height 1) with recessed mortar joints (height 0)
    text,         // raised glyphs of `text` (5x7 font) on a flat ground at height 0
    lines,        // `count` raised lines `line_width` texels wide (1 = one-texel lines)
    hemispheres,  // count x count hemispherical bumps
    cones,        // count x count cones
    sine,         // 0.5 + 0.5 sin(2 pi f u) sin(2 pi f v) with f = frequency
    spike,        // a single texel at height 1 on a ground at height 0
    pit,          // flat top (height 1) with a square pit of depth 1 at the centre
};

struct FieldSpec {
    FieldKind kind = FieldKind::flat;
    int size = 256;             // texels per side
    float level = 1.0f;         // flat: the constant height
    int count = 4;              // lines, hemispheres, cones: how many per side; bricks: rows
    float frequency = 4.0f;     // sine: periods per tile
    float mortar = 0.06f;       // bricks: joint width as a fraction of the tile
    int line_width = 1;         // lines: width in texels
    float radius = 0.25f;       // pit: half-width of the pit as a fraction of the tile
    std::string text = "ES";    // text: the glyphs to raise (A-Z, 0-9, space)
};

// Names as they appear in scene files: "flat", "bricks", ...
const char* field_kind_name(FieldKind kind);
Result<FieldKind> parse_field_kind(const std::string& name);
std::vector<std::string> field_kind_names();

// Checks the parameters the kind uses (other members of FieldSpec are
// ignored) without generating anything: the field's own rules (even brick
// rows, mortar width, glyphs, line spacing, sizes). make_height_field checks
// the same before it allocates.
Status validate_field_spec(const FieldSpec& spec);
Result<HeightField> make_height_field(const FieldSpec& spec);

// Tangent-space normal map of a height field whose relief is `height_scale`
// deep in tile units (the whole texture spans 1 unit in u and v), so the
// normals match the surface that the parallax techniques trace. Central
// differences, wrapping. Output RGB = normal * 0.5 + 0.5; alpha = height when
// pack_height is true (one fetch gives both), else 255.
Image derive_normal_map(const HeightField& field, float height_scale, bool pack_height);

// The field as an RGBA8 upload stores it and the GPU samples it: every
// texel clamped to [0, 1] and rounded to byte / 255. The renderer keeps this
// copy for displaced meshes and max pyramids; the reference traces it.
HeightField quantized_8bit(const HeightField& field);

// The height field as an 8-bit RGBA image: R, G and B hold height, alpha is
// 255 (opaque, so the file views as a grey image).
Image height_image(const HeightField& field);

// A colour that follows the relief: each texel's height mapped linearly from
// `low` (height 0: mortar, the ground under lettering) to `high` (height 1),
// times 1 + grain * n, with n a fixed noise in [-1, 1] (a hash of the texel
// blended with a smooth noise over 8-texel cells: speckle and blotches), so
// one procedural spec gives a surface its colour and, in the height slot,
// its relief. Channels clamp to [0, 1]. low 0, high 1, grain 0 is
// height_image. Colours in [0, 1], grain in [0, 1] (scene validation).
struct HeightRamp {
    float low[3] = {0.0f, 0.0f, 0.0f};
    float high[3] = {1.0f, 1.0f, 1.0f};
    float grain = 0.0f;
};
Image ramp_image(const HeightField& field, const HeightRamp& ramp);

}  // namespace px
