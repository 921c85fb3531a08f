// pom: parallax occlusion mapping (Tatarchuk 2005). Linear search, then the
// height profile between the last two samples is taken as a line and
// intersected with the view ray.
#define PX_HAS_TRACE
#define PX_TRACE_STARTS  // a bounded relief's side: the search starts at px_start_t (march.glsl)
#include "chunks/surface_common.glsl"
#include "chunks/march.glsl"

PxHit px_trace(PX_HIGHP vec2 uv, PX_VIEW_PRECISION vec3 view_ts PX_TRACE_GRADIENTS) {
#ifdef PX_CURVED
    PxMarch m = px_curved_search(uv, view_ts PX_TRACE_GRADIENT_ARGS);
#else
    PX_HIGHP vec2 parallax = px_parallax_vector(view_ts);
    PxMarch m = px_linear_search(uv, parallax, view_ts.z PX_TRACE_GRADIENT_ARGS);
#endif
    // Ray minus surface: positive above the surface, <= 0 on or under it.
    mediump float gap_above = m.ray_above - m.height_above;
    mediump float gap_below = m.ray_below - m.height_below;
    mediump float denominator = gap_above - gap_below;
    mediump float t = denominator > 0.0 ? clamp(gap_above / denominator, 0.0, 1.0) : 1.0;
    PxHit hit;
#ifdef PX_CURVED
    px_hit_mu = mix(m.mu_above, m.mu_below, t);
    hit.height = mix(m.ray_above, m.ray_below, t);
    hit.uv = px_curved_uv(uv, view_ts.xy, px_hit_mu);
#else
    hit.height = mix(m.ray_above, m.ray_below, t);
    hit.uv = uv + (hit.height - u_polygon_height) * parallax;
    if (m.ray_below == m.ray_above) hit.uv = px_search_start_uv(uv, parallax);  // hit where it starts
#endif
    return hit;
}
#include "chunks/surface_main.glsl"
