// The CPU images a material draws with, from its texture sources: albedo,
// normal map (height in alpha when packed) and a separate height map.
#pragma once

#include <optional>

#include "assets/heightfield.h"
#include "assets/image.h"
#include "core/result.h"
#include "scene/scene.h"

namespace px {

struct MaterialImages {
    Image albedo;
    Image normal;                 // RGB normal; alpha = height when packed
    std::optional<Image> height;  // separate height map (not packed)
    HeightField field;            // the height field itself, for references and tests
};

// Errors name the material and the source (file path or field).
Result<MaterialImages> build_material_images(const MaterialDesc& material, const std::string& base_dir);

// The scene's resources against the limits of core/limits.h, before anything
// is generated or decoded: every texture's size (procedural sizes from the
// scene, files from their headers when read_file_headers; a file's path is
// resolved against scene.base_dir) summed against kMaxSceneTexels, and
// every mesh's vertices (a displaced plane's from its material's field)
// against kMaxSceneVertices. Errors name the JSON path of the source or
// object that passes the limit.
Status check_scene_resources(const SceneDesc& scene, bool read_file_headers);

}  // namespace px
