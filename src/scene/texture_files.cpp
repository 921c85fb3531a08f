// The file readers of scene/material_images.h, in a file of their own: only
// what calls texture_file_readers() or build_material_images links the
// image and container readers and every CPU decoder.
#include "parallaxes/scene/material_images.h"
#include "parallaxes/texture/containers.h"
#include "parallaxes/texture/decode.h"

namespace px {

namespace {

Result<TextureData> read_container(const std::string& path) { return read_texture_file(path); }
Result<TextureShape> read_container_shape(const std::string& path) { return read_texture_file_shape(path); }
Result<Image> decode_level(const TextureData& data, std::size_t level) { return decode_rgba8(data, level); }
Result<HeightField> height_map(const TextureData& data) {
    return height_field_from_texture(data, HeightConvention::height);
}
int channels(TextureFormat format) { return format_info(format).channels; }

const TextureFileReaders kReaders{load_image, read_image_info, read_container, read_container_shape, decode_level,
                                  height_map,  height_bits,     channels};

}  // namespace

const TextureFileReaders* texture_file_readers() { return &kReaders; }

Result<MaterialImages> build_material_images(const MaterialDesc& material, const std::string& base_dir,
                                             const MaterialImageOptions& options) {
    MaterialImageOptions with_files = options;
    if (!with_files.files) with_files.files = &kReaders;
    return build_material_images_from(material, base_dir, with_files);
}

Status check_scene_resources(const SceneDesc& scene, bool read_file_headers) {
    return check_scene_resources_with(scene, read_file_headers ? &kReaders : nullptr);
}

}  // namespace px
