// Uploading images as GL textures with full mip chains. These change the
// texture binding of the active unit and the unpack state: call them inside
// a SavedGlState (gl/state.h), as Renderer::load does.
#pragma once

#include "assets/image.h"
#include "assets/max_mipmap.h"
#include "core/result.h"
#include "gl/caps.h"
#include "gl/handles.h"

namespace px {

struct Texture {
    TextureHandle handle;
    int width = 0;
    int height = 0;
};

// RGBA8 texture, GL_REPEAT, trilinear with a full mip chain. Errors: empty
// image, larger than the context allows, or a non-power-of-two size on an
// ES 2.0 context without GL_OES_texture_npot (which cannot repeat or mipmap it).
// With mipmaps = false: the base level only, GL_LINEAR (for reads inside
// tracing loops on GLSL ES 1.00, which has no gradient sampling).
Result<Texture> upload_texture(const Image& image, const Caps& caps, const std::string& what, bool mipmaps = true);

// The maximum mip-map pyramid (assets/max_mipmap.h): every level uploaded
// as it is (never glGenerateMipmap, which averages), GL_R8, nearest
// filtering, read with texelFetch. OpenGL ES 3.0 only.
Result<Texture> upload_max_mipmap(const MaxMipmap& pyramid, const Caps& caps, const std::string& what);

// Binds the texture to GL_TEXTURE_2D of the active unit.
void bind_texture(const Texture& texture);

}  // namespace px
