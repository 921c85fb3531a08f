#include "parallaxes/render/offscreen_target.h"

#include <string>

#include "parallaxes/gl/caps.h"
#include "parallaxes/gl/errors.h"
#include "parallaxes/gl/state.h"

namespace px {

Result<OffscreenTarget> OffscreenTarget::create(int width, int height) {
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
    if (width < 1 || height < 1 || width > max_size || height > max_size)
        return make_error("target size " + std::to_string(width) + "x" + std::to_string(height) +
                          " is outside 1.." + std::to_string(max_size) + " for this context");
    const Caps caps = query_caps();
    Result<ColorDepthFramebuffer> framebuffer = make_color_depth_framebuffer(width, height, ColorFormat::rgba8, caps);
    if (!framebuffer) return with_context("offscreen target", framebuffer.error());
    OffscreenTarget t;
    t.width_ = width;
    t.height_ = height;
    t.buffers_ = std::move(*framebuffer);
    t.caps_ = caps;
    return t;
}

Result<Image> OffscreenTarget::read_pixels() const {
    Image image;
    image.width = width_;
    image.height = height_;
    image.channels = 4;
    image.pixels.resize(static_cast<size_t>(width_) * height_ * 4);
    SavedGlState saved(caps_);
    glBindFramebuffer(GL_FRAMEBUFFER, buffers_.framebuffer.get());
    set_pack_defaults(caps_);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
    Status s = check_gl("reading the offscreen target back");
    if (!s) return s.error();
    return image;
}

}  // namespace px
