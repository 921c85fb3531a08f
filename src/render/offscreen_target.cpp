#include "parallaxes/render/offscreen_target.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "parallaxes/gl/caps.h"
#include "parallaxes/gl/errors.h"
#include "parallaxes/gl/state.h"

namespace px {
namespace {

// Mesa's llvmpipe on 64-bit ARM (Mesa 22.3.6, LLVM 15, under qemu-aarch64 7.2
// on every emulated CPU) crashes in its generated fragment code on the first
// depth-tested draw into a multisampled target whose shader does not write
// gl_FragDepth: tools/cross/msaa_depth.c reproduces it in 100 lines (README,
// "ARM builds"). Measured on 22.3 only: later versions are not held back.
// Returns why multisampling is off for this context, or "" where it is not.
std::string multisampling_withheld(const Caps& caps) {
#if defined(__aarch64__)
    if (caps.renderer.rfind("llvmpipe", 0) != 0) return "";
    const size_t at = caps.version.find("Mesa ");
    if (at == std::string::npos) return "";
    int major = 0, minor = 0;
    if (std::sscanf(caps.version.c_str() + at + 5, "%d.%d", &major, &minor) != 2) return "";
    if (major > 22 || (major == 22 && minor > 3)) return "";
    return "llvmpipe of Mesa " + std::to_string(major) + "." + std::to_string(minor) +
           " on 64-bit ARM crashes drawing depth-tested multisampled targets (tools/cross/msaa_depth.c)";
#else
    (void)caps;
    return "";
#endif
}

}  // namespace

Result<OffscreenTarget> OffscreenTarget::create(int width, int height, int samples) {
    if (samples < 1 || samples > 64)
        return make_error("multisampling: " + std::to_string(samples) + " samples per pixel is outside 1..64");
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
    if (samples == 1) return t;
    if (!caps.context_es3()) {
        t.sampling_note_ = std::to_string(samples) +
                           " samples asked for; an OpenGL ES 2.0 context has no multisampled renderbuffers: 1 sample";
        return t;
    }
    if (const std::string why = multisampling_withheld(caps); !why.empty()) {
        t.sampling_note_ = std::to_string(samples) + " samples asked for; " + why + ": 1 sample";
        return t;
    }
    GLint max_samples = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    const int granted = std::max(1, std::min(samples, static_cast<int>(max_samples)));
    if (granted < samples)
        t.sampling_note_ = std::to_string(samples) + " samples asked for; this context offers at most " +
                           std::to_string(max_samples) + ": " + std::to_string(granted);
    if (granted == 1) return t;
    SavedGlState saved(caps);
    t.multisampled_color_ = make_renderbuffer();
    glBindRenderbuffer(GL_RENDERBUFFER, t.multisampled_color_.get());
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, granted, GL_RGBA8, width, height);
    t.multisampled_depth_ = make_renderbuffer();
    glBindRenderbuffer(GL_RENDERBUFFER, t.multisampled_depth_.get());
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, granted, GL_DEPTH_COMPONENT24, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    t.multisampled_ = make_framebuffer();
    glBindFramebuffer(GL_FRAMEBUFFER, t.multisampled_.get());
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t.multisampled_color_.get());
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t.multisampled_depth_.get());
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return make_error("offscreen target: the " + std::to_string(granted) +
                          "-sample framebuffer is incomplete: " + framebuffer_status_name(status));
    if (Status s = check_gl("creating a multisampled offscreen target"); !s) return s.error();
    t.samples_ = granted;
    return t;
}

Result<Image> OffscreenTarget::read_pixels() const {
    Image image;
    image.width = width_;
    image.height = height_;
    image.channels = 4;
    image.pixels.resize(static_cast<size_t>(width_) * height_ * 4);
    SavedGlState saved(caps_);
    if (multisampled_) {
        // Resolve: every sample of a pixel averaged into the single-sampled
        // target (a blit obeys the scissor test: off for it).
        glDisable(GL_SCISSOR_TEST);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, multisampled_.get());
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, buffers_.framebuffer.get());
        glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        if (Status s = check_gl("resolving the multisampled offscreen target"); !s) return s.error();
    }
    glBindFramebuffer(GL_FRAMEBUFFER, buffers_.framebuffer.get());
    set_pack_defaults(caps_);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
    Status s = check_gl("reading the offscreen target back");
    if (!s) return s.error();
    return image;
}

}  // namespace px
