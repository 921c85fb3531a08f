#include "parallaxes/effects/variant.h"

#include <algorithm>
#include <iterator>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <utility>

#include "parallaxes/core/limits.h"

namespace px {

namespace {

bool has_option(Technique t, OptionFlag flag) { return (technique_info(t).options & flag) != 0; }

std::recursive_mutex g_fields_mutex;  // the field table, which add_variant_field extends

// Fields added at run time (add_variant_field), after the table's, in the
// order they were added.
std::vector<AddedVariantField>& added_fields() {
    static std::vector<AddedVariantField> fields;
    return fields;
}

const AddedVariantField* added_field(const std::string& word) {
    for (const AddedVariantField& f : added_fields())
        if (f.word == word) return &f;
    return nullptr;
}

}  // namespace

VariantKey VariantKey::canonical() const {
    VariantKey k = *this;
    if (!has_option(k.technique, kOptHeight)) k.packed_height = false;
    if (!has_option(k.technique, kOptHeight)) k.exact_view = false;
    if (!(technique_info(k.technique).options & kOptNormals)) k.normal_rg = false;
    if (!(technique_info(k.technique).options & kOptNormals)) k.normal_green_down = false;
    // Only the exact walk snaps heights to their texel grid.
    if (!has_option(k.technique, kOptSteps)) k.height_11bit = false;
    if (k.packed_height) k.height_11bit = false;
    // GLSL ES 1.00's walk reads 8-bit corners from its atlas (an ES 2.0
    // context decodes EAC R11 to 8 bits anyway).
    if (k.es_major < 3) k.height_11bit = false;
    if (!(technique_info(k.technique).options & kOptNormals)) k.flip_v &= static_cast<std::uint8_t>(~kFlipNormal);
    // Packed height is the normal texture's alpha: read where its normals are.
    if (!has_option(k.technique, kOptHeight) || k.packed_height) k.flip_v &= static_cast<std::uint8_t>(~kFlipHeight);
    if (has_option(k.technique, kOptHeight) && k.packed_height && (k.flip_v & kFlipNormal)) k.flip_v |= kFlipHeight;
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
    // Debug outputs write data, not colour.
    if (k.debug_output != 0) k.srgb_output = false;
    if (k.debug_output == 0 || !(has_option(k.technique, kOptSamples) || has_option(k.technique, kOptSteps)))
        k.count_work = false;
    if (k.debug_output != 1 || k.count_work || !has_option(k.technique, kOptHeight)) k.capture_ray = false;
    if (k.technique != Technique::offset_limited || k.ladder_step > kLadderSteps) k.ladder_step = 0;
    // The ladder's shaders have their own view vector (each step decides
    // where it is normalised) and the whitepaper's layouts only.
    if (k.ladder_step) {
        k.exact_view = false;
        k.normal_rg = false;
        k.normal_green_down = false;
        k.lod = false;
        k.flip_v = 0;
        k.bounded = false;
        k.curved = false;
        k.shape = 0;
        k.capture_ray = false;  // the ladder's shaders have no capture
    }
    // Only GLSL ES 1.00 shading at a moved uv reads with texture2D's bias.
    if (k.es_major >= 3 || !has_option(k.technique, kOptHeight) || k.ladder_step) k.no_derivatives = false;
    // Fields added at run time: only for techniques with their options,
    // and a zero is no entry (so that equal programs have equal keys).
    if (!k.added.empty()) {
        std::lock_guard<std::recursive_mutex> lock(g_fields_mutex);
        for (auto it = k.added.begin(); it != k.added.end();) {
            const AddedVariantField* f = added_field(it->first);
            const bool kept = it->second != 0 && f &&
                              (technique_info(k.technique).options & f->technique_options) == f->technique_options;
            it = kept ? std::next(it) : k.added.erase(it);
        }
    }
    return k;
}

namespace {

// A non-negative decimal of at most 6 digits, at most `limit`.
bool read_number(const std::string& text, long limit, long& out) {
    if (text.empty() || text.size() > 6 || text.find_first_not_of("0123456789") != std::string::npos) return false;
    out = std::stol(text);
    return out <= limit;
}

// `word` is `prefix` followed by a number within [low, limit].
bool prefixed_number(const std::string& word, const std::string& prefix, long low, long limit, long& out) {
    return word.rfind(prefix, 0) == 0 && read_number(word.substr(prefix.size()), limit, out) && out >= low;
}

const char* shape_name(std::uint8_t shape) {
    return shape == kShapeSphere ? "sphere" : shape == kShapeCylinder ? "cylinder" : "torus";
}

bool flag_set(const VariantField& f, const VariantKey& k) { return f.flag ? k.*f.flag : (k.flip_v & f.flip_bit) != 0; }

// Every field of a variant, in the order of its description: describe()
// and parse() read this table, defines() emits in its order, and the
// identity and the program cache's key come from the description. A flag
// is one row of data (its word, its define, its member or flip bit); the
// other fields have their own three functions. Adding a field is one row
// here, a member in VariantKey and its rule in canonical().
const VariantField kFields[] = {
    // The technique: the description's first word (parse reads it apart).
    {"technique", nullptr, nullptr, nullptr, 0,
     [](const VariantKey& k, std::string& out) { out += technique_name(k.technique); },
     [](const std::string&, VariantKey&) { return false; },
     [](const VariantKey& k, std::vector<ShaderDefine>& out) {
         const TechniqueInfo& info = technique_info(k.technique);
         out.push_back({"PX_MAX_LIGHTS", std::to_string(kMaxLights)});
         out.push_back({info.define, ""});
         if (info.options & kOptNormals) out.push_back({"PX_NORMAL_MAP", ""});
         if (info.options & kOptHeight) out.push_back({"PX_READS_HEIGHT", ""});
     }},
    {"es", nullptr, nullptr, nullptr, 0,
     [](const VariantKey& k, std::string& out) { out += " es" + std::to_string(int(k.es_major)); },
     [](const std::string& w, VariantKey& k) {
         long n = 0;
         if (!prefixed_number(w, "es", 2, 3, n)) return false;
         k.es_major = static_cast<std::uint8_t>(n);
         return true;
     },
     [](const VariantKey&, std::vector<ShaderDefine>&) {}},  // the preamble's #version
    // The loop bound: samples of a linear search, or steps of an exact walk.
    {"max_samples", nullptr, nullptr, nullptr, 0,
     [](const VariantKey& k, std::string& out) {
         if (k.max_samples)
             out += (has_option(k.technique, kOptSteps) ? " steps<=" : " samples<=") + std::to_string(k.max_samples);
     },
     [](const std::string& w, VariantKey& k) {
         long n = 0;
         if (!prefixed_number(w, "samples<=", 0, 65535, n) && !prefixed_number(w, "steps<=", 0, 65535, n)) return false;
         k.max_samples = static_cast<std::uint16_t>(n);
         return true;
     },
     [](const VariantKey& k, std::vector<ShaderDefine>& out) {
         if (has_option(k.technique, kOptSamples) || has_option(k.technique, kOptSteps))
             out.push_back({"PX_MAX_SAMPLES", std::to_string(k.max_samples)});
     }},
    {"refine_steps", nullptr, nullptr, nullptr, 0,
     [](const VariantKey& k, std::string& out) {
         if (has_option(k.technique, kOptRefine)) out += " refine=" + std::to_string(int(k.refine_steps));
     },
     [](const std::string& w, VariantKey& k) {
         long n = 0;
         if (!prefixed_number(w, "refine=", 0, 255, n)) return false;
         k.refine_steps = static_cast<std::uint8_t>(n);
         return true;
     },
     [](const VariantKey& k, std::vector<ShaderDefine>& out) {
         if (has_option(k.technique, kOptRefine)) out.push_back({"PX_REFINE_STEPS", std::to_string(k.refine_steps)});
     }},
    {"shadow", nullptr, nullptr, nullptr, 0,
     [](const VariantKey& k, std::string& out) {
         if (k.shadow != ShadowMode::none)
             out += std::string(" shadow=") + shadow_mode_name(k.shadow) + "x" + std::to_string(int(k.shadow_samples));
     },
     [](const std::string& w, VariantKey& k) {
         const size_t x = w.find('x');
         long n = 0;
         if (w.rfind("shadow=", 0) != 0 || x == std::string::npos || !read_number(w.substr(x + 1), 255, n)) return false;
         const std::string mode = w.substr(7, x - 7);
         if (mode != "hard" && mode != "soft") return false;
         k.shadow = mode == "hard" ? ShadowMode::hard : ShadowMode::soft;
         k.shadow_samples = static_cast<std::uint8_t>(n);
         return true;
     },
     [](const VariantKey& k, std::vector<ShaderDefine>& out) {
         if (k.shadow == ShadowMode::none) return;
         out.push_back({"PX_SHADOW", k.shadow == ShadowMode::hard ? "1" : "2"});
         out.push_back({"PX_SHADOW_SAMPLES", std::to_string(k.shadow_samples)});
     }},
    {"depth_write", "depth", "PX_DEPTH_WRITE", &VariantKey::depth_write},
    {"lod", "lod", "PX_LOD", &VariantKey::lod},
    {"exact_view", "exact-view", "PX_EXACT_VIEW", &VariantKey::exact_view},
    {"packed_height", nullptr, nullptr, nullptr, 0,
     [](const VariantKey& k, std::string& out) {
         if (has_option(k.technique, kOptHeight)) out += k.packed_height ? " packed" : " separate-height";
     },
     [](const std::string& w, VariantKey& k) {
         if (w != "packed" && w != "separate-height") return false;
         k.packed_height = w == "packed";
         return true;
     },
     [](const VariantKey& k, std::vector<ShaderDefine>& out) {
         if (k.packed_height) out.push_back({"PX_PACKED_HEIGHT", ""});
     }},
    {"normal_rg", "normal-rg", "PX_NORMAL_RG", &VariantKey::normal_rg},
    {"height_11bit", "height-11bit", "PX_HEIGHT_11BIT", &VariantKey::height_11bit},
    {"normal_green_down", "green-down", "PX_NORMAL_GREEN_DOWN", &VariantKey::normal_green_down},
    {"srgb_decode", "srgb-decode", "PX_SRGB_DECODE", &VariantKey::srgb_decode},
    {"srgb_output", "srgb-out", "PX_SRGB_OUTPUT", &VariantKey::srgb_output},
    {"debug_output", nullptr, nullptr, nullptr, 0,
     [](const VariantKey& k, std::string& out) {
         if (k.debug_output) out += " debug" + std::to_string(int(k.debug_output));
     },
     [](const std::string& w, VariantKey& k) {
         long n = 0;
         if (!prefixed_number(w, "debug", 1, 4, n)) return false;
         k.debug_output = static_cast<std::uint8_t>(n);
         return true;
     },
     [](const VariantKey& k, std::vector<ShaderDefine>& out) {
         if (k.debug_output) out.push_back({"PX_DEBUG_OUTPUT", std::to_string(k.debug_output)});
     }},
    {"count_work", "count-work", "PX_COUNT_WORK", &VariantKey::count_work},
    {"capture_ray", "capture-ray", "PX_CAPTURE_RAY", &VariantKey::capture_ray},
    {"bounded", "bounded", "PX_BOUNDED", &VariantKey::bounded},
    {"curved", "curved", "PX_CURVED", &VariantKey::curved},
    {"shape", nullptr, nullptr, nullptr, 0,
     [](const VariantKey& k, std::string& out) {
         if (k.shape) out += std::string(" shape=") + shape_name(k.shape);
     },
     [](const std::string& w, VariantKey& k) {
         for (std::uint8_t shape : {kShapeSphere, kShapeCylinder, kShapeTorus})
             if (w == std::string("shape=") + shape_name(shape)) {
                 k.shape = shape;
                 return true;
             }
         return false;
     },
     [](const VariantKey& k, std::vector<ShaderDefine>& out) {
         if (k.shape) out.push_back({"PX_SHAPE", std::to_string(k.shape)});
     }},
    {"no_fragment_highp", "no-fragment-highp", "PX_NO_FRAGMENT_HIGHP", &VariantKey::no_fragment_highp},
    {"ladder_step", nullptr, nullptr, nullptr, 0,
     [](const VariantKey& k, std::string& out) {
         if (k.ladder_step) out += " ladder" + std::to_string(int(k.ladder_step));
     },
     [](const std::string& w, VariantKey& k) {
         long n = 0;
         if (!prefixed_number(w, "ladder", 1, kLadderSteps, n)) return false;
         k.ladder_step = static_cast<std::uint8_t>(n);
         return true;
     },
     [](const VariantKey& k, std::vector<ShaderDefine>& out) {
         if (k.ladder_step) out.push_back({"PX_LADDER_STEP", std::to_string(k.ladder_step)});
     }},
    {"flip_albedo", "flip-albedo", "PX_FLIP_ALBEDO_V", nullptr, kFlipAlbedo},
    {"flip_normal", "flip-normal", "PX_FLIP_NORMAL_V", nullptr, kFlipNormal},
    {"flip_height", "flip-height", "PX_FLIP_HEIGHT_V", nullptr, kFlipHeight},
    // Its define is PX_SHADE_LOD_BIAS where derivatives bias the level.
    {"no_derivatives", nullptr, nullptr, nullptr, 0,
     [](const VariantKey& k, std::string& out) {
         if (k.no_derivatives) out += " no-derivatives";
     },
     [](const std::string& w, VariantKey& k) {
         if (w != "no-derivatives") return false;
         k.no_derivatives = true;
         return true;
     },
     [](const VariantKey& k, std::vector<ShaderDefine>& out) {
         if (k.shade_lod_bias()) out.push_back({"PX_SHADE_LOD_BIAS", ""});
     }},
};

void describe_field(const VariantField& f, const VariantKey& k, std::string& out) {
    if (f.describe) return f.describe(k, out);
    if (flag_set(f, k)) (out += ' ') += f.word;
}

bool parse_field(const VariantField& f, const std::string& word, VariantKey& k) {
    if (f.parse) return f.parse(word, k);
    if (word != f.word) return false;
    if (f.flag) k.*f.flag = true;
    else k.flip_v = static_cast<std::uint8_t>(k.flip_v | f.flip_bit);
    return true;
}

void field_defines(const VariantField& f, const VariantKey& k, std::vector<ShaderDefine>& out) {
    if (f.defines) return f.defines(k, out);
    if (flag_set(f, k)) out.push_back({f.define, ""});
}

}  // namespace

const VariantField* variant_fields(size_t& count) {
    count = sizeof kFields / sizeof kFields[0];
    return kFields;
}

Status add_variant_field(const AddedVariantField& field) {
    if (field.word.empty() || field.word.find_first_of(" =<0123456789") != std::string::npos)
        return make_error("variant field '" + field.word + "': a word of letters and '-', without digits or '='");
    if (field.define.rfind("PX_", 0) != 0 || field.define.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") !=
                                                 std::string::npos)
        return make_error("variant field '" + field.word + "': its define must be PX_ and capitals, got '" +
                          field.define + "'");
    if (field.max_value < 1) return make_error("variant field '" + field.word + "': max_value must be at least 1");
    VariantKey probe;
    for (const VariantField& f : kFields)
        if (field.word == f.name || parse_field(f, field.word, probe) || parse_field(f, field.word + "=1", probe))
            return make_error("variant field '" + field.word + "' is already a field");
    std::lock_guard<std::recursive_mutex> lock(g_fields_mutex);
    if (added_field(field.word)) return make_error("variant field '" + field.word + "' is already a field");
    added_fields().push_back(field);
    return {};
}

std::string VariantKey::id() const {
    const VariantKey k = canonical();
    std::string out;
    for (const VariantField& f : kFields) describe_field(f, k, out);
    if (k.added.empty()) return out;
    std::lock_guard<std::recursive_mutex> lock(g_fields_mutex);
    for (const AddedVariantField& f : added_fields()) {
        const auto it = k.added.find(f.word);
        if (it != k.added.end() && it->second != 0)
            out += " " + f.word + (f.max_value == 1 ? std::string() : "=" + std::to_string(it->second));
    }
    return out;
}

std::uint64_t VariantKey::hash() const {
    const std::string text = id();
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a, 64 bits
    for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
    return h;
}

std::vector<ShaderDefine> VariantKey::defines() const {
    const VariantKey k = canonical();
    std::vector<ShaderDefine> d;
    for (const VariantField& f : kFields) field_defines(f, k, d);
    if (k.added.empty()) return d;
    std::lock_guard<std::recursive_mutex> lock(g_fields_mutex);
    for (const AddedVariantField& f : added_fields()) {
        const auto it = k.added.find(f.word);
        if (it != k.added.end() && it->second != 0)
            d.push_back({f.define, f.max_value == 1 ? std::string() : std::to_string(it->second)});
    }
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

std::string VariantKey::describe() const { return id(); }

Result<VariantKey> VariantKey::parse(const std::string& name) {
    std::istringstream words(name);
    std::string word;
    if (!(words >> word)) return make_error("an empty variant name");
    Result<Technique> technique = parse_technique(word);
    if (!technique) return technique.error();
    VariantKey k;
    k.technique = *technique;
    k.packed_height = false;
    while (words >> word) {
        bool read = false;
        for (const VariantField& f : kFields)
            if (parse_field(f, word, k)) {
                read = true;
                break;
            }
        if (!read) {
            std::lock_guard<std::recursive_mutex> lock(g_fields_mutex);
            for (const AddedVariantField& f : added_fields()) {
                long n = 1;
                if (f.max_value == 1 ? word == f.word
                                     : prefixed_number(word, f.word + "=", 1, static_cast<long>(f.max_value), n)) {
                    k.added[f.word] = static_cast<std::uint32_t>(n);
                    read = true;
                    break;
                }
            }
        }
        if (!read) return make_error("variant '" + name + "': unknown word '" + word + "'");
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
    k.normal_green_down = layout.normal_green_down;
    k.srgb_decode = layout.albedo_srgb_decode;
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

namespace {

// The variants enumerated so far, canonical, in the order first added; a
// key whose canonical form is already there is dropped.
class VariantList {
public:
    void add(const VariantKey& k) {
        const VariantKey c = k.canonical();
        if (seen_.insert(c.id()).second) out_.push_back(c);
    }
    std::vector<VariantKey> take() { return std::move(out_); }

private:
    std::vector<VariantKey> out_;
    std::set<std::string> seen_;
};

// Every combination of packing, shadow, depth output, LOD and the exact
// view vector.
void add_option_grid(VariantList& list, const VariantKey& base) {
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
                    list.add(k);
                    k.exact_view = true;
                    list.add(k);
                }
}

// Compressed-texture layouts: two-channel normals, 11-bit heights, green down.
void add_compressed_layouts(VariantList& list, const VariantKey& base) {
    for (int layout = 0; layout < 2; ++layout) {
        VariantKey k = base;
        k.packed_height = false;
        k.normal_rg = true;
        k.height_11bit = layout != 0;
        k.normal_green_down = layout != 0;  // a DirectX-style normal file
        k.shadow = ShadowMode::soft;
        list.add(k);
    }
}

// A bounded relief (canonical() keeps it for traced techniques), with
// the options that touch the hit it tests: depth, LOD, debug output; and
// the curved reliefs.
void add_bounded_and_curved(VariantList& list, const VariantKey& base, int es_major) {
    for (int debug : {0, es_major >= 3 ? 1 : 2}) {
        VariantKey k = base;
        k.bounded = true;
        k.depth_write = true;
        k.lod = true;
        k.debug_output = static_cast<std::uint8_t>(debug);
        list.add(k);
        // Curved-relief silhouettes (canonical() keeps them for the linear searches).
        k.bounded = false;
        k.curved = true;
        k.shadow = ShadowMode::soft;
        list.add(k);
        // The exact curved search, one shape each.
        for (std::uint8_t shape : {kShapeSphere, kShapeCylinder, kShapeTorus}) {
            k.shape = shape;
            list.add(k);
        }
        // A bounded tube's (its ends in the search: PX_SHAPE_TUBE), and
        // an ES 2.0 context without fragment highp's.
        k.bounded = true;
        k.shape = kShapeCylinder;
        list.add(k);
        if (es_major < 3) {
            k.no_fragment_highp = true;
            list.add(k);
            // A context without GL_OES_standard_derivatives (no LOD there).
            k.no_derivatives = true;
            k.lod = false;
            list.add(k);
            k.no_derivatives = false;
            k.lod = true;
            k.bounded = false;
            k.shape = kShapeTorus;
            list.add(k);
            k.no_fragment_highp = false;
        }
        k.bounded = false;
        k.shape = 0;
    }
}

// Debug outputs, with every option the technique has switched on.
void add_debug_outputs(VariantList& list, const VariantKey& base, int es_major) {
    for (int debug = 1; debug <= 4; ++debug) {
        VariantKey k = base;
        k.shadow = ShadowMode::soft;
        k.depth_write = true;
        k.lod = true;
        k.debug_output = static_cast<std::uint8_t>(debug);
        if (es_major >= 3 || debug >= 2) list.add(k);
        // GLSL ES 1.00 without fragment highp: the 11-bit packing.
        k.no_fragment_highp = true;
        if (es_major < 3 && debug >= 2) list.add(k);
        // The work counts (canonical() keeps them for searches only).
        k.no_fragment_highp = false;
        k.count_work = true;
        if (es_major >= 3 || debug >= 2) list.add(k);
        // The traced ray in place of the hit (canonical() keeps it for the float target only).
        k.count_work = false;
        k.capture_ray = true;
        if (es_major >= 3 && debug == 1) list.add(k);
        k.capture_ray = false;
    }
}

// The PowerVR whitepaper's optimisation ladder (shaders_es/ladder/).
void add_ladder(VariantList& list, const VariantKey& base, int es_major) {
    for (int packed = 0; packed < 2; ++packed)
        for (int step = 1; step <= kLadderSteps; ++step) {
            VariantKey k = base;
            k.packed_height = packed != 0;
            k.ladder_step = static_cast<std::uint8_t>(step);
            list.add(k);
            for (int debug = 1; debug <= 4; ++debug) {
                k.debug_output = static_cast<std::uint8_t>(debug);
                if (es_major >= 3 || debug >= 2) list.add(k);
            }
        }
}

}  // namespace

std::vector<VariantKey> enumerate_variants(int es_major) {
    VariantList list;
    for (const TechniqueInfo& info : technique_table()) {
        if (info.min_es_major > es_major) continue;
        const VariantKey base = default_variant(info, es_major);
        add_option_grid(list, base);
        add_compressed_layouts(list, base);
        add_bounded_and_curved(list, base, es_major);
        add_debug_outputs(list, base, es_major);
        // The colour pipeline as frames draw it: encoded for an sRGB display,
        // with the albedo decoded in the shader where the texture unit cannot.
        {
            VariantKey k = base;
            k.srgb_output = true;
            list.add(k);
            k.srgb_decode = true;
            k.shadow = has_option(k.technique, kOptShadow) ? ShadowMode::soft : ShadowMode::none;
            list.add(k);
        }
        // Loop bounds at their extremes.
        if (info.options & (kOptSamples | kOptSteps)) {
            for (int samples : {1, info.max_samples_limit}) {
                VariantKey k = base;
                k.max_samples = static_cast<std::uint16_t>(samples);
                k.shadow = ShadowMode::soft;
                k.shadow_samples = 128;
                list.add(k);
            }
        }
        if (info.id == Technique::offset_limited) add_ladder(list, base, es_major);
        if (info.options & kOptRefine) {
            for (int steps : {0, 16}) {
                VariantKey k = base;
                k.refine_steps = static_cast<std::uint8_t>(steps);
                list.add(k);
            }
        }
    }
    return list.take();
}

}  // namespace px
