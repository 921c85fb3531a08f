#include "offscreen_target.h"

#include <string>

#include "gl/caps.h"
#include "gl/errors.h"

namespace px::platform {

Result<OffscreenTarget> OffscreenTarget::create(int width, int height) {
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
    if (width < 1 || height < 1 || width > max_size || height > max_size)
        return make_error("target size " + std::to_string(width) + "x" + std::to_string(height) +
                          " is outside 1.." + std::to_string(max_size) + " for this context");
    const Caps caps = query_caps();
    OffscreenTarget t;
    t.width_ = width;
    t.height_ = height;
    // Colour as a texture: RGBA/UNSIGNED_BYTE textures are colour-renderable
    // on every ES 2.0 context, RGBA8 renderbuffers only with OES_rgb8_rgba8.
    t.color_ = make_texture();
    glBindTexture(GL_TEXTURE_2D, t.color_.get());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glBindTexture(GL_TEXTURE_2D, 0);
    // 24-bit depth where the context has it (ES 3.0, or OES_depth24), else 16.
    t.depth_ = make_renderbuffer();
    glBindRenderbuffer(GL_RENDERBUFFER, t.depth_.get());
    const bool depth24 = caps.es_major >= 3 || caps.has("GL_OES_depth24");
    glRenderbufferStorage(GL_RENDERBUFFER, depth24 ? GL_DEPTH_COMPONENT24_OES : GL_DEPTH_COMPONENT16, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    t.framebuffer_ = make_framebuffer();
    glBindFramebuffer(GL_FRAMEBUFFER, t.framebuffer_.get());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t.color_.get(), 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t.depth_.get());
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return make_error(std::string("offscreen framebuffer is incomplete: ") + framebuffer_status_name(status));
    Status s = check_gl("creating the offscreen target");
    if (!s) return s.error();
    return t;
}

Result<Image> OffscreenTarget::read_pixels() const {
    Image image;
    image.width = width_;
    image.height = height_;
    image.channels = 4;
    image.pixels.resize(static_cast<size_t>(width_) * height_ * 4);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    Status s = check_gl("reading the offscreen target back");
    if (!s) return s.error();
    return image;
}

}  // namespace px::platform
