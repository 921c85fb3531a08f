// The surface shaders' interface, declared once: every vertex attribute with
// its slot, every uniform with its type and the variants that need it, and
// every sampler with its texture unit. gl/program resolves it per program
// when the program is built (binding the attribute slots and sampler units
// from here, and failing with the variant's defines when a needed name is
// missing or the shader has one that is not listed); the renderer sets the
// values through the typed slots below and points attributes and binds
// textures by the same table. No GL here: the types are the GLSL ES ones.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

#include "parallaxes/core/limits.h"
#include "parallaxes/core/result.h"
#include "parallaxes/effects/variant.h"

namespace px::shader {

// --- Vertex attributes: name, slot, float components --------------------------
#define PX_SURFACE_ATTRIBUTES(X) \
    X(position, "a_position", 3) \
    X(normal, "a_normal", 3)     \
    X(tangent, "a_tangent", 4)   \
    X(uv, "a_uv", 2)             \
    X(curvature, "a_curvature", 3) \
    X(uv_stretch, "a_uv_stretch", 2) \
    X(uv_bend_u, "a_uv_bend_u", 3) \
    X(uv_bend_v, "a_uv_bend_v", 3)

enum class Attribute : std::uint8_t {
#define PX_ENUM(id, name, components) id,
    PX_SURFACE_ATTRIBUTES(PX_ENUM)
#undef PX_ENUM
};

struct AttributeInfo {
    Attribute id;
    const char* name;
    int slot;        // glBindAttribLocation before linking; glVertexAttribPointer at draw
    int components;  // floats per vertex
};

// --- Uniforms: name, GLSL type, array length -----------------------------------
enum class Type : std::uint8_t { float1, vec2, vec3, vec4, mat2, mat3, mat4, int1, sampler2d };

#define PX_SURFACE_UNIFORMS(X)                                 \
    X(model, "u_model", mat4, 1)                               \
    X(view, "u_view", mat4, 1)                                 \
    X(projection, "u_projection", mat4, 1)                     \
    X(depth_projection, "u_depth_projection", mat4, 1)         \
    X(normal_matrix, "u_normal_matrix", mat3, 1)               \
    X(model_handedness, "u_model_handedness", float1, 1)       \
    X(camera_position, "u_camera_position", vec3, 1)           \
    X(uv_matrix, "u_uv_matrix", mat2, 1)                       \
    X(uv_offset, "u_uv_offset", vec2, 1)                       \
    X(uv_frame, "u_uv_frame", mat2, 1)                         \
    X(units_per_tile, "u_units_per_tile", float1, 1)           \
    X(height_scale, "u_height_scale", float1, 1)               \
    X(parallax_scale, "u_parallax_scale", float1, 1)           \
    X(inv_height_scale, "u_inv_height_scale", float1, 1)       \
    X(polygon_height, "u_polygon_height", float1, 1)           \
    X(light_vector, "u_light_vector", vec4, kMaxLights)        \
    X(light_color, "u_light_color", vec3, kMaxLights)          \
    X(light_angular_radius, "u_light_angular_radius", float1, kMaxLights) \
    X(light_count, "u_light_count", int1, 1)                   \
    X(ambient, "u_ambient", vec3, 1)                           \
    X(texture_size, "u_texture_size", vec2, 1)                 \
    X(sample_range, "u_sample_range", vec2, 1)                 \
    X(lod_range, "u_lod_range", vec2, 1)                       \
    X(specular, "u_specular", float1, 1)                       \
    X(shininess, "u_shininess", float1, 1)                     \
    X(max_levels, "u_max_levels", int1, 1)                     \
    X(max_atlas, "u_max_atlas", vec4, 1)                       \
    X(bounds_matrix, "u_bounds_matrix", mat2, 1)               \
    X(bounds_offset, "u_bounds_offset", vec2, 1)               \
    X(wall_scale, "u_wall_scale", float1, 1)                   \
    X(curvature_scale, "u_curvature_scale", float1, 1)         \
    X(shell, "u_shell", vec3, 1)                               \
    X(uv_bend_scale, "u_uv_bend_scale", float1, 1)             \
    X(shape, "u_shape", vec4, 1)                               \
    X(object_camera, "u_object_camera", vec3, 1)               \
    X(shape_uv_matrix, "u_shape_uv_matrix", mat2, 1)           \
    X(shape_uv_offset, "u_shape_uv_offset", vec2, 1)           \
    X(albedo_map, "u_albedo_map", sampler2d, 1)                \
    X(normal_map, "u_normal_map", sampler2d, 1)                \
    X(height_map, "u_height_map", sampler2d, 1)                \
    X(max_map, "u_max_map", sampler2d, 1)

enum class Uniform : std::uint8_t {
#define PX_ENUM(id, name, type, count) id,
    PX_SURFACE_UNIFORMS(PX_ENUM)
#undef PX_ENUM
};

struct UniformInfo {
    Uniform id;
    const char* name;
    Type type;
    int array_size;
};

// A uniform whose GLSL type is T: the renderer's setters take the matching
// C++ value, so a value of the wrong shape does not compile.
template <Type T>
struct UniformSlot {
    Uniform id;
};
namespace slot {
#define PX_SLOT(id, name, type, count) inline constexpr UniformSlot<Type::type> id{Uniform::id};
PX_SURFACE_UNIFORMS(PX_SLOT)
#undef PX_SLOT
}  // namespace slot

// --- Samplers: which uniform, which texture unit -------------------------------
enum class Sampler : std::uint8_t { albedo, normal, height, max_map };
struct SamplerInfo {
    Sampler id;
    Uniform uniform;
    int unit;  // GL_TEXTURE0 + unit; set once per program when it is built
};

inline constexpr std::size_t kAttributeCount = 0
#define PX_COUNT(id, name, components) +1
    PX_SURFACE_ATTRIBUTES(PX_COUNT)
#undef PX_COUNT
    ;
inline constexpr std::size_t kUniformCount = 0
#define PX_COUNT(id, name, type, count) +1
    PX_SURFACE_UNIFORMS(PX_COUNT)
#undef PX_COUNT
    ;
inline constexpr std::size_t kSamplerCount = 4;

const std::array<AttributeInfo, kAttributeCount>& attributes();
const std::array<UniformInfo, kUniformCount>& uniforms();
const std::array<SamplerInfo, kSamplerCount>& samplers();
const AttributeInfo& info(Attribute a);
const UniformInfo& info(Uniform u);
const SamplerInfo& info(Sampler s);
const char* type_name(Type t);  // "mat4", "sampler2D", ...

// Whether the variant's shaders read the uniform or attribute in a way that
// changes what they output (colour, depth or the debug outputs): a program
// of that variant that lacks it is broken. Derived from the shader sources;
// each case says where the value is used.
bool needed(Uniform u, const VariantKey& key);
bool needed(Attribute a, const VariantKey& key);

// Checks an assembled source's declarations against this table, with no GL:
// every `uniform` and every attribute (PX_ATTRIBUTE) it declares must be
// listed, with the listed GLSL type and array length. The error names the
// source line. assemble_variant runs it on every variant it assembles.
Status check_declarations(const std::string& source, const std::string& what);

}  // namespace px::shader
