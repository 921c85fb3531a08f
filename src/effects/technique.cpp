#include "parallaxes/effects/technique.h"
#include "parallaxes/core/text.h"

#include <cmath>

namespace px {

namespace {

constexpr std::uint32_t kMarchOptions =
    kOptHeight | kOptNormals | kOptSamples | kOptShadow | kOptDepth | kOptLod;

// kMaxMarchSamples and kMaxExactSteps: core/limits.h.

constexpr std::array<TechniqueInfo, kTechniqueCount> kTable = {{
    {Technique::flat, "flat", "PX_TECH_FLAT", "flat.frag", "albedo only, lit by the geometric normal", "-", 0u, 2,
     0, false, Technique::flat, 0, false},
    {Technique::normal, "normal", "PX_TECH_NORMAL", "normal.frag", "normal mapping: per-pixel normals, no parallax",
     "Blinn 1978; Peercy et al. 1997", kOptNormals, 2, 0, false, Technique::normal, 0, true},
    {Technique::parallax, "parallax", "PX_TECH_PARALLAX", "parallax.frag",
     "parallax mapping: one height fetch, offset h * V.xy / V.z", "Kaneko et al. 2001",
     kOptHeight | kOptNormals | kOptLod, 2, 0, false, Technique::parallax, 0, true},
    {Technique::offset_limited, "offset_limited", "PX_TECH_OFFSET_LIMITED", "offset_limited.frag",
     "parallax with offset limiting: offset h * V.xy, bounded by the height",
     "Welsh 2004; PowerVR Parallax Bumpmapping whitepaper", kOptHeight | kOptNormals | kOptLod, 2, 0, false,
     Technique::offset_limited, 0, true},
    {Technique::steep, "steep", "PX_TECH_STEEP", "steep.frag",
     "steep parallax: linear march, first sample under the surface", "McGuire & McGuire 2005", kMarchOptions, 2,
     kMaxMarchSamples, false, Technique::steep, 0, true},
    {Technique::pom, "pom", "PX_TECH_POM", "pom.frag",
     "parallax occlusion mapping: linear march, then the ray against the last linear segment", "Tatarchuk 2005",
     kMarchOptions, 2, kMaxMarchSamples, false, Technique::pom, 0, true},
    {Technique::relief, "relief", "PX_TECH_RELIEF", "relief.frag",
     "relief mapping: linear march, then binary refinement", "Policarpo et al. 2005", kMarchOptions | kOptRefine, 2,
     kMaxMarchSamples, false, Technique::relief, 0, true},
    {Technique::maxmip, "maxmip", "PX_TECH_MAXMIP", "maxmip.frag",
     "maximum mip-maps: skips empty space down a max pyramid of the filtered surface, then solves the "
     "bilinear patch exactly",
     "Tevs, Ihrke & Seidel 2008; Drobot 2010",
     kOptHeight | kOptNormals | kOptSteps | kOptShadow | kOptDepth | kOptLod, 2, kMaxExactSteps, true,
     Technique::relief, 64, true},
}};

constexpr bool rows_in_enum_order() {
    for (std::size_t i = 0; i < kTable.size(); ++i)
        if (static_cast<std::size_t>(kTable[i].id) != i) return false;
    return true;
}
static_assert(rows_in_enum_order(), "technique table rows must follow PX_TECHNIQUES");
// A fallback runs on every ES version (it is what an older context gets).
constexpr bool fallbacks_run_everywhere() {
    for (const TechniqueInfo& t : kTable)
        if (kTable[static_cast<std::size_t>(t.fallback)].min_es_major != 2) return false;
    return true;
}
static_assert(fallbacks_run_everywhere(), "a fallback technique must run on OpenGL ES 2.0");

}  // namespace

const std::array<TechniqueInfo, kTechniqueCount>& technique_table() { return kTable; }

const TechniqueInfo& technique_info(Technique t) { return kTable[static_cast<size_t>(t)]; }

const char* technique_name(Technique t) { return technique_info(t).name; }

std::string technique_names_with(std::uint32_t flags) {
    std::vector<const char*> names;
    for (const TechniqueInfo& info : kTable)
        if ((info.options & flags) == flags) names.push_back(info.name);
    std::string out;
    for (size_t i = 0; i < names.size(); ++i) {
        if (i > 0) out += i + 1 == names.size() ? " and " : ", ";
        out += names[i];
    }
    return out.empty() ? "none" : out;
}

std::string technique_names_joined(const char* separator) {
    std::string out;
    for (const TechniqueInfo& info : kTable) {
        if (!out.empty()) out += separator;
        out += info.name;
    }
    return out;
}

Result<Technique> parse_technique(const std::string& name) {
    for (const TechniqueInfo& info : kTable)
        if (name == info.name) return info.id;
    return make_error("unknown technique '" + echo(name) + "' (known: " + technique_names_joined() + ")");
}

const char* shadow_mode_name(ShadowMode m) {
    switch (m) {
        case ShadowMode::none: return "none";
        case ShadowMode::hard: return "hard";
        case ShadowMode::soft: return "soft";
    }
    return "?";
}

Result<ShadowMode> parse_shadow_mode(const std::string& name) {
    for (ShadowMode m : {ShadowMode::none, ShadowMode::hard, ShadowMode::soft})
        if (name == shadow_mode_name(m)) return m;
    return make_error("unknown shadow mode '" + echo(name) + "' (known: none, hard, soft)");
}

Status validate_options(const TechniqueOptions& o) {
    const TechniqueInfo& info = technique_info(o.technique);
    if (info.options & kOptSamples) {
        if (o.min_samples < 1)
            return make_error("min_samples must be at least 1 (got " + std::to_string(o.min_samples) + ")");
        if (o.max_samples < o.min_samples)
            return make_error("max_samples (" + std::to_string(o.max_samples) +
                              ") must not be below min_samples (" + std::to_string(o.min_samples) + ")");
        if (o.max_samples > info.max_samples_limit)
            return make_error("max_samples " + std::to_string(o.max_samples) + " exceeds the limit of " +
                              std::to_string(info.max_samples_limit) + " for " + info.name);
    }
    if ((info.options & kOptSteps) && (o.max_steps < 1 || o.max_steps > info.max_samples_limit))
        return make_error("max_steps must be within 1.." + std::to_string(info.max_samples_limit) + " (got " +
                          std::to_string(o.max_steps) + ")");
    if (o.refine_steps < 0 || o.refine_steps > 16)
        return make_error("refine_steps must be within 0..16 (got " + std::to_string(o.refine_steps) + ")");
    if (o.shadow_samples < 1 || o.shadow_samples > 128)
        return make_error("shadow_samples must be within 1..128 (got " + std::to_string(o.shadow_samples) + ")");
    if (!(o.lod_band > 0.0f) || !std::isfinite(o.lod_band))
        return make_error("lod_band must be a positive number of mip levels");
    if (!std::isfinite(o.lod_threshold) || o.lod_threshold < 0.0f)
        return make_error("lod_threshold must be a mip level of 0 or more");
    return {};
}

}  // namespace px
