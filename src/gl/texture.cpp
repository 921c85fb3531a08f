#include "parallaxes/gl/texture.h"

#include <string>

#include "parallaxes/core/numeric.h"
#include "parallaxes/gl/errors.h"
#include "parallaxes/gl/state.h"
#include "parallaxes/texture/format.h"
#include "parallaxes/texture/texture_data.h"

namespace px {

namespace {

// A new texture of this size, bound to the active unit, with the unpack
// state that tightly packed rows need.
Texture new_bound_texture(int width, int height, const Caps& caps) {
    Texture t;
    t.handle = make_texture();
    t.width = width;
    t.height = height;
    glBindTexture(GL_TEXTURE_2D, t.handle.get());
    set_unpack_defaults(caps);
    return t;
}

}  // namespace

namespace {

// GL_SRGB8_ALPHA8 (not in the GLES2 header).
constexpr GLenum kSrgb8Alpha8 = 0x8C43;

}  // namespace

Result<Texture> upload_texture(const Image& image, const Caps& caps, const std::string& what, bool mipmaps,
                               bool srgb) {
    if (srgb && !caps.srgb_textures())
        return make_error(what + ": sRGB textures need OpenGL ES 3.0 (decode in the shader instead)");
    if (image.width < 1 || image.height < 1 || image.pixels.empty())
        return make_error(what + ": empty image");
    if (image.width > caps.max_texture_size || image.height > caps.max_texture_size)
        return make_error(what + ": " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                          " exceeds this context's GL_MAX_TEXTURE_SIZE of " + std::to_string(caps.max_texture_size));
    if (!caps.npot_mipmaps() && !(is_power_of_two(image.width) && is_power_of_two(image.height)))
        return make_error(what + ": " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                          " is not a power of two, and this OpenGL ES 2.0 context lacks GL_OES_texture_npot, "
                          "so it can neither repeat nor mipmap it; resize the image");
    Image rgba;
    const Image* source = &image;
    if (image.channels != 4) {  // expand to RGBA: one upload path
        rgba.width = image.width;
        rgba.height = image.height;
        rgba.channels = 4;
        rgba.pixels.resize(static_cast<size_t>(image.width) * image.height * 4);
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                const std::uint8_t* s = image.texel(x, y);
                std::uint8_t* d = rgba.texel(x, y);
                d[0] = s[0];
                d[1] = image.channels >= 3 ? s[1] : s[0];
                d[2] = image.channels >= 3 ? s[2] : s[0];
                d[3] = image.channels == 4 ? s[3] : (image.channels == 2 ? s[1] : 255);
            }
        source = &rgba;
    }
    Texture t = new_bound_texture(image.width, image.height, caps);
    glTexImage2D(GL_TEXTURE_2D, 0, srgb ? static_cast<GLint>(kSrgb8Alpha8) : GL_RGBA, image.width, image.height, 0,
                 GL_RGBA, GL_UNSIGNED_BYTE, source->pixels.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, mipmaps ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    if (mipmaps) glGenerateMipmap(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, 0);
    Status s = check_gl("uploading " + what);
    if (!s) return s.error();
    return t;
}

Result<Texture> upload_max_mipmap(const MaxMipmap& pyramid, const Caps& caps, const std::string& what) {
    if (caps.es_major < 3) return make_error(what + ": the max pyramid needs OpenGL ES 3.0 (texelFetch with a level)");
    if (pyramid.levels.empty()) return make_error(what + ": empty max pyramid");
    Texture t = new_bound_texture(pyramid.width, pyramid.height, caps);
    for (int level = 0; level < pyramid.level_count(); ++level) {
        const Image& image = pyramid.levels[static_cast<size_t>(level)];
        const int channels = pyramid.bits == 11 ? 2 : 1;
        if (image.channels != channels)
            return make_error(what + ": max pyramid levels must have " + std::to_string(channels) + " channel(s)");
        glTexImage2D(GL_TEXTURE_2D, level, channels == 2 ? GL_RG8 : GL_R8, image.width, image.height, 0,
                     channels == 2 ? GL_RG : GL_RED, GL_UNSIGNED_BYTE, image.pixels.data());
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, pyramid.level_count() - 1);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    Status s = check_gl("uploading " + what);
    if (!s) return s.error();
    return t;
}

Result<Texture> upload_max_atlas(const MaxAtlas& atlas, const Caps& caps, const std::string& what) {
    const Image& image = atlas.image;
    if (image.width < 1 || image.height < 1 || image.channels != 4 ||
        image.pixels.size() != static_cast<size_t>(image.width) * image.height * 4)
        return make_error(what + ": malformed max atlas");
    if (image.width > caps.max_texture_size || image.height > caps.max_texture_size)
        return make_error(what + ": the max atlas is " + std::to_string(image.width) + "x" +
                          std::to_string(image.height) + " (one and a half times the height map's width), over "
                          "this context's GL_MAX_TEXTURE_SIZE of " + std::to_string(caps.max_texture_size));
    Texture t = new_bound_texture(image.width, image.height, caps);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, image.width, image.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 image.pixels.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    Status s = check_gl("uploading " + what);
    if (!s) return s.error();
    return t;
}

namespace {

// An uncompressed format's upload: the format and internal format this
// context takes for it (ES 2.0 has no sized ones, nor GL_RED).
void uncompressed_upload_formats(const Caps& caps, TextureFormat texture_format, GLenum& format, GLint& internal) {
    format = GL_RGBA;
    internal = GL_RGBA;
    switch (texture_format) {
    case TextureFormat::r8:
        format = caps.context_es3() ? GL_RED : GL_LUMINANCE;
        internal = caps.context_es3() ? GL_R8 : GL_LUMINANCE;
        break;
    case TextureFormat::rg8:
        format = GL_RG;
        internal = caps.context_es3() ? GL_RG8 : GL_RG;
        break;
    case TextureFormat::rgb8:
        format = GL_RGB;
        internal = caps.context_es3() ? GL_RGB8 : GL_RGB;
        break;
    default:
        format = GL_RGBA;
        internal = caps.context_es3() ? GL_RGBA8 : GL_RGBA;
        break;
    }
}

// The first `levels` levels into the bound texture: as they are where the
// context samples the format (direct), else decoded to RGBA8 on the CPU.
// gpu_bytes: what the GPU was given.
Status upload_levels(const TextureData& data, const Caps& caps, const std::string& what, bool direct, int levels,
                     DecodeLevel decode, bool srgb, std::uint64_t& gpu_bytes) {
    const FormatInfo& f = format_info(data.format);
    for (int level = 0; level < levels; ++level) {
        const TextureLevel& l = data.levels[static_cast<size_t>(level)];
        const GLsizei w = static_cast<GLsizei>(l.width), h = static_cast<GLsizei>(l.height);
        if (direct && f.compressed()) {
            const std::uint32_t internal =
                srgb ? srgb_internal_format(caps, data.format) : upload_internal_format(caps, data.format);
            glCompressedTexImage2D(GL_TEXTURE_2D, level, internal, w, h, 0,
                                   static_cast<GLsizei>(l.image_bytes), data.image(static_cast<size_t>(level)));
            gpu_bytes += l.image_bytes;
        } else if (direct) {
            GLenum format = GL_RGBA;
            GLint internal = GL_RGBA;
            uncompressed_upload_formats(caps, data.format, format, internal);
            if (srgb) internal = static_cast<GLint>(srgb_internal_format(caps, data.format));
            glTexImage2D(GL_TEXTURE_2D, level, internal, w, h, 0, format, GL_UNSIGNED_BYTE,
                         data.image(static_cast<size_t>(level)));
            gpu_bytes += l.image_bytes;
        } else {
            Result<Image> rgba = decode(data, static_cast<size_t>(level));
            if (!rgba) return with_context(what + " level " + std::to_string(level), rgba.error());
            glTexImage2D(GL_TEXTURE_2D, level, srgb ? static_cast<GLint>(kSrgb8Alpha8) : GL_RGBA, w, h, 0, GL_RGBA,
                         GL_UNSIGNED_BYTE, rgba->pixels.data());
            gpu_bytes += rgba->pixels.size();
        }
    }
    return {};
}

// How the texture went up, for TextureUpload::path: direct, or why it was
// decoded; and what became of its mip chain where it is partial.
std::string upload_path(const TextureData& data, bool direct, bool force_decode, bool mipmaps, bool use_mips,
                        int given, int chain) {
    const FormatInfo& f = format_info(data.format);
    std::string path;
    if (direct)
        path = f.compressed() ? "direct (glCompressedTexImage2D)" : "direct (glTexImage2D)";
    else if (force_decode)
        path = "CPU decode to RGBA8 (decoding forced)";
    else if (data.format == TextureFormat::rg8)
        path = "expanded to RGBA8 (no GL_EXT_texture_rg)";
    else
        path = std::string("CPU decode to RGBA8 (this context does not sample ") + format_name(data.format) +
               "; it needs " + format_requirement(data.format) + ")";
    if (mipmaps && given < chain)
        path += use_mips ? "; " + std::to_string(given) + " of " + std::to_string(chain) + " mip levels"
                         : "; no mip chain: sampled without mipmaps";
    return path;
}

}  // namespace

Result<Texture> upload_texture_data(const TextureData& data, const Caps& caps, const std::string& what,
                                    bool mipmaps, bool force_decode, TextureUpload* report, DecodeLevel decode,
                                    bool srgb) {
    if (srgb && !caps.srgb_textures())
        return make_error(what + ": sRGB textures need OpenGL ES 3.0 (decode in the shader instead)");
    if (data.levels.empty() || data.width < 1 || data.height < 1) return make_error(what + ": empty texture");
    const std::string size = std::to_string(data.width) + "x" + std::to_string(data.height);
    if (data.width > static_cast<std::uint32_t>(caps.max_texture_size) ||
        data.height > static_cast<std::uint32_t>(caps.max_texture_size))
        return make_error(what + ": " + size + " exceeds this context's GL_MAX_TEXTURE_SIZE of " +
                          std::to_string(caps.max_texture_size));
    const bool pot = is_power_of_two(data.width) && is_power_of_two(data.height);
    if (!caps.npot_mipmaps() && !pot)
        return make_error(what + ": " + size +
                          " is not a power of two, and this OpenGL ES 2.0 context lacks GL_OES_texture_npot, "
                          "so it can neither repeat nor mipmap it");
    const bool direct = !force_decode &&
                        (srgb ? context_samples_srgb(caps, data.format) : context_samples(caps, data.format)) &&
                        // ES 2.0 has no RG textures without GL_EXT_texture_rg: expand on the CPU.
                        !(data.format == TextureFormat::rg8 && !caps.context_es3() && !caps.has("GL_EXT_texture_rg"));
    if (!direct && !decode)
        return make_error(what + ": " + format_name(data.format) +
                          " must be decoded on the CPU for this context, and no decoder was given");
    const int chain = full_mip_count(data.width, data.height);
    const int given = static_cast<int>(data.levels.size());
    // ES 2.0 has no GL_TEXTURE_MAX_LEVEL: a partial chain is incomplete there.
    const bool use_mips = mipmaps && given > 1 && (given == chain || caps.context_es3());
    const int levels = use_mips ? given : 1;
    Texture t = new_bound_texture(static_cast<int>(data.width), static_cast<int>(data.height), caps);
    std::uint64_t gpu_bytes = 0, file_bytes = 0;
    for (int level = 0; level < given; ++level)
        file_bytes += data.levels[static_cast<size_t>(level)].image_bytes;
    if (Status uploaded = upload_levels(data, caps, what, direct, levels, decode, srgb, gpu_bytes); !uploaded)
        return uploaded.error();
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, use_mips ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    if (caps.context_es3()) glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels - 1);
    glBindTexture(GL_TEXTURE_2D, 0);
    Status s = check_gl("uploading " + what + " (" + format_name(data.format) + ")");
    if (!s) return s.error();
    if (report) {
        report->what = what;
        report->container = container_name(data.container);
        report->rows = std::string(row_order_name(data.rows)) + " (" + data.rows_source + ")";
        report->format = data.format;
        report->width = data.width;
        report->height = data.height;
        report->levels = levels;
        report->direct = direct;
        report->file_bytes = file_bytes;
        report->gpu_bytes = gpu_bytes;
        report->path = upload_path(data, direct, force_decode, mipmaps, use_mips, given, chain);
        if (srgb && !direct && !force_decode && context_samples(caps, data.format))
            report->path = std::string("CPU decode to sRGB RGBA8 (this context samples ") + format_name(data.format) +
                           " but not its sRGB form)" + report->path.substr(report->path.find(';') == std::string::npos
                                                                                ? report->path.size()
                                                                                : report->path.find(';'));
        report->color_space = srgb ? "sRGB" : "linear";
    }
    return t;
}

void bind_texture(const Texture& texture) { glBindTexture(GL_TEXTURE_2D, texture.handle.get()); }

}  // namespace px
