#include "parallaxes/scene/prepared_scene.h"

#include "parallaxes/core/text.h"

#include <algorithm>
#include <cmath>

namespace px {

namespace {

std::string scene_label(const SceneDesc& scene) {
    return scene.source.empty() ? "scene '" + echo(scene.name) + "'" : echo_path(scene.source);
}

Result<std::shared_ptr<const PreparedMaterial>> prepare_material(const MaterialDesc& m, const SceneDesc& scene,
                                                                 const PrepareOptions& options) {
    Result<MaterialImages> images = build_material_images_from(m, scene.base_dir, options.images);
    if (!images) return images.error();
    auto prepared = std::make_shared<PreparedMaterial>();
    prepared->images = std::move(*images);
    return std::shared_ptr<const PreparedMaterial>(std::move(prepared));
}

// The relief's depth in mesh units over a mesh of `units_per_uv`.
float relief_depth(const MaterialDesc& m, float units_per_uv) {
    return m.height_scale * units_per_uv / m.uv.area_scale<float>();
}

// Whether an object draws its material's curved silhouette where its
// technique can: a parallax-drawn sphere, torus or cylinder whose material
// asks for it, and whose relief does not reach through its centre or axis
// (relief_folds_through).
bool curved_silhouette(const MaterialDesc& m, const ObjectDesc& o, float units_per_uv) {
    return m.silhouette && mesh_kind_is_curved(o.mesh.kind) && !o.mesh.displaced &&
           !relief_folds_through(o.mesh, m, units_per_uv);
}

// A bounded tube's rim caps, or nothing: an annulus at each end over the
// relief's whole depth, whatever the technique's polygon height (1 or
// less: the relief from R - depth to R + depth at most), with room for the
// shell that surface.vert pushes every vertex out by along its normal (the
// caps' too: kShellOverSag chord sags, radially), which moved an inner
// edge set at the relief's bottom a tenth of a relief depth outward and
// cut the rays that come onto the tube just above its valleys (3.7 % of
// the contour at 60 degrees, 18.6 % at 89); a cap fragment outside the
// relief or in the hollow draws nothing (march.glsl).
std::optional<Mesh> build_rim_caps(const ObjectDesc& o, const MaterialDesc& m, const Mesh& prepared) {
    if (!(m.bounded && curved_silhouette(m, o, prepared.units_per_uv) && o.mesh.kind == MeshKind::cylinder))
        return std::nullopt;
    const float depth = relief_depth(m, prepared.units_per_uv);
    if (!(std::isfinite(depth) && depth > 0.0f)) return std::nullopt;
    const float r = o.mesh.radius;
    const float shell = kShellOverSag * prepared.chord_sag;
    const float inner = std::max(0.0f, r - 1.1f * depth - 2.0f * shell);
    const float outer = r + 1.1f * depth + 2.0f * shell;
    Mesh caps = make_tube_rim_caps(prepared, r, inner, outer);
    if (caps.indices.empty()) return std::nullopt;
    return caps;
}

// A bounded plane's side walls, or nothing: along its edges over the
// relief's whole depth, whatever the polygon's height in it (and a tenth of
// a relief depth past each end).
std::optional<Mesh> build_tile_walls(const ObjectDesc& o, const MaterialDesc& m, const Mesh& prepared) {
    if (!(m.bounded && o.mesh.kind == MeshKind::plane && !o.mesh.displaced)) return std::nullopt;
    const float depth = relief_depth(m, prepared.units_per_uv);
    const auto polygon = static_cast<float>(m.polygon_height());
    if (!(std::isfinite(depth) && depth > 0.0f && std::isfinite(polygon))) return std::nullopt;
    const float below = (std::max(polygon, 0.0f) + 0.1f) * depth;
    const float above = (std::max(1.0f - polygon, 0.0f) + 0.1f) * depth;
    Mesh walls = make_tile_walls(prepared, below, above);
    if (walls.indices.empty()) return std::nullopt;
    return walls;
}

// What a bounded relief draws besides the object's own mesh.
void prepare_drawn_extras(PreparedObject& prepared, const ObjectDesc& o, const MaterialDesc& m) {
    prepared.widened = build_widened_mesh(o.mesh, m);
    prepared.rim_caps.reset();
    prepared.tile_walls.reset();
    if (!prepared.widened) return;
    prepared.rim_caps = build_rim_caps(o, m, prepared.mesh);
    prepared.tile_walls = build_tile_walls(o, m, prepared.mesh);
}

Result<std::shared_ptr<const PreparedObject>> prepare_object(const ObjectDesc& o, size_t material_index,
                                                             const MaterialDesc& m, const PreparedMaterial& material) {
    auto prepared = std::make_shared<PreparedObject>();
    prepared->material = material_index;
    if (o.mesh.displaced && o.mesh.kind != MeshKind::plane) {
        if (o.mesh.kind == MeshKind::cube)
            return make_error("object '" + echo(o.name) + "': a cube cannot be displaced (mesh.displaced)");
        // Depth in object units as the parallax-drawn mesh has it.
        const float units_per_uv = build_object_mesh(o.mesh).units_per_uv;
        Result<Mesh> displaced = make_displaced_curved(
            o.mesh.kind, CurvedMeshSize{o.mesh.radius, o.mesh.tube_radius, o.mesh.size}, material.images.traced,
            m.uv.matrix<double>(), glm::dvec2(m.uv.offset), m.height_scale, static_cast<float>(m.polygon_height()),
            units_per_uv, o.mesh.vertices_per_texel);
        if (!displaced) return with_context("object '" + echo(o.name) + "'", displaced.error());
        prepared->mesh = std::move(*displaced);
    } else if (o.mesh.displaced) {
        // The relief under the shading's uv' (the material's uv transform), a
        // tile size / area_scale mesh units as the units_per_tile uniform says.
        Result<Mesh> displaced =
            make_displaced_plane(o.mesh.size, material.images.traced, m.uv.matrix<double>(), glm::dvec2(m.uv.offset),
                                 m.height_scale, static_cast<float>(m.polygon_height()), o.mesh.vertices_per_texel);
        if (!displaced) return with_context("object '" + echo(o.name) + "'", displaced.error());
        prepared->mesh = std::move(*displaced);
    } else {
        prepared->mesh = build_object_mesh(o.mesh);
    }
    prepare_drawn_extras(*prepared, o, m);
    return std::shared_ptr<const PreparedObject>(std::move(prepared));
}

// A scene that reads files, prepared without file readers: refused before
// anything is built, naming the first file.
Status check_files_readable(const SceneDesc& scene, const PrepareOptions& options) {
    if (options.images.files) return {};
    const std::string first = first_file_source(scene);
    if (first.empty()) return {};
    return make_error(first + ": the scene reads files, and this preparation has no file readers: set "
                              "RendererOptions::texture_files = px::texture_files() (or PrepareOptions::images.files "
                              "= px::texture_file_readers())");
}

Result<std::shared_ptr<const PreparedScene>> prepare_checked(const SceneDesc& scene, const PrepareOptions& options) {
    if (Status s = validate_scene(scene); !s) return s.error();
    if (Status s = check_files_readable(scene, options); !s) return s.error();
    if (Status s = check_scene_resources_with(scene, options.images.files); !s) return s.error();
    auto prepared = std::make_shared<PreparedScene>();
    prepared->desc = scene;
    prepared->options = options;
    for (const MaterialDesc& m : scene.materials) {
        // Keyed by their sources: a material whose images another one
        // already has shares them.
        std::shared_ptr<const PreparedMaterial> shared;
        for (size_t k = 0; k < prepared->materials.size() && !shared; ++k)
            if (same_material_images(scene.materials[k], m)) shared = prepared->materials[k];
        if (shared) {
            prepared->materials.push_back(std::move(shared));
            continue;
        }
        Result<std::shared_ptr<const PreparedMaterial>> material = prepare_material(m, scene, options);
        if (!material) return material.error();
        prepared->materials.push_back(std::move(*material));
    }
    for (const ObjectDesc& o : scene.objects) {
        const size_t mi = scene.material_index(o.material);  // validate_scene checked that it exists
        Result<std::shared_ptr<const PreparedObject>> object =
            prepare_object(o, mi, scene.materials[mi], *prepared->materials[mi]);
        if (!object) return object.error();
        prepared->objects.push_back(std::move(*object));
    }
    return std::shared_ptr<const PreparedScene>(std::move(prepared));
}

}  // namespace

Result<std::shared_ptr<const PreparedScene>> prepare_scene(const SceneDesc& scene, const PrepareOptions& options) {
    Result<std::shared_ptr<const PreparedScene>> prepared = out_of_memory_is_an_error(
        "preparing " + scene_label(scene), [&] { return prepare_checked(scene, options); });
    if (!prepared && !scene.source.empty()) return with_context(echo_path(scene.source), prepared.error());
    return prepared;
}

Result<std::shared_ptr<const PreparedScene>> replace_material(const PreparedScene& scene, const MaterialDesc& material) {
    const size_t mi = scene.desc.material_index(material.name);
    if (mi >= scene.desc.materials.size())
        return make_error("replace_material: the scene has no material '" + echo(material.name) + "'");
    return out_of_memory_is_an_error("replacing material '" + echo(material.name) + "'",
                                      [&]() -> Result<std::shared_ptr<const PreparedScene>> {
        auto next = std::make_shared<PreparedScene>(scene);
        next->desc.materials[mi] = material;
        // The rest of the scene was validated when it was prepared.
        if (Status s = validate_replaced_material(next->desc, mi); !s) return s.error();
        if (Status s = check_files_readable(next->desc, scene.options); !s) return s.error();
        if (Status s = check_scene_resources_with(next->desc, scene.options.images.files); !s) return s.error();
        // The images are kept where only what they do not depend on changed
        // (a technique, a sample count, a shadow).
        if (!images_serve(scene.materials[mi]->images, scene.desc.materials[mi], material)) {
            Result<std::shared_ptr<const PreparedMaterial>> prepared =
                prepare_material(material, next->desc, scene.options);
            if (!prepared) return prepared.error();
            next->materials[mi] = std::move(*prepared);
        }
        for (size_t i = 0; i < next->desc.objects.size(); ++i) {
            const ObjectDesc& o = next->desc.objects[i];
            if (next->objects[i]->material != mi) continue;
            const MaterialDesc& before = scene.desc.materials[mi];
            const bool same_displacement = next->materials[mi] == scene.materials[mi] &&
                                           before.uv.scale == material.uv.scale &&
                                           before.uv.offset == material.uv.offset &&
                                           before.uv.rotation_deg == material.uv.rotation_deg &&
                                           before.polygon_height() == material.polygon_height();
            if (o.mesh.displaced && !same_displacement) {  // displaced from the new relief
                Result<std::shared_ptr<const PreparedObject>> object =
                    prepare_object(o, mi, material, *next->materials[mi]);
                if (!object) return object.error();
                next->objects[i] = std::move(*object);
                continue;
            }
            // The same mesh; its widened copy, walls and rim caps follow the
            // new material's bounds, silhouette and depth.
            auto redrawn = std::make_shared<PreparedObject>(*next->objects[i]);
            prepare_drawn_extras(*redrawn, o, material);
            next->objects[i] = std::move(redrawn);
        }
        return std::shared_ptr<const PreparedScene>(std::move(next));
    });
}

}  // namespace px
