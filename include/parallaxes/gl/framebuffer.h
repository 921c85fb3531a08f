// A framebuffer with a colour texture and a depth renderbuffer: the
// offscreen target of headless runs and the debug-output capture.
#pragma once

#include <string>

#include "parallaxes/core/result.h"
#include "parallaxes/core/caps.h"
#include "parallaxes/gl/handles.h"

namespace px {

enum class ColorFormat {
    rgba8,    // colour-renderable on every ES 2.0 context (as a texture)
    rgba32f,  // ES 3.0 with GL_EXT_color_buffer_float
};

struct ColorDepthFramebuffer {
    TextureHandle color;
    RenderbufferHandle depth;
    FramebufferHandle framebuffer;
};

// 24-bit depth where the context has it (ES 3.0, or GL_OES_depth24), else 16.
// Errors name the format and the incomplete status. Leaves every binding as it was.
Result<ColorDepthFramebuffer> make_color_depth_framebuffer(int width, int height, ColorFormat format,
                                                           const Caps& caps);

}  // namespace px
