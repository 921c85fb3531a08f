// Reads back what the shaders computed per pixel (hit uv, height, visibility
// of the first light) by drawing the loaded scene with its debug variants.
// ES 3.0 with GL_EXT_color_buffer_float: one pass into an RGBA32F target.
// Otherwise (ES 2.0): three passes into RGBA8, packed in 24 and 16 bits
// (shaders_es/chunks/debug_output.glsl), or in 11 bits each where the
// fragment stage has no highp (1/2047 of a tile: 0.125 texel of a 256-texel
// map); uvs then come back modulo the tile, which is how errors are measured
// anyway. Restores every piece of GL state it changes (gl/state.h).
#pragma once

#include "parallaxes/core/result.h"
#include "parallaxes/core/surface_image.h"
#include "parallaxes/render/renderer.h"

namespace px {

// Whether capture_surfaces reads this context back through a float target
// (ES 3.0 with GL_EXT_color_buffer_float: debug output 1, full fp32, and
// RendererOptions::capture_ray), rather than the packed RGBA8 passes.
bool captures_floats(const Caps& caps);

// Needs a current context and a loaded scene; creates and deletes its own
// framebuffer and restores the host's binding.
Result<SurfaceImage> capture_surfaces(Renderer& renderer, int width, int height);

}  // namespace px
