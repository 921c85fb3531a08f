#include "parallaxes/core/counters.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/core/text.h"

#include "parallaxes/core/limits.h"
#include "parallaxes/core/numeric.h"
#include "parallaxes/scene/scene_format.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace px {

namespace {

std::string resolve(const std::string& base_dir, const std::string& path) {
    if (path.empty() || path[0] == '/' || base_dir.empty()) return path;
    return base_dir + "/" + path;
}

// The albedo's colour space: the scene's word, else the file's, else sRGB.
Status albedo_color_space(MaterialImages& out, const MaterialDesc& m, const std::string& base_dir,
                          const TextureFileReaders* files) {
    const TextureSource& s = m.albedo;
    std::string file_says;  // empty: the file declares nothing
    bool file_srgb = true;
    if (out.albedo_texture && out.albedo_texture->container != ContainerKind::astc) {
        file_srgb = out.albedo_texture->srgb;  // a container's format is linear or sRGB: it always says
        file_says = file_srgb ? out.albedo_texture->color_space_source : "its linear texture format";
    } else if (s.kind == TextureSource::Kind::file && files && !out.albedo_texture) {
        Result<ImageInfo> info = files->read_image_info(resolve(base_dir, s.path));
        if (!info) return info.error();
        file_srgb = info->encoding != ImageInfo::Encoding::linear;
        file_says = info->declared_by;
    }
    const bool scene_says = s.color_space != TextureSource::ColorSpace::file;
    out.albedo_srgb = scene_says ? s.color_space == TextureSource::ColorSpace::srgb : file_srgb;
    const char* space = out.albedo_srgb ? "sRGB" : "linear";
    out.albedo_color_space = std::string(space) + " (" +
                             (scene_says          ? "the scene's color_space"
                              : !file_says.empty() ? "declared by " + file_says
                              : s.kind == TextureSource::Kind::file ? std::string("the file declares nothing: colour's default")
                                                                    : std::string("the scene's colours are sRGB")) +
                             ")";
    if (scene_says && !file_says.empty() && file_srgb != out.albedo_srgb)
        out.notes.push_back("albedo '" + echo_path(s.path) + "' read as " + space + " as the scene says, though " +
                            file_says + " declares it " + (file_srgb ? "sRGB" : "linear"));
    return {};
}

// Height and normal maps are data: a texture file that declares sRGB is
// read as its linear format, and said so.
void data_slot_notes(MaterialImages& out, const MaterialDesc& m) {
    const std::pair<const std::optional<TextureData>*, const TextureSource*> slots[] = {
        {&out.normal_texture, &m.normal}, {&out.height_texture, &m.height}};
    for (auto [texture, source] : slots)
        if (*texture && (*texture)->srgb)
            out.notes.push_back(std::string(source == &m.normal ? "normal map" : "height map") + " '" +
                                echo_path(source->path) + "' declares sRGB (" + (*texture)->color_space_source +
                                "); height and normal maps are data, read as linear");
}

}  // namespace

Result<MaterialImages> build_material_images_as_given(const MaterialDesc& m, const std::string& base_dir,
                                                       const TextureFileReaders* files);

bool is_texture_file(const std::string& path) {
    auto ends = [&](const char* suffix) {
        const std::string s(suffix);
        if (path.size() < s.size()) return false;
        for (size_t i = 0; i < s.size(); ++i)
            if (std::tolower(static_cast<unsigned char>(path[path.size() - s.size() + i])) != s[i]) return false;
        return true;
    };
    return ends(".ktx") || ends(".ktx2") || ends(".pvr") || ends(".astc");
}

namespace {

Status no_readers(const TextureSource& s) {
    return make_error("'" + echo_path(s.path) +
                      "' is a file, and no file readers were given: set RendererOptions::texture_files = "
                      "px::texture_files() (or MaterialImageOptions::files = px::texture_file_readers())");
}

// One channel of an RGBA8 image, as a grey image. The alpha of a file that
// has none reads 255 everywhere: asked for as height, that is refused
// rather than drawn flat.
Result<Image> channel_image(const Image& rgba, const TextureSource& s) {
    const int c = channel_index(s.channel);
    Image one;
    one.width = rgba.width;
    one.height = rgba.height;
    one.channels = 1;
    one.pixels.resize(static_cast<std::size_t>(rgba.width) * static_cast<std::size_t>(rgba.height));
    bool opaque = true;
    for (std::size_t i = 0; i < one.pixels.size(); ++i) {
        one.pixels[i] = rgba.pixels[i * static_cast<std::size_t>(rgba.channels) + static_cast<std::size_t>(c)];
        opaque = opaque && one.pixels[i] == 255;
    }
    if (s.channel == TextureSource::Channel::a && opaque)
        return make_error("'" + echo_path(s.path) +
                          "' holds no height in its alpha (255 everywhere: no alpha channel, or an opaque one); name "
                          "the channel that holds it, or a separate height file");
    return one;
}

Result<HeightField> load_height(const MaterialDesc& m, const std::string& base_dir, const TextureFileReaders* files) {
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
            if (is_texture_file(s.path)) return make_error("internal: a texture file is loaded by build_material_images");
            if (!files) return no_readers(s).error();
            if (s.channel == TextureSource::Channel::grey) {
                Result<Image> image = files->load_image(resolve(base_dir, s.path), 1);
                if (!image) return image.error();
                return height_field_from_image(*image, s.convention);
            }
            Result<Image> image = files->load_image(resolve(base_dir, s.path), 4);
            if (!image) return image.error();
            Result<Image> one = channel_image(*image, s);
            if (!one) return one.error();
            return height_field_from_image(*one, s.convention);
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
// A material's texture is one 2D image with its mip levels: arrays and
// cube maps are refused from the header, before their data is read.
Status single_image(const TextureShape& t, const std::string& path) {
    if (t.layers == 1 && t.faces == 1) return {};
    return make_error("'" + echo_path(path) + "' holds " + std::to_string(t.layers) + " layers and " +
                      std::to_string(t.faces) + " faces; a material's texture is one 2D image (with its mip levels)");
}

Result<ImageInfo> source_size(const TextureSource& s, const std::string& base_dir, const TextureFileReaders* files) {
    switch (s.kind) {
        case TextureSource::Kind::none:
        case TextureSource::Kind::color: return ImageInfo{4, 4};
        case TextureSource::Kind::procedural: return ImageInfo{s.field.size, s.field.size};
        case TextureSource::Kind::file: {
            if (!files) return ImageInfo{0, 0};
            if (!is_texture_file(s.path)) return files->read_image_info(resolve(base_dir, s.path));
            // The header alone: nothing is inflated to learn a size.
            Result<TextureShape> t = files->read_texture_shape(resolve(base_dir, s.path));
            if (!t) return t.error();
            if (Status one = single_image(*t, s.path); !one) return one.error();
            return ImageInfo{static_cast<int>(t->width), static_cast<int>(t->height)};
        }
    }
    return ImageInfo{0, 0};
}

std::string count_text(std::int64_t n) {
    return std::to_string(n);
}

}  // namespace

std::string first_file_source(const SceneDesc& scene) {
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const MaterialDesc& m = scene.materials[i];
        const std::pair<const TextureSource*, const char*> slots[] = {
            {&m.albedo, "albedo"}, {&m.height, "height"}, {&m.normal, "normal"}};
        for (auto [source, slot] : slots)
            if (source->kind == TextureSource::Kind::file)
                return scene_format::index_path("materials", i) + "." + slot + " (material '" + echo(m.name) + "', file '" +
                       echo_path(source->path) + "')";
    }
    return {};
}

Status check_scene_resources_with(const SceneDesc& scene, const TextureFileReaders* files) {
    using scene_format::index_path;
    std::int64_t texels = 0;
    std::vector<ImageInfo> traced(scene.materials.size());
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const MaterialDesc& m = scene.materials[i];
        const std::pair<const TextureSource*, const char*> slots[] = {
            {&m.albedo, "albedo"}, {&m.height, "height"}, {&m.normal, "normal"}};
        for (auto [source, slot] : slots) {
            const std::string path = index_path("materials", i) + "." + slot + " (material '" + echo(m.name) + "')";
            Result<ImageInfo> size = source_size(*source, scene.base_dir, files);
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
                if (o.mesh.displaced) {  // about vertices_per_texel per texel of the material's transformed uv
                    const std::size_t k = scene.material_index(o.material);
                    const ImageInfo field = k < traced.size() ? traced[k] : ImageInfo{4, 4};
                    const glm::dmat2 uv_matrix =
                        k < traced.size() ? scene.materials[k].uv.matrix<double>() : glm::dmat2(1.0);
                    // The grid make_displaced_plane builds, from sizes alone.
                    const DisplacedGrid grid =
                        displaced_plane_grid(field.width, field.height, uv_matrix, o.mesh.vertices_per_texel);
                    columns = grid.columns;
                    rows = grid.rows;
                }
                n = (std::max<std::int64_t>(columns, 1) + 1) * (std::max<std::int64_t>(rows, 1) + 1);
                break;
            }
            case MeshKind::cube: n = 24; break;
            case MeshKind::sphere:
            case MeshKind::torus:
            case MeshKind::cylinder:
                n = 4096;  // fixed tessellations (mesh.h), rounded up
                if (o.mesh.displaced) {  // make_displaced_curved's grid, from sizes alone
                    const std::size_t k = scene.material_index(o.material);
                    const ImageInfo field = k < traced.size() ? traced[k] : ImageInfo{4, 4};
                    const glm::dmat2 uv_matrix =
                        k < traced.size() ? scene.materials[k].uv.matrix<double>() : glm::dmat2(1.0);
                    const DisplacedGrid grid = displaced_curved_grid(o.mesh.kind, field.width, field.height, uv_matrix,
                                                                     o.mesh.vertices_per_texel);
                    n = grid.vertex_count() + 2 * grid.columns;
                }
                break;
        }
        vertices += n;
        if (vertices > kMaxSceneVertices)
            return make_error(index_path("objects", i) + ".mesh: the scene's meshes pass the limit of " +
                              count_text(kMaxSceneVertices) + " vertices in all (this one adds " + count_text(n) +
                              (!o.mesh.displaced ? std::string()
                               : o.mesh.vertices_per_texel <= 1
                                   ? ", about one per texel of its material's height field under the uv transform"
                                   : ", about " + std::to_string(o.mesh.vertices_per_texel) +
                                         " per texel along each side of its material's height field under the uv "
                                         "transform (mesh.vertices_per_texel)") +
                              ")");
    }
    return {};
}

namespace {

int next_power_of_two(int v) {
    int p = 1;
    while (p < v && p < kMaxTextureSize) p *= 2;
    return p;
}

HeightField resample_field(const HeightField& f, int w, int h) {
    HeightField out;
    out.width = w;
    out.height = h;
    out.texels.resize(static_cast<size_t>(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            out.ref(x, y) = static_cast<float>(f.sample_bilinear((x + 0.5) / w, (y + 0.5) / h));
    return out;
}

Image resample_image(const Image& img, int w, int h) {
    Image out;
    out.width = w;
    out.height = h;
    out.channels = img.channels;
    out.pixels.resize(static_cast<size_t>(w) * h * img.channels);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const BilinearTaps t = bilinear_taps((x + 0.5) / w, (y + 0.5) / h, img.width, img.height);
            for (int c = 0; c < img.channels; ++c) {
                const double v = (1 - t.ax) * (1 - t.ay) * img.texel(t.x0, t.y0)[c] + t.ax * (1 - t.ay) * img.texel(t.x1, t.y0)[c] +
                                 (1 - t.ax) * t.ay * img.texel(t.x0, t.y1)[c] + t.ax * t.ay * img.texel(t.x1, t.y1)[c];
                out.texel(x, y)[c] = static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 255.0)));
            }
        }
    return out;
}

bool pot(int w, int h) { return is_power_of_two(w) && is_power_of_two(h); }

// Row 0 of a HeightField and of an Image is the bottom of the uv square (v = 0,
// where OpenGL samples a texture's first row): a file stored top row first
// is mirrored into that order for the CPU (the reference, the mesh, the max
// pyramid), while its texture goes up as it is and is read at 1 - v.
void flip_rows(HeightField& f) {
    reverse_rows(f.texels, static_cast<size_t>(f.width), static_cast<size_t>(f.height), 1);
}

void flip_rows(Image& img) {
    reverse_rows(img.pixels, static_cast<size_t>(img.width), static_cast<size_t>(img.height),
                 static_cast<size_t>(img.channels));
}

bool top_first(const std::optional<TextureData>& t) { return t && t->rows == RowOrder::top_first; }

std::string size_text(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

}  // namespace

namespace {

// maxmip (explicit, or possible under effects): its pyramid needs a field
// that halves exactly.
bool maxmip_possible(const MaterialDesc& m) {
    return m.effects ? (m.effects->parallax && m.height_scale > 0.0f) : m.technique.technique == Technique::maxmip;
}

bool same_field(const FieldSpec& a, const FieldSpec& b) {
    return a.kind == b.kind && a.size == b.size && a.level == b.level && a.count == b.count &&
           a.frequency == b.frequency && a.mortar == b.mortar && a.line_width == b.line_width &&
           a.radius == b.radius && a.text == b.text;
}

bool same_source(const TextureSource& a, const TextureSource& b) {
    return a.kind == b.kind && a.path == b.path && same_field(a.field, b.field) && a.low == b.low &&
           a.high == b.high && a.grain == b.grain && a.color == b.color && a.convention == b.convention &&
           a.first_row == b.first_row && a.channel == b.channel && a.green == b.green &&
           a.color_space == b.color_space;
}

}  // namespace

bool same_material_images(const MaterialDesc& a, const MaterialDesc& b) {
    // Every field of the material the builder below reads (the name only
    // labels its errors).
    return same_source(a.albedo, b.albedo) && same_source(a.height, b.height) && same_source(a.normal, b.normal) &&
           a.pack_height_in_normal_alpha == b.pack_height_in_normal_alpha && a.height_scale == b.height_scale &&
           maxmip_possible(a) == maxmip_possible(b);
}

bool images_serve(const MaterialImages& built, const MaterialDesc& built_for, const MaterialDesc& next) {
    if (same_material_images(built_for, next)) return true;
    // The same sources, and only the pyramid's need differs: where the field
    // already halves exactly and was not resampled for it, the images are
    // what the new material would build.
    MaterialDesc as_built = next;
    as_built.effects = built_for.effects;
    as_built.technique = built_for.technique;
    return same_material_images(built_for, as_built) && !maxmip_possible(built_for) &&
           pot(built.field.width, built.field.height);
}

Result<MaterialImages> build_material_images_from(const MaterialDesc& m, const std::string& base_dir,
                                                  const MaterialImageOptions& options) {
    counters::count(counters::Step::image_build);
    Result<MaterialImages> built = build_material_images_as_given(m, base_dir, options.files);
    if (!built) return built;
    MaterialImages& out = *built;
    // maxmip (explicit, or possible under effects) on a non-power-of-two field.
    const bool walks_pyramid = maxmip_possible(m);
    const bool field_npot = !pot(out.field.width, out.field.height);
    if (field_npot && (walks_pyramid || options.power_of_two_textures)) {
        const int w = next_power_of_two(out.field.width), h = next_power_of_two(out.field.height);
        out.notes.push_back("height " + size_text(out.field.width, out.field.height) + " resampled to " + size_text(w, h) +
                            " (bilinear, 8-bit): " +
                            (options.power_of_two_textures
                                 ? "this OpenGL ES 2.0 context lacks GL_OES_texture_npot"
                                 : "maxmip's max pyramid halves every level exactly"));
        out.field = resample_field(out.field, w, h);
        out.traced = quantized_8bit(out.field);
        out.layout.height_11bit = false;
        out.height_texture.reset();
        if (out.layout.packed_height) {
            // The packed normal map carries the height: rebuild it at the new size.
            Image normal = resample_image(out.normal, w, h);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) normal.texel(x, y)[3] = to_unorm8(out.traced.at(x, y));
            out.normal = std::move(normal);
            out.normal_texture.reset();
        } else {
            out.height = height_image(out.traced);
        }
    }
    if (options.power_of_two_textures) {
        const std::pair<Image*, std::optional<TextureData>*> slots[] = {{&out.albedo, &out.albedo_texture},
                                                                        {&out.normal, &out.normal_texture}};
        const char* names[] = {"albedo", "normal map"};
        for (int i = 0; i < 2; ++i) {
            Image& img = *slots[i].first;
            if (pot(img.width, img.height)) continue;
            const int w = next_power_of_two(img.width), h = next_power_of_two(img.height);
            out.notes.push_back(std::string(names[i]) + " " + size_text(img.width, img.height) + " resampled to " +
                                size_text(w, h) + " (bilinear" + (slots[i].second->has_value() ? ", decoded from its file" : "") +
                                "): this OpenGL ES 2.0 context lacks GL_OES_texture_npot");
            img = resample_image(img, w, h);
            slots[i].second->reset();
        }
    }
    // An sRGB albedo where the texture unit cannot decode it: the shader does.
    out.layout.albedo_srgb_decode = out.albedo_srgb && !options.srgb_textures;
    // A DirectX-style normal file uploaded as it is: the shaders negate its
    // green (an image's was turned on the CPU, and so was a decoded file's).
    out.layout.normal_green_down = m.normal.green == TextureSource::Green::down && out.normal_texture.has_value();
    // Files uploaded as they are, stored top row first: read at 1 - v.
    out.layout.flip_v = static_cast<std::uint8_t>((top_first(out.albedo_texture) ? kFlipAlbedo : 0) |
                                                  (top_first(out.normal_texture) ? kFlipNormal : 0) |
                                                  (top_first(out.height_texture) ? kFlipHeight : 0));
    return built;
}

namespace {

bool texture_file_source(const TextureSource& s) {
    return s.kind == TextureSource::Kind::file && is_texture_file(s.path);
}

// A slot's texture file, read as it is. Kind and size from the header
// first: an array of 2048 layers is refused before anything of it is
// inflated. The scene's first_row, where given, overrides the file's.
Result<TextureData> read_texture_source(const TextureSource& s, const char* slot, const std::string& where,
                                        const std::string& base_dir, const TextureFileReaders* files) {
    Result<TextureShape> shape = files->read_texture_shape(resolve(base_dir, s.path));
    if (!shape) return with_context(where + " " + slot, shape.error());
    if (Status one = single_image(*shape, s.path); !one) return with_context(where + " " + slot, one.error());
    Result<TextureData> t = files->read_texture_file(resolve(base_dir, s.path));
    if (!t) return with_context(where + " " + slot, t.error());
    if (s.first_row != TextureSource::FirstRow::file) {
        const bool top = s.first_row == TextureSource::FirstRow::top;
        t->rows = top ? RowOrder::top_first : RowOrder::bottom_first;
        t->rows_source = std::string("the scene's first_row \"") + (top ? "top" : "bottom") + "\" (the file says " +
                         t->rows_source + ")";
    }
    if (Status one = single_image(TextureShape{t->container, t->format, t->width, t->height, t->layers, t->faces,
                                               static_cast<std::uint32_t>(t->levels.size()), t->bytes.size()},
                                  s.path);
        !one)
        return with_context(where + " " + slot, one.error());
    return t;
}

Status depth_file_refused(const std::string& where, const std::string& path) {
    return make_error(where + " height: '" + echo_path(path) +
                      "' is a texture file, which the GPU samples as it is: it must hold height (white is "
                      "high); convert depth maps with `parallax convert --depth`");
}

// The height field: a texture file's as the GPU samples it, else loaded
// or made and quantised to 8 bits as it will be uploaded.
Status read_height(MaterialImages& out, const MaterialDesc& m, const std::string& where,
                   const std::string& base_dir, const TextureFileReaders* files) {
    if (texture_file_source(m.height) && m.height.channel != TextureSource::Channel::grey &&
        m.height.channel != TextureSource::Channel::r) {
        // Height in another channel than red, where the shaders read it:
        // level 0 decoded and the channel taken at 8 bits (the normal map's
        // own alpha, in the same file, is read in place: height_in_normal_file).
        Result<TextureData> t = read_texture_source(m.height, "height", where, base_dir, files);
        if (!t) return t.error();
        const int count = files->channels(t->format);
        if (channel_index(m.height.channel) >= count)
            return make_error(where + " height: '" + echo_path(m.height.path) + "' holds " + std::to_string(count) +
                              " channel" + (count == 1 ? "" : "s") +
                              "; it has no channel '" + channel_name(m.height.channel) + "'");
        Result<Image> level0 = files->decode_level(*t, 0);
        if (!level0) return with_context(where + " height '" + echo_path(m.height.path) + "'", level0.error());
        if (t->rows == RowOrder::top_first) flip_rows(*level0);
        Result<Image> one = channel_image(*level0, m.height);
        if (!one) return with_context(where + " height", one.error());
        out.field = height_field_from_image(*one, m.height.convention);
        out.traced = quantized_8bit(out.field);
        out.notes.push_back("height: channel " + std::string(channel_name(m.height.channel)) + " of '" +
                            echo_path(m.height.path) + "' decoded to 8 bits (the shaders read a height texture's red)");
        return {};
    }
    if (texture_file_source(m.height)) {
        if (m.height.convention == HeightConvention::depth) return depth_file_refused(where, m.height.path);
        Result<TextureData> t = read_texture_source(m.height, "height", where, base_dir, files);
        if (!t) return t.error();
        Result<HeightField> f = files->height_field(*t);
        if (!f) return with_context(where + " height '" + echo_path(m.height.path) + "'", f.error());
        out.field = std::move(*f);
        if (t->rows == RowOrder::top_first) flip_rows(out.field);
        out.traced = out.field;
        out.layout.height_11bit = files->height_bits(t->format) == 11;
        out.height_texture = std::move(*t);
    } else {
        Result<HeightField> field = load_height(m, base_dir, files);
        if (!field) return with_context(where + " height", field.error());
        out.field = std::move(*field);
        out.traced = quantized_8bit(out.field);
    }
    return {};
}

// A DirectX-style normal map in OpenGL's convention: green (v) negated,
// which for unorm texels is 255 - g exactly.
void green_to_up(Image& normal) {
    if (normal.channels < 2) return;
    for (std::size_t i = 1; i < normal.pixels.size(); i += static_cast<std::size_t>(normal.channels))
        normal.pixels[i] = static_cast<std::uint8_t>(255 - normal.pixels[i]);
}

// The normal and albedo slots given as texture files, with their base
// level decoded (bottom row first) for the CPU's uses.
Status read_texture_files(MaterialImages& out, const MaterialDesc& m, const std::string& where,
                          const std::string& base_dir, const TextureFileReaders* files) {
    if (texture_file_source(m.normal)) {
        Result<TextureData> t = read_texture_source(m.normal, "normal", where, base_dir, files);
        if (!t) return t.error();
        Result<Image> level0 = files->decode_level(*t, 0);
        if (!level0) return with_context(where + " normal '" + echo_path(m.normal.path) + "'", level0.error());
        out.layout.normal_rg = files->channels(t->format) == 2;
        if (t->rows == RowOrder::top_first) flip_rows(*level0);
        // The CPU's copy in OpenGL's convention (the reference, the planner);
        // the file goes up as it is and the shaders negate its green.
        if (m.normal.green == TextureSource::Green::down) green_to_up(*level0);
        out.normal = std::move(*level0);
        out.normal_texture = std::move(*t);
    }
    if (texture_file_source(m.albedo)) {
        Result<TextureData> t = read_texture_source(m.albedo, "albedo", where, base_dir, files);
        if (!t) return t.error();
        Result<Image> level0 = files->decode_level(*t, 0);
        if (!level0) return with_context(where + " albedo '" + echo_path(m.albedo.path) + "'", level0.error());
        if (t->rows == RowOrder::top_first) flip_rows(*level0);
        out.albedo = std::move(*level0);
        out.albedo_texture = std::move(*t);
    }
    return {};
}

// Normal map: derived from the height field so it matches the traced
// surface, unless the material gives one.
Status build_normal_map(MaterialImages& out, const MaterialDesc& m, const std::string& where,
                        const std::string& base_dir, const TextureFileReaders* files, bool packed) {
    if (out.normal_texture) {
        // read above
    } else if (m.normal.kind == TextureSource::Kind::file) {
        Result<Image> normal = files->load_image(resolve(base_dir, m.normal.path), 4);
        if (!normal) return with_context(where + " normal", normal.error());
        if (m.normal.green == TextureSource::Green::down) green_to_up(*normal);
        if (packed) {
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
        if (packed) {
            if (bumps->width != out.field.width || bumps->height != out.field.height)
                return make_error(where + ": the procedural normal field and the height field must be the same size "
                                          "to pack height into the normal map's alpha");
            for (int y = 0; y < bumps->height; ++y)
                for (int x = 0; x < bumps->width; ++x) out.normal.texel(x, y)[3] = to_unorm8(out.field.at(x, y));
        }
    } else {
        out.normal = derive_normal_map(out.field, m.height_scale, packed);
    }
    return {};
}

// The albedo where no texture file gives it: a default grey, a colour, an
// image file or a procedural field through its colour ramp.
Status build_albedo(MaterialImages& out, const MaterialDesc& m, const std::string& where,
                    const std::string& base_dir, const TextureFileReaders* files) {
    switch (m.albedo.kind) {
        case TextureSource::Kind::none:
            out.albedo = make_solid_image(4, 4, 204, 204, 204);
            break;
        case TextureSource::Kind::color:
            out.albedo = make_solid_image(4, 4, to_unorm8(m.albedo.color.r), to_unorm8(m.albedo.color.g),
                                          to_unorm8(m.albedo.color.b));
            break;
        case TextureSource::Kind::file: {
            Result<Image> albedo = files->load_image(resolve(base_dir, m.albedo.path), 4);
            if (!albedo) return with_context(where + " albedo", albedo.error());
            out.albedo = std::move(*albedo);
            break;
        }
        case TextureSource::Kind::procedural: {
            // A procedural albedo: the field through its colour ramp (grey by default).
            Result<HeightField> f = make_height_field(m.albedo.field);
            if (!f) return with_context(where + " albedo", f.error());
            HeightRamp ramp;
            for (int c = 0; c < 3; ++c) {
                ramp.low[c] = m.albedo.low[c];
                ramp.high[c] = m.albedo.high[c];
            }
            ramp.grain = m.albedo.grain;
            out.albedo = ramp_image(*f, ramp);
            break;
        }
    }
    return {};
}

}  // namespace

Result<MaterialImages> build_material_images_as_given(const MaterialDesc& m, const std::string& base_dir,
                                                       const TextureFileReaders* files) {
    const std::string where = "material '" + echo(m.name) + "'";
    if (!files) {
        const std::pair<const TextureSource*, const char*> slots[] = {
            {&m.height, "height"}, {&m.normal, "normal"}, {&m.albedo, "albedo"}};
        for (auto [source, slot] : slots)
            if (source->kind == TextureSource::Kind::file) return with_context(where + " " + slot, no_readers(*source).error());
    }
    MaterialImages out;
    // Texture files are never packed: each keeps its own layout (height in
    // one channel, normals in two or three).
    const bool any_texture_file =
        texture_file_source(m.height) || texture_file_source(m.normal) || texture_file_source(m.albedo);
    // A texture file that is both the normal map and, in its alpha, the
    // height (the whitepaper's back-to-back layout, as packs ship it): read
    // in place, one fetch for both, nothing repacked.
    const bool height_in_normal_file = texture_file_source(m.height) && texture_file_source(m.normal) &&
                                       m.height.path == m.normal.path && m.height.channel == TextureSource::Channel::a;
    const bool packed = height_in_normal_file || (m.pack_height_in_normal_alpha && !any_texture_file);
    out.layout.packed_height = packed;
    if (height_in_normal_file) {
        if (Status read = read_texture_files(out, m, where, base_dir, files); !read) return read.error();
        const int count = files->channels(out.normal_texture->format);
        if (count < 4)
            return make_error(where + " height: '" + echo_path(m.height.path) + "' holds " + std::to_string(count) +
                              " channels; it has no alpha to hold the height");
        Result<Image> alpha = channel_image(out.normal, m.height);
        if (!alpha) return with_context(where + " height", alpha.error());
        out.field = height_field_from_image(*alpha, m.height.convention);
        if (m.height.convention == HeightConvention::depth) return depth_file_refused(where, m.height.path).error();
        out.traced = out.field;
    } else {
        if (Status height = read_height(out, m, where, base_dir, files); !height) return height.error();
        if (Status read = read_texture_files(out, m, where, base_dir, files); !read) return read.error();
    }
    if (Status normal = build_normal_map(out, m, where, base_dir, files, packed); !normal) return normal.error();
    if (!packed) out.height = height_image(out.field);
    if (files && (out.height_texture || out.normal_texture || out.albedo_texture)) out.decode = files->decode_level;

    if (!out.albedo_texture) {
        if (Status albedo = build_albedo(out, m, where, base_dir, files); !albedo) return albedo.error();
    }
    if (Status space = albedo_color_space(out, m, base_dir, files); !space) return with_context(where + " albedo", space.error());
    data_slot_notes(out, m);
    return out;
}

}  // namespace px
