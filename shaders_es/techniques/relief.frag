// relief: relief mapping (Policarpo, Oliveira & Comba 2005). Linear search,
// then a binary search between the last sample above the surface and the
// first below it.
#define PX_HAS_TRACE
#define PX_TRACE_STARTS  // a bounded relief's side: the search starts at px_start_t (march.glsl)
#include "chunks/surface_common.glsl"
#include "chunks/march.glsl"

PxHit px_trace(PX_HIGHP vec2 uv, PX_VIEW_PRECISION vec3 view_ts PX_TRACE_GRADIENTS) {
#ifdef PX_CURVED
    PxMarch m = px_curved_search(uv, view_ts PX_TRACE_GRADIENT_ARGS);
    PX_HIGHP float mu_above = m.mu_above;  // known above the surface
    PX_HIGHP float mu_below = m.mu_below;  // known on or under it
    for (int i = 0; i < PX_REFINE_STEPS; i++) {
        PX_HIGHP float middle = 0.5 * (mu_above + mu_below);
        mediump float h = px_trace_height(px_curved_uv(uv, view_ts.xy, middle));
        PX_WORK(0.0, 1.0);  // a refinement: a fetch, not a search step
        if (h >= px_curved_height(middle, h)) {
            mu_below = middle;
        } else {
            mu_above = middle;
        }
    }
    PxHit hit;
    px_hit_mu = mu_below;
    hit.height = px_curved_height(mu_below, m.height_below);
    hit.uv = px_curved_uv(uv, view_ts.xy, mu_below);
    return hit;
#else
    PX_HIGHP vec2 parallax = px_parallax_vector(view_ts);
    PxMarch m = px_linear_search(uv, parallax, view_ts.z PX_TRACE_GRADIENT_ARGS);
    mediump float above = m.ray_above;  // ray height known to be above the surface
    mediump float below = m.ray_below;  // ray height known to be on or under it
    for (int i = 0; i < PX_REFINE_STEPS; i++) {
        mediump float middle = 0.5 * (above + below);
        mediump float h = px_trace_height(uv + (middle - u_polygon_height) * parallax);
        PX_WORK(0.0, 1.0);  // a refinement: a fetch, not a search step
        if (h >= middle) {
            below = middle;
        } else {
            above = middle;
        }
    }
    PxHit hit;
    hit.height = below;
    hit.uv = uv + (below - u_polygon_height) * parallax;
    if (m.ray_below == m.ray_above) hit.uv = px_search_start_uv(uv, parallax);  // hit where it starts
    return hit;
#endif
}
#include "chunks/surface_main.glsl"
