// steep: steep parallax mapping (McGuire & McGuire 2005). Linear search down
// the view ray; the first sample on or under the surface is the hit.
#define PX_HAS_TRACE
#define PX_TRACE_STARTS  // a bounded relief's side: the search starts at px_start_t (march.glsl)
#include "chunks/surface_common.glsl"
#include "chunks/march.glsl"

PxHit px_trace(PX_HIGHP vec2 uv, PX_VIEW_PRECISION vec3 view_ts PX_TRACE_GRADIENTS) {
#ifdef PX_CURVED
    PxMarch m = px_curved_search(uv, view_ts PX_TRACE_GRADIENT_ARGS);
    PxHit hit;
    px_hit_mu = m.mu_below;
    hit.height = m.ray_below;
    hit.uv = px_curved_uv(uv, view_ts.xy, px_hit_mu);
    return hit;
#else
    PX_HIGHP vec2 parallax = px_parallax_vector(view_ts);
    PxMarch m = px_linear_search(uv, parallax, view_ts.z PX_TRACE_GRADIENT_ARGS);
    PxHit hit;
    hit.height = m.ray_below;
    // The uv from highp uv and parallax again (as pom and relief do), not the
    // loop's m.uv_below: Mesa lowers a texture coordinate to the sampler's
    // mediump, and where the shading's coordinate is a loop-carried value it
    // moves that f2f16 up through the loop's phis, so m.uv_below came back in
    // fp16 (0.5-tile steps at uv 1000: the relief gone).
    hit.uv = uv + (hit.height - u_polygon_height) * parallax;
    if (m.ray_below == m.ray_above) hit.uv = px_search_start_uv(uv, parallax);  // hit where it starts
    return hit;
#endif
}
#include "chunks/surface_main.glsl"
