// Uploading images as GL textures with full mip chains.
#pragma once

#include "assets/image.h"
#include "core/result.h"
#include "gl/caps.h"
#include "gl/handles.h"

namespace px {

struct Texture {
    TextureHandle handle;
    int width = 0;
    int height = 0;
    bool mipmapped = false;
};

// RGBA8 texture, GL_REPEAT, trilinear with a full mip chain. Errors: empty
// image, larger than the context allows, or a non-power-of-two size on an
// ES 2.0 context without GL_OES_texture_npot (which cannot repeat or mipmap it).
// With mipmaps = false: the base level only, GL_LINEAR (for reads inside
// tracing loops on GLSL ES 1.00, which has no gradient sampling).
Result<Texture> upload_texture(const Image& image, const Caps& caps, const std::string& what, bool mipmaps = true);

// Binds the texture to GL_TEXTURE_2D of the active unit.
void bind_texture(const Texture& texture);

}  // namespace px
