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
#ifdef PX_CURVED
    PX_HIGHP float mu_above;  // px_curved_search: the samples' ray parameters
    PX_HIGHP float mu_below;
#endif
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

#ifdef PX_CURVED
// Curved relief (after Oliveira and Policarpo's curved relief mapping): the
// mesh bends away from its tangent plane by the quadric v_curvature, so
// along the view ray, uv(mu) = uv0 - mu * V.xy (V = view_ts: normalised, xy
// scaled by the relief depth), the ray's height within the relief is
//   H(mu) = polygon - mu * V.z + mu^2 * q,
//   q = v_curvature . (V.x^2, V.x V.y, V.y^2),
// polygon = u_polygon_height plus the shell's lift (v_shell_*), and q
// deepened below the relief's top (px_curved_height).
// Under a convex surface (q > 0) the relief's top falls away from the ray:
// H falls, then rises again, and a ray that comes back out through the top
// has passed the surface without meeting it. That fragment shows what lies
// behind (px_ray_left: surface_main.glsl discards it): the relief's own
// silhouette. mu is a distance along the ray in relief depths (px_write_depth).
bool px_ray_left = false;
PX_HIGHP float px_hit_mu = 0.0;  // the hit's mu (set by each trace)
PX_HIGHP float px_curve_q = 0.0;
PX_HIGHP float px_curve_cos = 1.0;
// This fragment's polygon height: u_polygon_height, raised by how far the
// polygon (drawn out as a shell past its chords) lies above the smooth
// surface (v_shell_*).
PX_HIGHP float px_curve_polygon = 1.0;

// k (px_curved_search): at height h the bend is q (1 + px_curve_deepen (1 - h)).
PX_HIGHP float px_curve_deepen = 0.0;

// The ray's height at mu, against a surface at height h: the bend matched
// to the circle at the surface's own depth below the relief's top.
PX_HIGHP float px_curved_height(PX_HIGHP float mu, mediump float h) {
    return px_curve_polygon - mu * px_curve_cos + mu * mu * px_curve_q * (1.0 + px_curve_deepen * (1.0 - h));
}

PxMarch px_curved_search(PX_HIGHP vec2 uv0, PX_VIEW_PRECISION vec3 view_ts PX_TRACE_GRADIENTS) {
    PX_HIGHP vec2 d = view_ts.xy;
    PX_HIGHP float c = view_ts.z;
    PX_HIGHP float q = dot(v_curvature, vec3(d.x * d.x, d.x * d.y, d.y * d.y));
    // The fitted quadric is the surface's osculating one: exact at the
    // relief's top, it bends too little below it. The relief's level at
    // depth d = 1 - h is the surface offset inward by d, a concentric circle
    // along the ray's direction (curvature k in relief depths, k = 2 |q| /
    // sin^2): its radius is 1 / k - d, so seen from the top's tangent plane
    // it falls away by x^2 / (2 (1 / k - d)), the top's q times 1 / (1 - k
    // d), here to first order, 1 + k d. (Until 2026-12-05, 1 + k d / 2, a
    // circle of the top's curvature matched at that depth: the flat rows,
    // whose outline is known, measured 5.7 / 7.0 / 2.3 % on the sphere and
    // 63 / 48 / 63 % on the torus, now 2.6 / 5.7 / 3.9 and 35 / 19 / 35 %;
    // docs/silhouettes.md.)
    PX_HIGHP float k_abs = 2.0 * abs(q) / max(1.0 - c * c, 1e-4);
    px_curve_deepen = min(k_abs, 1.0);
    px_curve_q = q;
    px_curve_cos = c;
    PX_HIGHP float ph = u_polygon_height + v_shell_lift + dot(v_view_position, vec3(v_shell_x, v_shell_y, v_shell_z));
    px_curve_polygon = ph;
    PX_HIGHP float e = 1.0 - ph;  // the relief above the polygon (< 0: the polygon above the relief)
    // The search starts where the ray comes in through the relief's top
    // (H = 1 at mu <= 0: the smaller root of q mu^2 - c mu - e = 0), and
    // ends at its bottom (H = 0: the smaller root of q_bottom mu^2 - c mu +
    // ph = 0, with the bend at the bottom's depth)
    // where the ray gets that deep, else where it goes out through the top
    // again (the larger root of the first): each in its stable form.
    PX_HIGHP float top_disc = c * c + 4.0 * q * e;
    PX_HIGHP float root_top = sqrt(max(top_disc, 0.0));
    // (1e-4, not smaller: without fragment highp these are fp16, whose
    // smallest normal is 6e-5; a quotient past 64 is clamped below anyway.)
    PX_HIGHP float mu_start = -2.0 * e / max(c + root_top, 1e-4);
    PX_HIGHP float q_bottom = q * (1.0 + px_curve_deepen);  // the bend at the bottom (h = 0)
    PX_HIGHP float disc = c * c - 4.0 * q_bottom * ph;
    PX_HIGHP float down = c + sqrt(max(disc, 0.0));
    bool leaves = !(disc >= 0.0 && down > 0.0);
    PX_HIGHP float mu_end = leaves ? (c > 0.0 ? (c + root_top) / (2.0 * q) : 2.0 * e / max(root_top - c, 1e-4))
                                   : 2.0 * ph / down;  // where the ray reaches the bottom
    // No farther than the flat searches reach (V.z clamped at 1/64).
    mu_start = clamp(mu_start, -64.0, 64.0);
    mu_end = min(mu_end, 64.0);
    // Steps no longer than the flat search's (a relief depth over its count,
    // mu 1 / (V.z count)): the bent ray's range is up to 4 times longer
    // (into the relief and out again), within the loop's bound.
    PX_HIGHP float flat_range = 1.0 / max(c, 1.0 / 64.0);
    mediump float count = min(floor(px_sample_count(c) * max((mu_end - mu_start) / flat_range, 1.0) + 0.5),
                              float(PX_MAX_SAMPLES));
    PX_HIGHP float step = (mu_end - mu_start) / count;
    PxMarch m;
    m.step = step;
    if (e < 0.0 && !(top_disc >= 0.0 && c + root_top > 0.0)) {
        // From above the relief, bending away (or going up) before it
        // reaches its top: both roots are negative, or there are none.
        px_ray_left = true;
        m.mu_above = mu_start;
        m.mu_below = mu_start;
        m.uv_above = uv0;
        m.uv_below = uv0;
        m.ray_above = ph;
        m.ray_below = ph;
        m.height_above = 0.0;
        m.height_below = 0.0;
        return m;
    }
    m.mu_above = mu_start;
    m.uv_above = uv0 - mu_start * d + (mu_start * mu_start) * v_uv_bend;
    m.height_above = px_trace_height(m.uv_above);
    m.ray_above = px_curved_height(mu_start, m.height_above);
    PX_WORK(0.0, 1.0);
    m.mu_below = m.mu_above;
    m.uv_below = m.uv_above;
    m.ray_below = m.ray_above;
    m.height_below = m.height_above;
    if (m.height_above >= m.ray_above) return m;  // hit where the search starts
    for (int i = 1; i <= PX_MAX_SAMPLES; i++) {
        PX_HIGHP float mu = mu_start + float(i) * step;
        PX_HIGHP vec2 uv = uv0 - mu * d + (mu * mu) * v_uv_bend;
        mediump float h = px_trace_height(uv);
        PX_HIGHP float ray = px_curved_height(mu, h);
        PX_WORK(1.0, 1.0);
        m.mu_below = mu;
        m.uv_below = uv;
        m.ray_below = ray;
        m.height_below = h;
        if (h >= ray || float(i) >= count) break;
        m.mu_above = mu;
        m.uv_above = uv;
        m.ray_above = ray;
        m.height_above = h;
    }
    // Through the relief and out of its top without meeting it.
    px_ray_left = leaves && m.height_below < m.ray_below;
    return m;
}
#endif
