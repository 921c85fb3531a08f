// Debug outputs: what the shader computed, not its colour, so that error is
// measured on the hit itself (src/render/surface_capture.cpp reads them).
//   PX_DEBUG_OUTPUT 1: a float target: (u, v, height, visibility of light 0).
//   PX_DEBUG_OUTPUT 2, 3, 4: RGBA8 passes (GLSL ES 1.00, or no float target):
//     fract(u) in 24 bits | fract(v) in 24 bits | height and visibility in
//     16 bits each. In passes 2 and 3, alpha 1 marks a drawn pixel (the
//     target is cleared to 0) and alpha 64/255 one where any of the values
//     was not finite (NaN or Inf: packing would clamp them into plausible
//     numbers); pass 4 uses all four channels for data.
// The packing needs exact integers: 24 bits in highp. A fragment stage
// without highp (GLSL ES 1.00 makes it optional; PX_NO_FRAGMENT_HIGHP
// emulates one) holds integers exactly only up to 2048 (mediump's 2^-10
// relative precision), so there every value is packed in 11 bits and alpha
// 128/255 tells the reader (src/render/surface_capture.cpp) which packing
// it got, rather than a silently wrong decode.
#if PX_ES >= 3 || (defined(GL_FRAGMENT_PRECISION_HIGH) && !defined(PX_NO_FRAGMENT_HIGHP))
#define PX_DEBUG_DRAWN 1.0
// NaN fails every comparison, so this is false for NaN and for +-Inf.
bool px_is_finite(PX_HIGHP float x) { return abs(x) < 1e30; }

PX_HIGHP vec3 px_pack24(PX_HIGHP float x) {
    PX_HIGHP float e = floor(clamp(x, 0.0, 1.0) * 16777215.0 + 0.5);
    PX_HIGHP float r = floor(e / 65536.0);
    e -= r * 65536.0;
    PX_HIGHP float g = floor(e / 256.0);
    PX_HIGHP float b = e - g * 256.0;
    return vec3(r, g, b) / 255.0;
}

PX_HIGHP vec2 px_pack16(PX_HIGHP float x) {
    PX_HIGHP float e = floor(clamp(x, 0.0, 1.0) * 65535.0 + 0.5);
    PX_HIGHP float high = floor(e / 256.0);
    return vec2(high, e - high * 256.0) / 255.0;
}
#else
// mediump: 11 bits in the same byte layout (the top byte 0), and no constant
// past mediump's guaranteed range of 2^14 (65536 would overflow to inf).
#define PX_DEBUG_DRAWN (128.0 / 255.0)
// mediump's guaranteed range is 2^14: past it a value is as good as Inf.
bool px_is_finite(mediump float x) { return abs(x) < 16384.0; }

mediump vec2 px_pack11(mediump float x) {
    mediump float e = floor(clamp(x, 0.0, 1.0) * 2047.0 + 0.5);
    mediump float high = floor(e / 256.0);
    return vec2(high, e - high * 256.0) / 255.0;
}
mediump vec3 px_pack24(mediump float x) { return vec3(0.0, px_pack11(x)); }
mediump vec2 px_pack16(mediump float x) { return px_pack11(x); }
#endif

#define PX_DEBUG_NON_FINITE (64.0 / 255.0)

PX_HIGHP vec4 px_debug_output(PX_HIGHP vec2 hit_uv, PX_HIGHP float hit_height, PX_HIGHP float visibility) {
#if PX_DEBUG_OUTPUT == 1
    // A float target keeps NaN and Inf as they are.
    return vec4(hit_uv, hit_height, visibility);
#else
#if PX_DEBUG_OUTPUT != 4  // passes 2 and 3 carry the mark in alpha; pass 4's alpha is data
    if (!(px_is_finite(hit_uv.x) && px_is_finite(hit_uv.y) && px_is_finite(hit_height) && px_is_finite(visibility)))
        return vec4(0.0, 0.0, 0.0, PX_DEBUG_NON_FINITE);
#endif
#if PX_DEBUG_OUTPUT == 2
    return vec4(px_pack24(fract(hit_uv.x)), PX_DEBUG_DRAWN);
#elif PX_DEBUG_OUTPUT == 3
    return vec4(px_pack24(fract(hit_uv.y)), PX_DEBUG_DRAWN);
#else
    return vec4(px_pack16(hit_height), px_pack16(visibility));
#endif
#endif
}
