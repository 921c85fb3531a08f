#include "parallaxes/scene/prepared_scene.h"

#include "parallaxes/core/text.h"

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
        if (Status s = validate_scene(next->desc); !s) return s.error();
        if (Status s = check_files_readable(next->desc, scene.options); !s) return s.error();
        if (Status s = check_scene_resources_with(next->desc, scene.options.images.files); !s) return s.error();
        Result<std::shared_ptr<const PreparedMaterial>> prepared = prepare_material(material, next->desc, scene.options);
        if (!prepared) return prepared.error();
        next->materials[mi] = std::move(*prepared);
        for (size_t i = 0; i < next->desc.objects.size(); ++i) {
            const ObjectDesc& o = next->desc.objects[i];
            if (next->objects[i]->material != mi || !o.mesh.displaced) continue;
            Result<std::shared_ptr<const PreparedObject>> object = prepare_object(o, mi, material, *next->materials[mi]);
            if (!object) return object.error();
            next->objects[i] = std::move(*object);
        }
        return std::shared_ptr<const PreparedScene>(std::move(next));
    });
}

}  // namespace px
