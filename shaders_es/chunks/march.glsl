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

// Where the linear search starts, from highp: the relief's top, or through
// a bounded relief's side where the ray comes in (px_start_t). The march's
// own heights are mediump (fp16 on Mesa): 1 - px_start_t rounded there
// moved a hit on a brick's face cut by the tile's edge up to 4e-3 of the
// tile off it at 85 to 89 degrees, and it was discarded (783 of 393
// contour pixels missing under a rotated uv, 2026-12-05). A technique
// whose search hits where it starts (m.ray_below == m.ray_above) takes its
// uv from here.
PX_HIGHP vec2 px_search_start_uv(PX_HIGHP vec2 uv0, PX_HIGHP vec2 parallax) {
#ifdef PX_BOUNDED
    return uv0 + ((1.0 - px_start_t) - u_polygon_height) * parallax;
#else
    return uv0 + (1.0 - u_polygon_height) * parallax;
#endif
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
    m.uv_above = px_search_start_uv(uv0, parallax);
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

#ifdef PX_SHAPE
// The exact curved search (PX_SHAPE 1: a sphere, 2: an open cylinder, 3: a
// torus, as scene/mesh.cpp builds them): each sample is taken where the ray
// really is, its mesh-space point, the mesh's own uv there (the analytic
// parameterisation) and its height along the surface's normal, as the
// displaced reference moves its vertices (make_displaced_curved). No
// quadric, no uv bend: nothing is interpolated but the fragment's position.
// x: the radius (a torus's ring), y: a torus's tube radius or a cylinder's
// height, z: relief depths per mesh unit, w: view-space units per relief
// depth (renderer.cpp set_object_uniforms).
uniform PX_HIGHP vec4 u_shape;
uniform PX_HIGHP vec3 u_object_camera;    // the camera in mesh space
// Mesh uv into material uv: surface.vert's u_uv_matrix and offset, the
// fragment stage's own (a uniform in both stages needs one precision).
uniform PX_HIGHP mat2 u_shape_uv_matrix;
uniform PX_HIGHP vec2 u_shape_uv_offset;
PX_HIGHP vec3 px_shape_origin = vec3(0.0);  // the ray at mu = 0, mesh space
PX_HIGHP vec3 px_shape_step = vec3(0.0);    // and its mesh units per unit of mu

PX_HIGHP vec3 px_shape_point(PX_HIGHP float mu) {
    return px_shape_origin + mu * px_shape_step;
}

// The relief height of mesh-space point p: u_polygon_height on the smooth
// surface, one more per relief depth out along its normal.
PX_HIGHP float px_shape_height(PX_HIGHP vec3 p) {
#if PX_SHAPE == 1
    PX_HIGHP float out_along = length(p) - u_shape.x;
#elif PX_SHAPE == 2
    PX_HIGHP float out_along = length(p.xy) - u_shape.x;
#else
    PX_HIGHP float out_along = length(vec2(length(p.xy) - u_shape.x, p.z)) - u_shape.y;
#endif
    return u_polygon_height + out_along * u_shape.z;
}

// The material uv over mesh-space point p (the mesh's uv: scene/mesh.cpp).
PX_HIGHP vec2 px_shape_uv(PX_HIGHP vec3 p) {
    PX_HIGHP float turn = 0.1591549431;  // 1 / 2 pi
#if PX_SHAPE == 3
    // u around the ring from +x, v around the tube from the outer equator.
    PX_HIGHP vec2 mesh_uv = fract(vec2(atan(p.y, p.x), atan(p.z, length(p.xy) - u_shape.x)) * turn);
#else
    // u around z from +y (the seam), towards -x.
    PX_HIGHP float u = fract(atan(-p.x, p.y) * turn);
#if PX_SHAPE == 1
    PX_HIGHP vec2 mesh_uv = vec2(u, atan(p.z, length(p.xy)) * (2.0 * turn) + 0.5);  // v: latitude
#else
    PX_HIGHP vec2 mesh_uv = vec2(u, p.z / u_shape.y + 0.5);
#endif
#endif
    return u_shape_uv_matrix * mesh_uv + u_shape_uv_offset;
}
#endif

#ifdef PX_SHAPE
#if PX_SHAPE == 2 && defined(PX_BOUNDED)
#define PX_SHAPE_TUBE
#endif
#endif
#ifdef PX_SHAPE_TUBE
// A bounded open tube (the only bounded curved mesh: a sphere's and torus's
// edges are seams) is a relief with no thickness: a sheet r = R - depth (1 -
// h) that exists along the tube's length only (mesh v in [0, 1]: |z| <= half
// its height). A ray meets its front only where it comes to the sheet from
// outside: from above the relief through the tube's side, or onto the
// tube's length through an end's plane outside the sheet; one that comes
// onto it in the hollow (under the sheet) meets the sheet's back first,
// which shows nothing (one-sided, as the displaced reference draws it).
// The tube itself is drawn unwidened; the rays that come onto its length
// through an end are traced from the end's plane by its rim caps (annuli
// over the relief's depth, make_tube_rim_caps, told from the tube by
// gl_FrontFacing): the relief on the far wall's outside standing past the
// rim, seen over it, and the near rim's bumps seen from above.
// [x, y]: the ray's mu range along the tube's length (empty: x > y),
// within +-1e4 (fp16 holds it, without fragment highp; the search reaches
// 64 relief depths).
PX_HIGHP vec2 px_tube_span(PX_HIGHP vec3 origin, PX_HIGHP vec3 step) {
    PX_HIGHP float half_length = 0.5 * u_shape.y;
    // Across the axis (z moves under 1e-4 of the step): z stays.
    if (abs(step.z) <= 1e-4 * length(step))
        return abs(origin.z) <= half_length ? vec2(-1e4, 1e4) : vec2(1e4, -1e4);
    PX_HIGHP float t0 = (-half_length - origin.z) / step.z;
    PX_HIGHP float t1 = (half_length - origin.z) / step.z;
    return clamp(vec2(min(t0, t1), max(t0, t1)), -1e4, 1e4);
}
#endif

// The search's uv at mu along the ray from uv0 (d: the view's uv step).
PX_HIGHP vec2 px_curved_uv(PX_HIGHP vec2 uv0, PX_HIGHP vec2 d, PX_HIGHP float mu) {
#ifdef PX_SHAPE
    return px_shape_uv(px_shape_point(mu));
#else
    return uv0 - mu * d + (mu * mu) * v_uv_bend;
#endif
}

// The ray's height at mu, against a surface at height h: exact with
// PX_SHAPE; else the bend matched to the circle at the surface's own depth
// below the relief's top.
PX_HIGHP float px_curved_height(PX_HIGHP float mu, mediump float h) {
#ifdef PX_SHAPE
    return px_shape_height(px_shape_point(mu));
#else
    return px_curve_polygon - mu * px_curve_cos + mu * mu * px_curve_q * (1.0 + px_curve_deepen * (1.0 - h));
#endif
}

PxMarch px_curved_search(PX_HIGHP vec2 uv0, PX_VIEW_PRECISION vec3 view_ts PX_TRACE_GRADIENTS) {
    PX_HIGHP vec2 d = view_ts.xy;
#ifdef PX_SHAPE
    // The ray in mesh space, mu in relief depths of view-space distance
    // (as elsewhere: px_write_depth_at). Its range and step count come from
    // the model below (the surface's osculating circle along the ray, from
    // the shape's own normal curvature at the fragment); the samples do not.
    PX_HIGHP vec3 p = v_object_position;
    px_shape_origin = p;
    px_shape_step = (p - u_object_camera) * (u_shape.w / length(v_view_position));
#if PX_SHAPE == 1
    PX_HIGHP vec3 n = normalize(p);
#else
    PX_HIGHP vec3 radial = normalize(vec3(p.xy, 0.0));
    PX_HIGHP vec3 around = vec3(-radial.y, radial.x, 0.0);
#if PX_SHAPE == 2
    PX_HIGHP vec3 n = radial;
#else
    PX_HIGHP vec3 n = normalize(p - u_shape.x * radial);
#endif
#endif
    PX_HIGHP float step_length = length(px_shape_step);
    PX_HIGHP vec3 dir = px_shape_step / step_length;
    PX_HIGHP float cos_in = -dot(dir, n);
    PX_HIGHP vec3 along = dir + cos_in * n;  // the ray's part along the surface
    PX_HIGHP float sin2 = dot(along, along);
#if PX_SHAPE == 1
    PX_HIGHP float k_normal = 1.0 / u_shape.x;
#else
    PX_HIGHP float a = dot(along, around);
    PX_HIGHP float around2 = sin2 > 1e-8 ? a * a / sin2 : 1.0;
#if PX_SHAPE == 2
    PX_HIGHP float k_normal = around2 / u_shape.x;
#else
    // Principal curvatures: the tube's 1 / r, the ring's cos(phi) / (R + r cos(phi)).
    PX_HIGHP float cos_phi = dot(n, radial);
    PX_HIGHP float k_normal = around2 * cos_phi / (u_shape.x + u_shape.y * cos_phi) + (1.0 - around2) / u_shape.y;
#endif
#endif
    PX_HIGHP float c = cos_in * step_length * u_shape.z;
    PX_HIGHP float q = 0.5 * k_normal * sin2 * step_length * step_length * u_shape.z;
    PX_HIGHP float ph = px_shape_height(p);
#else
    PX_HIGHP float c = view_ts.z;
    PX_HIGHP float q = dot(v_curvature, vec3(d.x * d.x, d.x * d.y, d.y * d.y));
    PX_HIGHP float ph = u_polygon_height + v_shell_lift + dot(v_view_position, vec3(v_shell_x, v_shell_y, v_shell_z));
#endif
    PX_HIGHP float k_abs = 2.0 * abs(q) / max(1.0 - c * c, 1e-4);
    px_curve_deepen = min(k_abs, 1.0);
    px_curve_q = q;
    px_curve_cos = c;
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
#ifdef PX_SHAPE
    // The samples are exact, the model only second order: from above the
    // relief the search starts at the fragment (the model's entry could lie
    // past the real one), and a ray the model has pass above the top, but
    // heading in, is searched to where the model's ray is as high again.
    // The range is a relief depth at least: a fragment just under the
    // top, its ray grazing it, had a range of nearly 0, and its steps (even
    // grown) stayed there, inside the relief: drawn though the ray passed.
    // From above, the start is the model's entry less a relief depth and a
    // hundredth, the fragment itself where that lands inside the relief:
    // the drawn polygon lies above the relief by the chords' sag, which on
    // a shallow relief (a height scale of 1e-6 tiles, or 4000 tiles around
    // a sphere) is thousands of relief depths, past any range: its whole
    // object was discarded when the search started at the fragment.
    if (top_disc < 0.0 && c > 0.0) mu_end = c / q;
    PX_HIGHP float entry = max(mu_start, -64.0);
    if (e < 0.0) {
        entry = top_disc >= 0.0 ? mu_start : 0.5 * mu_end;
        mu_start = max(0.0, 0.99 * entry - 1.0);
        if (px_shape_height(px_shape_point(mu_start)) <= 1.0) mu_start = 0.0;
    }
    mu_start = max(mu_start, -64.0);
    mu_end = min(max(mu_end, entry + 1.0), entry + 64.0);
    bool gone = e < 0.0 && c <= 0.0;  // from above the relief, heading away
    PX_HIGHP float march_cos = c;
#ifdef PX_SHAPE_TUBE
    PX_HIGHP vec2 span = px_tube_span(p, px_shape_step);
    PX_HIGHP float mu_last = span.y;  // the march goes no farther
    bool back = !gl_FrontFacing;
    bool round_rim = false;  // the march starts where the ray comes onto the tube's length
    if (back) {
        // A rim cap (drawn by its back faces: renderer.cpp draw_object): the
        // ray comes onto the tube's length here, and is marched from here to
        // where it leaves the relief's outer circle (the larger root) or the
        // tube's other end. (Outside that circle here, it may yet come into
        // the relief past the tube's polygon, which lies out by its shell.)
        // Under the sheet (in the hollow) it meets the sheet's back: the
        // first sample decides, below.
        // (The divisors are kept from 0 in fp16 too, without fragment highp.)
        PX_HIGHP float r_top = u_shape.x + (1.0 - u_polygon_height) / max(u_shape.z, 1e-4);
        PX_HIGHP vec2 across = px_shape_step.xy;
        PX_HIGHP float a2 = dot(across, across);
        PX_HIGHP float b = dot(p.xy, across);
        PX_HIGHP float disc_top = b * b - a2 * (dot(p.xy, p.xy) - r_top * r_top);
        // Along the axis (no step across it) the ray keeps its radius: in the
        // relief, if at all, to the tube's other end.
        bool along = a2 <= 1e-6 * dot(px_shape_step, px_shape_step);
        PX_HIGHP float out_of_relief = along ? span.y : (-b + sqrt(max(disc_top, 0.0))) / a2;
        mu_start = 0.0;
        mu_end = min(out_of_relief, span.y);
        mu_last = mu_end;
        gone = (disc_top < 0.0 && !along) || mu_end <= 0.0;
        march_cos = abs(c);
        round_rim = true;
    } else if (mu_start < span.x) {
        mu_start = span.x;
        mu_end = max(mu_end, span.x + 1.0);
        round_rim = true;
    }
    gone = gone || mu_start > mu_last;
#endif
#else
    // No farther than the flat searches reach (V.z clamped at 1/64).
    mu_start = clamp(mu_start, -64.0, 64.0);
    mu_end = min(mu_end, 64.0);
#endif
    // Steps no longer than the flat search's (a relief depth over its count,
    // mu 1 / (V.z count)): the bent ray's range is up to 4 times longer
    // (into the relief and out again), within the loop's bound.
#ifndef PX_SHAPE
    PX_HIGHP float march_cos = c;
#endif
    PX_HIGHP float flat_range = 1.0 / max(march_cos, 1.0 / 64.0);
    mediump float count = min(floor(px_sample_count(march_cos) * max((mu_end - mu_start) / flat_range, 1.0) + 0.5),
                              float(PX_MAX_SAMPLES));
#ifdef PX_SHAPE
    // A quarter of the loop is kept for a ray still in the relief past the
    // model's range (a torus's section is no circle: its model ended short
    // of the real exit, and the flat torus's outline was drawn 58 % too
    // wide): there the steps grow by 1.4 each, out to 16 ranges.
    count = min(count, floor(0.75 * float(PX_MAX_SAMPLES)));
#endif
    PX_HIGHP float step = (mu_end - mu_start) / count;
    PxMarch m;
    m.step = step;
#ifdef PX_SHAPE
    if (gone) {
#else
    if (e < 0.0 && !(top_disc >= 0.0 && c + root_top > 0.0)) {
#endif
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
    m.uv_above = px_curved_uv(uv0, d, mu_start);
    m.height_above = px_trace_height(m.uv_above);
    m.ray_above = px_curved_height(mu_start, m.height_above);
    PX_WORK(0.0, 1.0);
    m.mu_below = m.mu_above;
    m.uv_below = m.uv_above;
    m.ray_below = m.ray_above;
    m.height_below = m.height_above;
    if (m.height_above >= m.ray_above) {  // hit where the search starts
#ifdef PX_SHAPE_TUBE
        // Come round a rim into the hollow (under the sheet there): it
        // meets the sheet's back.
        px_ray_left = round_rim;
#endif
        return m;
    }
#ifdef PX_SHAPE
    PX_HIGHP float mu = mu_start;
    PX_HIGHP float shape_step = step;
    // The last sample's height kept in highp: the struct's mediump copy may
    // be fp16 (Mesa lowers it), which rounded a grazing ray's 1.00004 to 1
    // and drew the ray as if it had stayed in the relief.
    PX_HIGHP float last_ray = m.ray_above;
    bool met = false;
#endif
    for (int i = 1; i <= PX_MAX_SAMPLES; i++) {
#ifdef PX_SHAPE
        mu += shape_step;
        if (float(i) >= count) shape_step *= 1.4;
#ifdef PX_SHAPE_TUBE
        bool at_end = mu >= mu_last;  // the tube's end (or, from a back face, the fragment)
        mu = min(mu, mu_last);
#endif
        PX_HIGHP vec3 point = px_shape_point(mu);
        PX_HIGHP vec2 uv = px_shape_uv(point);
        mediump float h = px_trace_height(uv);
        PX_HIGHP float ray = px_shape_height(point);
#else
        PX_HIGHP float mu = mu_start + float(i) * step;
        PX_HIGHP vec2 uv = px_curved_uv(uv0, d, mu);
        mediump float h = px_trace_height(uv);
        PX_HIGHP float ray = px_curved_height(mu, h);
#endif
        PX_WORK(1.0, 1.0);
        m.mu_below = mu;
        m.uv_below = uv;
        m.ray_below = ray;
        m.height_below = h;
#ifdef PX_SHAPE
        last_ray = ray;
        met = h >= ray;
        // Past the model's range only while the ray is still in the relief.
#ifdef PX_SHAPE_TUBE
        if (met || at_end || (float(i) >= count && (ray > 1.0 || back))) break;
#else
        if (met || (float(i) >= count && ray > 1.0)) break;
#endif
#else
        if (h >= ray || float(i) >= count) break;
#endif
        m.mu_above = mu;
        m.uv_above = uv;
        m.ray_above = ray;
        m.height_above = h;
    }
    // Through the relief and out of its top without meeting it.
#ifdef PX_SHAPE_TUBE
    // Past the tube's end, or back at a back face, no relief is left to meet.
    px_ray_left = !met && (last_ray > 1.0 || back || mu >= mu_last);
#elif defined(PX_SHAPE)
    px_ray_left = !met && last_ray > 1.0;
#else
    px_ray_left = leaves && m.height_below < m.ray_below;
#endif
    return m;
}
#endif
