// The technique catalogue: one table (name, defines, options, minimum ES
// version, limits) that drives the CLI listing, the planner, the shader
// variant enumeration and the tests.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"

namespace px {

// Every technique, in catalogue order: the enum and its count come from this
// one list, and technique.cpp's table must hold a row for each, in order.
#define PX_TECHNIQUES(X)                                                                   \
    X(flat)           /* albedo only, lit by the geometric normal */                       \
    X(normal)         /* normal mapping */                                                 \
    X(parallax)       /* Kaneko 2001: uv += h * V.xy / V.z */                              \
    X(offset_limited) /* Welsh 2004 / PowerVR whitepaper: uv += h * V.xy */                \
    X(steep)          /* McGuire & McGuire 2005: linear march, first sample below */       \
    X(pom)            /* Tatarchuk 2005: linear march + the last linear segment */         \
    X(relief)         /* Policarpo et al. 2005: linear march + binary refinement */        \
    X(maxmip)         /* Tevs et al. 2008; Drobot 2010: max mip-map descent, exact solve */

enum class Technique : std::uint8_t {
#define PX_ENUM(id) id,
    PX_TECHNIQUES(PX_ENUM)
#undef PX_ENUM
};
inline constexpr int kTechniqueCount = 0
#define PX_COUNT(id) +1
    PX_TECHNIQUES(PX_COUNT)
#undef PX_COUNT
    ;

enum class ShadowMode : std::uint8_t {
    none,
    hard,  // a shadow ray toward the light; any blocker makes the point dark
    soft,  // the same ray, visibility from the blocker-to-receiver penumbra estimate
};

// What a material asks of its technique. Options a technique does not have
// are ignored by the planner, which says so.
struct TechniqueOptions {
    Technique technique = Technique::pom;
    // Tatarchuk's dynamic sample rate: min_samples when the view is along the
    // normal, rising linearly to max_samples as the view turns to grazing.
    int min_samples = 8;
    int max_samples = 32;
    int refine_steps = 5;     // relief: binary search steps after the linear search
    // maxmip: the iteration budget of the pyramid walk (a constant loop
    // bound; a ray stops early at its hit, so only the rays that need the
    // steps pay for them). Grazing rays beside 1-texel features need the
    // most: 831 on a 256-texel field 0.1 deep at 89 degrees
    // (tests/unit_maxmip.cpp); at 89.9 degrees a bench ray along the gap
    // between two rows of hemispheres needs 2310, so the default is the
    // technique's limit.
    int max_steps = 4096;
    ShadowMode shadow = ShadowMode::none;
    int shadow_samples = 16;  // samples along the shadow ray
    bool depth_write = false; // perspective-correct depth through gl_FragDepth
    // The view vector interpolated unnormalised in highp and normalised per
    // fragment (the default: exact on flat triangles; maxmip always uses it).
    // false: normalised per vertex in mediump, the PowerVR whitepaper's
    // saving of a normalise per fragment, which on one 4-unit quad seen from
    // 2 units puts a level-0 field at 0.14 of the relief's height instead of
    // 0 (docs/scene-format.md): an opt-in where the polygons are small.
    bool exact_view = true;
    // Mip-level LOD (Tatarchuk 2005): at mip levels past lod_threshold render
    // normal mapping; blend over the lod_band levels before it.
    bool lod = false;
    float lod_threshold = 3.0f;
    float lod_band = 1.0f;
    // The technique was imposed on the material (scene.h force_technique:
    // `parallax render --technique`, a benchmark's setting, a host's
    // override), not named by its author: what it cannot draw (a curved
    // silhouette, a bounded outline, a shadow) is dropped with a note in the
    // plan, never refused.
    bool forced = false;
};

// Option flags, as a bitmask in TechniqueInfo::options.
enum OptionFlag : std::uint32_t {
    kOptHeight = 1u << 0,   // reads the height map at all
    kOptSamples = 1u << 1,  // min/max samples (a linear search)
    kOptRefine = 1u << 2,   // refine_steps
    kOptShadow = 1u << 3,   // self-shadowing
    kOptDepth = 1u << 4,    // depth_write
    kOptLod = 1u << 5,      // mip-level LOD blend to normal mapping
    kOptSteps = 1u << 6,    // max_steps (an exact walk's iteration budget)
    kOptNormals = 1u << 7,  // shades with the normal map (PX_NORMAL_MAP); flat does not
};

struct TechniqueInfo {
    Technique id;
    const char* name;      // as written in scene files and on the command line
    const char* define;    // defined in every variant of the technique (PX_TECH_POM, ...)
    const char* source;    // shaders_es/techniques/<source>
    const char* summary;   // one line
    const char* citation;  // the paper the shader follows
    std::uint32_t options; // OptionFlag bits
    int min_es_major;      // lowest OpenGL ES major version that runs it
    int max_samples_limit; // largest max_samples (or max_steps) accepted: a constant loop bound
    // Exact only with an exact ray: the view vector is always interpolated
    // unnormalised in highp (PX_EXACT_VIEW), whatever the material asks.
    bool always_exact_view;
    // What the planner draws where a context cannot run it (older than
    // min_es_major; for maxmip also a field its pyramid cannot halve, or an
    // atlas too wide: planner.h why_technique_cannot_run): the most accurate
    // technique that runs there, at this many samples at least.
    Technique fallback;
    int fallback_min_samples;
    // Measured by `parallax bench`. flat is not: it draws no surface detail,
    // and normal mapping is the bench's baseline for "no parallax".
    bool benched;
};

const std::array<TechniqueInfo, kTechniqueCount>& technique_table();
const TechniqueInfo& technique_info(Technique t);
const char* technique_name(Technique t);
// "steep, pom, relief and maxmip": the techniques with every bit of `flags`,
// for messages that say which techniques have an option.
std::string technique_names_with(std::uint32_t flags);
Result<Technique> parse_technique(const std::string& name);
std::string technique_names_joined(const char* separator = ", ");

const char* shadow_mode_name(ShadowMode m);
Result<ShadowMode> parse_shadow_mode(const std::string& name);

// Range checks on the numbers in TechniqueOptions; the message names the field.
Status validate_options(const TechniqueOptions& options);

}  // namespace px
