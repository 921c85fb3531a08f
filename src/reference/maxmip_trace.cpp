#include "reference/maxmip_trace.h"

#include "core/numeric.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace px::reference {

namespace {

// Double to float, rounded for certain: through a volatile, because GCC 12.2
// at -O2 folds a double -> float -> double round trip of a vectorised pair
// away (wrong code), and the mirror must trace exactly the shader's floats.
float to_float(double x) {
    volatile float f = static_cast<float>(x);
    return f;
}
glm::vec2 to_float(glm::dvec2 v) { return {to_float(v.x), to_float(v.y)}; }

// "Never" for a node exit along an axis the ray does not move on.
constexpr float kNever = 1e30f;

int log2_pow2(int n) {
    int l = 0;
    while ((1 << l) < n) ++l;
    return l;
}

float corner_height(const HeightField& field, int x, int y) {
    // The 8-bit texel the GPU samples as exactly byte / 255 (the shader's
    // px_exact_8bit undoes a mediump sampler's fp16 rounding).
    return static_cast<float>(to_unorm8(field.texels[static_cast<size_t>(y) * field.width + x])) / 255.0f;
}

// The ray in the traversal's frame, as maxmip.frag sets it up. Cell space is
// texel space minus 0.5, so cell (i, j) is [i, i+1] x [j, j+1]. Cell indices
// are integers counted from a tile origin (a multiple of the field size, so
// nodes of every level stay aligned and fetches wrap with a mask); positions
// are floats relative to the `anchor` cell where the ray enters, so their
// rounding grows with the distance travelled, not with the uv.
// t = height descended: z = z0 - t, position = origin + t * dir.
struct Frame {
    glm::ivec2 anchor;  // the entry cell
    glm::vec2 origin;   // entry point relative to the anchor cell: [0, 1)^2
    glm::vec2 dir;      // cells per unit of t
    float z0;           // entry height (1: the relief's top)
};

struct Walk {
    float t = 0.0f;
    int iterations = 0;
    bool exhausted = false;
};

// First s in [0, 1] where the ray segment from (p0, z0) to (p1, z1) inside one
// cell (local coordinates) is on or under the bilinear patch with corners
// h00..h11. f(s) = ray - surface = f0 + f1 s + f2 s^2 is quadratic because
// the patch's twist term k x y is; roots via the cancellation-free forms.
bool solve_patch(glm::vec2 p0, glm::vec2 p1, float z0, float z1, float h00, float h10, float h01, float h11,
                 float& s) {
    const float a = h10 - h00;
    const float b = h01 - h00;
    const float k = h00 - h10 - h01 + h11;
    const glm::vec2 d = p1 - p0;
    const float f0 = z0 - (h00 + a * p0.x + b * p0.y + k * p0.x * p0.y);
    if (f0 <= 0.0f) {  // entered on or under the surface
        s = 0.0f;
        return true;
    }
    const float f1 = (z1 - z0) - (a * d.x + b * d.y + k * (p0.x * d.y + p0.y * d.x));
    const float f2 = -k * d.x * d.y;
    const float disc = f1 * f1 - 4.0f * f2 * f0;
    s = 2.0f;
    if (disc >= 0.0f) {
        const float root = std::sqrt(disc);
        if (f1 < 0.0f) {
            s = 2.0f * f0 / (root - f1);  // the smaller positive root (any f2)
        } else if (f2 < 0.0f) {
            s = (f1 + root) / (-2.0f * f2);  // the only positive root
        }
    }
    // A sign change over the span guarantees a root: rounding must not lose it.
    const float f_end = z1 - (h00 + a * p1.x + b * p1.y + k * p1.x * p1.y);
    if (f_end <= 0.0f) s = std::min(s, 1.0f);
    return s <= 1.0f;
}

// Cells only move forward along the ray: a rounded position must never send
// the walk back into a cell it has left (it could then revisit it forever).
int forward_index(float position, int anchor, int current, float direction) {
    const int i = anchor + static_cast<int>(std::floor(position));
    if (direction > 0.0f) return std::max(i, current);
    if (direction < 0.0f) return std::min(i, current);
    return current;
}

// The cell holding the ray's point p (relative to the anchor), moving only
// forward from `cell` and staying inside the node [lo, hi).
glm::ivec2 cell_at(glm::vec2 p, const Frame& ray, glm::ivec2 cell, glm::ivec2 lo, glm::ivec2 hi) {
    const glm::ivec2 c(forward_index(p.x, ray.anchor.x, cell.x, ray.dir.x),
                       forward_index(p.y, ray.anchor.y, cell.y, ray.dir.y));
    return glm::clamp(c, lo, hi - 1);
}

// The quadtree descent, step for step as in maxmip.frag.
Walk walk(const MaxMipmap& pyramid, const HeightField& field, const Frame& ray, int budget) {
    const glm::ivec2 size(pyramid.width, pyramid.height);
    const glm::ivec2 mask = size - 1;
    const glm::ivec2 size_log2(log2_pow2(size.x), log2_pow2(size.y));
    const int top = pyramid.level_count() - 1;
    const glm::vec2 o = ray.origin;
    const glm::vec2 d = ray.dir;
    const float t_end = ray.z0;  // the relief's bottom (z = 0): every ray hits by then
    // A node's max, `level` and `node` as integers from the tile origin.
    const auto node_max = [&](int level, glm::ivec2 node, glm::ivec2 shift) {
        return pyramid.max_height(level, node.x & (mask.x >> shift.x), node.y & (mask.y >> shift.y));
    };

    Walk w;
    int level = top;  // Tevs et al.: start at the root, the whole tile
    glm::ivec2 cell = ray.anchor;
    float t = 0.0f;
    for (int i = 0; i < budget; ++i) {
        w.iterations = i + 1;
        // The node of `level` holding `cell`: 2^shift cells per side (a side
        // stops growing at the field size, as the mip chain's does).
        const glm::ivec2 shift = glm::min(glm::ivec2(level), size_log2);
        const glm::ivec2 node(cell.x >> shift.x, cell.y >> shift.y);
        // node * 2^shift: cells may have negative indices (the ray wraps
        // across tiles), and a left shift of a negative int is undefined.
        const glm::ivec2 lo(node.x * (1 << shift.x), node.y * (1 << shift.y));
        const glm::ivec2 hi((node.x + 1) * (1 << shift.x), (node.y + 1) * (1 << shift.y));
        // Where the ray leaves the node's xy square (bounds relative to the anchor).
        const glm::vec2 lo_rel(lo - ray.anchor);
        const glm::vec2 hi_rel(hi - ray.anchor);
        const float tx = d.x > 0.0f ? (hi_rel.x - o.x) / d.x : d.x < 0.0f ? (lo_rel.x - o.x) / d.x : kNever;
        const float ty = d.y > 0.0f ? (hi_rel.y - o.y) / d.y : d.y < 0.0f ? (lo_rel.y - o.y) / d.y : kNever;
        const float t_out = std::min(tx, ty);
        if (level == 0) {
            // One cell: the ray against the bilinear patch itself, exactly
            // (Drobot 2010 ends with a search instead; solving cannot miss a
            // feature thinner than a search step).
            const float t_stop = std::min(t_out, t_end);
            const glm::vec2 p0 = glm::clamp(o + t * d - lo_rel, 0.0f, 1.0f);
            const glm::vec2 p1 = glm::clamp(o + t_stop * d - lo_rel, 0.0f, 1.0f);
            const int x0 = cell.x & mask.x;
            const int y0 = cell.y & mask.y;
            const int x1 = (cell.x + 1) & mask.x;
            const int y1 = (cell.y + 1) & mask.y;
            float s = 0.0f;
            if (solve_patch(p0, p1, ray.z0 - t, ray.z0 - t_stop, corner_height(field, x0, y0),
                            corner_height(field, x1, y0), corner_height(field, x0, y1), corner_height(field, x1, y1),
                            s)) {
                w.t = t + s * (t_stop - t);
                return w;
            }
            if (t_out >= t_end) {  // reached the bottom (only by rounding: S >= 0 there)
                w.t = t_end;
                return w;
            }
        } else {
            const float t_plane = ray.z0 - node_max(level, node, shift);  // where the ray comes down to the node's max
            if (t >= t_plane) {  // at or under the max here: look closer, without moving
                --level;
                continue;
            }
            if (t_plane < t_out) {  // comes down to the max inside the node: go there, look closer
                t = t_plane;
                cell = cell_at(o + t * d, ray, cell, lo, hi);
                --level;
                continue;
            }
        }
        // Above the node's max all the way across: on to the neighbour node
        // through the exit side(s); both at a corner.
        t = std::max(t, t_out);
        glm::ivec2 next = cell_at(o + t * d, ray, cell, lo, hi);
        if (tx <= ty) next.x = d.x > 0.0f ? hi.x : lo.x - 1;
        if (ty <= tx) next.y = d.y > 0.0f ? hi.y : lo.y - 1;
        // Tevs et al. 2008: after crossing into another parent, go up to it,
        // so empty space is skipped in ever larger steps. Only when the ray
        // is above the new parent's max here (one more fetch): going up
        // otherwise would just come down again next iteration, which beside
        // tall features costs ~1.5x the iterations.
        if (level < top) {
            const glm::ivec2 up = glm::min(glm::ivec2(level + 1), size_log2);
            const glm::ivec2 parent(next.x >> up.x, next.y >> up.y);
            if (((cell.x >> up.x) != parent.x || (cell.y >> up.y) != parent.y) &&
                t < ray.z0 - node_max(level + 1, parent, up))
                ++level;
        }
        cell = next;
    }
    w.t = t;
    w.exhausted = true;
    return w;
}

// The view ray's frame as maxmip.frag builds it, in float (highp, the
// parallax division included). view_ts.xy carries the height scale there;
// here it is applied first, then rounded to float.
struct ViewSetup {
    glm::vec2 uv0;
    glm::vec2 parallax;
    float polygon_height;
    glm::vec2 tile;  // floor(uv where the ray enters the top)
    Frame frame;
};

ViewSetup view_setup(const MaxMipmap& pyramid, glm::dvec2 uv, glm::dvec3 view_ts, double height_scale,
                     double polygon_height) {
    ViewSetup v;
    v.uv0 = to_float(uv);
    const glm::vec3 view(to_float(view_ts.x * height_scale), to_float(view_ts.y * height_scale), to_float(view_ts.z));
    v.polygon_height = to_float(polygon_height);
    // maxmip.frag's divisor: V.z kept off zero only where the ray would cross
    // more than 2^24 texels over the relief's depth (no grazing clamp).
    const float longest_side = static_cast<float>(std::max(pyramid.width, pyramid.height));
    const float z_min = std::max(glm::length(glm::vec2(view.x, view.y)) * longest_side / 16777216.0f, 1e-30f);
    v.parallax = glm::vec2(view.x, view.y) / std::max(view.z, z_min);
    const glm::vec2 uv_top = v.uv0 + (1.0f - v.polygon_height) * v.parallax;  // the ray enters the top here
    v.tile = glm::floor(uv_top);
    const glm::vec2 size(static_cast<float>(pyramid.width), static_cast<float>(pyramid.height));
    const glm::vec2 local = (uv_top - v.tile) * size - 0.5f;  // exact: fract, power-of-two scale
    const glm::vec2 anchor = glm::floor(local);
    v.frame.anchor = glm::ivec2(anchor);
    v.frame.origin = local - anchor;
    v.frame.dir = -v.parallax * size;
    v.frame.z0 = 1.0f;
    return v;
}

MaxmipHit finish(const Walk& w, const Frame& f, glm::dvec2 tile_origin, glm::dvec2 size) {
    MaxmipHit out;
    out.hit = !w.exhausted;
    out.iterations = w.iterations;
    out.budget_exhausted = w.exhausted;
    out.height = static_cast<double>(f.z0 - w.t);
    const glm::dvec2 xy = tile_origin + glm::dvec2(f.anchor) + glm::dvec2(f.origin) +
                          static_cast<double>(w.t) * glm::dvec2(f.dir) + 0.5;
    out.position = glm::dvec3(xy, out.height);
    out.uv = xy / size;
    return out;
}

// The pyramid must be built from this field (same size), and both non-empty.
bool usable(const MaxMipmap& pyramid, const HeightField& field) {
    return pyramid.level_count() > 0 && field.width == pyramid.width && field.height == pyramid.height &&
           field.texels.size() >= static_cast<size_t>(field.width) * field.height;
}

}  // namespace

MaxmipHit maxmip_first_hit(const MaxMipmap& pyramid, const HeightField& field, const Ray& ray, int budget) {
    if (!(ray.direction.z < 0.0) || !usable(pyramid, field)) return MaxmipHit{};
    // Move a start above the relief down to its top.
    const double t_top = std::max(0.0, (ray.origin.z - 1.0) / -ray.direction.z);
    const glm::dvec3 start = ray.origin + t_top * ray.direction;
    const glm::dvec2 size(pyramid.width, pyramid.height);
    const glm::dvec2 tile_origin = glm::floor(glm::dvec2(start) / size) * size;  // whole tiles, as floor(uv)
    const glm::dvec2 local = glm::dvec2(start) - 0.5 - tile_origin;
    const glm::dvec2 anchor = glm::floor(local);
    Frame f;
    f.anchor = glm::ivec2(anchor);
    f.origin = to_float(local - anchor);
    f.dir = to_float(glm::dvec2(ray.direction) / -ray.direction.z);  // cells per unit of height
    f.z0 = to_float(std::min(start.z, 1.0));
    const Walk w = walk(pyramid, field, f, budget);
    MaxmipHit out = finish(w, f, tile_origin, size);
    out.t = t_top + static_cast<double>(w.t) / -ray.direction.z;
    return out;
}

MaxmipHit maxmip_trace_view(const MaxMipmap& pyramid, const HeightField& field, glm::dvec2 uv, glm::dvec3 view_ts,
                            double height_scale, double polygon_height, int budget) {
    if (!usable(pyramid, field)) return MaxmipHit{};
    const ViewSetup v = view_setup(pyramid, uv, view_ts, height_scale, polygon_height);
    const Walk w = walk(pyramid, field, v.frame, budget);
    const glm::dvec2 size(pyramid.width, pyramid.height);
    MaxmipHit out = finish(w, v.frame, glm::dvec2(v.tile) * size, size);
    out.t = static_cast<double>(w.t);
    // As the shader returns it: on the view ray, from the polygon's uv.
    const float height = 1.0f - w.t;
    out.uv = glm::dvec2(v.uv0 + (height - v.polygon_height) * v.parallax);
    return out;
}

Ray maxmip_view_ray(const MaxMipmap& pyramid, glm::dvec2 uv, glm::dvec3 view_ts, double height_scale,
                    double polygon_height) {
    const ViewSetup v = view_setup(pyramid, uv, view_ts, height_scale, polygon_height);
    const glm::dvec2 size(pyramid.width, pyramid.height);
    Ray r;
    r.origin = glm::dvec3(glm::dvec2(v.tile) * size + glm::dvec2(v.frame.anchor) + glm::dvec2(v.frame.origin) + 0.5,
                          static_cast<double>(v.frame.z0));
    r.direction = glm::dvec3(glm::dvec2(v.frame.dir), -1.0);
    return r;
}

}  // namespace px::reference
