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

}  // namespace px
