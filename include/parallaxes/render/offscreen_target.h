// An offscreen framebuffer (RGBA8 colour + depth) of a requested size, and
// reading its pixels back: the target of headless runs (tools, tests,
// benchmarks) and of hosts that have no framebuffer of their own to give.
// Needs a current context.
#pragma once

#include <string>

#include "parallaxes/assets/image.h"
#include "parallaxes/core/result.h"
#include "parallaxes/core/caps.h"
#include "parallaxes/gl/framebuffer.h"
#include "parallaxes/render/target.h"

namespace px {

class OffscreenTarget {
public:
    // Errors: sizes out of range for the context, an incomplete framebuffer
    // (named by its status). Leaves the context's framebuffer binding as it was.
    //
    // `samples` > 1 asks for multisampling: draws go to multisampled colour
    // and depth renderbuffers, resolved into the single-sampled target when
    // read. Where the context offers fewer (OpenGL ES 2.0 has no
    // multisampled renderbuffers; ES 3.0 has GL_MAX_SAMPLES, at least 4),
    // it gets what there is, down to 1: samples() and sampling_note() say so.
    static Result<OffscreenTarget> create(int width, int height, int samples = 1);

    RenderTarget target() const {
        return RenderTarget{(multisampled_ ? multisampled_ : buffers_.framebuffer).get(), width_, height_};
    }
    int width() const { return width_; }
    int height() const { return height_; }
    int samples() const { return samples_; }
    // Why samples() is fewer than asked for; empty when it is not.
    const std::string& sampling_note() const { return sampling_note_; }
    // RGBA8, row 0 = bottom row (as GL reads it, and as Image stores it);
    // resolved first when multisampled. Restores the framebuffer bindings
    // and GL_PACK_ALIGNMENT it changes.
    Result<Image> read_pixels() const;

private:
    ColorDepthFramebuffer buffers_;
    FramebufferHandle multisampled_;  // empty when single-sampled
    RenderbufferHandle multisampled_color_;
    RenderbufferHandle multisampled_depth_;
    int samples_ = 1;
    std::string sampling_note_;
    Caps caps_;
    int width_ = 0;
    int height_ = 0;
};

}  // namespace px
