#include "parallaxes/gl/caps.h"

#include <cstdio>
#include <sstream>
#include <vector>

#include "parallaxes/gl/gl.h"

namespace px {

namespace {

std::string gl_string(GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? reinterpret_cast<const char*>(s) : "";
}

PrecisionInfo precision(GLenum shader, GLenum type) {
    GLint range[2] = {0, 0};
    GLint bits = 0;
    glGetShaderPrecisionFormat(shader, type, range, &bits);
    return PrecisionInfo{range[0], range[1], bits};
}

}  // namespace

Caps query_caps() {
    Caps c;
    c.version = gl_string(GL_VERSION);
    c.glsl_version = gl_string(GL_SHADING_LANGUAGE_VERSION);
    c.renderer = gl_string(GL_RENDERER);
    c.vendor = gl_string(GL_VENDOR);
    // "OpenGL ES 3.2 Mesa 22.3.6": the numbers after "OpenGL ES ".
    int major = 2, minor = 0;
    if (std::sscanf(c.version.c_str(), "OpenGL ES %d.%d", &major, &minor) != 2 &&
        std::sscanf(c.version.c_str(), "OpenGL ES-%*2s %d.%d", &major, &minor) != 2) {
        major = 2;
        minor = 0;
    }
    c.es_major = major;
    c.es_minor = minor;
    std::istringstream ext(gl_string(GL_EXTENSIONS));
    for (std::string e; ext >> e;) c.extensions.insert(e);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &c.max_texture_size);
    GLint formats = 0;
    glGetIntegerv(GL_NUM_COMPRESSED_TEXTURE_FORMATS, &formats);
    if (formats > 0 && formats <= 4096) {
        std::vector<GLint> list(static_cast<std::size_t>(formats));
        glGetIntegerv(GL_COMPRESSED_TEXTURE_FORMATS, list.data());
        for (GLint f : list) c.compressed_formats.push_back(static_cast<std::uint32_t>(f));
    }
    glGetIntegerv(GL_MAX_VARYING_VECTORS, &c.max_varying_vectors);
    c.fragment_mediump_float = precision(GL_FRAGMENT_SHADER, GL_MEDIUM_FLOAT);
    c.fragment_highp_float = precision(GL_FRAGMENT_SHADER, GL_HIGH_FLOAT);
    c.fragment_highp = c.fragment_highp_float.precision > 0;
    return c;
}

}  // namespace px
