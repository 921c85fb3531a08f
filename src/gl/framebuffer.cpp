#include "parallaxes/gl/framebuffer.h"

#include "parallaxes/gl/errors.h"
#include "parallaxes/gl/state.h"

namespace px {

Result<ColorDepthFramebuffer> make_color_depth_framebuffer(int width, int height, ColorFormat format,
                                                           const Caps& caps) {
    const char* format_name = format == ColorFormat::rgba32f ? "RGBA32F" : "RGBA8";
    if (format == ColorFormat::rgba32f && !(caps.context_es3() && caps.has("GL_EXT_color_buffer_float")))
        return make_error(std::string("an ") + format_name +
                          " target needs OpenGL ES 3.0 with GL_EXT_color_buffer_float");
    SavedGlState saved(caps);
    ColorDepthFramebuffer t;
    t.color = make_texture();
    glBindTexture(GL_TEXTURE_2D, t.color.get());
    set_unpack_defaults(caps);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    if (format == ColorFormat::rgba32f)
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, width, height, 0, GL_RGBA, GL_FLOAT, nullptr);
    else
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glBindTexture(GL_TEXTURE_2D, 0);
    t.depth = make_renderbuffer();
    glBindRenderbuffer(GL_RENDERBUFFER, t.depth.get());
    const bool depth24 = caps.context_es3() || caps.has("GL_OES_depth24");
    glRenderbufferStorage(GL_RENDERBUFFER, depth24 ? GL_DEPTH_COMPONENT24_OES : GL_DEPTH_COMPONENT16, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    t.framebuffer = make_framebuffer();
    glBindFramebuffer(GL_FRAMEBUFFER, t.framebuffer.get());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t.color.get(), 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t.depth.get());
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return make_error(std::string(format_name) + " framebuffer is incomplete: " + framebuffer_status_name(status));
    Status s = check_gl(std::string("creating an ") + format_name + " framebuffer");
    if (!s) return s.error();
    return t;
}

}  // namespace px
