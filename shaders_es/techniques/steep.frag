// steep: steep parallax mapping (McGuire & McGuire 2005). Linear search down
// the view ray; the first sample on or under the surface is the hit.
#define PX_HAS_TRACE
#include "chunks/surface_common.glsl"
#include "chunks/march.glsl"

PxHit px_trace(PX_HIGHP vec2 uv, PX_VIEW_PRECISION vec3 view_ts PX_TRACE_GRADIENTS) {
    PxMarch m = px_linear_search(uv, px_parallax_vector(view_ts), view_ts.z PX_TRACE_GRADIENT_ARGS);
    PxHit hit;
    hit.uv = m.uv_below;
    hit.height = m.ray_below;
    return hit;
}
#include "chunks/surface_main.glsl"
