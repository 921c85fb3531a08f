// offset_limited: parallax mapping with offset limiting (Welsh 2004; PowerVR
// Parallax Bumpmapping whitepaper): V.z is dropped, so the offset never
// exceeds the scaled height: uv' = uv + h_sb * V.xy.
#define PX_HAS_TRACE
#include "chunks/surface_common.glsl"

PxHit px_trace(PX_HIGHP vec2 uv, PX_VIEW_PRECISION vec3 view_ts PX_TRACE_GRADIENTS) {
    mediump float h = px_trace_height(uv);
    PxHit hit;
    hit.uv = uv + (h - u_polygon_height) * view_ts.xy;
    hit.height = h;
    return hit;
}
#include "chunks/surface_main.glsl"
