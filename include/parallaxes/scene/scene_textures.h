// The asset step for whole scenes: every material's textures converted to
// one variant (texture/convert.h) and written as texture files, and the
// scene made to draw from them. Used by `parallax convert --scene`,
// `parallax render --textures`, the benchmark and the tests.
#pragma once

#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/scene/scene.h"
#include "parallaxes/texture/containers.h"
#include "parallaxes/texture/convert.h"

namespace px {
struct ConvertOptions {
    AssetFormats formats;            // per slot
    ContainerKind container = ContainerKind::ktx1;  // ktx1, ktx2 or pvr3
    int zstd_level = 0;              // KTX 2.0: 0 none, 1..22
    bool mipmaps = true;
};

// One written file, for the command's report.
struct ConvertedFile {
    std::string material;
    std::string slot;    // height, normal, albedo
    std::string path;
    TextureFormat format = TextureFormat::rgba8;
    std::uint32_t width = 0, height = 0;
    int levels = 0;
    std::uint64_t bytes = 0;       // the file's size
    // An albedo of sRGB colour: written as its format's sRGB form (srgb), or,
    // where the container has none for it, as the linear form with the
    // converted scene's albedo saying "color_space": "srgb" (scene_says_srgb).
    bool srgb = false;
    bool scene_says_srgb = false;
    std::uint64_t rgba8_bytes = 0; // the same texture as RGBA8 with a full chain
    double seconds = 0.0;          // encoding time
};

// Converts each material's file and procedural sources (colour sources stay
// colours) into `folder`/<material index>_<slot>.<ext>, and returns the
// files. `scene` is changed to read them (texture files are never packed).
// `progress`: called per texture ("material 'stone' height", i, n).
Result<std::vector<ConvertedFile>> convert_scene_textures(SceneDesc& scene, const ConvertOptions& options,
                                                          const std::string& folder,
                                                          void (*progress)(const char*, int, int, const std::string&));

const char* container_extension(ContainerKind kind);  // "ktx", "ktx2", "pvr"

}  // namespace px
