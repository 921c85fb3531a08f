// Shader variants: a small value naming one compiled program, and the
// planner that picks the variant for a material on a given context.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/effects/technique.h"

namespace px {

enum class ShaderStage { vertex, fragment };

struct ShaderDefine {
    std::string name;
    std::string value;  // empty: "#define NAME"
};

// How a material's textures hold what the shaders read; set at load from
// the texture files (scene/material_images.h) and applied to every variant
// drawn with the material.
struct TextureLayout {
    bool packed_height = true;  // height in the normal map's alpha (RGBA8 sources)
    bool normal_rg = false;     // normal x, y in R, G (EAC RG11, BC5); z = sqrt(1 - x^2 - y^2)
    bool height_11bit = false;  // traced height has 11-bit texels (EAC R11): the exact walk snaps to 1/2047
    // The normal texture as uploaded has DirectX's green (-v): the shaders
    // negate it (a texture file; an image's green is flipped on the CPU).
    bool normal_green_down = false;
    // The albedo is sRGB-encoded and this context's texture unit cannot
    // decode it (ES 2.0): the shader decodes each read.
    bool albedo_srgb_decode = false;
    // Texture files stored top row first (texture_data.h RowOrder), uploaded
    // as they are: the shaders read them at v' = 1 - v (kFlip* bits).
    std::uint8_t flip_v = 0;
};

// VariantKey::flip_v and TextureLayout::flip_v bits: which textures are read
// at 1 - v.
inline constexpr std::uint8_t kFlipAlbedo = 1, kFlipNormal = 2, kFlipHeight = 4;

// VariantKey::shape values: the curved meshes whose shape the exact curved
// search knows (scene/mesh.cpp's uv sphere, open cylinder and torus).
inline constexpr std::uint8_t kShapeSphere = 1, kShapeCylinder = 2, kShapeTorus = 3;

struct VariantKey {
    Technique technique = Technique::normal;
    ShadowMode shadow = ShadowMode::none;
    bool depth_write = false;
    bool lod = false;
    bool packed_height = true;    // height in the normal map's alpha
    bool exact_view = false;      // PX_EXACT_VIEW: highp unnormalised view vector
    bool normal_rg = false;       // PX_NORMAL_RG: two-channel normal map, z reconstructed
    bool height_11bit = false;    // PX_HEIGHT_11BIT: highp height reads snapped to 1/2047 (maxmip)
    bool normal_green_down = false;  // PX_NORMAL_GREEN_DOWN: the normal map's green is -v (DirectX style)
    // PX_SRGB_DECODE: the shader decodes the albedo's sRGB texels to linear
    // light (TextureLayout::albedo_srgb_decode).
    bool srgb_decode = false;
    // PX_SRGB_OUTPUT: the shader encodes its linear colour for an sRGB
    // display (HostFrame::TargetColor::srgb_encoded); off for debug outputs.
    bool srgb_output = false;
    std::uint8_t es_major = 3;    // 2: GLSL ES 1.00, 3: GLSL ES 3.00
    // GLSL ES 1.00 only: the fragment stage has no highp (PX_NO_FRAGMENT_HIGHP),
    // as on Mali-400-class GPUs; PX_HIGHP declarations there are mediump.
    bool no_fragment_highp = false;
    std::uint16_t max_samples = 0;   // linear-search loop bound (march techniques)
    std::uint8_t refine_steps = 0;   // relief
    std::uint8_t shadow_samples = 0; // shadow-ray loop bound
    // 0: colour. 1: hit uv, height and visibility to a float target. 2, 3, 4:
    // the same packed into RGBA8 over three passes (shaders_es/chunks/debug_output.glsl).
    std::uint8_t debug_output = 0;
    // With a debug output, a search's loop iterations and texture fetches
    // per pixel in place of the hit uv (PX_COUNT_WORK,
    // include/parallaxes/profiling/measurement/work.h). Searching techniques only.
    bool count_work = false;
    // With the float debug output (1), the ray the trace was handed in
    // place of its hit: (uv, parallax.x, parallax.y), parallax the uv shift
    // per unit of normalised height as the trace computes it (PX_CAPTURE_RAY;
    // profiling/measurement/bench.cpp measures the trace against the exact
    // reference of that same ray). Height-reading techniques only.
    bool capture_ray = false;
    // PX_BOUNDED: the material is a bounded relief (MaterialDesc::bounded);
    // a traced hit outside its mesh uv [0, 1]^2 is discarded. Traced
    // techniques only; set from the material, as the texture layout is.
    bool bounded = false;
    // PX_CURVED: curved-relief silhouettes (MaterialDesc::silhouette on a
    // curved mesh): the march follows the surface's per-vertex quadric
    // (Vertex::curvature) and discards where the ray leaves the relief
    // without meeting it. The linear searches (steep, pom, relief) only;
    // set per object (the mesh decides), the planner drops it where no
    // contour is on screen.
    bool curved = false;
    // With curved: the mesh's own shape (kShape*: PX_SHAPE), whose
    // parameterisation the search evaluates exactly at each sample in place
    // of the fitted quadric (march.glsl). 0: the quadric (a context without
    // fragment highp, where the angles would be fp16).
    std::uint8_t shape = 0;
    // The PowerVR whitepaper's optimisation ladder (offset_limited only,
    // shaders_es/ladder/): 0 is the shipped shader; 1 the whitepaper's
    // baseline, and 2..6 each step it took, in its order (kLadderSteps).
    std::uint8_t ladder_step = 0;
    // Textures read at v' = 1 - v (kFlipAlbedo | kFlipNormal | kFlipHeight):
    // files stored top row first, uploaded without decoding
    // (PX_FLIP_ALBEDO_V, PX_FLIP_NORMAL_V, PX_FLIP_HEIGHT_V).
    std::uint8_t flip_v = 0;
    // GLSL ES 1.00 only: the context lacks GL_OES_standard_derivatives. With
    // them (the default), a technique that moves the uv shades at the hit
    // with the mip level of the unshifted uv: texture2D's implicit level
    // comes from the hit uv's derivatives, which jump where the relief
    // occludes itself (a brick's edge, a hemisphere's rim), so those pixels
    // read a blurred mip (PX_SHADE_LOD_BIAS cancels the difference through
    // texture2D's bias; GLSL ES 3.00 reads with textureGrad). Without them
    // the implicit level stays (no-derivatives).
    bool no_derivatives = false;

    // Fields added at run time (add_variant_field), by word: 0 or absent
    // is off. The built-in fields are the members above.
    std::map<std::string, std::uint32_t> added;

    // The same variant with every field the technique does not use zeroed,
    // so that equal programs have equal keys.
    VariantKey canonical() const;
    // The variant's identity: its canonical description (describe()), made
    // from the field table, so that it has room for any number of fields.
    // The program cache's key; another process (`parallax profile`'s NIR
    // capture) is handed variants this way, and parse() reads it back.
    std::string id() const;
    // A 64-bit FNV-1a hash of id(), for compact labels (not a key: two
    // variants may share one).
    std::uint64_t hash() const;
    bool operator==(const VariantKey& o) const { return id() == o.id(); }
    bool operator!=(const VariantKey& o) const { return !(*this == o); }

    std::vector<ShaderDefine> defines() const;
    std::vector<std::string> extensions(ShaderStage stage) const;  // #extension lines needed on ES 2.0
    // PX_SHADE_LOD_BIAS: GLSL ES 1.00, a uv-moving technique, derivatives (no_derivatives).
    bool shade_lod_bias() const;
    std::string describe() const;  // "pom es3 samples<=32 shadow=softx16 depth exact-view packed"
    // The key a describe() string names (any variant, enumerated or not);
    // an error names the word it does not know.
    static Result<VariantKey> parse(const std::string& name);

    // The shader entries (relative to shaders_es/) the variant is built from.
    std::string vertex_entry() const;
    std::string fragment_entry() const;

    // The key with a material's texture layout applied.
    VariantKey with_layout(const TextureLayout& layout) const;
};

// One field of a variant: how it is written in the description, read back
// and turned into shader defines. VariantKey::describe, parse, defines and
// id (and so the program cache's key) all read one table of these
// (variant.cpp), in the description's order. A flag is data: its word, its
// define, and the member (or flip_v bit) that holds it; any other field has
// its three functions.
struct VariantField {
    const char* name;
    const char* word = nullptr;    // a flag's word in the description
    const char* define = nullptr;  // a flag's bare define
    bool VariantKey::*flag = nullptr;
    std::uint8_t flip_bit = 0;     // a flag held in VariantKey::flip_v
    // Appends the field's word (with a leading space; the technique's has
    // none) where it differs from its default.
    void (*describe)(const VariantKey&, std::string&) = nullptr;
    // Reads one word of a description into the key; false: not its word.
    bool (*parse)(const std::string&, VariantKey&) = nullptr;
    // Appends its defines (of a canonical key).
    void (*defines)(const VariantKey&, std::vector<ShaderDefine>&) = nullptr;
};
// The table, `count` rows.
const VariantField* variant_fields(size_t& count);

// A field added after the table at run time, held in VariantKey::added: a
// flag (max_value 1: "word" and a bare define) or a number ("word=N" and
// the define set to N, 1..max_value). Present only for techniques with every
// bit of `technique_options` (OptionFlag; 0: every technique). For shader
// experiments and tests; the built-in fields are rows of variant.cpp's
// table. Errors: a word that is empty, has digits, '=' or spaces, or is
// already a field's; a define not PX_ and capitals.
struct AddedVariantField {
    std::string word;
    std::string define;
    std::uint32_t max_value = 1;
    std::uint32_t technique_options = 0;
};
Status add_variant_field(const AddedVariantField& field);

// The optimisation ladder's steps (VariantKey::ladder_step 1..kLadderSteps):
// what each one changes, for reports.
constexpr int kLadderSteps = 6;
struct LadderStep {
    int step;
    const char* name;    // short, for tables: "baseline", "eye-to-tangent matrix", ...
    const char* change;  // what it does, in the whitepaper's words
};
const LadderStep& ladder_step_info(int step);  // 1..kLadderSteps

// A technique's variant with the default loop bounds of TechniqueOptions
// (its other options off): the base every enumeration starts from.
VariantKey default_variant(const TechniqueInfo& info, int es_major);

// Every variant the program can build for an ES version on a context that
// has every optional extension: each technique with each of its options on
// and off, at the default and extreme loop bounds. Shader validation tests
// compile all of them.
std::vector<VariantKey> enumerate_variants(int es_major);

}  // namespace px
