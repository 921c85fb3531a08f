// The checks every scene (parsed or built in code) must pass, with the JSON
// path of the offending field; and the scene description's small methods.
// No JSON here: a host app that builds its scene in code links this without
// the parser (scene_json.cpp).
#include "parallaxes/core/counters.h"
#include "parallaxes/scene/scene.h"
#include "parallaxes/core/text.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include "parallaxes/core/limits.h"
#include "parallaxes/core/numeric.h"
#include "parallaxes/scene/scene_format.h"

namespace px {

namespace {

using namespace scene_format;

// --- Validation -------------------------------------------------------------------

// Records the first failed requirement, as "path: what".
class Checker {
public:
    bool require(bool ok, const std::string& path, const std::string& what) {
        if (!ok && !error_) error_ = make_error(path + ": " + what);
        return ok;
    }
    // A check that words its own message (path included).
    bool require(const Status& s) {
        if (!s && !error_) error_ = s.error();
        return s.ok();
    }
    bool failed() const { return error_.has_value(); }
    Status status() const { return error_ ? Status(*error_) : Status(); }

private:
    std::optional<Error> error_;
};

template <glm::length_t N>
bool within(const glm::vec<N, float, glm::defaultp>& v, float lo, float hi) {
    for (glm::length_t i = 0; i < N; ++i)
        if (!(v[i] >= lo && v[i] <= hi)) return false;  // NaN fails too
    return true;
}

// Every component's magnitude at most `hi` (NaN fails).
template <glm::length_t N>
bool bounded(const glm::vec<N, float, glm::defaultp>& v, float hi) {
    return within(v, -hi, hi);
}

// Every component's magnitude within [lo, hi] (so non-zero; NaN fails).
template <glm::length_t N>
bool magnitudes_within(const glm::vec<N, float, glm::defaultp>& v, float lo, float hi) {
    for (glm::length_t i = 0; i < N; ++i)
        if (!(std::abs(v[i]) >= lo && std::abs(v[i]) <= hi)) return false;
    return true;
}

bool in_range(float x, float lo, float hi) { return x >= lo && x <= hi; }  // NaN fails

// Names are quoted in every message about the thing they name: short and printable.
void check_name(Checker& c, const std::string& name, const std::string& path, std::size_t max_bytes = kMaxEchoBytes) {
    bool printable = true;
    for (const char ch : name)
        if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) printable = false;
    c.require(name.size() <= max_bytes, path,
              "must be at most " + std::to_string(max_bytes) + " bytes, got " + std::to_string(name.size()));
    c.require(printable, path, "must not contain control characters");
}


void check_source(Checker& c, const TextureSource& s, const std::string& path, bool albedo_slot) {
    switch (s.kind) {
        case TextureSource::Kind::none: return;
        case TextureSource::Kind::file:
            c.require(!s.path.empty(), path, "the file path is empty");
            return;
        case TextureSource::Kind::color:
            c.require(within(s.color, 0.0f, 1.0f), path + ".color",
                      "components must be within [0, 1], got " + num(s.color));
            return;
        case TextureSource::Kind::procedural: {
            if (albedo_slot) {
                c.require(within(s.low, 0.0f, 1.0f), path + ".low", "components must be within [0, 1], got " + num(s.low));
                c.require(within(s.high, 0.0f, 1.0f), path + ".high",
                          "components must be within [0, 1], got " + num(s.high));
                c.require(s.grain >= 0.0f && s.grain <= 1.0f, path + ".grain",
                          "must be within [0, 1], got " + num(s.grain));
            } else {
                const bool coloured = s.low != glm::vec3(0.0f) || s.high != glm::vec3(1.0f) || s.grain != 0.0f;
                c.require(!coloured, path, "low, high and grain colour a procedural albedo; a height or normal map has no colour");
            }
            // Any size: where a context or technique needs a power of two
            // (ES 2.0 without GL_OES_texture_npot, maxmip's pyramid), the
            // load resamples and says so (scene/material_images.h).
            // The field's own rules live with the generator, which checks
            // them without generating the field.
            const Status field = validate_field_spec(s.field);
            c.require(field.ok(), path, field.ok() ? "" : field.error().message);
            return;
        }
    }
}

void check_camera(Checker& c, const CameraDesc& cam) {
    const std::string coordinate = "components must be within ±" + num(kMaxCoordinate) + ", got ";
    c.require(bounded(cam.position, kMaxCoordinate), "camera.position", coordinate + num(cam.position));
    c.require(bounded(cam.target, kMaxCoordinate), "camera.target", coordinate + num(cam.target));
    c.require(bounded(cam.up, kMaxCoordinate), "camera.up",
              "components must be within ±" + num(kMaxCoordinate) + ", got " + num(cam.up));
    // Past these the projection's tan(fov/2) and far/near overflow or lose
    // every bit of depth precision.
    c.require(in_range(cam.fov_y_deg, 1.0f, 170.0f), "camera.fov_y_deg",
              "must be within [1, 170] degrees, got " + num(cam.fov_y_deg));
    c.require(in_range(cam.near_plane, kMinExtent, kMaxCoordinate), "camera.near",
              "must be within [" + num(kMinExtent) + ", " + num(kMaxCoordinate) + "], got " + num(cam.near_plane));
    c.require(cam.far_plane > cam.near_plane && cam.far_plane <= 1e6f * cam.near_plane &&
                  cam.far_plane <= 2.0f * kMaxCoordinate,
              "camera.far",
              "must be greater than near (" + num(cam.near_plane) + "), at most 10^6 times near and at most " +
                  num(2.0f * kMaxCoordinate) + ", got " + num(cam.far_plane));
    const glm::vec3 view = cam.target - cam.position;
    if (c.require(glm::length(view) > 0.0f, "camera.target", "must differ from camera.position"))
        c.require(glm::length(glm::cross(view, cam.up)) > 1e-6f * glm::length(view) * glm::length(cam.up),
                  "camera.up",
                  "must be non-zero and not parallel to the view direction, got " + num(cam.up));
}

void check_light(Checker& c, const LightDesc& l, const std::string& path) {
    if (l.kind == LightKind::directional)
        // Normalised in float: a length under 1e-6 squares to an underflow.
        c.require(bounded(l.direction, kMaxCoordinate) && glm::length(l.direction) >= 1e-6f, path + ".direction",
                  "must be a non-zero vector (length at least 1e-6, components within ±" + num(kMaxCoordinate) +
                      "), got " + num(l.direction));
    else
        c.require(bounded(l.position, kMaxCoordinate), path + ".position",
                  "components must be within ±" + num(kMaxCoordinate) + ", got " + num(l.position));
    // The shading runs in mediump: fp16 overflows at 65504.
    c.require(within(l.color, 0.0f, kMaxRadiance), path + ".color",
              "components must be within [0, " + num(kMaxRadiance) + "], got " + num(l.color));
    c.require(in_range(l.intensity, 0.0f, kMaxRadiance), path + ".intensity",
              "must be within [0, " + num(kMaxRadiance) + "], got " + num(l.intensity));
    if (!c.failed())
        c.require(std::max({l.color.r, l.color.g, l.color.b}) * l.intensity <= kMaxRadiance, path + ".intensity",
                  "color * intensity must be at most " + num(kMaxRadiance) + " (the shading runs in mediump), got " +
                      num(std::max({l.color.r, l.color.g, l.color.b}) * l.intensity));
    c.require(l.angular_radius_deg >= 0.0f && l.angular_radius_deg <= 45.0f, path + ".angular_radius_deg",
              "must be within [0, 45] degrees, got " + num(l.angular_radius_deg));
}

// Inlined into validate_scene as it was before validate_replaced_material
// called it too: a host app that never replaces a material links one copy.
[[gnu::always_inline]] inline void check_material(Checker& c, const MaterialDesc& m, const std::string& path) {
    c.require(!m.name.empty(), path + ".name", "a material needs a name");
    check_name(c, m.name, path + ".name");
    c.require(in_range(m.height_scale, 0.0f, kMaxHeightScale), path + ".height_scale",
              "must be within [0, " + num(kMaxHeightScale) + "] tiles, got " + num(m.height_scale));
    c.require(in_range(m.bias(), -2.0f * kMaxHeightScale, 2.0f * kMaxHeightScale), path + ".height_bias",
              "must be within ±" + num(2.0f * kMaxHeightScale) + " tiles, got " + num(m.bias()));
    // Texture coordinates run in fp32 (mediump on some paths): past these
    // a texel's position is lost to rounding.
    c.require(magnitudes_within(m.uv.scale, kMinUvScale, kMaxUvScale), path + ".uv.scale",
              "components must be non-zero with magnitudes within [1/16384, 16384], got " + num(m.uv.scale));
    c.require(bounded(m.uv.offset, kMaxUvOffset), path + ".uv.offset",
              "components must be within ±" + num(kMaxUvOffset) + ", got " + num(m.uv.offset));
    c.require(in_range(m.uv.rotation_deg, -kMaxAngleDeg, kMaxAngleDeg), path + ".uv.rotation_deg",
              "must be within ±" + num(kMaxAngleDeg) + " degrees, got " + num(m.uv.rotation_deg));
    c.require(m.specular >= 0.0f && m.specular <= 16.0f, path + ".specular",
              "must be within [0, 16], got " + num(m.specular));
    // The exponent runs in mediump (fp16 on mobile GPUs): past 1024 the
    // highlight is a single pixel and pow's result underflows.
    c.require(m.shininess >= 1.0f && m.shininess <= 1024.0f, path + ".shininess",
              "must be within [1, 1024], got " + num(m.shininess));
    check_source(c, m.albedo, path + ".albedo", true);
    check_source(c, m.height, path + ".height", false);
    check_source(c, m.normal, path + ".normal", false);
    const Status options = validate_options(m.technique);
    c.require(options.ok(), path + ".options", options.ok() ? "" : options.error().message);
    if (m.effects) c.require(validate_effect_request(*m.effects, path + ".effects"));
    // A named technique must be one whose search can follow the bend (a
    // planned material gets one from the planner).
    c.require(!m.silhouette || m.effects || m.technique.forced ||
                  (technique_info(m.technique.technique).options & kOptSamples) != 0,
              path + ".silhouette",
              std::string("a curved silhouette is drawn by the linear searches (steep, pom, relief), not by '") +
                  technique_name(m.technique.technique) + "'");
}

[[gnu::always_inline]] inline void check_object(Checker& c, const ObjectDesc& o, const SceneDesc& scene, const std::string& path) {
    const MeshDesc& mesh = o.mesh;
    const std::string extent = "must be within [" + num(kMinExtent) + ", " + num(kMaxExtent) + "], got ";
    c.require(in_range(mesh.size, kMinExtent, kMaxExtent), path + ".mesh.size", extent + num(mesh.size));
    c.require(mesh.segments >= 1 && mesh.segments <= 1024, path + ".mesh.segments",
              "must be within 1..1024, got " + std::to_string(mesh.segments));
    c.require(in_range(mesh.radius, kMinExtent, kMaxExtent), path + ".mesh.radius", extent + num(mesh.radius));
    c.require(!mesh.displaced || mesh.kind != MeshKind::cube, path + ".mesh.displaced",
              "a cube cannot be displaced (its faces would open at the edges); a plane, sphere, torus or cylinder can");
    c.require(mesh.vertices_per_texel >= 1 && mesh.vertices_per_texel <= kMaxDisplacedVerticesPerTexel,
              path + ".mesh.vertices_per_texel",
              "must be within 1.." + std::to_string(kMaxDisplacedVerticesPerTexel) + ", got " +
                  std::to_string(mesh.vertices_per_texel));
    c.require(mesh.displaced || mesh.vertices_per_texel == 1, path + ".mesh.vertices_per_texel",
              "only a displaced mesh (\"displaced\": true) has vertices per texel");
    c.require(in_range(mesh.tube_radius, kMinExtent, kMaxExtent), path + ".mesh.tube_radius",
              extent + num(mesh.tube_radius));
    // Any direction, zero and parallel ones included (surface.vert falls
    // back); only the magnitude is bounded, as every coordinate is.
    for (auto [key, v] : {std::pair{".mesh.tangent", &mesh.tangent}, std::pair{".mesh.normal", &mesh.normal}})
        if (v->has_value()) {
            c.require(mesh.kind == MeshKind::plane, path + key, "only a plane takes an authored frame");
            c.require(!mesh.displaced, path + key, "a displaced plane keeps the plane's frame (+u, +z)");
            c.require(bounded(**v, kMaxCoordinate), path + key,
                      "components must be within ±" + num(kMaxCoordinate) + ", got " + num(**v));
        }
    if (mesh.kind == MeshKind::torus)  // a thicker tube passes through the axis and folds over itself
        c.require(mesh.tube_radius < mesh.radius, path + ".mesh.tube_radius",
                  "must be less than radius (" + num(mesh.radius) + "), got " + num(mesh.tube_radius));

    const TransformDesc& t = o.transform;
    c.require(bounded(t.translate, kMaxCoordinate), path + ".transform.translate",
              "components must be within ±" + num(kMaxCoordinate) + ", got " + num(t.translate));
    c.require(bounded(t.rotate_deg, kMaxAngleDeg), path + ".transform.rotate_deg",
              "components must be within ±" + num(kMaxAngleDeg) + " degrees, got " + num(t.rotate_deg));
    // The normal matrix inverts the scale: both stay inside fp32.
    c.require(magnitudes_within(t.scale, kMinExtent, kMaxExtent), path + ".transform.scale",
              "components must be non-zero with magnitudes within [" + num(kMinExtent) + ", " + num(kMaxExtent) +
                  "], got " + num(t.scale));
    check_name(c, o.name, path + ".name");

    if (!scene.find_material(o.material)) {
        std::vector<std::string> names;
        for (const MaterialDesc& m : scene.materials) names.push_back(m.name);
        c.require(false, path + ".material",
                  "no material named '" + echo(o.material) + "' (" +
                      (names.empty() ? std::string("the scene defines none") : "materials: " + joined(names)) +
                      ")");
    } else if (scene.find_material(o.material)->bounded) {
        // A sphere's or a torus's uv wraps around it: its uv edges are seams,
        // where a bounded relief would be cut open (a plane's and each cube
        // face's are the tile's own edges; an open cylinder's v edges are its
        // ends, bounds along v only, while u wraps around).
        c.require(mesh.kind == MeshKind::plane || mesh.kind == MeshKind::cube || mesh.kind == MeshKind::cylinder,
                  path + ".material",
                  "material '" + echo(o.material) + "' is bounded (a tile or a decal), and a " +
                      mesh_kind_name(mesh.kind) + "'s uv edges are seams where its surface wraps around, not bounds");
    }
}

}  // namespace

std::optional<double> relief_folds_through(const MeshDesc& d, const MaterialDesc& m, double units_per_uv) {
    if (!mesh_kind_is_curved(d.kind) || !(m.height_scale > 0.0f)) return std::nullopt;
    const double area_scale = m.uv.area_scale<double>();
    if (!(area_scale > 0.0)) return std::nullopt;
    const double below = static_cast<double>(m.height_scale) * units_per_uv / area_scale * std::max(m.polygon_height(), 0.0);
    const double radius = d.kind == MeshKind::torus ? d.tube_radius : d.radius;
    if (!(below >= radius)) return std::nullopt;
    return below;
}

std::string silhouette_folds_note(const MeshDesc& d, double below) {
    const bool torus = d.kind == MeshKind::torus;
    return "silhouette off: the relief reaches " + fixed_text(below, 3) + " mesh units below the polygon, through the " +
           mesh_kind_name(d.kind) + (torus ? "'s tube (tube radius " : "'s centre (radius ") +
           fixed_text(torus ? d.tube_radius : d.radius, 3) +
           "), where the displaced surface folds over itself and has no outline to trace; the smooth outline is drawn "
           "(a smaller height_scale, under " +
           fixed_text(d.kind == MeshKind::torus ? d.tube_radius : d.radius, 3) + " units deep, keeps the silhouette)";
}

std::optional<std::string> open_tube_ends_note(const MeshDesc& d, const MaterialDesc& m) {
    if (d.kind != MeshKind::cylinder || !m.silhouette || m.bounded || d.displaced || !(m.height_scale > 0.0f))
        return std::nullopt;
    return std::string("open ends: the tube is not bounded, so its relief runs on past the rims and the ends keep the "
                       "smooth rim's outline (\"bounded\": true traces them)");
}

std::vector<std::string> force_technique(MaterialDesc& m, Technique t) {
    std::vector<std::string> notes;
    const TechniqueInfo& info = technique_info(t);
    const std::string who = "material '" + echo(m.name) + "': ";
    if (m.effects) notes.push_back(who + "its effect request gives way to " + info.name);
    m.effects.reset();
    TechniqueOptions& o = m.technique;
    o.technique = t;
    o.forced = true;
    const int limit = info.max_samples_limit;
    if (info.options & kOptSamples) {
        const int min = std::clamp(o.min_samples, 1, limit), max = std::clamp(o.max_samples, min, limit);
        if (min != o.min_samples || max != o.max_samples)
            notes.push_back(who + "samples " + std::to_string(o.min_samples) + ".." + std::to_string(o.max_samples) +
                            " -> " + std::to_string(min) + ".." + std::to_string(max) + " (" + info.name +
                            "'s range is 1.." + std::to_string(limit) + ")");
        o.min_samples = min;
        o.max_samples = max;
    }
    if ((info.options & kOptSteps) && (o.max_steps < 1 || o.max_steps > limit)) {
        notes.push_back(who + "max_steps " + std::to_string(o.max_steps) + " -> " +
                        std::to_string(std::clamp(o.max_steps, 1, limit)) + " (" + info.name + "'s range is 1.." +
                        std::to_string(limit) + ")");
        o.max_steps = std::clamp(o.max_steps, 1, limit);
    }
    return notes;
}

std::vector<std::string> force_technique(SceneDesc& scene, Technique t) {
    std::vector<std::string> notes;
    for (MaterialDesc& m : scene.materials) {
        std::vector<std::string> n = force_technique(m, t);
        notes.insert(notes.end(), n.begin(), n.end());
    }
    return notes;
}

double bounded_margin(const MaterialDesc& m) {
    if (!m.bounded || !(m.height_scale > 0.0f)) return 0.0;
    const double area_scale = m.uv.area_scale<double>();
    if (!(area_scale > 0.0)) return 0.0;
    constexpr double kTan80 = 5.671281819617709;
    return std::min(4.0, static_cast<double>(m.height_scale) * kTan80 / area_scale);
}

glm::mat4 TransformDesc::matrix() const {
    glm::mat4 m = glm::translate(glm::mat4(1.0f), translate);
    m = glm::rotate(m, glm::radians(rotate_deg.z), glm::vec3(0.0f, 0.0f, 1.0f));
    m = glm::rotate(m, glm::radians(rotate_deg.y), glm::vec3(0.0f, 1.0f, 0.0f));
    m = glm::rotate(m, glm::radians(rotate_deg.x), glm::vec3(1.0f, 0.0f, 0.0f));
    return glm::scale(m, scale);
}

const char* channel_name(TextureSource::Channel c) {
    switch (c) {
        case TextureSource::Channel::grey: return "grey";
        case TextureSource::Channel::r: return "r";
        case TextureSource::Channel::g: return "g";
        case TextureSource::Channel::b: return "b";
        case TextureSource::Channel::a: return "a";
    }
    return "?";
}

int channel_index(TextureSource::Channel c) {
    return c == TextureSource::Channel::grey ? 0 : static_cast<int>(c) - 1;
}

TextureSource::TextureSource() = default;
TextureSource::TextureSource(const TextureSource&) = default;
TextureSource::TextureSource(TextureSource&&) noexcept = default;
TextureSource& TextureSource::operator=(const TextureSource&) = default;
TextureSource& TextureSource::operator=(TextureSource&&) noexcept = default;
TextureSource::~TextureSource() = default;

MaterialDesc::MaterialDesc() = default;
MaterialDesc::MaterialDesc(const MaterialDesc&) = default;
MaterialDesc::MaterialDesc(MaterialDesc&&) noexcept = default;
MaterialDesc& MaterialDesc::operator=(const MaterialDesc&) = default;
MaterialDesc& MaterialDesc::operator=(MaterialDesc&&) noexcept = default;
MaterialDesc::~MaterialDesc() = default;

ObjectDesc::ObjectDesc() = default;
ObjectDesc::ObjectDesc(const ObjectDesc&) = default;
ObjectDesc::ObjectDesc(ObjectDesc&&) noexcept = default;
ObjectDesc& ObjectDesc::operator=(const ObjectDesc&) = default;
ObjectDesc& ObjectDesc::operator=(ObjectDesc&&) noexcept = default;
ObjectDesc::~ObjectDesc() = default;

SceneDesc::SceneDesc() = default;
SceneDesc::SceneDesc(const SceneDesc&) = default;
SceneDesc::SceneDesc(SceneDesc&&) noexcept = default;
SceneDesc& SceneDesc::operator=(const SceneDesc&) = default;
SceneDesc& SceneDesc::operator=(SceneDesc&&) noexcept = default;
SceneDesc::~SceneDesc() = default;

size_t SceneDesc::material_index(const std::string& material_name) const {
    for (size_t i = 0; i < materials.size(); ++i)
        if (materials[i].name == material_name) return i;
    return materials.size();
}

const MaterialDesc* SceneDesc::find_material(const std::string& material_name) const {
    const size_t i = material_index(material_name);
    return i < materials.size() ? &materials[i] : nullptr;
}

Status validate_replaced_material(const SceneDesc& scene, size_t mi) {
    if (mi >= scene.materials.size())
        return make_error("materials: no material " + std::to_string(mi) + " (the scene has " +
                          std::to_string(scene.materials.size()) + ")");
    Checker c;
    const std::string path = index_path("materials", mi);
    check_material(c, scene.materials[mi], path);
    for (std::size_t k = 0; k < scene.materials.size(); ++k)
        c.require(k == mi || scene.materials[k].name != scene.materials[mi].name, path + ".name",
                  "duplicate material name '" + echo(scene.materials[mi].name) + "' (also " +
                      index_path("materials", k) + ")");
    // The objects drawn with it: what they may be drawn with depends on it
    // (a bounded material's meshes).
    for (std::size_t i = 0; i < scene.objects.size(); ++i)
        if (scene.objects[i].material == scene.materials[mi].name)
            check_object(c, scene.objects[i], scene, index_path("objects", i));
    return c.status();
}

Status validate_scene(const SceneDesc& scene) {
    counters::count(counters::Step::validation);
    Checker c;
    check_name(c, scene.name, "name", 255);  // a file's stem is the default: up to 255 bytes
    check_camera(c, scene.camera);
    c.require(within(scene.ambient, 0.0f, kMaxRadiance), "ambient",
              "components must be within [0, " + num(kMaxRadiance) + "], got " + num(scene.ambient));
    // Drawn per object in one pass with a constant loop bound: a light past
    // the last would be dropped without a word, so it is refused.
    c.require(scene.lights.size() <= static_cast<std::size_t>(kMaxLights), index_path("lights", kMaxLights),
              "at most " + std::to_string(kMaxLights) + " lights are drawn, got " + std::to_string(scene.lights.size()) +
                  "; remove lights[" + std::to_string(kMaxLights) + "] and after");
    c.require(scene.materials.size() <= static_cast<std::size_t>(kMaxMaterials), "materials",
              "at most " + std::to_string(kMaxMaterials) + " materials, got " + std::to_string(scene.materials.size()));
    c.require(scene.objects.size() <= static_cast<std::size_t>(kMaxObjects), "objects",
              "at most " + std::to_string(kMaxObjects) + " objects, got " + std::to_string(scene.objects.size()));
    c.require(within(scene.background, 0.0f, 1.0f), "background",
              "components must be within [0, 1], got " + num(scene.background));
    for (std::size_t i = 0; i < scene.lights.size(); ++i) check_light(c, scene.lights[i], index_path("lights", i));
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const std::string path = index_path("materials", i);
        check_material(c, scene.materials[i], path);
        for (std::size_t k = 0; k < i; ++k)
            c.require(scene.materials[k].name != scene.materials[i].name, path + ".name",
                      "duplicate material name '" + echo(scene.materials[i].name) + "' (also " +
                          index_path("materials", k) + ")");
    }
    c.require(!scene.objects.empty(), "objects", "a scene needs at least one object");
    for (std::size_t i = 0; i < scene.objects.size(); ++i)
        check_object(c, scene.objects[i], scene, index_path("objects", i));
    return c.status();
}

namespace {

bool widens(const MeshDesc& d, const MaterialDesc& m) {
    return !d.displaced && bounded_margin(m) > 0.0 && (d.kind == MeshKind::plane || d.kind == MeshKind::cylinder);
}

}  // namespace

std::optional<Mesh> build_widened_mesh(const MeshDesc& d, const MaterialDesc& m) {
    if (!widens(d, m)) return std::nullopt;
    // Not counted as a mesh build: the object's own mesh is (one per object,
    // tests/render_stats.sh); this is the drawn copy of it.
    const auto margin = static_cast<float>(bounded_margin(m));
    // As build_object_mesh makes the plane and the cylinder, wider.
    if (d.kind == MeshKind::plane) return make_widened_plane(d.size, d.segments, margin, d.tangent, d.normal);
    return make_widened_cylinder(d.radius, d.size, margin);
}

double drawn_length_scale(const MeshDesc& d, const MaterialDesc& m) {
    return widens(d, m) ? 1.0 + 2.0 * bounded_margin(m) : 1.0;
}

Mesh build_object_mesh(const MeshDesc& d) {
    counters::count(counters::Step::mesh_build);
    switch (d.kind) {
        case MeshKind::plane: return make_plane(d.size, d.segments, d.tangent, d.normal);
        case MeshKind::cube: return make_cube(d.size);
        case MeshKind::sphere: return make_uv_sphere(d.radius);
        case MeshKind::torus: return make_torus(d.radius, d.tube_radius);
        case MeshKind::cylinder: return make_cylinder(d.radius, d.size);
    }
    return make_plane();
}

}  // namespace px
