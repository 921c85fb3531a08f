// Uploading images as GL textures with full mip chains. These change the
// texture binding of the active unit and the unpack state: call them inside
// a SavedGlState (gl/state.h), as Renderer::load does.
#pragma once

#include "parallaxes/assets/image.h"
#include "parallaxes/assets/max_mipmap.h"
#include "parallaxes/core/result.h"
#include "parallaxes/gl/caps.h"
#include "parallaxes/gl/handles.h"
#include "parallaxes/texture/texture_data.h"

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
// srgb: the texels are sRGB-encoded colour, decoded by the texture unit
// (Caps::srgb_textures must hold): GL_SRGB8_ALPHA8, with the GPU's mip chain.
Result<Texture> upload_texture(const Image& image, const Caps& caps, const std::string& what, bool mipmaps = true,
                               bool srgb = false);

// How a texture file's data reached the GPU, for the render's report.
struct TextureUpload {
    std::string what;        // "material 'stone' height (file 'h.ktx')"
    std::string container;   // "KTX 1.1", ..., or "image"
    TextureFormat format = TextureFormat::rgba8;  // as the file holds it
    std::uint32_t width = 0, height = 0;
    int levels = 0;          // uploaded
    bool direct = true;      // the context samples the format: uploaded as it is
    std::string path;        // "direct (glCompressedTexImage2D)", "CPU decode to RGBA8 (needs ...)"
    std::uint64_t file_bytes = 0;  // the data as given, all levels
    std::uint64_t gpu_bytes = 0;   // what the upload handed the GPU, all levels
    std::string rows;              // "top row first (KTXOrientation \"S=r,T=d,R=i\")"; empty for images
    // How its colour is read: "linear", "sRGB" (by the texture unit); an
    // albedo's also says what decided it ("sRGB, decoded by the texture
    // unit, sRGB (declared by its sRGB chunk)", "sRGB, decoded in the shader
    // (no sRGB textures here), ...").
    std::string color_space;
};

// A TextureData (texture/texture_data.h), level 0 of layer 0, face 0 and
// every level the file gives below it, as they are: through
// glCompressedTexImage2D where the context samples the format
// (context_samples), otherwise decoded on the CPU and uploaded as RGBA8
// (force_decode: always). Levels fewer than the full chain are used as
// given (ES 3.0: GL_TEXTURE_MAX_LEVEL; ES 2.0: the base level alone,
// sampled without mipmaps). mipmaps = false: the base level only,
// GL_LINEAR. Errors: an empty or oversized texture, a non-power-of-two size
// on an ES 2.0 context without GL_OES_texture_npot, a GL error.
// `decode`: the CPU decoder for a format the context does not sample
// (texture/decode.h decode_rgba8 of one level); null: such a texture is an
// error that names its format and what the context lacks.
using DecodeLevel = Result<Image> (*)(const TextureData& data, std::size_t level);
// srgb: sampled as sRGB colour (its format's sRGB twin where the context
// samples it, else decoded on the CPU and uploaded as sRGB RGBA8), as above.
Result<Texture> upload_texture_data(const TextureData& data, const Caps& caps, const std::string& what,
                                    bool mipmaps, bool force_decode, TextureUpload* report, DecodeLevel decode,
                                    bool srgb = false);

// The maximum mip-map pyramid (assets/max_mipmap.h): every level uploaded
// as it is (never glGenerateMipmap, which averages), GL_R8, nearest
// filtering, read with texelFetch. OpenGL ES 3.0 only. 11-bit pyramids go
// up as GL_RG8 (R = high bits, G = low byte).
Result<Texture> upload_max_mipmap(const MaxMipmap& pyramid, const Caps& caps, const std::string& what);
// GLSL ES 1.00's pyramid (assets/max_mipmap.h, build_max_atlas): one RGBA8
// level, nearest filtering, CLAMP_TO_EDGE (core ES 2.0 samples NPOT that
// way). Any context; an atlas over GL_MAX_TEXTURE_SIZE is an error naming both.
Result<Texture> upload_max_atlas(const MaxAtlas& atlas, const Caps& caps, const std::string& what);

// Binds the texture to GL_TEXTURE_2D of the active unit.
void bind_texture(const Texture& texture);

}  // namespace px
