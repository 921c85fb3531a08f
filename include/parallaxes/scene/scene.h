// The scene description: what a scene file (JSON) or a built-in scene asks
// for. Plain data: no GL here.
#pragma once

#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "parallaxes/assets/heightfield.h"
#include "parallaxes/core/result.h"
#include "parallaxes/effects/effects.h"
#include "parallaxes/effects/technique.h"
#include "parallaxes/scene/mesh.h"

namespace px {

struct CameraDesc {
    glm::vec3 position{0.0f, -3.0f, 1.0f};
    glm::vec3 target{0.0f, 0.0f, 0.0f};
    glm::vec3 up{0.0f, 0.0f, 1.0f};
    float fov_y_deg = 50.0f;
    float near_plane = 0.05f;
    float far_plane = 50.0f;
};

enum class LightKind { directional, point };

struct LightDesc {
    LightKind kind = LightKind::directional;
    glm::vec3 direction{0.0f, 0.0f, -1.0f};  // directional: the way the light travels
    glm::vec3 position{0.0f, 0.0f, 3.0f};    // point
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    // Angular radius of the light's disc as seen from the surface: the soft
    // shadow penumbra scales with it (0 = point-like, hard).
    float angular_radius_deg = 2.0f;
};

// Where a texture's data comes from: a file, a procedural field, or a colour.
struct TextureSource {
    // Out of line (scene.cpp): an app that copies descriptions calls the
    // library's one copy instead of inlining every member's at each site.
    TextureSource();
    TextureSource(const TextureSource&);
    TextureSource(TextureSource&&) noexcept;
    TextureSource& operator=(const TextureSource&);
    TextureSource& operator=(TextureSource&&) noexcept;
    ~TextureSource();

    enum class Kind { none, file, procedural, color } kind = Kind::none;
    std::string path;                 // file (resolved against the scene file's folder)
    FieldSpec field;                  // procedural
    // A procedural albedo's colour (ramp_image, assets/heightfield.h): the
    // field's height 0 shown as `low`, 1 as `high`, grain its noise. The
    // defaults show the field as grey. Albedo slots only (validation).
    glm::vec3 low{0.0f};
    glm::vec3 high{1.0f};
    float grain = 0.0f;
    glm::vec3 color{0.8f};            // color
    HeightConvention convention = HeightConvention::height;  // file height maps
    // Which stored row of a texture container is the top of the image: as
    // the file declares (KTXorientation, PVR v3 metadata, or the documented
    // default), or the scene's word for an odd file ("first_row": "top" or
    // "bottom"). PNG and JPEG files always store the top row first.
    enum class FirstRow { file, top, bottom } first_row = FirstRow::file;
    // Where a height map's height is ("channel" in a scene file): `grey`
    // (the default) reads an image as grey and a texture file's red
    // channel; r, g, b or a read that one channel of the file, so that a
    // normal map carrying height in its alpha (`*_norm`, `*_nm`: McGuire's
    // steep parallax, many game packs) or one channel of a packed mask is
    // used as it ships. Height slots only (validation).
    enum class Channel : std::uint8_t { grey, r, g, b, a } channel = Channel::grey;
    // Which way a normal map's green channel points ("green" in a scene
    // file): up (+v, OpenGL's convention, the default) or down (DirectX's).
    // Normal slots given as files only (validation).
    enum class Green : std::uint8_t { up, down } green = Green::up;
    // How a colour texture's texels are encoded ("color_space"): as the
    // file declares (a KTX 1.1 sRGB internal format, KTX 2.0's transfer
    // function, PVR v3's colour space, a PNG's sRGB, gAMA or iCCP chunk) or,
    // where it declares nothing, sRGB, which is what every real albedo is;
    // or the scene's word for an odd file. Albedo slots only; height and
    // normal maps are data (linear) always.
    enum class ColorSpace : std::uint8_t { file, srgb, linear } color_space = ColorSpace::file;
};

// The channel's name ("grey", "r", ..., "a") and its index in an RGBA texel
// (grey reads red: 0).
const char* channel_name(TextureSource::Channel c);
int channel_index(TextureSource::Channel c);

struct UvTransform {
    glm::vec2 scale{1.0f};
    glm::vec2 offset{0.0f};
    float rotation_deg = 0.0f;

    // The linear part of uv' = R(rotation) * S(scale) * uv + offset, in float
    // (what the renderer uploads) or double (the reference).
    template <typename T>
    glm::mat<2, 2, T> matrix() const {
        const T a = glm::radians(static_cast<T>(rotation_deg));
        const glm::mat<2, 2, T> rotation(std::cos(a), std::sin(a), -std::sin(a), std::cos(a));
        return rotation * glm::mat<2, 2, T>(static_cast<T>(scale.x), T(0), T(0), static_cast<T>(scale.y));
    }
    // Tiles per mesh uv unit, as a mean over directions: sqrt(|det|) of the
    // linear part (the uniform part of the scale).
    template <typename T>
    T area_scale() const {
        return std::sqrt(std::fabs(glm::determinant(matrix<T>())));
    }
    // The linear part over its area scale: carries mesh-tangent directions
    // into the material's texture frame (rotation and mirroring only).
    template <typename T>
    glm::mat<2, 2, T> frame() const {
        const T s = area_scale<T>();
        return s > T(0) ? matrix<T>() / s : glm::mat<2, 2, T>(T(1));
    }
};

struct MaterialDesc {
    // Out of line (scene.cpp): an app that copies descriptions calls the
    // library's one copy instead of inlining every member's at each site.
    MaterialDesc();
    MaterialDesc(const MaterialDesc&);
    MaterialDesc(MaterialDesc&&) noexcept;
    MaterialDesc& operator=(const MaterialDesc&);
    MaterialDesc& operator=(MaterialDesc&&) noexcept;
    ~MaterialDesc();

    std::string name;
    TextureSource albedo;  // default: a light grey colour
    TextureSource height;  // default: flat at height 1 (no relief)
    TextureSource normal;  // default: derived from the height map
    // Depth of the relief in texture-tile units (one tile spans 1 in u and v).
    float height_scale = 0.05f;
    // Height of the relief's bottom relative to the polygon, in tile units
    // (Welsh 2004's bias): the relief spans [bias, bias + scale] around the
    // polygon. Default -scale: the relief lies under the polygon, its top on it.
    std::optional<float> height_bias;
    // One fetch gives normal and height (height in the normal map's alpha).
    bool pack_height_in_normal_alpha = true;
    UvTransform uv;
    // A bounded relief (a tile or a decal): the relief ends at the mesh's uv
    // edges (0 and 1), so a view ray that leaves mesh uv [0, 1]^2 before it
    // meets the relief sees what lies behind, and the traced techniques
    // discard there (PX_BOUNDED): the relief's own silhouette instead of the
    // polygon's straight edge. A bounded plane is drawn wider by
    // bounded_margin, so that rays coming into the relief through its side
    // are traced from there (docs/silhouettes.md).
    bool bounded = false;
    // The relief's own outline on a curved mesh (a sphere, torus or
    // cylinder): the search traces the mesh's own shape (PX_SHAPE; without
    // fragment highp, the fitted bend Vertex::curvature) and a ray that
    // passes the relief without meeting it shows what lies behind
    // (PX_CURVED), instead of the smooth mesh's outline. Drawn by the
    // linear searches (steep, pom, relief); a planned material gets one of
    // them wherever the object's contour can be on screen. No effect on
    // planes and cubes (`bounded` is theirs). docs/silhouettes.md.
    bool silhouette = false;
    TechniqueOptions technique;  // technique and its options
    // Set: the material declares the effects it needs ("effects" in a scene
    // file) and the planner chooses technique and options per object and
    // frame (include/parallaxes/planner/planner.h); `technique` is then unused.
    std::optional<EffectRequest> effects;
    // Lighting: Lambert diffuse plus Blinn-Phong specular, as the renderer's
    // shaders_es/chunks/lighting.glsl and the reference both compute it.
    float specular = 0.25f;   // specular intensity
    float shininess = 32.0f;  // Blinn-Phong exponent

    float bias() const { return height_bias.value_or(-height_scale); }
    // Where the polygon sits within the relief, in units of its depth
    // (-bias / scale: 1 = on the relief's top); 1 when there is no relief.
    double polygon_height() const {
        return height_scale > 0.0f ? -static_cast<double>(bias()) / height_scale : 1.0;
    }
};

// How much wider a bounded relief's plane is drawn on each side, in mesh uv
// (docs/silhouettes.md): how far a ray 80 degrees from the normal moves
// sideways while it descends the relief's depth (height_scale tiles of
// 1 / area_scale mesh uv each), so that rays coming into the tile through
// its side are traced up to that angle. At most 4; 0 when not bounded.
double bounded_margin(const MaterialDesc& m);

struct MeshDesc;
// Where a curved silhouette has no outline to trace: the relief of `m` on
// a sphere, torus or cylinder `d` (of `units_per_uv` mesh units per uv,
// Mesh::units_per_uv) reaches as deep below the polygon as the shape's
// smallest radius (a sphere's or cylinder's radius, a torus's tube
// radius), so that the displaced surface would fold through the centre or
// the axis. Returns the relief's depth below the polygon in mesh units
// there, else nothing (also for other kinds, or no relief).
std::optional<double> relief_folds_through(const MeshDesc& d, const MaterialDesc& m, double units_per_uv);
// The plan's note for it: "silhouette off: the relief reaches 0.46 units
// below the polygon, through the torus's tube (radius 0.4) ...".
std::string silhouette_folds_note(const MeshDesc& d, double below);
// A cylinder drawn with a silhouette but not bounded: its relief runs on
// past the rims, so its open ends keep the smooth rim's outline. The
// plan's note saying so, else nothing.
std::optional<std::string> open_tube_ends_note(const MeshDesc& d, const MaterialDesc& m);

struct TransformDesc {
    glm::vec3 translate{0.0f};
    glm::vec3 rotate_deg{0.0f};  // applied x, then y, then z
    glm::vec3 scale{1.0f};
    glm::mat4 matrix() const;
};

struct MeshDesc {
    MeshKind kind = MeshKind::plane;
    float size = 2.0f;          // plane, cube; a cylinder's height
    int segments = 1;           // plane
    float radius = 1.0f;        // sphere and cylinder radius, torus ring radius
    float tube_radius = 0.35f;  // torus
    // Real geometry instead of parallax: the relief of the object's material
    // displaced along the normals at one vertex per texel (a plane: the
    // accuracy benchmark's baseline; a sphere, torus or cylinder: the
    // silhouettes' reference, make_displaced_curved). Drawn with the
    // material's shading. Not a cube.
    bool displaced = false;
    // A displaced mesh's vertices per texel along u and v, 1 to 8 (1: the
    // accuracy benchmark's baseline). One vertex per texel lands its
    // vertices on texel corners, between the bilinear patches' corners
    // (the texel centres), so its triangles cut across the patches; an
    // even count puts a vertex on every texel centre and converges to the
    // filtered relief (docs/silhouettes.md: 2 is what a contour reference
    // at steep walls needs). Only with `displaced`.
    int vertices_per_texel = 1;
    // plane only: the vertices' tangent and normal as authored, instead of
    // +u and +z (tangent w stays +1). Any value is accepted, zero and
    // parallel vectors included: the renderer falls back to a usable frame
    // (shaders_es/surface.vert says how), and so does the exact reference.
    std::optional<glm::vec3> tangent;
    std::optional<glm::vec3> normal;
};

struct ObjectDesc {
    // Out of line (scene.cpp): an app that copies descriptions calls the
    // library's one copy instead of inlining every member's at each site.
    ObjectDesc();
    ObjectDesc(const ObjectDesc&);
    ObjectDesc(ObjectDesc&&) noexcept;
    ObjectDesc& operator=(const ObjectDesc&);
    ObjectDesc& operator=(ObjectDesc&&) noexcept;
    ~ObjectDesc();

    std::string name;
    MeshDesc mesh;
    TransformDesc transform;
    std::string material;  // name of an entry in SceneDesc::materials
};

struct SceneDesc {
    // Out of line (scene.cpp): an app that copies descriptions calls the
    // library's one copy instead of inlining every member's at each site.
    SceneDesc();
    SceneDesc(const SceneDesc&);
    SceneDesc(SceneDesc&&) noexcept;
    SceneDesc& operator=(const SceneDesc&);
    SceneDesc& operator=(SceneDesc&&) noexcept;
    ~SceneDesc();

    std::string name;
    std::string base_dir;  // folder that relative texture paths resolve against
    std::string source;    // the scene file it was read from (empty: built in code)
    CameraDesc camera;
    std::vector<LightDesc> lights;
    std::vector<MaterialDesc> materials;
    std::vector<ObjectDesc> objects;
    glm::vec3 ambient{0.08f};
    glm::vec3 background{0.02f, 0.02f, 0.03f};

    const MaterialDesc* find_material(const std::string& name) const;
    // Index of the material of that name in `materials`, or materials.size().
    size_t material_index(const std::string& name) const;
};

// The mesh an object draws (a displaced plane: its flat plane; the
// renderer displaces it from the material's field).
Mesh build_object_mesh(const MeshDesc& mesh);
// The mesh a bounded relief is drawn on, so that rays coming into it through
// its bounds have fragments to be traced in: on a plane (not displaced) the
// plane widened by bounded_margin on each side (make_widened_plane), on an
// open cylinder the tube longer by it at each end (make_widened_cylinder);
// std::nullopt for every other object, drawn on build_object_mesh's mesh
// (docs/silhouettes.md). The renderer draws this; the planner and the exact
// reference size what is drawn by drawn_length_scale.
std::optional<Mesh> build_widened_mesh(const MeshDesc& mesh, const MaterialDesc& m);
// How many times its MeshDesc's size the mesh build_widened_mesh makes is
// along its bounded directions: 1 + 2 bounded_margin where it widens, else 1.
double drawn_length_scale(const MeshDesc& mesh, const MaterialDesc& m);

// Scenes built into the program.
std::vector<std::string> builtin_scene_names();
Result<SceneDesc> builtin_scene(const std::string& name);

// Parses a scene from JSON text. `origin` names the source in errors (a file
// path); errors give line and column for malformed JSON, and the JSON path of
// the offending field (e.g. materials[1].technique) for unknown fields,
// wrong types and bad values.
Result<SceneDesc> parse_scene(const std::string& json_text, const std::string& origin);
// What loading checks: everything (value ranges, cross references, resource
// limits with file headers read), or the syntax, the fields and that texture
// files exist only, for a caller that hands the description straight to
// prepare_scene (scene/prepared_scene.h), which validates it once.
enum class SceneChecks { validate, syntax_only };
// Reads and parses a scene file.
Result<SceneDesc> load_scene_file(const std::string& path, SceneChecks checks = SceneChecks::validate);
// Either a built-in scene's name or a path to a JSON file.
Result<SceneDesc> load_scene(const std::string& name_or_path, SceneChecks checks = SceneChecks::validate);

// Checks cross references (object -> material) and value ranges.
Status validate_scene(const SceneDesc& scene);
// A valid scene with material `mi` replaced: checks only that material (its
// fields, its name against the others) and the objects drawn with it, with
// the same messages and JSON paths as validate_scene. Not counted as a
// scene validation (PipelineCounters::validations): replace_material's check.
Status validate_replaced_material(const SceneDesc& scene, size_t mi);

// Draws material `m` (or every material of `scene`) with technique `t`, as
// an override does: effect requests give way, the options are kept where
// `t` has them (a sample count past its limit is clamped), and the
// technique is marked forced (TechniqueOptions::forced), so that what `t`
// cannot draw is dropped with a note in the plan instead of refused.
// Returns a note for each option changed to fit `t`.
std::vector<std::string> force_technique(MaterialDesc& m, Technique t);
std::vector<std::string> force_technique(SceneDesc& scene, Technique t);

}  // namespace px
