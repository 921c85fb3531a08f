// The CPU images a material draws with, from its texture sources: albedo,
// normal map (height in alpha when packed) and a separate height map.
#pragma once

#include <optional>

#include "parallaxes/assets/heightfield.h"
#include "parallaxes/assets/image.h"
#include "parallaxes/core/result.h"
#include "parallaxes/effects/variant.h"
#include "parallaxes/scene/scene.h"
#include "parallaxes/texture/texture_data.h"

namespace px {

struct MaterialImages {
    // Level 0 of each texture as RGBA8 (decoded where a file is compressed):
    // what the exact reference shades with.
    Image albedo;
    Image normal;                 // RGB normal (RG with z reconstructed when layout.normal_rg); alpha = height when packed
    std::optional<Image> height;  // separate height map (not packed)
    HeightField field;            // the height field itself, for references and tests
    // The field as the GPU samples it: 8-bit texels (byte / 255), or 11-bit
    // ones (v / 2047) from an EAC height map. What the reference traces.
    HeightField traced;
    // Texture files (KTX 1.1, KTX 2.0, PVR v3) as given, with every level:
    // uploaded as they are (or decoded on the CPU where the context cannot
    // sample their format). Empty: the slot uploads the Image above.
    std::optional<TextureData> albedo_texture, normal_texture, height_texture;
    // The CPU decoder of the files above (TextureFileReaders::decode_level),
    // for a context that cannot sample their format; null without files.
    Result<Image> (*decode)(const TextureData& data, std::size_t level) = nullptr;
    TextureLayout layout;         // how the textures hold what the shaders read
    // The albedo's texels are sRGB-encoded colour (lit after decoding to
    // linear light), or linear; and what decided it: the scene's
    // "color_space", the file's declaration (a texture container's format or
    // colour space, a PNG's sRGB, iCCP or gAMA chunk), or the default for
    // colour (sRGB: what real albedo textures, colour pickers and the
    // project's procedural ramps hold).
    bool albedo_srgb = true;
    std::string albedo_color_space = "sRGB (colour's default)";
    // What was resampled on the way, and why ("height 200x120 resampled to
    // 256x128 (bilinear): maxmip's max pyramid halves every level exactly").
    std::vector<std::string> notes;
};

// How a material's files are read: images (PNG, JPEG, TGA), texture
// containers (KTX 1.1, KTX 2.0, PVR v3) and their CPU decoders. A table of
// functions, so that a renderer that draws procedural textures alone links
// none of them (no codecs, no libjpeg, libzstd or libastcenc): pass
// texture_file_readers() where files are wanted.
struct TextureFileReaders {
    Result<Image> (*load_image)(const std::string& path, int channels);
    Result<ImageInfo> (*read_image_info)(const std::string& path);
    Result<TextureData> (*read_texture_file)(const std::string& path);
    // Its header only (texture/containers.h): kind and size checked before
    // anything is inflated.
    Result<TextureShape> (*read_texture_shape)(const std::string& path);
    Result<Image> (*decode_level)(const TextureData& data, std::size_t level);  // RGBA8
    // A height map's level 0 as the GPU samples it (texture/decode.h), and
    // the bits of height its format holds (8 or 11).
    Result<HeightField> (*height_field)(const TextureData& data);
    int (*height_bits)(TextureFormat format);
    int (*channels)(TextureFormat format);
};

// Every reader this library has (scene/texture_files.cpp).
const TextureFileReaders* texture_file_readers();

// What the context asks of sizes; the same for the renderer and the exact
// reference, so that both see the same textures.
struct MaterialImageOptions {
    // Every non-power-of-two texture resampled to the next power of two
    // (bilinear; files decoded first): an ES 2.0 context without
    // GL_OES_texture_npot can neither repeat nor mipmap it.
    bool power_of_two_textures = false;
    // The context decodes sRGB textures in the texture unit
    // (Caps::srgb_textures): an sRGB albedo goes up as sRGB. Without it the
    // shader decodes (TextureLayout::albedo_srgb_decode).
    bool srgb_textures = true;
    // The file readers. build_material_images: null means every reader;
    // build_material_images_from: null means a file source is an error.
    const TextureFileReaders* files = nullptr;
};

// Whether two materials' images are the same images (the same sources,
// height packing, depth and pyramid needs, under the same base folder):
// what build_material_images_from reads of a material, so that a prepared
// scene shares them between materials and across replace_material (a change
// of technique, sample count or shadow builds nothing again).
bool same_material_images(const MaterialDesc& a, const MaterialDesc& b);
// Whether images `built` for material `built_for` are what `next` would
// build: the same images, or the same sources on a field that already halves
// exactly where only `next` walks a max pyramid (maxmip).
bool images_serve(const MaterialImages& built, const MaterialDesc& built_for, const MaterialDesc& next);

// Errors name the material and the source (file path or field). A file is
// read as a texture container when it starts with a KTX or PVR identifier,
// and as an image (PNG, JPEG, TGA) otherwise.
// A maxmip material (by its technique, or by effects, under which the
// planner may choose it) with a non-power-of-two height map gets
// it resampled to the next power of two each way (bilinear, 8-bit): the max
// pyramid halves every level exactly. Both resamplings are in `notes`.
Result<MaterialImages> build_material_images(const MaterialDesc& material, const std::string& base_dir,
                                             const MaterialImageOptions& options = {});
// The same with exactly the readers in options.files (none: a material that
// reads a file is refused, naming the file): what prepare_scene calls.
Result<MaterialImages> build_material_images_from(const MaterialDesc& material, const std::string& base_dir,
                                                  const MaterialImageOptions& options);

// Whether a source file is read as a texture container (by its extension:
// .ktx, .ktx2, .pvr, any case) rather than as an image.
bool is_texture_file(const std::string& path);

// The scene's resources against the limits of core/limits.h, before anything
// is generated or decoded: every texture's size (procedural sizes from the
// scene, files from their headers when read_file_headers; a file's path is
// resolved against scene.base_dir) summed against kMaxSceneTexels, and
// every mesh's vertices (a displaced plane's from its material's field)
// against kMaxSceneVertices. Errors name the JSON path of the source or
// object that passes the limit.
Status check_scene_resources(const SceneDesc& scene, bool read_file_headers);
// The same, reading file headers with `files` (null: headers not read).
Status check_scene_resources_with(const SceneDesc& scene, const TextureFileReaders* files);

// The first file source of the scene, as "materials[i].slot" with the file's
// name, or "" when the scene reads no files.
std::string first_file_source(const SceneDesc& scene);

}  // namespace px
