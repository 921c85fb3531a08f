#include "gl/texture.h"

#include <string>

#include "core/numeric.h"
#include "gl/errors.h"
#include "gl/state.h"

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

Result<Texture> upload_texture(const Image& image, const Caps& caps, const std::string& what, bool mipmaps) {
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
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, image.width, image.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 source->pixels.data());
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
        if (image.channels != 1) return make_error(what + ": max pyramid levels must have one channel");
        glTexImage2D(GL_TEXTURE_2D, level, GL_R8, image.width, image.height, 0, GL_RED, GL_UNSIGNED_BYTE,
                     image.pixels.data());
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, pyramid.level_count() - 1);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    Status s = check_gl("uploading " + what);
    if (!s) return s.error();
    return t;
}

void bind_texture(const Texture& texture) { glBindTexture(GL_TEXTURE_2D, texture.handle.get()); }

}  // namespace px
