#include "scene/material_images.h"
#include "core/text.h"

#include "core/limits.h"
#include "core/numeric.h"
#include "scene/scene_format.h"

#include <algorithm>
#include <cmath>

namespace px {

namespace {

std::string resolve(const std::string& base_dir, const std::string& path) {
    if (path.empty() || path[0] == '/' || base_dir.empty()) return path;
    return base_dir + "/" + path;
}


Result<HeightField> load_height(const MaterialDesc& m, const std::string& base_dir) {
    const TextureSource& s = m.height;
    switch (s.kind) {
        case TextureSource::Kind::none: {
            FieldSpec flat;
            flat.kind = FieldKind::flat;
            flat.size = 4;
            flat.level = 1.0f;
            return make_height_field(flat);
        }
        case TextureSource::Kind::procedural: return make_height_field(s.field);
        case TextureSource::Kind::file: {
            Result<Image> image = load_image(resolve(base_dir, s.path), 1);
            if (!image) return image.error();
            return height_field_from_image(*image, s.convention);
        }
        case TextureSource::Kind::color: {
            FieldSpec flat;
            flat.kind = FieldKind::flat;
            flat.size = 4;
            flat.level = std::clamp(s.color.r, 0.0f, 1.0f);
            return make_height_field(flat);
        }
    }
    return make_error("unhandled height source");
}

// Texels per side of a source; 0 x 0 for a file whose header is not read.
Result<ImageInfo> source_size(const TextureSource& s, const std::string& base_dir, bool read_file_headers) {
    switch (s.kind) {
        case TextureSource::Kind::none:
        case TextureSource::Kind::color: return ImageInfo{4, 4};
        case TextureSource::Kind::procedural: return ImageInfo{s.field.size, s.field.size};
        case TextureSource::Kind::file:
            if (!read_file_headers) return ImageInfo{0, 0};
            return read_image_info(resolve(base_dir, s.path));
    }
    return ImageInfo{0, 0};
}

std::string count_text(std::int64_t n) {
    return std::to_string(n);
}

}  // namespace

Status check_scene_resources(const SceneDesc& scene, bool read_file_headers) {
    using scene_format::index_path;
    std::int64_t texels = 0;
    std::vector<ImageInfo> traced(scene.materials.size());
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const MaterialDesc& m = scene.materials[i];
        const std::pair<const TextureSource*, const char*> slots[] = {
            {&m.albedo, "albedo"}, {&m.height, "height"}, {&m.normal, "normal"}};
        for (auto [source, slot] : slots) {
            const std::string path = index_path("materials", i) + "." + slot + " (material '" + echo(m.name) + "')";
            Result<ImageInfo> size = source_size(*source, scene.base_dir, read_file_headers);
            if (!size) return with_context(path, size.error());
            if (source == &m.height) traced[i] = *size;
            // Each side is at most kMaxTextureSize: no overflow in 64 bits.
            const std::int64_t n = static_cast<std::int64_t>(size->width) * size->height;
            texels += n;
            if (texels > kMaxSceneTexels)
                return make_error(path + ": the scene's textures pass the limit of " + count_text(kMaxSceneTexels) +
                                  " texels in all (" + count_text(texels - n) + " before this one, which adds " +
                                  count_text(n) + "); use smaller textures or fewer materials");
        }
    }
    std::int64_t vertices = 0;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const ObjectDesc& o = scene.objects[i];
        std::int64_t n = 0;
        switch (o.mesh.kind) {
            case MeshKind::plane: {
                std::int64_t columns = o.mesh.segments, rows = o.mesh.segments;
                if (o.mesh.displaced) {  // about one vertex per texel of the material's transformed uv
                    const std::size_t k = scene.material_index(o.material);
                    const ImageInfo field = k < traced.size() ? traced[k] : ImageInfo{4, 4};
                    const glm::dmat2 uv_matrix =
                        k < traced.size() ? scene.materials[k].uv.matrix<double>() : glm::dmat2(1.0);
                    // The grid make_displaced_plane builds, from sizes alone.
                    const DisplacedGrid grid = displaced_plane_grid(field.width, field.height, uv_matrix);
                    columns = grid.columns;
                    rows = grid.rows;
                }
                n = (std::max<std::int64_t>(columns, 1) + 1) * (std::max<std::int64_t>(rows, 1) + 1);
                break;
            }
            case MeshKind::cube: n = 24; break;
            case MeshKind::sphere:
            case MeshKind::torus: n = 4096; break;  // fixed tessellations (mesh.h), rounded up
        }
        vertices += n;
        if (vertices > kMaxSceneVertices)
            return make_error(index_path("objects", i) + ".mesh: the scene's meshes pass the limit of " +
                              count_text(kMaxSceneVertices) + " vertices in all (this one adds " + count_text(n) +
                              (o.mesh.displaced ? ", about one per texel of its material's height field under the uv transform" : "") + ")");
    }
    return {};
}

Result<MaterialImages> build_material_images(const MaterialDesc& m, const std::string& base_dir) {
    const std::string where = "material '" + echo(m.name) + "'";
    MaterialImages out;
    Result<HeightField> field = load_height(m, base_dir);
    if (!field) return with_context(where + " height", field.error());
    out.field = std::move(*field);

    // Normal map: derived from the height field so it matches the traced
    // surface, unless the material gives one.
    if (m.normal.kind == TextureSource::Kind::file) {
        Result<Image> normal = load_image(resolve(base_dir, m.normal.path), 4);
        if (!normal) return with_context(where + " normal", normal.error());
        if (m.pack_height_in_normal_alpha) {
            if (normal->width != out.field.width || normal->height != out.field.height)
                return make_error(where + ": the normal map '" + echo_path(m.normal.path) + "' (" + std::to_string(normal->width) + "x" +
                                  std::to_string(normal->height) + ") and height map" + (m.height.kind == TextureSource::Kind::file ? " '" + echo_path(m.height.path) + "'" : std::string()) + " (" +
                                  std::to_string(out.field.width) + "x" + std::to_string(out.field.height) +
                                  ") must be the same size to pack height into the normal map's alpha");
            for (int y = 0; y < normal->height; ++y)
                for (int x = 0; x < normal->width; ++x) normal->texel(x, y)[3] = to_unorm8(out.field.at(x, y));
        }
        out.normal = std::move(*normal);
    } else if (m.normal.kind == TextureSource::Kind::procedural) {
        // Normals of another field than the one traced (packing keeps the traced height).
        Result<HeightField> bumps = make_height_field(m.normal.field);
        if (!bumps) return with_context(where + " normal", bumps.error());
        out.normal = derive_normal_map(*bumps, m.height_scale, false);
        if (m.pack_height_in_normal_alpha) {
            if (bumps->width != out.field.width || bumps->height != out.field.height)
                return make_error(where + ": the procedural normal field and the height field must be the same size "
                                          "to pack height into the normal map's alpha");
            for (int y = 0; y < bumps->height; ++y)
                for (int x = 0; x < bumps->width; ++x) out.normal.texel(x, y)[3] = to_unorm8(out.field.at(x, y));
        }
    } else {
        out.normal = derive_normal_map(out.field, m.height_scale, m.pack_height_in_normal_alpha);
    }
    if (!m.pack_height_in_normal_alpha) out.height = height_image(out.field);

    switch (m.albedo.kind) {
        case TextureSource::Kind::none:
            out.albedo = make_solid_image(4, 4, 204, 204, 204);
            break;
        case TextureSource::Kind::color:
            out.albedo = make_solid_image(4, 4, to_unorm8(m.albedo.color.r), to_unorm8(m.albedo.color.g),
                                          to_unorm8(m.albedo.color.b));
            break;
        case TextureSource::Kind::file: {
            Result<Image> albedo = load_image(resolve(base_dir, m.albedo.path), 4);
            if (!albedo) return with_context(where + " albedo", albedo.error());
            out.albedo = std::move(*albedo);
            break;
        }
        case TextureSource::Kind::procedural: {
            // A procedural albedo: the field as grey levels.
            Result<HeightField> f = make_height_field(m.albedo.field);
            if (!f) return with_context(where + " albedo", f.error());
            out.albedo = height_image(*f);
            break;
        }
    }
    return out;
}

}  // namespace px
