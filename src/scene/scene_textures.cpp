#include "parallaxes/scene/scene_textures.h"

#include <chrono>
#include <filesystem>

#include "parallaxes/core/files.h"
#include "parallaxes/core/text.h"
#include "parallaxes/scene/material_images.h"

namespace px {

const char* container_extension(ContainerKind kind) {
    switch (kind) {
    case ContainerKind::ktx2: return "ktx2";
    case ContainerKind::pvr3: return "pvr";
    default: return "ktx";
    }
}

namespace {

Result<std::vector<std::uint8_t>> write_container(const TextureData& t, const ConvertOptions& o) {
    switch (o.container) {
    case ContainerKind::ktx2: return write_ktx2(t, o.zstd_level);
    case ContainerKind::pvr3: return write_pvr3(t);
    default: return write_ktx1(t);
    }
}

std::uint64_t rgba8_chain_bytes(std::uint32_t w, std::uint32_t h) {
    std::uint64_t total = 0;
    for (int l = 0; l < full_mip_count(w, h); ++l) total += 4ull * mip_extent(w, l) * mip_extent(h, l);
    return total;
}

// One texture to write: a material's slot.
struct Job {
    size_t material;
    const char* slot;
};

// The slots converted, material by material: those given as files or made
// procedurally, and every normal map a height derives.
std::vector<Job> conversion_jobs(const SceneDesc& scene) {
    std::vector<Job> jobs;
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const MaterialDesc& m = scene.materials[i];
        const auto converts = [](const TextureSource& s) {
            return s.kind == TextureSource::Kind::file || s.kind == TextureSource::Kind::procedural;
        };
        if (converts(m.height)) jobs.push_back({i, "height"});
        // The normal map is derived from the height where none is given.
        if (converts(m.normal) || converts(m.height)) jobs.push_back({i, "normal"});
        if (converts(m.albedo)) jobs.push_back({i, "albedo"});
    }
    return jobs;
}

// The scene reads the files from now on (absolute paths or relative to
// the folder's parent are both fine: the path is used as written).
void use_converted_files(SceneDesc& scene, const std::vector<ConvertedFile>& files) {
    for (const ConvertedFile& f : files) {
        for (MaterialDesc& m : scene.materials) {
            if (m.name != f.material) continue;
            TextureSource s;
            s.kind = TextureSource::Kind::file;
            s.path = std::filesystem::absolute(f.path).string();
            if (f.slot == "height") m.height = s;
            if (f.slot == "normal") m.normal = s;
            if (f.slot == "albedo") {
                // Linear files of sRGB colour (a format without an sRGB form
                // in the container) carry the colour space in the scene.
                if (f.scene_says_srgb) s.color_space = TextureSource::ColorSpace::srgb;
                m.albedo = s;
            }
            m.pack_height_in_normal_alpha = false;
        }
    }
}

}  // namespace

Result<std::vector<ConvertedFile>> convert_scene_textures(SceneDesc& scene, const ConvertOptions& options,
                                                          const std::string& folder,
                                                          void (*progress)(const char*, int, int, const std::string&)) {
    std::error_code ec;
    std::filesystem::create_directories(folder, ec);
    if (ec) return make_error("cannot create folder '" + echo_path(folder) + "': " + ec.message());
    const std::vector<Job> jobs = conversion_jobs(scene);
    std::vector<ConvertedFile> files;
    std::vector<MaterialImages> images(scene.materials.size());
    std::vector<bool> built(scene.materials.size(), false);
    const int total = static_cast<int>(jobs.size());
    for (int k = 0; k < total; ++k) {
        const Job& job = jobs[static_cast<size_t>(k)];
        MaterialDesc& m = scene.materials[job.material];
        const std::string what = "material '" + echo(m.name) + "' " + job.slot;
        if (progress) progress("convert", k, total, what);
        if (!built[job.material]) {
            Result<MaterialImages> im = build_material_images(m, scene.base_dir);
            if (!im) return im.error();
            images[job.material] = std::move(*im);
            built[job.material] = true;
        }
        const MaterialImages& im = images[job.material];
        const std::string slot = job.slot;
        const TextureFormat format = slot == "height"   ? options.formats.height
                                     : slot == "normal" ? options.formats.normal
                                                        : options.formats.albedo;
        const auto start = std::chrono::steady_clock::now();
        Result<TextureData> t = slot == "height"   ? encode_height_texture(im.field, format, options.mipmaps)
                                : slot == "normal" ? encode_normal_texture(im.normal, format, options.mipmaps)
                                                   : encode_color_texture(im.albedo, format, options.mipmaps, im.albedo_srgb);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!t) return with_context(what + " as " + format_name(format), t.error());
        t->container = options.container;
        // An sRGB albedo is written as the format's sRGB form where the
        // container has one (KTX 1.1 has none for ETC1; .astc declares
        // nothing): else the converted scene says so itself.
        bool scene_says_srgb = false;
        if (slot == "albedo" && im.albedo_srgb) {
            const FormatInfo& info = format_info(format);
            const bool declarable = options.container == ContainerKind::pvr3 ||
                                    (options.container == ContainerKind::ktx1 && srgb_gl_of_linear(info.gl_internal_format)) ||
                                    (options.container == ContainerKind::ktx2 && srgb_vk_of_linear(info.vk_format));
            t->srgb = declarable;
            scene_says_srgb = !declarable;
        }
        Result<std::vector<std::uint8_t>> bytes = write_container(*t, options);
        if (!bytes) return with_context(what, bytes.error());
        const std::string name = std::to_string(job.material) + "_" + slot + "." + container_extension(options.container);
        const std::string path = folder + "/" + name;
        Status written = write_file_atomically(path, bytes->data(), bytes->size());
        if (!written) return written.error();
        ConvertedFile f;
        f.material = m.name;
        f.slot = slot;
        f.path = path;
        f.format = format;
        f.width = t->width;
        f.height = t->height;
        f.levels = static_cast<int>(t->levels.size());
        f.bytes = bytes->size();
        f.rgba8_bytes = rgba8_chain_bytes(t->width, t->height);
        f.seconds = seconds;
        f.srgb = t->srgb;
        f.scene_says_srgb = scene_says_srgb;
        files.push_back(f);
    }
    if (progress && total > 0) progress("convert", total, total, "done");
    use_converted_files(scene, files);
    return files;
}

}  // namespace px
