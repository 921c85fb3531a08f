// main() shared by every technique. A technique entry defines
//   PxHit px_trace(PX_HIGHP vec2 uv, PX_VIEW_PRECISION vec3 view_ts PX_TRACE_GRADIENTS)
// when it defines PX_HAS_TRACE, and includes this file last.
#include "chunks/lighting.glsl"
#ifdef PX_SHADOW
#include "chunks/shadows.glsl"
#endif
#ifdef PX_DEBUG_OUTPUT
#include "chunks/debug_output.glsl"
#endif

#ifdef PX_DEPTH_WRITE
uniform PX_HIGHP mat4 u_depth_projection;  // the vertex stage's u_projection, kept apart: a uniform in both stages must have one precision (GLSL ES 1.00, 4.5.3)
uniform PX_HIGHP float u_units_per_tile;  // view-space units per texture tile (relief depth conversion)

// Perspective-correct depth (Tatarchuk 2005; McGuire 2005): push the
// fragment along the view ray to the hit, then project it again.
// `distance`: how far along the view ray the hit lies, in view-space units.
void px_write_depth_at(PX_HIGHP float distance) {
    PX_HIGHP vec3 hit_position = v_view_position + normalize(v_view_position) * distance;
    PX_HIGHP vec4 clip = u_depth_projection * vec4(hit_position, 1.0);
    PX_FRAG_DEPTH = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
}

void px_write_depth(mediump float hit_height, mediump float cos_view) {
    PX_HIGHP float depth_below_polygon = (u_polygon_height - hit_height) * u_height_scale * u_units_per_tile;
#if defined(PX_BOUNDED) && !defined(PX_CURVED)
    // A side wall's fragment lies v_wall_height above the polygon (added
    // apart: the polygon's own depth keeps its precision, 0 added; in highp,
    // u_polygon_height - hit_height moved a flush panel's depth against the
    // bricks under it by enough to flip 5 pixels of the default scene).
    depth_below_polygon += v_wall_height * u_height_scale * u_units_per_tile;
#endif
    px_write_depth_at(depth_below_polygon / max(cos_view, 1.0 / 64.0));
}
#endif

#ifdef PX_BOUNDED
// A bounded relief (a tile or a decal, MaterialDesc::bounded): mesh uv =
// u_bounds_matrix * (uv - u_bounds_offset), surface.vert's uv transform
// inverted (its own uniforms are the vertex stage's, highp there).
uniform PX_HIGHP mat2 u_bounds_matrix;
uniform PX_HIGHP vec2 u_bounds_offset;

// Whether texture uv `uv` lies on the tile (mesh uv [0, 1]^2), to within
// PX_TILE_SLACK of the tile: a ray that comes in through the tile's side
// and meets a brick's face there hits exactly on the edge, where the
// rounding of its uv (the wall's interpolated height, a rotated or scaled
// uv transform's products) put every other pixel outside: a speckled band
// of discarded pixels along the near edge, 32 to 191 % of the contour
// (2026-12-05). 2^-14 of the tile: 0.03 texel of a 256-texel map at uv
// scale 2.
#define PX_TILE_SLACK (1.0 / 16384.0)
bool px_on_tile(PX_HIGHP vec2 uv) {
    PX_HIGHP vec2 m = u_bounds_matrix * (uv - u_bounds_offset);
    return all(greaterThanEqual(m, vec2(-PX_TILE_SLACK))) && all(lessThanEqual(m, vec2(1.0 + PX_TILE_SLACK)));
}
#endif

#ifdef PX_LOD
uniform mediump vec2 u_lod_range;  // x: threshold mip level, y: transition band in levels

// Tatarchuk 2005: the mip level the height map is read at, from the screen
// derivatives of its texel coordinates.
mediump float px_mip_level(PX_HIGHP vec2 uv) {
    PX_HIGHP vec2 texel_dx = dFdx(uv) * u_texture_size;
    PX_HIGHP vec2 texel_dy = dFdy(uv) * u_texture_size;
    PX_HIGHP float footprint = max(dot(texel_dx, texel_dx), dot(texel_dy, texel_dy));
    return 0.5 * log2(max(footprint, 1e-8));
}
#endif

// A texture-frame vector (its xy F applied to the tangent frame's, F =
// u_uv_frame times the mesh's uv stretch, surface.vert) for shading: F's
// area taken out, F / sqrt(det F), so that the normal map's axes keep the
// surface's own proportions. A uv sphere's u runs twice as long as its v,
// and a material scaled 2 x 1 on it is square on the surface: F is then a
// rotation, where u_uv_frame alone stretched the shading twice over (until
// 2026-12-05). On planes the stretch is 1 and F = u_uv_frame (det +-1).
PX_HIGHP vec3 px_shading_vector(PX_HIGHP vec3 v) {
#ifdef PX_UV_STRETCH
    return vec3(v.xy * v_frame_scale, v.z);
#else
    return v;
#endif
}

#ifdef PX_SHADE_LOD_BIAS
// GLSL ES 1.00 reads the shading textures with texture2D, whose mip level
// comes from the derivatives of the uv it is given: at the hit, those jump
// wherever the relief occludes itself (a brick's edge, a hemisphere's rim),
// and the pixels there read a blurred mip (4.9 % of a hemispheres view more
// than 8 levels off its GLSL ES 3.00 image, which reads with textureGrad at
// the unshifted uv's gradients). This bias, added to that implicit level,
// makes it the unshifted uv's: both levels as GL computes them, rho the
// larger screen derivative in texels (the traced height's size standing for
// every map's aspect). Texels / 64, so that fp16 squares (no fragment highp)
// neither overflow below about 16,000 texels a pixel nor matter where they
// underflow (magnified: the base level either way).
mediump float px_shade_bias = 0.0;
mediump float px_level_bias(PX_HIGHP vec2 uv, PX_HIGHP vec2 hit_uv) {
    PX_HIGHP vec2 s = u_texture_size * (1.0 / 64.0);
    PX_HIGHP vec2 ax = dFdx(uv) * s;
    PX_HIGHP vec2 ay = dFdy(uv) * s;
    PX_HIGHP vec2 bx = dFdx(hit_uv) * s;
    PX_HIGHP vec2 by = dFdy(hit_uv) * s;
    PX_HIGHP float a = clamp(max(dot(ax, ax), dot(ay, ay)), 1e-6, 65000.0);
    PX_HIGHP float b = clamp(max(dot(bx, bx), dot(by, by)), 1e-6, 65000.0);
    return clamp(0.5 * (log2(a) - log2(b)), -16.0, 16.0);
}
#define PX_SHADE_BIAS , px_shade_bias
#else
#define PX_SHADE_BIAS
#endif

mediump vec3 px_shade(PX_HIGHP vec2 uv, mediump float hit_height, mediump vec3 view_dir PX_TRACE_GRADIENTS) {
    // The two dependent reads issued back to back, before any arithmetic on
    // them (PowerVR whitepaper 3.2.1: one wait instead of two).
#if PX_ES >= 3
    mediump vec4 albedo = textureGrad(u_albedo_map, PX_ALBEDO_UV(uv), PX_ALBEDO_D(uv_dx), PX_ALBEDO_D(uv_dy));
#ifdef PX_NORMAL_MAP
    mediump vec4 normal_texel = textureGrad(u_normal_map, PX_NORMAL_UV(uv), PX_NORMAL_D(uv_dx), PX_NORMAL_D(uv_dy));
#endif
#else
    mediump vec4 albedo = texture2D(u_albedo_map, PX_ALBEDO_UV(uv) PX_SHADE_BIAS);
#ifdef PX_NORMAL_MAP
    mediump vec4 normal_texel = texture2D(u_normal_map, PX_NORMAL_UV(uv) PX_SHADE_BIAS);
#endif
#endif
#ifdef PX_SRGB_DECODE
    albedo.rgb = px_srgb_to_linear(albedo.rgb);
#endif
#if defined(PX_NORMAL_MAP) && defined(PX_NORMAL_RG)
    // Two-channel normal maps (EAC RG11, BC5) hold x and y; z >= 0 follows.
    mediump vec2 normal_xy = normal_texel.xy * 2.0 - 1.0;
    mediump vec3 normal = normalize(vec3(normal_xy, sqrt(max(1.0 - dot(normal_xy, normal_xy), 0.0))));
#elif defined(PX_NORMAL_MAP)
    mediump vec3 normal = normalize(normal_texel.xyz * 2.0 - 1.0);
#else
    mediump vec3 normal = vec3(0.0, 0.0, 1.0);
#endif
#if defined(PX_NORMAL_MAP) && defined(PX_NORMAL_GREEN_DOWN)
    // A DirectX-style normal file (green is -v), uploaded as it is.
    normal.y = -normal.y;
#endif
    mediump vec3 color = u_ambient * albedo.rgb;
    for (int i = 0; i < PX_MAX_LIGHTS; i++) {
        if (i >= u_light_count) break;
        mediump vec3 light_shading = px_shading_vector(v_light_ts[i]);
        mediump vec3 light_dir = normalize(light_shading);
        mediump float visibility = 1.0;
#ifdef PX_SHADOW
        // The shadow ray steps in uv as the view's trace does: F's own xy, over
        // the shading length (its z the cosine, as the view's).
        visibility = px_light_visibility(uv, hit_height, v_light_ts[i] / length(light_shading),
                                         u_light_angular_radius[i] PX_TRACE_GRADIENT_ARGS);
#endif
        color += px_light_term(albedo.rgb, normal, view_dir, light_dir, u_light_color[i], visibility);
    }
    return color;
}

void main() {
    PX_HIGHP vec2 uv = v_uv;
#if PX_ES >= 3
    // Gradients of the unshifted uv, taken once in uniform control flow.
    PX_HIGHP vec2 uv_dx = dFdx(uv);
    PX_HIGHP vec2 uv_dy = dFdy(uv);
#endif
    PX_VIEW_PRECISION vec3 view_ts = v_view_ts;
    // The view direction for shading: the texture frame's xy without the
    // relief's scale and without the area of the frame F (u_uv_frame times
    // the uv stretch): F / sqrt(det F) turns the tangent frame into the
    // texture's axes at the surface's own proportions (px_shading_vector).
    PX_VIEW_PRECISION vec3 view_unscaled = view_ts;
#ifdef PX_READS_HEIGHT
    view_unscaled.xy = view_ts.xy * u_inv_height_scale;
#endif
    view_unscaled = px_shading_vector(view_unscaled);
#ifdef PX_EXACT_VIEW
    // Interpolated unnormalised: normalise here, keeping xy scaled and z the
    // cosine of the view angle, as the per-vertex path delivers it.
    view_ts /= length(view_unscaled);
#endif
    mediump vec3 view_dir = normalize(view_unscaled);

#if defined(PX_BOUNDED) && defined(PX_HAS_TRACE) && !defined(PX_SHAPE)
    // (A bounded tube's shape search clips its exact ray to the tube's
    // length itself: march.glsl, PX_SHAPE_TUBE.)
    // A bounded relief exists over mesh uv [0, 1]^2 only, and its polygon is
    // drawn wider by the relief's reach: the t range over which this
    // fragment's ray (from the relief's top, t = 0, to its bottom, t = 1) is
    // inside the tile, from the mesh uv where it enters the top and its step.
    {
        // The ray the trace follows: the exact one, or the searches' with V.z
        // clamped at 1/64 (march.glsl px_parallax_vector).
#ifdef PX_TRACE_EXACT_RAY
        PX_HIGHP vec2 parallax = view_ts.xy / max(view_ts.z, 1e-6);
#else
        PX_HIGHP vec2 parallax = view_ts.xy / max(view_ts.z, 1.0 / 64.0);
#endif
#ifndef PX_CURVED
        // A side wall's fragment (make_tile_walls: where rays come into the
        // tile through its side, past the wider polygon's reach at grazing
        // views) lies v_wall_height above the polygon: its ray crosses the
        // polygon's plane at this uv.
        uv -= v_wall_height * parallax;
#endif
        PX_HIGHP vec2 top = u_bounds_matrix * (uv + (1.0 - u_polygon_height) * parallax - u_bounds_offset);
        PX_HIGHP vec2 step = -(u_bounds_matrix * parallax);
        PX_HIGHP float t_in = 0.0;
        PX_HIGHP float t_out = 1.0;
        for (int a = 0; a < 2; a++) {
            PX_HIGHP float p = a == 0 ? top.x : top.y;
            PX_HIGHP float d = a == 0 ? step.x : step.y;
            if (abs(d) < 1e-6) {  // moves under a millionth of the tile: constant here
                if (p < 0.0 || p > 1.0) t_in = 2.0;  // never inside along this axis
            } else {
                PX_HIGHP float t0 = -p / d;
                PX_HIGHP float t1 = (1.0 - p) / d;
                t_in = max(t_in, min(t0, t1));
                t_out = min(t_out, max(t0, t1));
            }
        }
        if (t_in > t_out) discard;  // passes by the tile between the relief's top and bottom
#ifdef PX_TRACE_STARTS
        px_start_t = t_in;  // the trace starts where the ray comes into the tile
#else
        // A single fetch (parallax, offset_limited) has no ray to start part
        // way down: a fragment outside the tile is not theirs to draw.
        if (!px_on_tile(uv)) discard;
#endif
    }
#endif
    PxHit surface;  // the polygon itself: what normal mapping shades
    surface.uv = uv;
    surface.height = u_polygon_height;
#ifdef PX_HAS_TRACE
#ifdef PX_LOD
    mediump float mip = px_mip_level(uv);
    // 0 below the band (full effect), 1 past the threshold (normal mapping).
    mediump float lod_blend = clamp((mip - (u_lod_range.x - u_lod_range.y)) / u_lod_range.y, 0.0, 1.0);
    PxHit hit = surface;
#ifdef PX_CURVED
    // A curved silhouette is decided by the trace at every fragment: at the
    // contour the view grazes and the uv's footprint is largest, so LOD
    // skipped the trace exactly there and drew the smooth outline (98 to
    // 211 % of the contour mismatched, against 0 to 1.5 % without LOD).
    // Only the shading fades.
    hit = px_trace(uv, view_ts PX_TRACE_GRADIENT_ARGS);
#else
    if (lod_blend < 1.0) hit = px_trace(uv, view_ts PX_TRACE_GRADIENT_ARGS);
#endif
#else
    PxHit hit = px_trace(uv, view_ts PX_TRACE_GRADIENT_ARGS);
#endif
#else
    PxHit hit = surface;
#endif

#if defined(PX_CURVED) && defined(PX_HAS_TRACE)
    // The ray passed the curved relief without meeting it (march.glsl).
    if (px_ray_left) discard;
#endif
#if defined(PX_BOUNDED) && defined(PX_HAS_TRACE) && !defined(PX_SHAPE)
    // The ray left the relief's bounds before it met the relief: it sees
    // what lies behind (the relief's silhouette, not the polygon's edge).
    // (A bounded tube's shape search samples its ray on the tube's length
    // only, so its hit is there.)
    if (!px_on_tile(hit.uv)) discard;
#endif
#ifdef PX_SHADE_LOD_BIAS
    px_shade_bias = px_level_bias(uv, hit.uv);  // here, in uniform control flow
#endif
    mediump vec3 color = px_shade(hit.uv, hit.height, view_dir PX_TRACE_GRADIENT_ARGS);
#if defined(PX_HAS_TRACE) && defined(PX_LOD)
    if (lod_blend > 0.0) {
#ifdef PX_SHADE_LOD_BIAS
        px_shade_bias = 0.0;  // the polygon's own uv
#endif
        color = mix(color, px_shade(surface.uv, surface.height, view_dir PX_TRACE_GRADIENT_ARGS), lod_blend);
    }
#endif
#ifdef PX_DEPTH_WRITE
#if defined(PX_CURVED) && defined(PX_HAS_TRACE)
    // The curved trace's hit, by its distance along the ray (relief depths).
#ifdef PX_LOD
    px_write_depth_at(mix(px_hit_mu, 0.0, lod_blend) * u_height_scale * u_units_per_tile);
#else
    px_write_depth_at(px_hit_mu * u_height_scale * u_units_per_tile);
#endif
#elif defined(PX_HAS_TRACE) && defined(PX_LOD)
    px_write_depth(mix(hit.height, surface.height, lod_blend), view_ts.z);
#else
    px_write_depth(hit.height, view_ts.z);
#endif
#endif
#ifdef PX_DEBUG_OUTPUT
    PxHit shown = hit;
#if defined(PX_HAS_TRACE) && defined(PX_LOD)
    // In the band the colour blends two shadings; the hit shown moves the
    // same share of the way to the polygon's uv, so it changes as smoothly
    // as the image does (a switch at half-way would pop by the whole offset).
    shown.uv = mix(hit.uv, surface.uv, lod_blend);
    shown.height = mix(hit.height, surface.height, lod_blend);
#endif
    // The first light's visibility: the shadow ray's where there is one,
    // else the polygon's horizon (px_light_term lights nothing past it), so
    // that what is reported is what the shading used.
    mediump float visibility = 1.0;
    if (u_light_count > 0) {
        visibility = normalize(v_light_ts[0]).z > 0.0 ? 1.0 : 0.0;
#ifdef PX_SHADOW
        visibility = px_light_visibility(shown.uv, shown.height, v_light_ts[0] / length(px_shading_vector(v_light_ts[0])),
                                         u_light_angular_radius[0] PX_TRACE_GRADIENT_ARGS);
#endif
    }
#ifdef PX_COUNT_WORK
    // include/parallaxes/profiling/measurement/work.h: the counts in place of the uv, scaled
    // into [0, 1) for the packed passes (exact: a power of two).
    shown.uv = px_work / 65536.0;
#endif
#ifdef PX_CAPTURE_RAY
    // The view ray this fragment was handed (its uv, and the parallax vector
    // as PX_EXACT_VIEW's exact trace computes it: maxmip.frag's px_trace),
    // in place of the hit, in highp throughout (PxHit.height and
    // `visibility` are mediump); -1 in the last channel would read as
    // "nothing drawn" (surface_capture.cpp).
    PX_HIGHP vec2 captured = view_ts.xy / max(view_ts.z, 1e-30);
    if (captured.y == -1.0) captured.y = -1.0000001;
    // Never true (heights and visibilities are >= 0): keeps the trace and
    // its uniforms alive, as the program interface expects.
    if (shown.uv.x + shown.uv.y < -1e30 || shown.height < -1.0 || visibility < -1.0) captured = vec2(0.0);
    PX_FRAG_COLOR = px_debug_output(uv, captured.x, captured.y);
#else
    PX_FRAG_COLOR = px_debug_output(shown.uv, shown.height, visibility);
#endif
#elif defined(PX_SRGB_OUTPUT)
    PX_FRAG_COLOR = vec4(px_linear_to_srgb(color), 1.0);
#else
    PX_FRAG_COLOR = vec4(color, 1.0);
#endif
}
