// parallax texinfo FILE [--es 2|3]
// parallax convert [HEIGHT] [--albedo A] [--normal N] [--scene SCENE] --format VARIANT --out DIR ...
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "commands.h"
#include "parallaxes/gl/caps.h"
#include "parallaxes/platform/headless_context.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/texture/containers.h"
#include "parallaxes/texture/decode.h"
#include "parallaxes/core/files.h"
#include "texture_assets.h"

namespace px::tools {

namespace {

struct TexinfoArgs {
    std::string file;
    int es = 3;
    bool formats = false;
};

std::string bytes_text(std::uint64_t n) {
    char b[64];
    if (n >= (1u << 20))
        std::snprintf(b, sizeof b, "%llu (%.2f MiB)", static_cast<unsigned long long>(n), static_cast<double>(n) / (1 << 20));
    else if (n >= 1024)
        std::snprintf(b, sizeof b, "%llu (%.1f KiB)", static_cast<unsigned long long>(n), static_cast<double>(n) / 1024);
    else
        std::snprintf(b, sizeof b, "%llu", static_cast<unsigned long long>(n));
    return b;
}

// --formats: what this context samples, from its own lists (the ES
// version, its extensions, GL_COMPRESSED_TEXTURE_FORMATS).
int run_formats(int es) {
    platform::ContextOptions options;
    options.es_major = es;
    Result<std::unique_ptr<platform::HeadlessContext>> context = platform::HeadlessContext::create(options);
    if (!context) return fail("texinfo --formats: " + context.error().message);
    const Caps caps = query_caps();
    std::printf("context    %s | %s\n", caps.version.c_str(), caps.renderer.c_str());
    std::printf("GL_COMPRESSED_TEXTURE_FORMATS (%zu):", caps.compressed_formats.size());
    for (std::uint32_t f : caps.compressed_formats) std::printf(" 0x%04X", f);
    std::printf("\n%-18s %-8s %s\n", "format", "GL", "upload on this context");
    for (const FormatInfo& f : all_formats()) {
        if (!f.compressed()) continue;
        const bool direct = context_samples(caps, f.format);
        std::printf("%-18s 0x%04X   %s\n", f.name, f.gl_internal_format,
                    direct ? "direct (glCompressedTexImage2D)"
                           : ("CPU decode to RGBA8 (needs " + std::string(format_requirement(f.format)) + ")").c_str());
    }
    return 0;
}

int run_texinfo(const TexinfoArgs& a) {
    if (a.formats) return run_formats(a.es);
    if (a.file.empty()) return fail("texinfo: give a texture file, or --formats");
    Result<TextureData> t = read_texture_file(a.file);
    if (!t) return fail(t.error().message);
    const FormatInfo& f = format_info(t->format);
    std::printf("file       %s\n", a.file.c_str());
    std::printf("container  %s%s\n", container_name(t->container),
                t->supercompression.empty() || t->supercompression == "none"
                    ? ""
                    : (", supercompression " + t->supercompression).c_str());
    std::printf("format     %s (%s; %dx%d blocks of %d bytes, %d channel(s), GL 0x%04X)\n", f.name,
                f.compressed() ? "compressed" : "uncompressed", f.block_width, f.block_height, f.block_bytes,
                f.channels, f.gl_internal_format);
    std::printf("size       %ux%u, %zu level(s) of %d in a full chain, %u layer(s), %u face(s)\n", t->width,
                t->height, t->levels.size(), full_mip_count(t->width, t->height), t->layers, t->faces);
    std::printf("colour     %s\n", t->srgb ? ("sRGB, declared by " + t->color_space_source +
                                               ": an albedo is decoded to linear light when sampled; as a height "
                                               "or normal map it is read as its linear format").c_str()
                                            : t->container == ContainerKind::astc
                                                ? ".astc declares none: an albedo is read as sRGB (colour's default), "
                                                  "height and normal maps as linear data"
                                                : "linear (its format is not an sRGB one)");
    std::printf("rows       %s (%s)%s\n", row_order_name(t->rows), t->rows_source.c_str(),
                t->rows == RowOrder::top_first ? "; drawn at v' = 1 - v, the image the right way up" : "");
    for (const std::string& note : t->notes) std::printf("note       %s\n", note.c_str());
    std::printf("bytes      %s of texel data\n", bytes_text(t->total_bytes()).c_str());
    for (size_t i = 0; i < t->levels.size(); ++i)
        std::printf("  level %-2zu %5ux%-5u %s\n", i, t->levels[i].width, t->levels[i].height,
                    bytes_text(t->levels[i].image_bytes).c_str());
    // Level 0 decodes here (a check of the data itself, and what a CPU
    // fallback would upload).
    Result<Image> decoded = decode_rgba8(*t);
    if (!decoded) return fail(a.file + ": level 0 does not decode: " + decoded.error().message);
    platform::ContextOptions options;
    options.es_major = a.es;
    Result<std::unique_ptr<platform::HeadlessContext>> context = platform::HeadlessContext::create(options);
    if (!context) {
        std::printf("context    none (%s): cannot say whether it samples %s\n", context.error().message.c_str(), f.name);
        return 0;
    }
    const Caps caps = query_caps();
    const bool direct = context_samples(caps, t->format);
    std::printf("context    %s | %s\n", caps.version.c_str(), caps.renderer.c_str());
    std::printf("sampling   %s\n", direct ? "direct: the context samples this format (uploaded as it is)"
                                          : ("CPU decode to RGBA8: the context does not sample it (needs " +
                                             std::string(format_requirement(t->format)) + ")")
                                                .c_str());
    return 0;
}

struct ConvertArgs {
    std::string height;      // image or texture file
    std::string albedo, normal;
    std::string scene;       // convert a whole scene instead
    std::string format = "etc2";
    std::string height_format, normal_format, albedo_format;
    std::string container = "ktx";
    int zstd = 0;
    float height_scale = 0.05f;
    bool depth = false;
    bool no_mipmaps = false;
    std::string out;
};

// The formats, container, mip chain and compression --format and its
// overrides ask for; an error names the option.
Result<ConvertOptions> convert_options(const ConvertArgs& a) {
    Result<AssetFormats> formats = asset_formats(a.format);
    if (!formats) return make_error("--format: " + formats.error().message);
    const std::pair<const std::string*, TextureFormat*> overrides[] = {
        {&a.height_format, &formats->height}, {&a.normal_format, &formats->normal}, {&a.albedo_format, &formats->albedo}};
    for (auto [text, slot] : overrides) {
        if (text->empty()) continue;
        Result<TextureFormat> f = parse_format(*text);
        if (!f) return f.error();
        *slot = *f;
    }
    if (format_info(formats->normal).channels < 2)
        return make_error(std::string("--normal-format: a normal map needs two or more channels; ") +
                          format_name(formats->normal) + " has one");
    ConvertOptions options;
    options.formats = *formats;
    options.mipmaps = !a.no_mipmaps;
    if (a.container == "ktx") options.container = ContainerKind::ktx1;
    else if (a.container == "ktx2") options.container = ContainerKind::ktx2;
    else if (a.container == "pvr") options.container = ContainerKind::pvr3;
    else return make_error("--container must be ktx, ktx2 or pvr, got '" + a.container + "'");
    if (a.zstd < 0 || a.zstd > 22) return make_error("--zstd must be 0 (none) or a level 1..22");
    if (a.zstd > 0 && options.container != ContainerKind::ktx2) return make_error("--zstd needs --container ktx2");
    options.zstd_level = a.zstd;
    return options;
}

// The scene whose textures are converted: --scene's, or one material made
// of the images given.
Result<SceneDesc> convert_scene(const ConvertArgs& a) {
    if (!a.scene.empty()) return load_scene(a.scene);
    if (!(a.height_scale >= 0.0f && a.height_scale <= 4.0f)) return make_error("--height-scale must be within 0..4");
    MaterialDesc m;
    m.name = std::filesystem::path(a.height).stem().string();
    m.height.kind = TextureSource::Kind::file;
    m.height.path = a.height;
    m.height.convention = a.depth ? HeightConvention::depth : HeightConvention::height;
    if (!a.albedo.empty()) {
        m.albedo.kind = TextureSource::Kind::file;
        m.albedo.path = a.albedo;
    }
    if (!a.normal.empty()) {
        m.normal.kind = TextureSource::Kind::file;
        m.normal.path = a.normal;
    }
    m.height_scale = a.height_scale;
    SceneDesc scene;
    scene.materials.push_back(m);
    return scene;
}

void print_converted(const std::vector<ConvertedFile>& files) {
    std::uint64_t total = 0, rgba = 0;
    std::printf("%-12s %-7s %-16s %-10s %-7s %12s %12s %8s  %s\n", "material", "slot", "format", "size", "levels",
                "bytes", "RGBA8+mips", "encode s", "file");
    for (const ConvertedFile& f : files) {
        std::printf("%-12s %-7s %-16s %4ux%-5u %-7d %12llu %12llu %8.2f  %s\n", f.material.c_str(), f.slot.c_str(),
                    format_name(f.format), f.width, f.height, f.levels, static_cast<unsigned long long>(f.bytes),
                    static_cast<unsigned long long>(f.rgba8_bytes), f.seconds, f.path.c_str());
        total += f.bytes;
        rgba += f.rgba8_bytes;
    }
    std::printf("total      %s in %zu file(s), %.1f%% of RGBA8 with mips (%s)\n", bytes_text(total).c_str(),
                files.size(), rgba ? 100.0 * static_cast<double>(total) / static_cast<double>(rgba) : 0.0,
                bytes_text(rgba).c_str());
}

// A material snippet per material, to paste into a scene (paths relative to DIR).
Status write_materials_snippet(const SceneDesc& scene, const std::vector<ConvertedFile>& files, const std::string& out) {
    nlohmann::json materials = nlohmann::json::array();
    for (const MaterialDesc& m : scene.materials) {
        nlohmann::json j = {{"name", m.name}, {"height_scale", m.height_scale}};
        for (const ConvertedFile& f : files)
            if (f.material == m.name) {
                const std::string name = std::filesystem::path(f.path).filename().string();
                if (f.scene_says_srgb) j[f.slot] = {{"file", name}, {"color_space", "srgb"}};
                else j[f.slot] = name;
            }
        materials.push_back(j);
    }
    const std::string snippet = nlohmann::json{{"materials", materials}}.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    const std::string snippet_path = out + "/materials.json";
    Status written = write_file_atomically(snippet_path, snippet);
    if (!written) return written;
    std::printf("materials  %s (the materials, reading these files; paste into a scene in %s)\n", snippet_path.c_str(),
                out.c_str());
    return {};
}

int run_convert(const ConvertArgs& a) {
    if (a.out.empty()) return fail("convert: --out DIR is required");
    if (a.height.empty() == a.scene.empty()) return fail("convert: give a HEIGHT image or --scene SCENE (one of them)");
    Result<ConvertOptions> options = convert_options(a);
    if (!options) return fail(options.error().message);
    Result<SceneDesc> scene = convert_scene(a);
    if (!scene) return fail(scene.error().message);
    Status resources = check_scene_resources(*scene, true);
    if (!resources) return fail(in_scene_file(scene->source, resources.error().message));
    // The folder made and checked writable once the arguments are known good, before any encoding.
    if (const std::string unwritable = check_output_folder(a.out); !unwritable.empty()) return fail("--out: " + unwritable);
    Result<std::vector<ConvertedFile>> files = convert_scene_textures(*scene, *options, a.out, show_progress);
    if (!files) return fail(in_scene_file(scene->source, files.error().message));
    print_converted(*files);
    if (Status s = write_materials_snippet(*scene, *files, a.out); !s) return fail(s.error().message);
    return 0;
}

}  // namespace

void add_texture_commands(CLI::App& app) {
    auto info = std::make_shared<TexinfoArgs>();
    CLI::App* t = app.add_subcommand("texinfo", "Print what a texture file (KTX 1.1, KTX 2.0, PVR v3, .astc) holds, or why it is rejected");
    t->add_option("file", info->file, "The texture file");
    t->add_flag("--formats", info->formats, "List every compressed format and whether this context samples it");
    t->add_option("--es", info->es, "OpenGL ES version of the context asked whether it samples the format")
        ->check(CLI::IsMember({2, 3}))
        ->capture_default_str();
    t->callback([info]() { set_exit_status(run_texinfo(*info)); });

    auto conv = std::make_shared<ConvertArgs>();
    CLI::App* c = app.add_subcommand(
        "convert", "Make a material's textures (height, normal map, albedo) into compressed texture files with full mip chains");
    c->add_option("height", conv->height, "Height map image (PNG, JPEG, TGA) or texture file");
    c->add_option("--albedo", conv->albedo, "Albedo image");
    c->add_option("--normal", conv->normal, "Normal map image (default: derived from the height)");
    c->add_option("--scene", conv->scene, "Convert every material of this scene (file or built-in name) instead");
    c->add_option("--format", conv->format, "Variant: raw, etc1, etc2, astc, astc_WxH, pvrtc, bc")->capture_default_str();
    c->add_option("--height-format", conv->height_format, "Format of the height map (overrides the variant's)");
    c->add_option("--normal-format", conv->normal_format, "Format of the normal map");
    c->add_option("--albedo-format", conv->albedo_format, "Format of the albedo");
    c->add_option("--container", conv->container, "ktx (KTX 1.1), ktx2 (KTX 2.0) or pvr (PVR v3)")->capture_default_str();
    c->add_option("--zstd", conv->zstd, "KTX 2.0 Zstandard supercompression level (1..22; 0: none)")->capture_default_str();
    c->add_option("--height-scale", conv->height_scale, "Relief depth in tile units (the derived normal map's slope)")
        ->capture_default_str();
    c->add_flag("--depth", conv->depth, "The height image holds depth (white is deep)");
    c->add_flag("--no-mipmaps", conv->no_mipmaps, "Write the base level only");
    c->add_option("--out", conv->out, "Output folder")->required();
    c->callback([conv]() { set_exit_status(run_convert(*conv)); });
}

}  // namespace px::tools
