// An offscreen framebuffer (RGBA8 colour + depth) of a requested size, and
// reading its pixels back. Needs a current context.
#pragma once

#include "assets/image.h"
#include "core/result.h"
#include "gl/framebuffer.h"
#include "render/target.h"

namespace px::platform {

class OffscreenTarget {
public:
    // Errors: sizes out of range for the context, an incomplete framebuffer
    // (named by its status).
    static Result<OffscreenTarget> create(int width, int height);

    RenderTarget target() const { return RenderTarget{buffers_.framebuffer.get(), width_, height_}; }
    int width() const { return width_; }
    int height() const { return height_; }
    // RGBA8, row 0 = bottom row (as GL reads it, and as Image stores it).
    Result<Image> read_pixels() const;

private:
    ColorDepthFramebuffer buffers_;
    int width_ = 0;
    int height_ = 0;
};

}  // namespace px::platform
