// maxmip: maximum mip-maps / quadtree displacement mapping (Tevs, Ihrke &
// Seidel 2008; Drobot 2010), exact against the bilinearly filtered surface.
// GLSL ES 3.00 and GLSL ES 1.00 (Appendix A: a constant loop bound with an
// early exit, texture2D at texel centres, no lod reads): one walk in float
// arithmetic (cells are whole numbers, exact in highp up to 2^24), the
// pyramid read per version (px_node_max, px_cell_corners below).
//
// The pyramid bounds the FILTERED surface, not the texel samples (cone maps
// and sample-based max maps are not conservative under bilinear filtering:
// Bán, Valasek et al., EGSR 2024): level 0 texel (i, j) is the max of the four
// texels around CELL (i, j), the square between texel centres (i+.5, j+.5)
// and (i+1.5, j+1.5) where one bilinear patch lives; a patch is a convex
// combination of its corners, so that max bounds it exactly. Level k is the
// max over 2x2 of level k-1 (assets/max_mipmap.h builds it).
//
// The walk: start at the root; in the node (level L) holding the current
// point, if the ray is above the node's max, advance to where it comes down
// to that max (then look closer: L-1) or to where it leaves the node (then
// the neighbour node, and one level up when the ray is above the new parent's
// max, as Tevs et al. climb back to skip empty space in growing steps); if it
// is at or under the max, look closer without moving. In one cell (level 0)
// the ray is solved against the bilinear patch in closed form (a quadratic),
// so no feature, however thin, is stepped over.
//
// The GPU tests and the stability catalogue hold this function to the exact
// reference, and its mobile precisions are emulated on this source itself
// (src/emulation), so there is no second, CPU transcription to drift.
// Exactness needs highp: without GL_FRAGMENT_PRECISION_HIGH (PX_HIGHP is
// mediump) the walk still ends, but fp16 cells and positions cost it its
// exactness (docs/stability.md, nohighp; the plan says so).
#ifndef PX_READS_HEIGHT
#error "maxmip needs PX_READS_HEIGHT"
#endif
#if PX_ES < 3 && defined(PX_HEIGHT_11BIT)
#error "maxmip on GLSL ES 1.00 reads 8-bit heights (its atlas packs a cell's corners in RGBA8)"
#endif
#define PX_HAS_TRACE
#define PX_TRACE_STARTS  // a bounded relief's side: the walk starts at px_start_t
#define PX_TRACE_EXACT_RAY  // no grazing clamp (px_trace below)
#include "chunks/surface_common.glsl"

// 8-bit maxima: mediump tells every 8-bit value apart (px_exact_height
// makes each one exactly byte / 255 again).
uniform mediump sampler2D u_max_map;
uniform mediump int u_max_levels;  // pyramid levels: log2(max(width, height)) + 1

#define PX_NEVER 1e30  // node exit along an axis the ray does not move on

// An 8-bit texel as exactly byte / 255 in highp. mediump samplers keep 8-bit
// values apart, but may return them rounded to fp16 (Mesa llvmpipe does: up
// to 2.4e-4 off), and on a grazing ray a height that far off moves the hit
// by texels. Rounding to the nearest 1/255 restores the exact value (the
// same for the pyramid and the corners, so the bound stays conservative).
// An 11-bit height map (PX_HEIGHT_11BIT, EAC R11, GLSL ES 3.00 only) is
// snapped to v / 2047 the same way, its height read at highp; its pyramid
// holds each maximum in two exact 8-bit channels (R * 256 + G), divided by
// the same 2047.0.
#ifdef PX_HEIGHT_11BIT
PX_HIGHP float px_exact_height(PX_HIGHP float texel) {
    return floor(texel * 2047.0 + 0.5) / 2047.0;
}
#else
PX_HIGHP float px_exact_height(PX_HIGHP float texel) {
    return floor(texel * 255.0 + 0.5) / 255.0;
}
#endif

// Whole-number arithmetic in floats that rounding cannot break (exp2 and
// division may be approximations: a quotient of 0.99999 must not floor to 0).
// 2^e for whole e:
#define px_pow2(e) floor(exp2(e) + 0.5)
// floor(a / b) for whole a and b a power of two, from `inv`, about 1 / b:
// it may be a few ulps off (an approximate division), and the floor is still
// exact, since (a + 0.5) / b is at least 0.5 / b away from every whole number
// while |a| is below 2^20 cells (4096 tiles of 256 texels) for the 2.5 ulps
// GLSL ES allows a division. The walk divides nothing in its loop.
#define px_mul_floor(a, inv) floor(((a) + 0.5) * (inv))

#if PX_ES >= 3
// GLSL ES 3.00: the pyramid's levels are mip levels of u_max_map, the
// corners texels of the height map itself, read with texelFetch; indices
// wrap with a mask (sizes are powers of two, so this is GL_REPEAT).
// A height file stored top row first is fetched at the mirrored row, as
// px_trace_height reads it at 1 - v (surface_common.glsl).
#ifdef PX_FLIP_HEIGHT_V
#define px_height_texel(c) texelFetch(PX_HEIGHT_SAMPLER, ivec2((c).x, mask.y - (c).y), 0).PX_HEIGHT_CHANNEL
#else
#define px_height_texel(c) texelFetch(PX_HEIGHT_SAMPLER, (c), 0).PX_HEIGHT_CHANNEL
#endif

// The max of `node` (whole numbers, from the tile origin) at `level` (>= 1),
// whose level is `count` nodes a side (`inv_count`: about 1 / count).
PX_HIGHP float px_node_max(PX_HIGHP float level, PX_HIGHP vec2 node, PX_HIGHP vec2 count, PX_HIGHP vec2 inv_count) {
    highp ivec2 n = ivec2(node) & (ivec2(count) - 1);
    PX_WORK(0.0, 1.0);
#ifdef PX_HEIGHT_11BIT
    mediump vec2 t = texelFetch(u_max_map, n, int(level)).rg;
    return (floor(t.r * 255.0 + 0.5) * 256.0 + floor(t.g * 255.0 + 0.5)) / 2047.0;
#else
    return px_exact_height(texelFetch(u_max_map, n, int(level)).r);
#endif
}

// The heights at the four corners of `cell` (h00, h10, h01, h11); `inv_size`
// (about 1 / the texture's size) serves the GLSL ES 1.00 wrap.
PX_HIGHP vec4 px_cell_corners(PX_HIGHP vec2 cell, PX_HIGHP vec2 inv_size) {
    highp ivec2 mask = ivec2(u_texture_size) - 1;
    highp ivec2 c0 = ivec2(cell) & mask;
    highp ivec2 c1 = (ivec2(cell) + 1) & mask;
    PX_WORK(0.0, 4.0);
    return vec4(px_exact_height(px_height_texel(c0)), px_exact_height(px_height_texel(ivec2(c1.x, c0.y))),
                px_exact_height(px_height_texel(ivec2(c0.x, c1.y))), px_exact_height(px_height_texel(c1)));
}
#else
// GLSL ES 1.00: one RGBA8 texture without mips (an atlas; NPOT is core with
// CLAMP_TO_EDGE and NEAREST), read at texel centres, so the implicit lod of
// texture2D in the walk's non-uniform control flow cannot matter. Its
// layout (assets/max_mipmap.h, max_atlas_origin): cell (i, j)'s four corner
// heights in RGBA at texel (i, j) of a width x height block at the origin;
// level k >= 1 (R: its max) at x = width, y = the sum of the heights of
// levels 1..k-1.
// u_max_atlas: xy = 1 / the atlas size, z = width, w = log2(height).
uniform PX_HIGHP vec4 u_max_atlas;

// The atlas texel at `texel` (whole numbers).
#define px_atlas_texel(texel) texture2D(u_max_map, ((texel) + 0.5) * u_max_atlas.xy)

PX_HIGHP float px_node_max(PX_HIGHP float level, PX_HIGHP vec2 node, PX_HIGHP vec2 count, PX_HIGHP vec2 inv_count) {
    PX_HIGHP vec2 n = node - count * px_mul_floor(node, inv_count);  // wraps, as GL_REPEAT
    PX_WORK(0.0, 1.0);
    // Levels 1..k-1 are u_texture_size.y / 2^j rows each while that is at
    // least one, then one row each: the rows above level k are the texture's
    // height less level k-1's rows (twice k's while k is at most log2 height).
    PX_HIGHP float rows_before = level <= u_max_atlas.w ? 2.0 * count.y : 1.0;
    PX_HIGHP float y = u_texture_size.y - rows_before + max(level - 1.0 - u_max_atlas.w, 0.0);
    return px_exact_height(px_atlas_texel(n + vec2(u_max_atlas.z, y)).r);
}

PX_HIGHP vec4 px_cell_corners(PX_HIGHP vec2 cell, PX_HIGHP vec2 inv_size) {
    PX_HIGHP vec2 c = cell - u_texture_size * px_mul_floor(cell, inv_size);
    PX_HIGHP vec4 h = px_atlas_texel(c);
    PX_WORK(0.0, 1.0);
    return floor(h * 255.0 + 0.5) / 255.0;
}
#endif

// Cells only move forward along the ray: a rounded position must never send
// the walk back into a cell it has left (it could revisit it forever).
PX_HIGHP float px_forward_index(PX_HIGHP float position, PX_HIGHP float anchor, PX_HIGHP float current,
                                PX_HIGHP float direction) {
    PX_HIGHP float i = anchor + floor(position);
    if (direction > 0.0) return max(i, current);
    if (direction < 0.0) return min(i, current);
    return current;
}

// The cell holding the ray's point p (relative to the anchor cell), moving
// only forward from `cell` and staying inside the node [lo, hi).
PX_HIGHP vec2 px_cell_at(PX_HIGHP vec2 p, PX_HIGHP vec2 anchor, PX_HIGHP vec2 cell, PX_HIGHP vec2 dir,
                         PX_HIGHP vec2 lo, PX_HIGHP vec2 hi) {
    PX_HIGHP vec2 c = vec2(px_forward_index(p.x, anchor.x, cell.x, dir.x), px_forward_index(p.y, anchor.y, cell.y, dir.y));
    return clamp(c, lo, hi - 1.0);
}

// First s in [0, 1] where the ray segment from (p0, z0) to (p1, z1) in one
// cell (local coordinates) is on or under the bilinear patch with corners
// h = (h00, h10, h01, h11). Ray minus surface is f0 + f1 s + f2 s^2 (the
// patch's twist term makes it quadratic); roots in cancellation-free form.
bool px_solve_patch(PX_HIGHP vec2 p0, PX_HIGHP vec2 p1, PX_HIGHP float z0, PX_HIGHP float z1, PX_HIGHP vec4 h,
                    out PX_HIGHP float s) {
    PX_HIGHP float a = h.y - h.x;
    PX_HIGHP float b = h.z - h.x;
    PX_HIGHP float k = h.x - h.y - h.z + h.w;
    PX_HIGHP vec2 d = p1 - p0;
    PX_HIGHP float f0 = z0 - (h.x + a * p0.x + b * p0.y + k * p0.x * p0.y);
    s = 0.0;
    if (f0 <= 0.0) return true;  // entered on or under the surface
    PX_HIGHP float f1 = (z1 - z0) - (a * d.x + b * d.y + k * (p0.x * d.y + p0.y * d.x));
    PX_HIGHP float f2 = -k * d.x * d.y;
    PX_HIGHP float disc = f1 * f1 - 4.0 * f2 * f0;
    s = 2.0;
    if (disc >= 0.0) {
        PX_HIGHP float root = sqrt(disc);
        if (f1 < 0.0) {
            s = 2.0 * f0 / (root - f1);  // the smaller positive root (any f2)
        } else if (f2 < 0.0) {
            s = (f1 + root) / (-2.0 * f2);  // the only positive root
        }
    }
    // A sign change over the span guarantees a root: rounding must not lose it.
    PX_HIGHP float f_end = z1 - (h.x + a * p1.x + b * p1.y + k * p1.x * p1.y);
    if (f_end <= 0.0) s = min(s, 1.0);
    return s <= 1.0;
}

PxHit px_trace(PX_HIGHP vec2 uv, PX_VIEW_PRECISION vec3 view_ts PX_TRACE_GRADIENTS) {
    // px_parallax_vector (march.glsl) without its clamp, divided in highp: from mediump
    // operands the division runs at mediump (fp16 on Mesa llvmpipe), whose
    // ~1e-3 relative error moves a grazing ray's hit by texels.
    PX_HIGHP vec3 view = view_ts;
    // No grazing clamp: a ray past 89.1 degrees (V.z < 1/64, march.glsl's
    // clamp) is still the exact ray (clamping it there cost 2 texels of mean
    // error at 89 degrees, docs/accuracy.md). V.z is kept off zero only where
    // the ray would cross more than 2^24 texels over the relief's depth:
    // there t (24-bit mantissa, in [0, 1]) could no longer give every cell
    // boundary its own value, and the offset would run to infinity.
    PX_HIGHP float z_min = max(length(view.xy) * max(u_texture_size.x, u_texture_size.y) / 16777216.0, 1e-30);
    PX_HIGHP vec2 parallax = view.xy / max(view.z, z_min);
    // The frame: cell space (texel space - 0.5: cell (i, j) is [i, i+1]^2),
    // integer cells counted from the tile where the ray enters the top (a
    // whole number of tiles, so every level's nodes stay aligned), float
    // positions relative to the entry cell (`anchor`), so rounding grows with
    // the distance walked, not with the uv. t is the height descended:
    // height = 1 - t, position = o + t * dir.
    PX_HIGHP vec2 uv_top = uv + (1.0 - u_polygon_height) * parallax;
    PX_HIGHP vec2 tile = floor(uv_top);
    PX_HIGHP vec2 local = (uv_top - tile) * u_texture_size - 0.5;
    PX_HIGHP vec2 anchor = floor(local);
    PX_HIGHP vec2 o = local - anchor;
    PX_HIGHP vec2 dir = -parallax * u_texture_size;
    // Node exits as products: three divisions per pixel, none per iteration.
    PX_HIGHP vec2 inv_dir = vec2(dir.x != 0.0 ? 1.0 / dir.x : 0.0, dir.y != 0.0 ? 1.0 / dir.y : 0.0);
    PX_HIGHP vec2 inv_size = 1.0 / u_texture_size;
    PX_HIGHP float top = float(u_max_levels - 1);

    // Levels and cells are whole numbers held in floats (exact in highp).
    // Tevs et al. start at the root, the whole tile. A ray whose whole
    // descent (t from 0 to 1) moves `reach` cells along each axis at most
    // stays within two nodes a side of level ceil(log2(reach + 1)): starting
    // there skips only the descent to it (one iteration a level), never
    // space, since every level's max bounds the same surface.
    PX_HIGHP float reach = max(abs(dir.x), abs(dir.y));
    PX_HIGHP float level = clamp(ceil(log2(reach + 1.0)), 0.0, top);
    // 2^level, exact, and about 2^-level, carried as the level changes
    // (doubling and halving are exact), so the loop needs no exp2 and no
    // division: a node's side is min(scale, size), its reciprocal
    // max(inv_scale, inv_size) (px_mul_floor tolerates its rounding).
    PX_HIGHP float scale = px_pow2(level);
    PX_HIGHP float inv_scale = 1.0 / scale;
    PX_HIGHP vec2 cell = anchor;
    PX_HIGHP float t = 0.0;
#ifdef PX_BOUNDED
    // Through a bounded relief's side: the ray above this point is outside
    // the relief, so the walk starts here (in the cell holding it).
    t = px_start_t;
    cell = anchor + floor(o + t * dir);
#endif
    // Appendix A form: a constant bound (the iteration budget) with an early break.
    for (int i = 0; i < PX_MAX_SAMPLES; i++) {
        PX_WORK(1.0, 0.0);
        // The node of `level` holding `cell`: `side` cells a side (a side
        // stops growing at the texture's size, as the mip chain's does).
        PX_HIGHP vec2 side = min(vec2(scale), u_texture_size);
        PX_HIGHP vec2 inv_side = max(vec2(inv_scale), inv_size);
        PX_HIGHP vec2 node = px_mul_floor(cell, inv_side);
        PX_HIGHP vec2 lo = node * side;
        PX_HIGHP vec2 hi = lo + side;
        // Where the ray leaves the node's square.
        PX_HIGHP vec2 lo_rel = lo - anchor;
        PX_HIGHP vec2 hi_rel = hi - anchor;
        PX_HIGHP float tx = dir.x > 0.0 ? (hi_rel.x - o.x) * inv_dir.x : (dir.x < 0.0 ? (lo_rel.x - o.x) * inv_dir.x : PX_NEVER);
        PX_HIGHP float ty = dir.y > 0.0 ? (hi_rel.y - o.y) * inv_dir.y : (dir.y < 0.0 ? (lo_rel.y - o.y) * inv_dir.y : PX_NEVER);
        PX_HIGHP float t_out = min(tx, ty);
        if (level == 0.0) {
            // One cell: the ray against the bilinear patch, exactly (Drobot
            // 2010 ends with a search; solving cannot miss a thin feature).
            // The relief's bottom (t = 1) ends every ray: heights are >= 0.
            PX_HIGHP float t_stop = min(t_out, 1.0);
            PX_HIGHP vec2 p0 = clamp(o + t * dir - lo_rel, 0.0, 1.0);
            PX_HIGHP vec2 p1 = clamp(o + t_stop * dir - lo_rel, 0.0, 1.0);
            PX_HIGHP float s;
            if (px_solve_patch(p0, p1, 1.0 - t, 1.0 - t_stop, px_cell_corners(cell, inv_size), s)) {
                t = t + s * (t_stop - t);
                break;
            }
            if (t_out >= 1.0) {  // reached the bottom (only by rounding)
                t = 1.0;
                break;
            }
        } else {
            // The level is u_texture_size / side nodes a side (whole numbers).
            PX_HIGHP vec2 count = floor(u_texture_size * inv_side + 0.5);
            PX_HIGHP float t_plane = 1.0 - px_node_max(level, node, count, side * inv_size);  // ray down to the node's max
            if (t >= t_plane) {  // at or under the max here: look closer, without moving
                level -= 1.0;
                scale *= 0.5;
                inv_scale *= 2.0;
                continue;
            }
            if (t_plane < t_out) {  // comes down to the max inside the node: go there, look closer
                t = t_plane;
                cell = px_cell_at(o + t * dir, anchor, cell, dir, lo, hi);
                level -= 1.0;
                scale *= 0.5;
                inv_scale *= 2.0;
                continue;
            }
        }
        // Above the node's max all the way across: into the neighbour node
        // through the exit side (both sides at a corner).
        t = max(t, t_out);
        PX_HIGHP vec2 next = px_cell_at(o + t * dir, anchor, cell, dir, lo, hi);
        if (tx <= ty) next.x = dir.x > 0.0 ? hi.x : lo.x - 1.0;
        if (ty <= tx) next.y = dir.y > 0.0 ? hi.y : lo.y - 1.0;
        // Tevs et al.: into another parent, go up to it, but only when the
        // ray is above its max here (else it would come straight back down).
        if (level < top) {
            PX_HIGHP vec2 up = min(vec2(2.0 * scale), u_texture_size);
            PX_HIGHP vec2 inv_up = max(vec2(0.5 * inv_scale), inv_size);
            PX_HIGHP vec2 parent = px_mul_floor(next, inv_up);
            if (any(notEqual(px_mul_floor(cell, inv_up), parent)) &&
                t < 1.0 - px_node_max(level + 1.0, parent, floor(u_texture_size * inv_up + 0.5), up * inv_size)) {
                level += 1.0;
                scale *= 2.0;
                inv_scale *= 0.5;
            }
        }
        cell = next;
    }
    // On a hit, t is where the ray meets the surface; if the budget ran out,
    // the last point known to be above it. uv on the view ray, from highp t
    // (hit.height is mediump: too coarse to place the uv on grazing rays).
    PX_HIGHP float height = 1.0 - t;
    PxHit hit;
    hit.uv = uv + (height - u_polygon_height) * parallax;
    hit.height = height;
    return hit;
}
#include "chunks/surface_main.glsl"
