#include "parallaxes/shaders/effect_code.h"

#include <cctype>

namespace px {

namespace {

bool has(const VariantKey& k, OptionFlag flag) { return (technique_info(k.technique).options & flag) != 0; }

bool shadows(const VariantKey& k) { return k.shadow != ShadowMode::none; }
bool hard_shadows(const VariantKey& k) { return k.shadow == ShadowMode::hard; }
bool soft_shadows(const VariantKey& k) { return k.shadow == ShadowMode::soft; }
bool depth_write(const VariantKey& k) { return k.depth_write; }
bool lod(const VariantKey& k) { return k.lod; }
bool derivatives(const VariantKey& k) { return k.lod || k.shade_lod_bias(); }
bool shade_lod_bias(const VariantKey& k) { return k.shade_lod_bias(); }
bool reads_height(const VariantKey& k) { return has(k, kOptHeight); }
bool normal_map(const VariantKey& k) { return has(k, kOptNormals); }
bool green_down(const VariantKey& k) { return has(k, kOptNormals) && k.normal_green_down; }
bool srgb_decode(const VariantKey& k) { return k.srgb_decode; }
bool srgb_output(const VariantKey& k) { return k.srgb_output && !k.debug_output; }
bool separate_height(const VariantKey& k) { return has(k, kOptHeight) && (!k.packed_height || k.es_major < 3); }
bool linear_search(const VariantKey& k) { return has(k, kOptSamples); }
bool refinement(const VariantKey& k) { return has(k, kOptRefine); }
bool max_pyramid(const VariantKey& k) { return has(k, kOptSteps); }
bool exact_view(const VariantKey& k) { return k.exact_view; }
bool per_vertex_view(const VariantKey& k) { return !k.exact_view; }
// The optimisation ladder keeps a highp view varying until its precision step.
bool highp_view_varying(const VariantKey& k) { return k.exact_view || (k.ladder_step && k.ladder_step < kLadderSteps); }
bool mediump_view_varying(const VariantKey& k) { return !highp_view_varying(k); }
bool debug_output(const VariantKey& k) { return k.debug_output != 0; }
bool count_work(const VariantKey& k) { return k.count_work; }
bool capture_ray(const VariantKey& k) { return k.capture_ray; }
bool bounded(const VariantKey& k) { return k.bounded; }
bool curved(const VariantKey& k) { return k.curved; }
bool curve_quadric(const VariantKey& k) { return k.curved && k.shape == 0; }
bool curve_shape(const VariantKey& k) { return k.curved && k.shape != 0; }
// GLSL ES 1.00 debug outputs: the 11-bit packing stays for the driver to pick
// (GL_FRAGMENT_PRECISION_HIGH) unless the key rules highp out.
bool mediump_packing(const VariantKey& k) { return k.debug_output != 0 && k.es_major < 3; }
bool highp_packing(const VariantKey& k) { return k.debug_output != 0 && !k.no_fragment_highp; }

const std::vector<EffectMarker> kMarkers = {
    // shadows.glsl: the shadow ray itself.
    {"shadows", "px_light_visibility", shadows},
    // shadows.glsl: the light's size, declared beside the only code that reads it.
    {"shadows", "u_light_angular_radius", shadows},
    // The shadow ray's loop bound, a variant define.
    {"shadows", "PX_SHADOW_SAMPLES", shadows},
    // shadows.glsl's mode constant.
    {"shadows", "PX_SHADOW_HARD", shadows},
    // The switch itself: no #ifdef PX_SHADOW is left for the driver.
    {"shadows", "PX_SHADOW", shadows},
    // shadows.glsl, hard branch: half an 8-bit quantum counts as a blocker.
    {"hard shadows", "h > ray + 1.0 / 512.0", hard_shadows},
    // shadows.glsl, soft branch: the steepest blocker's elevation (the penumbra).
    {"soft shadows", "blocker_elevation", soft_shadows},
    // surface_main.glsl: perspective-correct depth.
    {"depth write", "px_write_depth", depth_write},
    // The preamble's depth output, defined only with PX_DEPTH_WRITE.
    {"depth write", "PX_FRAG_DEPTH", depth_write},
    // GLSL ES 3.00 depth output.
    {"depth write", "gl_FragDepth", depth_write},
    // GLSL ES 1.00 depth output (GL_EXT_frag_depth).
    {"depth write", "gl_FragDepthEXT", depth_write},
    // The extension line of GLSL ES 1.00 depth variants.
    {"depth write", "GL_EXT_frag_depth", depth_write},
    // px_write_depth's projection and unit conversion.
    {"depth write", "u_depth_projection", depth_write},
    {"depth write", "u_units_per_tile", depth_write},
    // The switch: no #ifdef PX_DEPTH_WRITE is left.
    {"depth write", "PX_DEPTH_WRITE", depth_write},
    // surface_main.glsl: the mip level of the height map.
    {"lod", "px_mip_level", lod},
    // Its threshold and band.
    {"lod", "u_lod_range", lod},
    // main()'s blend toward normal mapping.
    {"lod", "lod_blend", lod},
    // The extension line of GLSL ES 1.00 LOD and shading-bias variants (dFdx, dFdy).
    {"derivatives", "GL_OES_standard_derivatives", derivatives},
    // surface_main.glsl: GLSL ES 1.00 shading at the hit with the unshifted uv's mip level.
    {"shading lod bias", "px_shade_bias", shade_lod_bias},
    {"shading lod bias", "PX_SHADE_LOD_BIAS", shade_lod_bias},
    // The switch: no #ifdef PX_LOD is left.
    {"lod", "PX_LOD", lod},
    // The technique's trace function (techniques/*.frag, called from surface_main.glsl).
    {"trace", "px_trace", reads_height},
    // Its flag: no #ifdef PX_HAS_TRACE is left in untraced variants.
    {"trace", "PX_HAS_TRACE", reads_height},
    // surface_common.glsl: the base-level height fetch.
    {"trace", "px_trace_height", reads_height},
    {"trace", "PX_HEIGHT_SAMPLER", reads_height},
    // surface.vert: the relief depth folded into the view vector.
    {"trace", "view_ts.xy *= u_parallax_scale", reads_height},
    // surface_main.glsl: the view vector unscaled for shading.
    {"trace", "view_ts.xy * u_inv_height_scale", reads_height},
    // The switch: no #ifdef PX_READS_HEIGHT is left.
    {"trace", "PX_READS_HEIGHT", reads_height},
    // surface_common.glsl: the height texture apart from the normal map.
    {"separate height map", "u_height_map", separate_height},
    // surface_main.glsl: the normal-map read (flat shades with +z).
    {"normal map", "normal_texel", normal_map},
    {"normal map", "PX_NORMAL_MAP", normal_map},
    // surface_main.glsl: a DirectX-style normal file's green negated.
    {"green down", "normal.y = -normal.y", green_down},
    {"green down", "PX_NORMAL_GREEN_DOWN", green_down},
    // lighting.glsl: the sRGB curve where the texture unit has none.
    {"srgb decode", "px_srgb_to_linear", srgb_decode},
    {"srgb decode", "PX_SRGB_DECODE", srgb_decode},
    // lighting.glsl: the output encoded for an sRGB display.
    {"srgb output", "px_linear_to_srgb", srgb_output},
    {"srgb output", "PX_SRGB_OUTPUT", srgb_output},
    // march.glsl: the linear search of steep, pom and relief.
    {"linear search", "px_linear_search", linear_search},
    {"linear search", "PxMarch", linear_search},
    // march.glsl: Tatarchuk's dynamic sample count.
    {"linear search", "u_sample_range", linear_search},
    // relief.frag: the binary refinement's bound.
    {"refinement", "PX_REFINE_STEPS", refinement},
    // maxmip.frag: the max pyramid and its walk.
    {"max pyramid", "u_max_map", max_pyramid},
    {"max pyramid", "u_max_levels", max_pyramid},
    {"max pyramid", "u_max_atlas", max_pyramid},
    {"max pyramid", "px_node_max", max_pyramid},
    {"max pyramid", "px_solve_patch", max_pyramid},
    // surface.vert, PX_EXACT_VIEW: the view vector left unnormalised in highp.
    {"exact view", "highp vec3 view_ts = vec3(", exact_view},
    // surface_main.glsl, PX_EXACT_VIEW: normalised per fragment.
    {"exact view", "view_ts /= length(view_unscaled)", exact_view},
    // interface.glsl, PX_EXACT_VIEW: the view varying's precision.
    {"exact view", "#define PX_VIEW_PRECISION PX_HIGHP", highp_view_varying},
    // The switch: no #ifdef PX_EXACT_VIEW is left.
    {"exact view", "PX_EXACT_VIEW", exact_view},
    // surface.vert without PX_EXACT_VIEW: normalised per vertex in mediump.
    {"per-vertex view", "mediump vec3 view_ts = normalize(", per_vertex_view},
    // interface.glsl without PX_EXACT_VIEW.
    {"per-vertex view", "#define PX_VIEW_PRECISION mediump", mediump_view_varying},
    // debug_output.glsl: the output and its packing helpers.
    {"debug output", "px_debug_output", debug_output},
    {"debug output", "px_pack24", debug_output},
    {"debug output", "px_pack16", debug_output},
    {"debug output", "px_is_finite", debug_output},
    {"debug output", "PX_DEBUG_NON_FINITE", debug_output},
    {"debug output", "PX_DEBUG_DRAWN", debug_output},
    // The switch: no #ifdef PX_DEBUG_OUTPUT is left.
    {"debug output", "PX_DEBUG_OUTPUT", debug_output},
    // surface_common.glsl: the work counter (VariantKey::count_work).
    {"work counts", "px_work", count_work},
    {"work counts", "PX_COUNT_WORK", count_work},
    // surface_main.glsl: the traced ray in place of the hit (VariantKey::capture_ray).
    {"ray capture", "PX_CAPTURE_RAY", capture_ray},
    // surface_main.glsl: a bounded relief's discard.
    {"bounded", "u_bounds_matrix", bounded},
    {"bounded", "u_wall_scale", bounded},
    {"bounded", "v_wall_height", bounded},
    {"bounded", "PX_BOUNDED", bounded},
    // surface.vert and march.glsl: the curved relief's quadric and march.
    {"curved", "px_curved_uv", curved},
    {"curved quadric", "a_curvature", curve_quadric},
    {"curved quadric", "u_curvature_scale", curve_quadric},
    {"curved quadric", "u_uv_bend_scale", curve_quadric},
    {"curved quadric", "v_uv_bend", curve_quadric},
    // march.glsl: the exact curved search's shape.
    {"curved shape", "u_shape", curve_shape},
    {"curved shape", "px_shape_uv", curve_shape},
    {"curved shape", "v_object_position", curve_shape},
    {"curved shape", "PX_SHAPE", curve_shape},
    {"curved", "px_curved_search", curved},
    {"curved", "PX_CURVED", curved},
    // debug_output.glsl: the 11-bit packing of a fragment stage without highp.
    {"mediump debug packing", "px_pack11", mediump_packing},
    // debug_output.glsl: the 24-bit packing, which needs highp.
    {"highp debug packing", "16777215.0", highp_packing},
};

bool is_word(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// Comments removed (code only: a comment may name what it no longer holds)
// and whitespace runs, newlines included, as one space.
std::string code_only(const std::string& s) {
    std::string out;
    bool space = false;
    for (size_t i = 0; i < s.size(); ++i) {
        char c = s[i];
        if (s.compare(i, 2, "//") == 0) {
            i = s.find('\n', i);
            if (i == std::string::npos) break;
            c = '\n';
        } else if (s.compare(i, 2, "/*") == 0) {
            i = s.find("*/", i + 2);
            if (i == std::string::npos) break;
            ++i;
            c = ' ';
        }
        if (std::isspace(static_cast<unsigned char>(c))) {
            space = true;
            continue;
        }
        if (space && !out.empty()) out += ' ';
        space = false;
        out += c;
    }
    return out;
}

bool contains(const std::string& code, const std::string& marker) {
    for (size_t at = code.find(marker); at != std::string::npos; at = code.find(marker, at + 1)) {
        const size_t end = at + marker.size();
        const bool starts_word = at > 0 && is_word(marker.front()) && is_word(code[at - 1]);
        const bool ends_word = end < code.size() && is_word(marker.back()) && is_word(code[end]);
        if (!starts_word && !ends_word) return true;
    }
    return false;
}

}  // namespace

const std::vector<EffectMarker>& effect_markers() { return kMarkers; }

std::vector<std::size_t> effect_markers_in(const VariantSources& sources) {
    const std::string vertex = code_only(sources.vertex.text);
    const std::string fragment = code_only(sources.fragment.text);
    std::vector<std::size_t> found;
    for (std::size_t i = 0; i < kMarkers.size(); ++i)
        if (contains(vertex, kMarkers[i].code) || contains(fragment, kMarkers[i].code)) found.push_back(i);
    return found;
}

std::vector<std::string> unused_effect_code(const VariantKey& key, const VariantSources& sources) {
    const VariantKey k = key.canonical();
    std::vector<std::string> out;
    for (std::size_t i : effect_markers_in(sources)) {
        const EffectMarker& m = kMarkers[i];
        if (!m.used(k))
            out.push_back(std::string(m.effect) + ": '" + m.code + "' in variant '" + k.describe() +
                          "', which does not use it");
    }
    return out;
}

}  // namespace px
