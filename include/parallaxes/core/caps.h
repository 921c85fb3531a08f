// What an OpenGL ES context can do, as plain data: gl/caps.h queries it from
// the current context once; the planner and the tests also build it by hand,
// without any GL.
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace px {

struct PrecisionInfo {
    int range_min = 0;   // log2 of the smallest representable magnitude bound
    int range_max = 0;   // log2 of the largest
    int precision = 0;   // bits of precision (0 for an integer format)
};

struct Caps {
    int es_major = 3;
    int es_minor = 0;
    // The context's own major version where es_major was lowered to draw as
    // an older one (RendererOptions::emulate_es2); 0: es_major. What GL state
    // exists (vertex arrays, sampler objects, pixel buffers) follows it.
    int context_es_major = 0;
    std::string version;       // GL_VERSION
    std::string glsl_version;  // GL_SHADING_LANGUAGE_VERSION
    std::string renderer;      // GL_RENDERER
    std::string vendor;        // GL_VENDOR
    std::set<std::string> extensions;
    // GL_COMPRESSED_TEXTURE_FORMATS: what glCompressedTexImage2D takes here.
    std::vector<std::uint32_t> compressed_formats;
    int max_texture_size = 2048;
    int max_varying_vectors = 8;
    bool fragment_highp = true;  // fragment shaders have highp float
    PrecisionInfo fragment_mediump_float;
    PrecisionInfo fragment_highp_float;

    bool has(const std::string& extension) const { return extensions.count(extension) != 0; }
    bool frag_depth() const { return es_major >= 3 || has("GL_EXT_frag_depth"); }
    bool derivatives() const { return es_major >= 3 || has("GL_OES_standard_derivatives"); }
    bool npot_mipmaps() const { return es_major >= 3 || has("GL_OES_texture_npot"); }
    bool uint_indices() const { return es_major >= 3 || has("GL_OES_element_index_uint"); }
    bool khr_debug() const { return has("GL_KHR_debug"); }
    // A browser's WebGL context (GL_VERSION "OpenGL ES 3.0 (WebGL 2.0 ...)"
    // through Emscripten): the few places WebGL differs from OpenGL ES.
    bool webgl() const { return version.find("WebGL") != std::string::npos; }
    // sRGB textures decoded to linear by the texture unit (before filtering):
    // ES 3.0. An ES 2.0 context decodes in the shader, GL_EXT_sRGB or not:
    // EXT_sRGB textures cannot be mipmapped by glGenerateMipmap, and one ES
    // 2.0 path is the one this machine tests (llvmpipe offers no EXT_sRGB).
    bool srgb_textures() const { return es_major >= 3; }
    bool context_es3() const { return (context_es_major ? context_es_major : es_major) >= 3; }

    // An ES 3.0 context with every extension the renderer can use; for tests
    // and for enumerating variants without a context.
    static Caps full(int es_major);
};

}  // namespace px
