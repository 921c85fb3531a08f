// One preparation of a scene, shared by everything that draws, plans, traces
// or measures it (DESIGN.md): the description validated once, each
// material's images, texture files and texture layout built once, each
// object's mesh built once (a displaced plane displaced: the mesh that is
// drawn is the mesh the planner surveys). GL-free and immutable: the renderer
// uploads it, the planner, the exact reference, the benchmark and the
// stability catalogue read it.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/scene/mesh.h"
#include "parallaxes/scene/scene.h"

namespace px {

struct PreparedMaterial {
    MaterialImages images;
};

// One object as it is drawn: its mesh, and what a bounded or silhouetted
// relief draws besides (GL-free; the renderer only uploads these).
struct PreparedObject {
    size_t material = 0;  // index into PreparedScene::materials (and desc.materials)
    Mesh mesh;            // the object's own mesh (a displaced one displaced): what the planner surveys
    // A bounded relief on a plane or an open cylinder: the mesh drawn wider
    // by bounded_margin (build_widened_mesh), so that the traces that leave
    // the tile through its side start where the ray comes in; `mesh` is
    // still drawn by the variants that trace nothing.
    std::optional<Mesh> widened;
    // A bounded tube with a curved silhouette: an annulus at each end over
    // the relief's whole depth (what the exact shape search draws the rims with).
    std::optional<Mesh> rim_caps;
    // A bounded plane: its side walls over the relief's whole depth (for the
    // rays that come into the tile through its side past about 80 degrees).
    std::optional<Mesh> tile_walls;
};

struct PrepareOptions {
    // What the context asks of texture sizes (Renderer::prepare_options()
    // gives the right ones for a context; the reference must see the same).
    // images.files: the file readers; null (the default) refuses a scene
    // that reads files, naming the first one.
    MaterialImageOptions images;
};

struct PreparedScene {
    SceneDesc desc;
    PrepareOptions options;
    // Shared, so that a scene with one material replaced shares the rest.
    std::vector<std::shared_ptr<const PreparedMaterial>> materials;  // one per desc.materials
    std::vector<std::shared_ptr<const PreparedObject>> objects;      // one per desc.objects

    const MaterialDesc& material_desc(size_t i) const { return desc.materials[i]; }
};

// Validates the scene (value ranges, cross references, resource limits with
// file headers read) and builds every material's images and every object's
// mesh. Errors name the scene file (desc.source) where there is one, the
// JSON path of the field and the texture file.
Result<std::shared_ptr<const PreparedScene>> prepare_scene(const SceneDesc& scene, const PrepareOptions& options = {});

// The same scene with the material of `material.name` replaced: only that
// material's images, and the meshes displaced from its relief, are built
// again; everything else is shared with `scene`. Errors: no material of that
// name, or the new material is invalid (the scene is unchanged).
Result<std::shared_ptr<const PreparedScene>> replace_material(const PreparedScene& scene, const MaterialDesc& material);

}  // namespace px
