// An offscreen framebuffer (RGBA8 colour + depth) of a requested size, and
// reading its pixels back: the target of headless runs (tools, tests,
// benchmarks) and of hosts that have no framebuffer of their own to give.
// Needs a current context.
#pragma once

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
    static Result<OffscreenTarget> create(int width, int height);

    RenderTarget target() const { return RenderTarget{buffers_.framebuffer.get(), width_, height_}; }
    int width() const { return width_; }
    int height() const { return height_; }
    // RGBA8, row 0 = bottom row (as GL reads it, and as Image stores it).
    // Restores the framebuffer binding and GL_PACK_ALIGNMENT it changes.
    Result<Image> read_pixels() const;

private:
    ColorDepthFramebuffer buffers_;
    Caps caps_;
    int width_ = 0;
    int height_ = 0;
};

}  // namespace px
