#include "parallaxes/effects/variant.h"

#include <algorithm>
#include <sstream>

#include "parallaxes/core/limits.h"

namespace px {

namespace {

bool has_option(Technique t, OptionFlag flag) { return (technique_info(t).options & flag) != 0; }

}  // namespace

VariantKey VariantKey::canonical() const {
    VariantKey k = *this;
    if (!has_option(k.technique, kOptHeight)) k.packed_height = false;
    if (!has_option(k.technique, kOptHeight)) k.exact_view = false;
    if (!(technique_info(k.technique).options & kOptNormals)) k.normal_rg = false;
    // Only the exact walk snaps heights to their texel grid.
    if (!has_option(k.technique, kOptSteps)) k.height_11bit = false;
    if (k.packed_height) k.height_11bit = false;
    // GLSL ES 1.00's walk reads 8-bit corners from its atlas (an ES 2.0
    // context decodes EAC R11 to 8 bits anyway).
    if (k.es_major < 3) k.height_11bit = false;
    if (!(technique_info(k.technique).options & kOptNormals)) k.flip_v &= static_cast<std::uint8_t>(~kFlipNormal);
    if (!has_option(k.technique, kOptHeight) || k.packed_height) k.flip_v &= static_cast<std::uint8_t>(~kFlipHeight);
    k.flip_v &= kFlipAlbedo | kFlipNormal | kFlipHeight;
    if (technique_info(k.technique).always_exact_view) k.exact_view = true;
    if (!has_option(k.technique, kOptSamples) && !has_option(k.technique, kOptSteps)) k.max_samples = 0;
    if (!has_option(k.technique, kOptRefine)) k.refine_steps = 0;
    if (!has_option(k.technique, kOptShadow)) k.shadow = ShadowMode::none;
    if (k.shadow == ShadowMode::none) k.shadow_samples = 0;
    if (!has_option(k.technique, kOptDepth)) k.depth_write = false;
    if (!has_option(k.technique, kOptLod)) k.lod = false;
    if (k.es_major >= 3) k.no_fragment_highp = false;  // ES 3.0 guarantees fragment highp
    // Only a trace can leave the bounds: normal mapping shades the polygon.
    if (!has_option(k.technique, kOptHeight)) k.bounded = false;
    // The curved march is the linear search's (march.glsl px_curved_search).
    if (!has_option(k.technique, kOptSamples)) k.curved = false;
    if (!k.curved || k.shape > kShapeTorus) k.shape = 0;
    if (k.debug_output == 0 || !(has_option(k.technique, kOptSamples) || has_option(k.technique, kOptSteps)))
        k.count_work = false;
    if (k.debug_output != 1 || k.count_work || !has_option(k.technique, kOptHeight)) k.capture_ray = false;
    if (k.technique != Technique::offset_limited || k.ladder_step > kLadderSteps) k.ladder_step = 0;
    // The ladder's shaders have their own view vector (each step decides
    // where it is normalised) and the whitepaper's layouts only.
    if (k.ladder_step) {
        k.exact_view = false;
        k.normal_rg = false;
        k.lod = false;
        k.flip_v = 0;
        k.bounded = false;
        k.curved = false;
        k.shape = 0;
        k.capture_ray = false;  // the ladder's shaders have no capture
    }
    // Only GLSL ES 1.00 shading at a moved uv reads with texture2D's bias.
    if (k.es_major >= 3 || !has_option(k.technique, kOptHeight) || k.ladder_step) k.no_derivatives = false;
    return k;
}

std::uint64_t VariantKey::bits() const {
    const VariantKey k = canonical();
    std::uint64_t b = 0;
    static_assert(kTechniqueCount <= 8, "the key holds the technique in 3 bits");
    b |= static_cast<std::uint64_t>(k.technique);             // 3 bits
    b |= static_cast<std::uint64_t>(k.shadow) << 3;           // 2 bits
    b |= static_cast<std::uint64_t>(k.depth_write) << 5;
    b |= static_cast<std::uint64_t>(k.lod) << 6;
    b |= static_cast<std::uint64_t>(k.packed_height) << 7;
    b |= static_cast<std::uint64_t>(k.es_major & 0xF) << 8;   // 4 bits
    b |= static_cast<std::uint64_t>(k.max_samples) << 12;     // 16 bits
    b |= static_cast<std::uint64_t>(k.refine_steps) << 28;    // 8 bits
    b |= static_cast<std::uint64_t>(k.shadow_samples) << 36;  // 8 bits
    b |= static_cast<std::uint64_t>(k.debug_output & 0x7) << 44;  // 3 bits
    b |= static_cast<std::uint64_t>(k.exact_view) << 47;
    b |= static_cast<std::uint64_t>(k.no_fragment_highp) << 48;
    b |= static_cast<std::uint64_t>(k.normal_rg) << 49;
    b |= static_cast<std::uint64_t>(k.height_11bit) << 50;
    b |= static_cast<std::uint64_t>(k.ladder_step & 0x7) << 51;  // 3 bits
    b |= static_cast<std::uint64_t>(k.flip_v & 0x7) << 54;       // 3 bits
    b |= static_cast<std::uint64_t>(k.count_work) << 57;
    b |= static_cast<std::uint64_t>(k.bounded) << 58;
    b |= static_cast<std::uint64_t>(k.capture_ray) << 59;
    b |= static_cast<std::uint64_t>(k.curved) << 60;
    b |= static_cast<std::uint64_t>(k.shape & 0x3) << 61;  // 2 bits
    b |= static_cast<std::uint64_t>(k.no_derivatives) << 63;
    return b;
}

std::optional<VariantKey> VariantKey::from_bits(std::uint64_t b) {
    VariantKey k;
    const std::uint64_t technique = b & 0x7;
    if (technique >= static_cast<std::uint64_t>(kTechniqueCount)) return std::nullopt;
    k.technique = static_cast<Technique>(technique);
    const std::uint64_t shadow = (b >> 3) & 0x3;
    if (shadow > 2) return std::nullopt;
    k.shadow = static_cast<ShadowMode>(shadow);
    k.depth_write = (b >> 5) & 1;
    k.lod = (b >> 6) & 1;
    k.packed_height = (b >> 7) & 1;
    k.es_major = static_cast<std::uint8_t>((b >> 8) & 0xF);
    k.max_samples = static_cast<std::uint16_t>((b >> 12) & 0xFFFF);
    k.refine_steps = static_cast<std::uint8_t>((b >> 28) & 0xFF);
    k.shadow_samples = static_cast<std::uint8_t>((b >> 36) & 0xFF);
    k.debug_output = static_cast<std::uint8_t>((b >> 44) & 0x7);
    k.exact_view = (b >> 47) & 1;
    k.no_fragment_highp = (b >> 48) & 1;
    k.normal_rg = (b >> 49) & 1;
    k.height_11bit = (b >> 50) & 1;
    k.ladder_step = static_cast<std::uint8_t>((b >> 51) & 0x7);
    k.flip_v = static_cast<std::uint8_t>((b >> 54) & 0x7);
    k.count_work = (b >> 57) & 1;
    k.bounded = (b >> 58) & 1;
    k.capture_ray = (b >> 59) & 1;
    k.curved = (b >> 60) & 1;
    k.shape = static_cast<std::uint8_t>((b >> 61) & 0x3);
    k.no_derivatives = (b >> 63) & 1;
    if (k.bits() != b) return std::nullopt;  // not canonical, or bits past the key's
    return k;
}

std::vector<ShaderDefine> VariantKey::defines() const {
    const VariantKey k = canonical();
    const TechniqueInfo& info = technique_info(k.technique);
    std::vector<ShaderDefine> d;
    d.push_back({"PX_MAX_LIGHTS", std::to_string(kMaxLights)});
    d.push_back({info.define, ""});
    if (info.options & kOptNormals) d.push_back({"PX_NORMAL_MAP", ""});
    if (info.options & kOptHeight) d.push_back({"PX_READS_HEIGHT", ""});
    if (k.packed_height) d.push_back({"PX_PACKED_HEIGHT", ""});
    if (k.exact_view) d.push_back({"PX_EXACT_VIEW", ""});
    if (k.normal_rg) d.push_back({"PX_NORMAL_RG", ""});
    if (k.height_11bit) d.push_back({"PX_HEIGHT_11BIT", ""});
    // The loop bound: samples of a linear search, or steps of an exact walk.
    if (info.options & (kOptSamples | kOptSteps)) d.push_back({"PX_MAX_SAMPLES", std::to_string(k.max_samples)});
    if (info.options & kOptRefine) d.push_back({"PX_REFINE_STEPS", std::to_string(k.refine_steps)});
    if (k.shadow != ShadowMode::none) {
        d.push_back({"PX_SHADOW", k.shadow == ShadowMode::hard ? "1" : "2"});
        d.push_back({"PX_SHADOW_SAMPLES", std::to_string(k.shadow_samples)});
    }
    if (k.depth_write) d.push_back({"PX_DEPTH_WRITE", ""});
    if (k.lod) d.push_back({"PX_LOD", ""});
    if (k.debug_output) d.push_back({"PX_DEBUG_OUTPUT", std::to_string(k.debug_output)});
    if (k.count_work) d.push_back({"PX_COUNT_WORK", ""});
    if (k.capture_ray) d.push_back({"PX_CAPTURE_RAY", ""});
    if (k.bounded) d.push_back({"PX_BOUNDED", ""});
    if (k.curved) d.push_back({"PX_CURVED", ""});
    if (k.shape) d.push_back({"PX_SHAPE", std::to_string(k.shape)});
    if (k.no_fragment_highp) d.push_back({"PX_NO_FRAGMENT_HIGHP", ""});
    if (k.ladder_step) d.push_back({"PX_LADDER_STEP", std::to_string(k.ladder_step)});
    if (k.flip_v & kFlipAlbedo) d.push_back({"PX_FLIP_ALBEDO_V", ""});
    if (k.flip_v & kFlipNormal) d.push_back({"PX_FLIP_NORMAL_V", ""});
    if (k.flip_v & kFlipHeight) d.push_back({"PX_FLIP_HEIGHT_V", ""});
    if (k.shade_lod_bias()) d.push_back({"PX_SHADE_LOD_BIAS", ""});
    return d;
}

bool VariantKey::shade_lod_bias() const {
    const VariantKey k = canonical();
    return k.es_major < 3 && has_option(k.technique, kOptHeight) && !k.ladder_step && !k.no_derivatives;
}

std::vector<std::string> VariantKey::extensions(ShaderStage stage) const {
    const VariantKey k = canonical();
    std::vector<std::string> e;
    if (k.es_major >= 3 || stage != ShaderStage::fragment) return e;
    if (k.depth_write) e.push_back("GL_EXT_frag_depth");
    if (k.lod || k.shade_lod_bias()) e.push_back("GL_OES_standard_derivatives");
    return e;
}

std::string VariantKey::describe() const {
    const VariantKey k = canonical();
    std::ostringstream s;
    s << technique_name(k.technique) << " es" << int(k.es_major);
    if (k.max_samples) s << (has_option(k.technique, kOptSteps) ? " steps<=" : " samples<=") << k.max_samples;
    if (has_option(k.technique, kOptRefine)) s << " refine=" << int(k.refine_steps);
    if (k.shadow != ShadowMode::none) s << " shadow=" << shadow_mode_name(k.shadow) << "x" << int(k.shadow_samples);
    if (k.depth_write) s << " depth";
    if (k.lod) s << " lod";
    if (k.exact_view) s << " exact-view";
    if (has_option(k.technique, kOptHeight)) s << (k.packed_height ? " packed" : " separate-height");
    if (k.normal_rg) s << " normal-rg";
    if (k.height_11bit) s << " height-11bit";
    if (k.debug_output) s << " debug" << int(k.debug_output);
    if (k.count_work) s << " count-work";
    if (k.capture_ray) s << " capture-ray";
    if (k.bounded) s << " bounded";
    if (k.curved) s << " curved";
    if (k.shape) s << " shape=" << (k.shape == kShapeSphere ? "sphere" : k.shape == kShapeCylinder ? "cylinder" : "torus");
    if (k.no_fragment_highp) s << " no-fragment-highp";
    if (k.ladder_step) s << " ladder" << int(k.ladder_step);
    if (k.flip_v & kFlipAlbedo) s << " flip-albedo";
    if (k.flip_v & kFlipNormal) s << " flip-normal";
    if (k.flip_v & kFlipHeight) s << " flip-height";
    if (k.no_derivatives) s << " no-derivatives";
    return s.str();
}

Result<VariantKey> VariantKey::parse(const std::string& name) {
    std::istringstream words(name);
    std::string word;
    if (!(words >> word)) return make_error("an empty variant name");
    Result<Technique> technique = parse_technique(word);
    if (!technique) return technique.error();
    VariantKey k;
    k.technique = *technique;
    k.packed_height = false;
    auto number = [](const std::string& text, long limit, long& out) {
        if (text.empty() || text.size() > 6 || text.find_first_not_of("0123456789") != std::string::npos) return false;
        out = std::stol(text);
        return out <= limit;
    };
    while (words >> word) {
        long n = 0;
        if (word.rfind("es", 0) == 0 && number(word.substr(2), 3, n) && n >= 2) k.es_major = static_cast<std::uint8_t>(n);
        else if ((word.rfind("samples<=", 0) == 0 && number(word.substr(9), 65535, n)) ||
                 (word.rfind("steps<=", 0) == 0 && number(word.substr(7), 65535, n)))
            k.max_samples = static_cast<std::uint16_t>(n);
        else if (word.rfind("refine=", 0) == 0 && number(word.substr(7), 255, n)) k.refine_steps = static_cast<std::uint8_t>(n);
        else if (word.rfind("shadow=", 0) == 0 && word.find('x') != std::string::npos) {
            const std::string mode = word.substr(7, word.find('x') - 7);
            if (!number(word.substr(word.find('x') + 1), 255, n)) return make_error("variant '" + name + "': bad '" + word + "'");
            if (mode == "hard") k.shadow = ShadowMode::hard;
            else if (mode == "soft") k.shadow = ShadowMode::soft;
            else return make_error("variant '" + name + "': bad '" + word + "'");
            k.shadow_samples = static_cast<std::uint8_t>(n);
        } else if (word == "depth") k.depth_write = true;
        else if (word == "lod") k.lod = true;
        else if (word == "exact-view") k.exact_view = true;
        else if (word == "packed") k.packed_height = true;
        else if (word == "separate-height") k.packed_height = false;
        else if (word == "normal-rg") k.normal_rg = true;
        else if (word == "height-11bit") k.height_11bit = true;
        else if (word.rfind("debug", 0) == 0 && number(word.substr(5), 4, n) && n >= 1) k.debug_output = static_cast<std::uint8_t>(n);
        else if (word == "no-fragment-highp") k.no_fragment_highp = true;
        else if (word == "count-work") k.count_work = true;
        else if (word == "capture-ray") k.capture_ray = true;
        else if (word == "bounded") k.bounded = true;
        else if (word == "curved") k.curved = true;
        else if (word == "shape=sphere") k.shape = kShapeSphere;
        else if (word == "shape=cylinder") k.shape = kShapeCylinder;
        else if (word == "shape=torus") k.shape = kShapeTorus;
        else if (word == "flip-albedo") k.flip_v |= kFlipAlbedo;
        else if (word == "flip-normal") k.flip_v |= kFlipNormal;
        else if (word == "flip-height") k.flip_v |= kFlipHeight;
        else if (word == "no-derivatives") k.no_derivatives = true;
        else if (word.rfind("ladder", 0) == 0 && number(word.substr(6), kLadderSteps, n) && n >= 1)
            k.ladder_step = static_cast<std::uint8_t>(n);
        else return make_error("variant '" + name + "': unknown word '" + word + "'");
    }
    // What the technique ignores is dropped; a name that is not what the
    // key describes (an option the technique lacks) is refused.
    if (k.describe() != name)
        return make_error("variant '" + name + "' is not a variant's name (the nearest is '" + k.describe() + "')");
    return k.canonical();
}

std::string VariantKey::vertex_entry() const {
    return canonical().ladder_step ? "ladder/offset_ladder.vert" : "surface.vert";
}

std::string VariantKey::fragment_entry() const {
    const VariantKey k = canonical();
    if (k.ladder_step) return "ladder/offset_ladder.frag";
    return std::string("techniques/") + technique_info(k.technique).source;
}

const LadderStep& ladder_step_info(int step) {
    // PowerVR "Parallax Bumpmapping" whitepaper (2016), sections 3.1 to 3.2.2.
    static const LadderStep steps[kLadderSteps] = {
        {1, "baseline", "everything highp; the eye-to-tangent matrix built per vertex from the world-view product; "
                        "the view vector normalised and the parallax scale applied in the fragment shader; "
                        "texture reads interleaved with the math that uses them"},
        {2, "eye-to-tangent matrix", "the frame from the inverse-transpose matrix the CPU computes (a uniform) "
                                     "instead of per-vertex matrix products (3.1)"},
        {3, "view normalised per vertex", "the view vector normalised in the vertex shader, not per fragment (3.1)"},
        {4, "scale in the vertex shader", "the parallax scale folded into the view vector per vertex (3.2)"},
        {5, "reads back to back", "the two dependent reads (normal, albedo) issued together before any math on "
                                  "them: one wait instead of two (3.2.1)"},
        {6, "lowp and mediump", "fragment math in mediump, colours and normals in lowp, where they hold (3.2.2)"},
    };
    static const LadderStep none{0, "shipped", "the shipped offset_limited shader"};
    return step >= 1 && step <= kLadderSteps ? steps[step - 1] : none;
}

VariantKey VariantKey::with_layout(const TextureLayout& layout) const {
    VariantKey k = *this;
    k.packed_height = layout.packed_height;
    k.normal_rg = layout.normal_rg;
    k.height_11bit = layout.height_11bit;
    k.flip_v = layout.flip_v;
    return k;
}

VariantKey default_variant(const TechniqueInfo& info, int es_major) {
    const TechniqueOptions defaults;
    VariantKey base;
    base.technique = info.id;
    base.es_major = static_cast<std::uint8_t>(es_major);
    base.max_samples = static_cast<std::uint16_t>((info.options & kOptSteps) ? defaults.max_steps : defaults.max_samples);
    base.refine_steps = static_cast<std::uint8_t>(defaults.refine_steps);
    base.shadow_samples = static_cast<std::uint8_t>(defaults.shadow_samples);
    return base;
}

std::vector<VariantKey> enumerate_variants(int es_major) {
    std::vector<VariantKey> out;
    auto add = [&out](const VariantKey& k) {
        const VariantKey c = k.canonical();
        for (const VariantKey& e : out)
            if (e == c) return;
        out.push_back(c);
    };
    for (const TechniqueInfo& info : technique_table()) {
        if (info.min_es_major > es_major) continue;
        const VariantKey base = default_variant(info, es_major);
        for (int packed = 0; packed < 2; ++packed)
            for (ShadowMode shadow : {ShadowMode::none, ShadowMode::hard, ShadowMode::soft})
                for (int depth = 0; depth < 2; ++depth)
                    for (int lod = 0; lod < 2; ++lod) {
                        VariantKey k = base;
                        k.packed_height = packed != 0;
                        k.shadow = shadow;
                        k.depth_write = depth != 0;
                        k.lod = lod != 0;
                        k.exact_view = false;  // canonical() keeps it on where the technique always has it
                        add(k);
                        k.exact_view = true;
                        add(k);
                    }
        // Compressed-texture layouts: two-channel normals, 11-bit heights.
        for (int layout = 0; layout < 2; ++layout) {
            VariantKey k = base;
            k.packed_height = false;
            k.normal_rg = true;
            k.height_11bit = layout != 0;
            k.shadow = ShadowMode::soft;
            add(k);
        }
        // A bounded relief (canonical() keeps it for traced techniques), with
        // the options that touch the hit it tests: depth, LOD, debug output.
        for (int debug : {0, es_major >= 3 ? 1 : 2}) {
            VariantKey k = base;
            k.bounded = true;
            k.depth_write = true;
            k.lod = true;
            k.debug_output = static_cast<std::uint8_t>(debug);
            add(k);
            // Curved-relief silhouettes (canonical() keeps them for the linear searches).
            k.bounded = false;
            k.curved = true;
            k.shadow = ShadowMode::soft;
            add(k);
            // The exact curved search, one shape each.
            for (std::uint8_t shape : {kShapeSphere, kShapeCylinder, kShapeTorus}) {
                k.shape = shape;
                add(k);
            }
            // A bounded tube's (its ends in the search: PX_SHAPE_TUBE), and
            // an ES 2.0 context without fragment highp's.
            k.bounded = true;
            k.shape = kShapeCylinder;
            add(k);
            if (es_major < 3) {
                k.no_fragment_highp = true;
                add(k);
                // A context without GL_OES_standard_derivatives (no LOD there).
                k.no_derivatives = true;
                k.lod = false;
                add(k);
                k.no_derivatives = false;
                k.lod = true;
                k.bounded = false;
                k.shape = kShapeTorus;
                add(k);
                k.no_fragment_highp = false;
            }
            k.bounded = false;
            k.shape = 0;
        }
        // Debug outputs, with every option the technique has switched on.
        for (int debug = 1; debug <= 4; ++debug) {
            VariantKey k = base;
            k.shadow = ShadowMode::soft;
            k.depth_write = true;
            k.lod = true;
            k.debug_output = static_cast<std::uint8_t>(debug);
            if (es_major >= 3 || debug >= 2) add(k);
            // GLSL ES 1.00 without fragment highp: the 11-bit packing.
            k.no_fragment_highp = true;
            if (es_major < 3 && debug >= 2) add(k);
            // The work counts (canonical() keeps them for searches only).
            k.no_fragment_highp = false;
            k.count_work = true;
            if (es_major >= 3 || debug >= 2) add(k);
            // The traced ray in place of the hit (canonical() keeps it for the float target only).
            k.count_work = false;
            k.capture_ray = true;
            if (es_major >= 3 && debug == 1) add(k);
            k.capture_ray = false;
        }
        // Loop bounds at their extremes.
        if (info.options & (kOptSamples | kOptSteps)) {
            for (int samples : {1, info.max_samples_limit}) {
                VariantKey k = base;
                k.max_samples = static_cast<std::uint16_t>(samples);
                k.shadow = ShadowMode::soft;
                k.shadow_samples = 128;
                add(k);
            }
        }
        // The PowerVR whitepaper's optimisation ladder (shaders_es/ladder/).
        if (info.id == Technique::offset_limited)
            for (int packed = 0; packed < 2; ++packed)
                for (int step = 1; step <= kLadderSteps; ++step) {
                    VariantKey k = base;
                    k.packed_height = packed != 0;
                    k.ladder_step = static_cast<std::uint8_t>(step);
                    add(k);
                    for (int debug = 1; debug <= 4; ++debug) {
                        k.debug_output = static_cast<std::uint8_t>(debug);
                        if (es_major >= 3 || debug >= 2) add(k);
                    }
                }
        if (info.options & kOptRefine) {
            for (int steps : {0, 16}) {
                VariantKey k = base;
                k.refine_steps = static_cast<std::uint8_t>(steps);
                add(k);
            }
        }
    }
    return out;
}

}  // namespace px
