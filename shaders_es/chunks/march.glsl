// The linear search shared by steep, pom and relief: walk the view ray down
// through the relief in equal height steps until it is under the surface.
//
// Heights are normalised to the relief: 0 at its bottom, 1 at its top; the
// polygon sits at u_polygon_height. Along the view ray, the point at height H
// has uv = uv0 + (H - u_polygon_height) * parallax, where
// parallax = scale * V.xy / V.z is the uv shift per unit of height
// (Tatarchuk's parallax offset vector).

struct PxMarch {
    PX_HIGHP vec2 uv_above;     // last sample above the surface
    mediump float ray_above; // ray height there
    mediump float height_above;
    PX_HIGHP vec2 uv_below;     // first sample on or under the surface
    mediump float ray_below;
    mediump float height_below;
    mediump float step;      // height step of the search
};

// Tatarchuk 2005: the sample count rises linearly from u_sample_range.x with
// the view along the normal to u_sample_range.y at grazing view.
uniform mediump vec2 u_sample_range;

mediump float px_sample_count(mediump float cos_view) {
    return floor(mix(u_sample_range.y, u_sample_range.x, clamp(cos_view, 0.0, 1.0)) + 0.5);
}

// The ray enters the relief at its top (height 1). A view nearly parallel
// to the surface is clamped so the offset stays finite.
PX_HIGHP vec2 px_parallax_vector(PX_VIEW_PRECISION vec3 view_ts) {
    // The division in highp: from mediump operands llvmpipe divides in fp16,
    // which moved grazing hits by up to 0.6 texel (measured against the
    // reference); one highp division per pixel costs nothing next to the march.
    PX_HIGHP vec3 view = view_ts;
    return view.xy / max(view.z, 1.0 / 64.0);
}

PxMarch px_linear_search(PX_HIGHP vec2 uv0, PX_HIGHP vec2 parallax, mediump float cos_view PX_TRACE_GRADIENTS) {
    mediump float count = min(px_sample_count(cos_view), float(PX_MAX_SAMPLES));
    // The search spans the relief from its top (or, through a bounded
    // relief's side, from where the ray comes in: px_start_t) to its bottom.
    mediump float start = 1.0;
#ifdef PX_BOUNDED
    start = 1.0 - px_start_t;
#endif
    mediump float step = start / count;
    PxMarch m;
    m.step = step;
    m.ray_above = start;
    m.uv_above = uv0 + (start - u_polygon_height) * parallax;
    m.height_above = px_trace_height(m.uv_above);
    PX_WORK(0.0, 1.0);
    m.uv_below = m.uv_above;
    m.ray_below = m.ray_above;
    m.height_below = m.height_above;
    if (m.height_above >= m.ray_above) return m;  // hit where the search starts
    // GLSL ES 1.00 Appendix A: a constant bound with an early break.
    for (int i = 1; i <= PX_MAX_SAMPLES; i++) {
        mediump float ray = start - float(i) * step;
        PX_HIGHP vec2 uv = uv0 + (ray - u_polygon_height) * parallax;
        mediump float h = px_trace_height(uv);
        PX_WORK(1.0, 1.0);
        m.uv_below = uv;
        m.ray_below = ray;
        m.height_below = h;
        if (h >= ray || float(i) >= count) break;
        m.uv_above = uv;
        m.ray_above = ray;
        m.height_above = h;
    }
    return m;
}
