#include "parallaxes/shaders/interface.h"

#include <optional>
#include <sstream>

namespace px::shader {

namespace {

constexpr std::array<AttributeInfo, kAttributeCount> kAttributes = [] {
    std::array<AttributeInfo, kAttributeCount> a{};
    int slot = 0;
#define PX_ROW(id, name, components) \
    a[static_cast<std::size_t>(slot)] = AttributeInfo{Attribute::id, name, slot, components}; \
    ++slot;
    PX_SURFACE_ATTRIBUTES(PX_ROW)
#undef PX_ROW
    return a;
}();

constexpr std::array<UniformInfo, kUniformCount> kUniforms = {{
#define PX_ROW(id, name, type, count) {Uniform::id, name, Type::type, count},
    PX_SURFACE_UNIFORMS(PX_ROW)
#undef PX_ROW
}};

// Units 0..3, in the order the shading reads them.
constexpr std::array<SamplerInfo, kSamplerCount> kSamplers = {{
    {Sampler::albedo, Uniform::albedo_map, 0},
    {Sampler::normal, Uniform::normal_map, 1},
    {Sampler::height, Uniform::height_map, 2},
    {Sampler::max_map, Uniform::max_map, 3},
}};

template <typename Table, typename Id>
constexpr bool rows_in_enum_order(const Table& table) {
    for (std::size_t i = 0; i < table.size(); ++i)
        if (static_cast<std::size_t>(table[i].id) != i) return false;
    return true;
}
static_assert(rows_in_enum_order<decltype(kAttributes), Attribute>(kAttributes));
static_assert(rows_in_enum_order<decltype(kUniforms), Uniform>(kUniforms));
static_assert(rows_in_enum_order<decltype(kSamplers), Sampler>(kSamplers));

bool has(const VariantKey& k, OptionFlag flag) { return (technique_info(k.technique).options & flag) != 0; }

}  // namespace

const std::array<AttributeInfo, kAttributeCount>& attributes() { return kAttributes; }
const std::array<UniformInfo, kUniformCount>& uniforms() { return kUniforms; }
const std::array<SamplerInfo, kSamplerCount>& samplers() { return kSamplers; }
const AttributeInfo& info(Attribute a) { return kAttributes[static_cast<std::size_t>(a)]; }
const UniformInfo& info(Uniform u) { return kUniforms[static_cast<std::size_t>(u)]; }
const SamplerInfo& info(Sampler s) { return kSamplers[static_cast<std::size_t>(s)]; }

const char* type_name(Type t) {
    switch (t) {
        case Type::float1: return "float";
        case Type::vec2: return "vec2";
        case Type::vec3: return "vec3";
        case Type::vec4: return "vec4";
        case Type::mat2: return "mat2";
        case Type::mat3: return "mat3";
        case Type::mat4: return "mat4";
        case Type::int1: return "int";
        case Type::sampler2d: return "sampler2D";
    }
    return "?";
}

namespace {

// What a variant's output depends on, in the terms the rules below use.
struct Uses {
    bool shading;      // colour out (debug_output 0)
    bool shows_uv;     // the hit uv is output: colour, or debug pass 1, 2 (u) or 3 (v)
    bool shows_height; // the hit height and light 0's visibility: debug pass 1 or 4
    bool traced;       // PX_READS_HEIGHT: a parallax offset or a trace
    bool searches;     // a search along the view ray (march or maxmip): the hit height depends on the view
    bool shadow;       // a shadow ray, read by the shading or by the shown visibility
    bool view_in_trace;  // the view vector changes an output through the trace or the depth
    // The interpolated view vector (v_view_ts) changes an output: as
    // view_in_trace, but the exact curved search (PX_SHAPE) traces the
    // mesh-space ray instead, so there only shading reads it.
    bool view_vector;
    bool frame;          // the texture-space frame (n, t, b) changes an output
};

Uses uses(const VariantKey& k) {
    Uses u{};
    u.shading = k.debug_output == 0;
    u.shows_uv = u.shading || k.debug_output == 1 || k.debug_output == 2 || k.debug_output == 3;
    u.shows_height = k.debug_output == 1 || k.debug_output == 4;
    u.traced = has(k, kOptHeight);
    u.searches = has(k, kOptSamples) || has(k, kOptSteps);
    u.shadow = k.shadow != ShadowMode::none && (u.shading || u.shows_height);
    // The hit uv always moves with the view; the hit height only where a
    // search finds it (parallax and offset limiting read it at the unshifted
    // uv); the visibility from the hit; the depth from the view's cosine.
    u.view_in_trace = u.traced && (u.shows_uv || (u.shows_height && u.searches) || u.shadow || k.depth_write);
    // The view vector (specular shading and the trace) and the light vectors
    // (shading and the shadow ray) are both built from the frame.
    // (The shape search clips its own ray to a bounded tube's ends.)
    u.view_vector = u.shading || (u.view_in_trace && !(k.curved && k.shape));
    u.frame = u.view_vector || u.shadow;
    return u;
}

// The optimisation ladder's shaders (shaders_es/ladder/) differ from the
// shipped ones in where they build the frame and apply the scale; every
// other uniform is needed as for the shipped offset_limited.
std::optional<bool> ladder_needs(Uniform uniform, const VariantKey& k, const Uses& u) {
    if (!k.ladder_step) return std::nullopt;
    const bool world_view_frame = k.ladder_step == 1;  // the frame from u_view * u_model, per vertex
    const bool scale_in_fragment = k.ladder_step < 4;  // u_height_scale per fragment, not u_parallax_scale
    switch (uniform) {
        case Uniform::normal_matrix:
        case Uniform::camera_position: return u.frame && !world_view_frame;
        case Uniform::parallax_scale: return u.traced && !scale_in_fragment && (u.shading || u.view_in_trace);
        case Uniform::height_scale: return u.traced && scale_in_fragment && u.view_in_trace;
        case Uniform::inv_height_scale: return u.traced && !scale_in_fragment && u.shading;
        default: return std::nullopt;
    }
}

// The maps the shading and the trace read their normals and height from.
bool map_needed(Uniform uniform, const VariantKey& k, const Uses& u) {
    switch (uniform) {
        // Shading reads normals; on GLSL ES 3.00 a packed normal map is also
        // the traced height (surface_common.glsl PX_HEIGHT_SAMPLER).
        case Uniform::normal_map:
            return (u.shading && has(k, kOptNormals)) || (u.traced && k.packed_height && k.es_major >= 3);
        // The traced height's own texture: a separate height map, or on GLSL
        // ES 1.00 a base-level copy of the packed one.
        // GLSL ES 1.00's exact walk reads its atlas instead, so there only a
        // shadow ray reads it.
        case Uniform::height_map:
            if (has(k, kOptSteps) && k.es_major < 3) return u.traced && u.shadow;
            return u.traced && (!k.packed_height || k.es_major < 3);
        default: return true;
    }
}

}  // namespace

bool needed(Uniform uniform, const VariantKey& key) {
    const VariantKey k = key.canonical();
    const Uses u = uses(k);
    if (const std::optional<bool> ladder = ladder_needs(uniform, k, u)) return *ladder;
    switch (uniform) {
        // surface.vert: gl_Position.
        case Uniform::model:
        case Uniform::view:
        case Uniform::projection: return true;
        // surface.vert: v_uv, where the uv is shown or the height is read at it.
        case Uniform::uv_matrix:
        case Uniform::uv_offset:
            // The exact curved search takes its uv from the ray's point:
            // the polygon's uv is left to the shading's gradients (GLSL ES
            // 3.00 textureGrad) and LOD (a bounded tube's ends clip the
            // ray in the search).
            if (k.curved && k.shape) return (u.shading && k.es_major >= 3) || k.lod;
            return u.shows_uv || u.traced;
        // surface.vert: n, t, b and from them the view and light vectors.
        case Uniform::normal_matrix:
        case Uniform::model_handedness:
        case Uniform::uv_frame: return u.frame;
        case Uniform::camera_position: return u.view_vector;
        // surface.vert: the light vectors (shading, or light 0's shadow ray).
        case Uniform::light_vector:
        case Uniform::light_count: return u.shading || u.shadow;
        // surface_main.glsl px_write_depth, in every pass (depth is output).
        case Uniform::depth_projection:
        case Uniform::units_per_tile: return k.depth_write;
        // surface.vert folds the relief depth into the view vector (highp,
        // vertex stage only); shadows.glsl and px_write_depth read the
        // fragment stage's mediump copy.
        case Uniform::parallax_scale: return u.traced && u.view_vector;
        case Uniform::height_scale: return u.traced && (u.shadow || k.depth_write);
        // surface_main.glsl: unscales the view vector for shading, and for the
        // trace when the exact view vector is normalised per fragment.
        case Uniform::inv_height_scale: return u.traced && (u.shading || (k.exact_view && u.view_vector));
        // Every trace starts from the polygon; the debug outputs show it as
        // the height of an untraced (or LOD-faded) surface.
        case Uniform::polygon_height:
            return u.traced ? (u.view_in_trace || (u.shows_height && k.lod)) : u.shows_height;
        // surface_main.glsl px_shade.
        case Uniform::light_color:
        case Uniform::ambient:
        case Uniform::specular:
        case Uniform::shininess:
        case Uniform::albedo_map: return u.shading;
        // shadows.glsl: the penumbra of a soft shadow.
        case Uniform::light_angular_radius: return u.shadow && k.shadow == ShadowMode::soft;
        // px_mip_level (LOD) and maxmip's texel walk.
        case Uniform::texture_size: return k.lod || has(k, kOptSteps);
        // march.glsl: Tatarchuk's dynamic sample count.
        case Uniform::sample_range: return has(k, kOptSamples);
        case Uniform::lod_range: return k.lod;
        case Uniform::max_levels:
        case Uniform::max_map: return has(k, kOptSteps);
        // GLSL ES 1.00 reads the pyramid from an atlas (maxmip.frag).
        case Uniform::max_atlas: return has(k, kOptSteps) && k.es_major < 3;
        // surface_main.glsl: a bounded relief's discard (PX_BOUNDED).
        case Uniform::bounds_matrix:
        case Uniform::bounds_offset: return k.bounded && !(k.curved && k.shape);  // a tube's: its ends in the search
        // surface.vert: a bounded tile's side walls, their height (v_wall_height).
        case Uniform::wall_scale: return k.bounded && !k.curved;
        // surface.vert: the curved relief's quadric into relief depths (PX_CURVED).
        case Uniform::shell: return k.curved;
        case Uniform::curvature_scale:
        case Uniform::uv_bend_scale: return k.curved && k.shape == 0;
        // march.glsl: the exact curved search (PX_SHAPE).
        case Uniform::shape:
        case Uniform::object_camera:
        case Uniform::shape_uv_matrix:
        case Uniform::shape_uv_offset: return k.curved && k.shape != 0;
        // The normal and height maps (map_needed says when).
        case Uniform::normal_map:
        case Uniform::height_map: return map_needed(uniform, k, u);
    }
    return true;
}

bool needed(Attribute a, const VariantKey& key) {
    const VariantKey k = key.canonical();
    switch (a) {
        case Attribute::position: return true;
        case Attribute::uv: return needed(Uniform::uv_matrix, k);
        // The texture-space frame (see uses()).
        // (And the curved relief's shell, drawn out along the normals.)
        case Attribute::normal: return uses(k).frame || k.curved;
        case Attribute::tangent: return uses(k).frame;
        // surface.vert: the curved relief's quadric (PX_CURVED).
        case Attribute::curvature:
        case Attribute::uv_bend_u:
        case Attribute::uv_bend_v: return k.curved && k.shape == 0;
        // surface.vert: the texture frame F = u_uv_frame times the mesh's uv
        // stretch, for the searches' uv step and for shading (every variant
        // with a frame but the ladder's own shaders).
        case Attribute::uv_stretch: return uses(k).frame && k.ladder_step == 0;
    }
    return true;
}

namespace {

bool is_precision(const std::string& t) {
    return t == "lowp" || t == "mediump" || t == "highp" || t == "PX_HIGHP" || t == "PX_VIEW_PRECISION";
}

}  // namespace

Status check_declarations(const std::string& source, const std::string& what) {
    std::istringstream in(source);
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        std::istringstream words(line);
        std::string kind;
        words >> kind;
        const bool uniform = kind == "uniform";
        if (!uniform && kind != "PX_ATTRIBUTE") continue;
        std::string type, name;
        words >> type;
        if (is_precision(type)) words >> type;
        words >> name;
        // "u_light_color[PX_MAX_LIGHTS];" -> name and array length text
        const size_t end = name.find_first_of("[;");
        const bool array = end != std::string::npos && name[end] == '[';
        const std::string bare = name.substr(0, end);
        const std::string where = what + ", line " + std::to_string(number) + ": ";
        if (uniform) {
            const UniformInfo* found = nullptr;
            for (const UniformInfo& u : uniforms())
                if (bare == u.name) found = &u;
            if (!found)
                return make_error(where + "uniform '" + bare + "' is not in include/parallaxes/shaders/interface.h, so no program "
                                  "would ever set it");
            if (type != type_name(found->type) || array != (found->array_size > 1))
                return make_error(where + "uniform '" + bare + "' is declared as " + type + (array ? "[]" : "") +
                                  ", and include/parallaxes/shaders/interface.h lists it as " + type_name(found->type) +
                                  (found->array_size > 1 ? "[]" : ""));
        } else {
            const AttributeInfo* found = nullptr;
            for (const AttributeInfo& a : attributes())
                if (bare == a.name) found = &a;
            if (!found)
                return make_error(where + "attribute '" + bare + "' is not in include/parallaxes/shaders/interface.h, so it has "
                                  "no slot");
            const std::string expected = found->components == 1 ? "float" : "vec" + std::to_string(found->components);
            if (type != expected)
                return make_error(where + "attribute '" + bare + "' is declared as " + type +
                                  ", and include/parallaxes/shaders/interface.h gives it " + std::to_string(found->components) +
                                  " components (" + expected + ")");
        }
    }
    return {};
}

}  // namespace px::shader
