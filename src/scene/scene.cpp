// The checks every scene (parsed or built in code) must pass, with the JSON
// path of the offending field; and the scene description's small methods.
// No JSON here: a host app that builds its scene in code links this without
// the parser (scene_json.cpp).
#include "scene/scene.h"

#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "core/numeric.h"
#include "scene/scene_format.h"

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
    bool failed() const { return error_.has_value(); }
    Status status() const { return error_ ? Status(*error_) : Status(); }

private:
    std::optional<Error> error_;
};

template <glm::length_t N>
bool finite(const glm::vec<N, float, glm::defaultp>& v) {
    for (glm::length_t i = 0; i < N; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

template <glm::length_t N>
bool within(const glm::vec<N, float, glm::defaultp>& v, float lo, float hi) {
    for (glm::length_t i = 0; i < N; ++i)
        if (!(v[i] >= lo && v[i] <= hi)) return false;  // NaN fails too
    return true;
}

template <glm::length_t N>
bool non_negative(const glm::vec<N, float, glm::defaultp>& v) {
    return finite(v) && within(v, 0.0f, std::numeric_limits<float>::max());
}

template <glm::length_t N>
bool no_zero(const glm::vec<N, float, glm::defaultp>& v) {
    for (glm::length_t i = 0; i < N; ++i)
        if (v[i] == 0.0f) return false;
    return true;
}


void check_source(Checker& c, const TextureSource& s, const std::string& path) {
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
            // ES 2.0 leaves a non-power-of-two texture incomplete under
            // GL_REPEAT or mipmapping, and relief textures need both.
            if (!c.require(is_power_of_two(s.field.size), path + ".size",
                           "must be a power of two (OpenGL ES 2.0 repeats only those), got " +
                               std::to_string(s.field.size)))
                return;
            // The field's own rules live with the generator, which checks
            // them without generating the field.
            const Status field = validate_field_spec(s.field);
            c.require(field.ok(), path, field.ok() ? "" : field.error().message);
            return;
        }
    }
}

void check_camera(Checker& c, const CameraDesc& cam) {
    c.require(finite(cam.position), "camera.position", "must be finite, got " + num(cam.position));
    c.require(finite(cam.target), "camera.target", "must be finite, got " + num(cam.target));
    c.require(finite(cam.up), "camera.up", "must be finite, got " + num(cam.up));
    c.require(cam.fov_y_deg > 0.0f && cam.fov_y_deg < 180.0f, "camera.fov_y_deg",
              "must be within (0, 180) degrees, got " + num(cam.fov_y_deg));
    c.require(cam.near_plane > 0.0f && std::isfinite(cam.near_plane), "camera.near",
              "must be greater than 0, got " + num(cam.near_plane));
    c.require(cam.far_plane > cam.near_plane && std::isfinite(cam.far_plane), "camera.far",
              "must be greater than near (" + num(cam.near_plane) + "), got " + num(cam.far_plane));
    const glm::vec3 view = cam.target - cam.position;
    if (c.require(glm::length(view) > 0.0f, "camera.target", "must differ from camera.position"))
        c.require(glm::length(glm::cross(view, cam.up)) > 1e-6f * glm::length(view) * glm::length(cam.up),
                  "camera.up",
                  "must be non-zero and not parallel to the view direction, got " + num(cam.up));
}

void check_light(Checker& c, const LightDesc& l, const std::string& path) {
    if (l.kind == LightKind::directional)
        c.require(finite(l.direction) && glm::length(l.direction) > 0.0f, path + ".direction",
                  "must be a finite non-zero vector, got " + num(l.direction));
    else
        c.require(finite(l.position), path + ".position", "must be finite, got " + num(l.position));
    c.require(non_negative(l.color), path + ".color",
              "components must be 0 or more, got " + num(l.color));
    c.require(l.intensity >= 0.0f && std::isfinite(l.intensity), path + ".intensity",
              "must be 0 or more, got " + num(l.intensity));
    c.require(l.angular_radius_deg >= 0.0f && l.angular_radius_deg <= 45.0f, path + ".angular_radius_deg",
              "must be within [0, 45] degrees, got " + num(l.angular_radius_deg));
}

void check_material(Checker& c, const MaterialDesc& m, const std::string& path) {
    c.require(!m.name.empty(), path + ".name", "a material needs a name");
    c.require(m.height_scale >= 0.0f && std::isfinite(m.height_scale), path + ".height_scale",
              "must be 0 or more, got " + num(m.height_scale));
    c.require(std::isfinite(m.bias()), path + ".height_bias", "must be finite, got " + num(m.bias()));
    c.require(finite(m.uv.scale) && no_zero(m.uv.scale), path + ".uv.scale",
              "components must be finite and non-zero, got " + num(m.uv.scale));
    c.require(finite(m.uv.offset), path + ".uv.offset", "must be finite, got " + num(m.uv.offset));
    c.require(std::isfinite(m.uv.rotation_deg), path + ".uv.rotation_deg", "must be finite");
    c.require(m.specular >= 0.0f && m.specular <= 16.0f, path + ".specular",
              "must be within [0, 16], got " + num(m.specular));
    // The exponent runs in mediump (fp16 on mobile GPUs): past 1024 the
    // highlight is a single pixel and pow's result underflows.
    c.require(m.shininess >= 1.0f && m.shininess <= 1024.0f, path + ".shininess",
              "must be within [1, 1024], got " + num(m.shininess));
    check_source(c, m.albedo, path + ".albedo");
    check_source(c, m.height, path + ".height");
    check_source(c, m.normal, path + ".normal");
    const Status options = validate_options(m.technique);
    c.require(options.ok(), path + ".options", options.ok() ? "" : options.error().message);
}

void check_object(Checker& c, const ObjectDesc& o, const SceneDesc& scene, const std::string& path) {
    const MeshDesc& mesh = o.mesh;
    c.require(mesh.size > 0.0f && std::isfinite(mesh.size), path + ".mesh.size",
              "must be greater than 0, got " + num(mesh.size));
    c.require(mesh.segments >= 1 && mesh.segments <= 1024, path + ".mesh.segments",
              "must be within 1..1024, got " + std::to_string(mesh.segments));
    c.require(mesh.radius > 0.0f && std::isfinite(mesh.radius), path + ".mesh.radius",
              "must be greater than 0, got " + num(mesh.radius));
    c.require(!mesh.displaced || mesh.kind == MeshKind::plane, path + ".mesh.displaced",
              "only a plane can be displaced");
    c.require(mesh.tube_radius > 0.0f && std::isfinite(mesh.tube_radius), path + ".mesh.tube_radius",
              "must be greater than 0, got " + num(mesh.tube_radius));
    if (mesh.kind == MeshKind::torus)  // a thicker tube passes through the axis and folds over itself
        c.require(mesh.tube_radius < mesh.radius, path + ".mesh.tube_radius",
                  "must be less than radius (" + num(mesh.radius) + "), got " + num(mesh.tube_radius));

    const TransformDesc& t = o.transform;
    c.require(finite(t.translate), path + ".transform.translate", "must be finite, got " + num(t.translate));
    c.require(finite(t.rotate_deg), path + ".transform.rotate_deg", "must be finite, got " + num(t.rotate_deg));
    c.require(finite(t.scale) && no_zero(t.scale), path + ".transform.scale",
              "components must be finite and non-zero, got " + num(t.scale));

    if (!scene.find_material(o.material)) {
        std::vector<std::string> names;
        for (const MaterialDesc& m : scene.materials) names.push_back(m.name);
        c.require(false, path + ".material",
                  "no material named '" + o.material + "' (" +
                      (names.empty() ? std::string("the scene defines none") : "materials: " + joined(names)) +
                      ")");
    }
}

}  // namespace

glm::mat4 TransformDesc::matrix() const {
    glm::mat4 m = glm::translate(glm::mat4(1.0f), translate);
    m = glm::rotate(m, glm::radians(rotate_deg.z), glm::vec3(0.0f, 0.0f, 1.0f));
    m = glm::rotate(m, glm::radians(rotate_deg.y), glm::vec3(0.0f, 1.0f, 0.0f));
    m = glm::rotate(m, glm::radians(rotate_deg.x), glm::vec3(1.0f, 0.0f, 0.0f));
    return glm::scale(m, scale);
}

size_t SceneDesc::material_index(const std::string& material_name) const {
    for (size_t i = 0; i < materials.size(); ++i)
        if (materials[i].name == material_name) return i;
    return materials.size();
}

const MaterialDesc* SceneDesc::find_material(const std::string& material_name) const {
    const size_t i = material_index(material_name);
    return i < materials.size() ? &materials[i] : nullptr;
}

Status validate_scene(const SceneDesc& scene) {
    Checker c;
    check_camera(c, scene.camera);
    c.require(non_negative(scene.ambient), "ambient",
              "components must be 0 or more, got " + num(scene.ambient));
    c.require(within(scene.background, 0.0f, 1.0f), "background",
              "components must be within [0, 1], got " + num(scene.background));
    for (std::size_t i = 0; i < scene.lights.size(); ++i) check_light(c, scene.lights[i], index_path("lights", i));
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const std::string path = index_path("materials", i);
        check_material(c, scene.materials[i], path);
        for (std::size_t k = 0; k < i; ++k)
            c.require(scene.materials[k].name != scene.materials[i].name, path + ".name",
                      "duplicate material name '" + scene.materials[i].name + "' (also " +
                          index_path("materials", k) + ")");
    }
    c.require(!scene.objects.empty(), "objects", "a scene needs at least one object");
    for (std::size_t i = 0; i < scene.objects.size(); ++i)
        check_object(c, scene.objects[i], scene, index_path("objects", i));
    return c.status();
}

}  // namespace px
