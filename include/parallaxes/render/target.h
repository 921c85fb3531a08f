// Where the renderer draws: any framebuffer of the current context. The host
// app passes its own (its on-screen framebuffer is not guaranteed to be 0);
// platform/ makes an offscreen one for headless runs.
#pragma once

#include "parallaxes/gl/gl.h"

namespace px {

struct RenderTarget {
    GLuint framebuffer = 0;
    int width = 0;
    int height = 0;
};

}  // namespace px
