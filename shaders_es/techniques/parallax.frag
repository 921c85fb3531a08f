// parallax: parallax mapping (Kaneko et al. 2001, in Welsh 2004's notation).
// One height fetch at the polygon's uv; the offset assumes the surface is at
// that height all along the ray: uv' = uv + h_sb * V.xy / V.z, with
// h_sb = scale * h + bias = scale * (h - polygon height).
#define PX_HAS_TRACE
#include "chunks/surface_common.glsl"

PxHit px_trace(PX_HIGHP vec2 uv, PX_VIEW_PRECISION vec3 view_ts PX_TRACE_GRADIENTS) {
    mediump float h = px_trace_height(uv);
    PxHit hit;
    // V.z clamped at grazing view, where the unlimited offset runs away.
    hit.uv = uv + (h - u_polygon_height) * (view_ts.xy / max(view_ts.z, 1.0 / 64.0));
    hit.height = h;
    return hit;
}
#include "chunks/surface_main.glsl"
