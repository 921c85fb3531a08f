#include "parallaxes/reference/tracer.h"

#include "parallaxes/core/numeric.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace px::reference {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Beyond this many texels from the origin a double cannot resolve a cell's
// local coordinates to better than ~1e-4, so the walk refuses to start.
constexpr double kMaxCoordinate = 1e12;

int wrap_index(long long i, int n) {
    const long long r = i % n;
    return static_cast<int>(r < 0 ? r + n : r);
}

// One cell of the walk: the ray is inside it for t in [t0, t1]. Local
// coordinates a = x - (i + 0.5), b = y - (j + 0.5) are a0, b0 at t0 and
// advance by direction.x, direction.y per unit t (cells are one texel wide).
struct Cell {
    double t0 = 0.0, t1 = 0.0;
    double a0 = 0.0, b0 = 0.0;
    double z0 = 0.0, z1 = 0.0;  // ray height at t0 and t1
    double h00 = 0.0, h10 = 0.0, h01 = 0.0, h11 = 0.0;

    double max_corner() const { return std::max(std::max(h00, h10), std::max(h01, h11)); }
    double surface(double a, double b) const {
        a = std::clamp(a, 0.0, 1.0);
        b = std::clamp(b, 0.0, 1.0);
        return h00 * (1 - a) * (1 - b) + h10 * a * (1 - b) + h01 * (1 - a) * b + h11 * a * b;
    }
};

// f(s) = z - S along the ray, s = t - t0: with a = a0 + s dx, b = b0 + s dy
// the bilinear patch is quadratic in s (the ab term), z is linear.
struct Quadratic {
    double q0, q1, q2;  // f(s) = q0 + q1 s + q2 s^2
};

Quadratic cell_quadratic(const Cell& c, const glm::dvec3& d) {
    const double A = c.h10 - c.h00;
    const double B = c.h01 - c.h00;
    const double C = c.h00 - c.h10 - c.h01 + c.h11;
    Quadratic q;
    q.q0 = c.z0 - c.surface(c.a0, c.b0);
    q.q1 = d.z - (A * d.x + B * d.y + C * (c.a0 * d.y + c.b0 * d.x));
    q.q2 = -C * d.x * d.y;
    return q;
}

// Amanatides & Woo (1987): visits, in order, every cell the ray's xy
// projection crosses for t in [t_min, t_max]; cell boundaries are at
// x - 0.5 and y - 0.5 integer (texel centres). `visit` returns true to stop.
// Boundary times are computed from the origin each step, not accumulated,
// so long walks do not drift. Returns the number of cells visited.
template <typename Visit>
long walk_cells(const HeightField& field, const Ray& ray, double t_min, double t_max, Visit&& visit) {
    const glm::dvec3& d = ray.direction;
    const double ox = ray.origin.x - 0.5;
    const double oy = ray.origin.y - 0.5;
    const double x_start = ox + t_min * d.x;
    const double y_start = oy + t_min * d.y;
    if (!(std::abs(x_start) < kMaxCoordinate && std::abs(y_start) < kMaxCoordinate)) return 0;
    long long i = static_cast<long long>(std::floor(x_start));
    long long j = static_cast<long long>(std::floor(y_start));
    const int w = field.width;
    const int h = field.height;
    int iw = wrap_index(i, w);
    int jw = wrap_index(j, h);
    const int step_x = d.x > 0 ? 1 : (d.x < 0 ? -1 : 0);
    const int step_y = d.y > 0 ? 1 : (d.y < 0 ? -1 : 0);
    // Time at which the ray leaves the current cell through its x (y) side.
    // (A reciprocal: off by an ulp or so, which only moves a boundary by as
    // much; local coordinates are recomputed from the origin and clamped.)
    const double inv_x = step_x != 0 ? 1.0 / d.x : 0.0;
    const double inv_y = step_y != 0 ? 1.0 / d.y : 0.0;
    const auto next_x = [&] {
        return step_x > 0 ? (static_cast<double>(i + 1) - ox) * inv_x
                          : (step_x < 0 ? (static_cast<double>(i) - ox) * inv_x : kInf);
    };
    const auto next_y = [&] {
        return step_y > 0 ? (static_cast<double>(j + 1) - oy) * inv_y
                          : (step_y < 0 ? (static_cast<double>(j) - oy) * inv_y : kInf);
    };
    double tx = next_x();
    double ty = next_y();
    const float* texels = field.texels.data();
    long visited = 0;
    Cell c;
    c.t0 = t_min;
    for (;;) {
        // Rounding can put a boundary a hair before t0: the cell is then
        // visited over a zero-length interval, which is harmless.
        c.t1 = std::max(c.t0, std::min(std::min(tx, ty), t_max));
        const int iw1 = iw + 1 == w ? 0 : iw + 1;
        const int jw1 = jw + 1 == h ? 0 : jw + 1;
        const size_t row0 = static_cast<size_t>(jw) * w;
        const size_t row1 = static_cast<size_t>(jw1) * w;
        c.h00 = texels[row0 + iw];
        c.h10 = texels[row0 + iw1];
        c.h01 = texels[row1 + iw];
        c.h11 = texels[row1 + iw1];
        c.a0 = std::clamp(ox + c.t0 * d.x - static_cast<double>(i), 0.0, 1.0);
        c.b0 = std::clamp(oy + c.t0 * d.y - static_cast<double>(j), 0.0, 1.0);
        c.z0 = ray.origin.z + c.t0 * d.z;
        c.z1 = ray.origin.z + c.t1 * d.z;
        ++visited;
        if (visit(c)) break;
        if (c.t1 >= t_max) break;
        if (tx <= ty) {
            i += step_x;
            iw = step_x > 0 ? (iw + 1 == w ? 0 : iw + 1) : (iw == 0 ? w - 1 : iw - 1);
            tx = next_x();
        } else {
            j += step_y;
            jw = step_y > 0 ? (jw + 1 == h ? 0 : jw + 1) : (jw == 0 ? h - 1 : jw - 1);
            ty = next_y();
        }
        c.t0 = c.t1;
    }
    return visited;
}

bool usable(const HeightField& field, const Ray& ray, double t_min, double t_max) {
    if (field.width <= 0 || field.height <= 0 ||
        field.texels.size() < static_cast<size_t>(field.width) * field.height)
        return false;
    const bool finite = std::isfinite(ray.origin.x) && std::isfinite(ray.origin.y) && std::isfinite(ray.origin.z) &&
                        std::isfinite(ray.direction.x) && std::isfinite(ray.direction.y) &&
                        std::isfinite(ray.direction.z) && std::isfinite(t_min);
    return finite && !std::isnan(t_max) && t_min <= t_max;
}

// An unbounded t_max is clipped to where the ray leaves the field's height
// range on the side it is heading to (nothing beyond can be hit). A level
// ray inside the range gets a walk of 64 tiles' diagonal: an arbitrary bound,
// as an exact answer may need an unbounded walk.
double finite_t_max(const HeightField& field, const Ray& ray, double t_min) {
    const auto [lo, hi] = std::minmax_element(field.texels.begin(), field.texels.end());
    const double dz = ray.direction.z;
    if (dz < 0) return std::max(t_min, (static_cast<double>(*lo) - ray.origin.z) / dz);
    if (dz > 0) return std::max(t_min, (static_cast<double>(*hi) - ray.origin.z) / dz);
    const double speed = std::hypot(ray.direction.x, ray.direction.y);
    if (speed == 0.0) return t_min;  // a point: only t_min matters
    return t_min + 64.0 * std::hypot(field.width, field.height) / speed;
}

}  // namespace

Hit first_hit(const HeightField& field, const Ray& ray, double t_min, double t_max) {
    Hit result;
    if (!usable(field, ray, t_min, t_max)) return result;
    if (std::isinf(t_max)) t_max = finite_t_max(field, ray, t_min);
    const glm::dvec3 d = ray.direction;
    result.cells_visited = walk_cells(field, ray, t_min, t_max, [&](const Cell& c) {
        // The patch is a convex combination of its corners: a ray above the
        // highest corner over the whole interval cannot touch it.
        if (std::min(c.z0, c.z1) > c.max_corner()) return false;
        const Quadratic q = cell_quadratic(c, d);
        if (q.q0 <= 0.0) {  // on or under the surface where it enters
            result.hit = true;
            result.t = c.t0;
            return true;
        }
        // f(0) > 0: the first root in [0, L] is where the ray reaches the
        // surface. Stable quadratic formula (no cancellation between -q1 and
        // sqrt(D)); q2 = 0 exactly (flat, ruled or axis-aligned rays) is linear.
        const double L = c.t1 - c.t0;
        double s = kInf;
        if (q.q2 == 0.0) {
            if (q.q1 < 0.0) s = -q.q0 / q.q1;
        } else {
            const double D = q.q1 * q.q1 - 4.0 * q.q2 * q.q0;
            if (D >= 0.0) {
                const double k = -0.5 * (q.q1 + std::copysign(std::sqrt(D), q.q1));
                if (k != 0.0) {
                    for (const double r : {k / q.q2, q.q0 / k})
                        if (r >= 0.0 && r < s) s = r;
                }
            }
        }
        if (s <= L) {
            result.hit = true;
            result.t = std::min(c.t0 + s, c.t1);
            return true;
        }
        // A root pushed just past the interval by rounding: f(L) decides.
        if (c.z1 - c.surface(c.a0 + L * d.x, c.b0 + L * d.y) <= 0.0) {
            result.hit = true;
            result.t = c.t1;
            return true;
        }
        return false;
    });
    if (result.hit) result.position = ray.origin + result.t * ray.direction;
    return result;
}

bool occluded(const HeightField& field, const Ray& ray, double t_min, double t_max, double epsilon) {
    if (!usable(field, ray, t_min, t_max) || !(t_max > t_min)) return false;  // (t_min, t_max] empty
    if (std::isinf(t_max)) t_max = finite_t_max(field, ray, t_min);
    const glm::dvec3 d = ray.direction;
    bool blocked = false;
    walk_cells(field, ray, t_min, t_max, [&](const Cell& c) {
        // g = z - S + epsilon; blocked where g < 0. Since g is continuous and
        // t_max > t_min, g < 0 at t_min implies g < 0 just after it, so the
        // closed interval's minimum decides for the half-open range too.
        if (std::min(c.z0, c.z1) + epsilon >= c.max_corner()) return false;
        const Quadratic q = cell_quadratic(c, d);
        const double L = c.t1 - c.t0;
        double g_min = std::min(q.q0, c.z1 - c.surface(c.a0 + L * d.x, c.b0 + L * d.y));
        if (q.q2 > 0.0) {  // convex: the vertex may be the minimum
            const double s = -q.q1 / (2.0 * q.q2);
            if (s > 0.0 && s < L) g_min = std::min(g_min, q.q0 - q.q1 * q.q1 / (4.0 * q.q2));
        }
        blocked = g_min + epsilon < 0.0;
        return blocked;
    });
    return blocked;
}

Ray view_ray(const HeightField& field, glm::dvec2 uv, glm::dvec3 view_ts, double height_scale,
             double polygon_height) {
    // Exact geometry, unlike the shader's clamp of V.z to 1/64; the guard only
    // keeps the division finite (trace_view refuses such rays).
    const double vz = std::max(view_ts.z, 1e-9);
    const glm::dvec2 parallax = height_scale * glm::dvec2(view_ts.x, view_ts.y) / vz;
    const glm::dvec2 size(field.width, field.height);
    // uv at height H is uv + (H - polygon_height) * parallax; enter at H = 1
    // (nothing above the relief top can be hit, even if the polygon is higher).
    const glm::dvec2 entry = (uv + (1.0 - polygon_height) * parallax) * size;
    Ray r;
    r.origin = glm::dvec3(entry, 1.0);
    r.direction = glm::dvec3(-parallax * size, -1.0);  // t in [0, 1]: height 1 down to 0
    return r;
}

ReliefHit trace_view(const HeightField& field, glm::dvec2 uv, glm::dvec3 view_ts, double height_scale,
                     double polygon_height) {
    ReliefHit out;
    if (!(view_ts.z > 1e-9) || field.width <= 0 || field.height <= 0) {
        // No view ray reaches the relief: report the top at uv.
        out.uv = uv;
        out.height = 1.0;
        return out;
    }
    const Ray r = view_ray(field, uv, view_ts, height_scale, polygon_height);
    const Hit h = first_hit(field, r, 0.0, 1.0);
    // Heights are >= 0, so t = 1 (height 0) is always a hit; a field with
    // negative values falls back to the bottom of the relief.
    const glm::dvec3 p = h.hit ? h.position : r.origin + r.direction;
    out.uv = glm::dvec2(p.x / field.width, p.y / field.height);
    out.height = p.z;
    return out;
}

double fp32_input_floor(const HeightField& field, glm::dvec2 uv, glm::dvec3 view_ts, double height_scale,
                        double polygon_height) {
    const ReliefHit at = trace_view(field, uv, view_ts, height_scale, polygon_height);
    auto ulp = [](double x) {
        const float f = std::fabs(static_cast<float>(x));
        return static_cast<double>(std::nextafter(f, std::numeric_limits<float>::infinity()) - f);
    };
    const double view_step = std::ldexp(glm::length(view_ts), -24);
    const glm::dvec2 size(field.width, field.height);
    double floor = 0.0;
    for (int axis = 0; axis < 2; ++axis)
        for (double sign : {-1.0, 1.0}) {
            glm::dvec2 moved_uv = uv;
            moved_uv[axis] += sign * ulp(uv[axis]);
            glm::dvec3 turned = view_ts;
            turned[axis] += sign * view_step;
            for (const ReliefHit& h : {trace_view(field, moved_uv, view_ts, height_scale, polygon_height),
                                       trace_view(field, uv, turned, height_scale, polygon_height)})
                floor = std::max(floor, glm::length((h.uv - at.uv) * size));
        }
    return floor;
}

double hard_visibility(const HeightField& field, glm::dvec2 uv, double height, glm::dvec3 light_ts,
                       double height_scale) {
    if (!(light_ts.z > 0.0)) return 0.0;  // below the geometric horizon
    if (height >= 1.0) return 1.0;        // at the top: nothing above can block
    const glm::dvec2 size(field.width, field.height);
    // Per unit of normalised height the light ray shifts height_scale *
    // L.xy / L.z in uv (shadows.glsl), so t runs in height up to the top.
    Ray r;
    r.origin = glm::dvec3(uv * size, height);
    r.direction = glm::dvec3(height_scale * glm::dvec2(light_ts.x, light_ts.y) / light_ts.z * size, 1.0);
    const double t_max = 1.0 - height;
    return occluded(field, r, 1e-7 * t_max, t_max, 1e-9) ? 0.0 : 1.0;
}

double soft_visibility(const HeightField& field, glm::dvec2 uv, double height, glm::dvec3 light_ts,
                       double height_scale, double angular_radius, int samples) {
    if (!(angular_radius > 0.0) || samples <= 1) return hard_visibility(field, uv, height, light_ts, height_scale);
    const double len = glm::length(light_ts);
    if (!(len > 0.0)) return 0.0;
    const glm::dvec3 L = light_ts / len;
    // Orthonormal frame around the disc centre.
    const glm::dvec3 helper = std::abs(L.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
    const glm::dvec3 t1 = glm::normalize(glm::cross(L, helper));
    const glm::dvec3 t2 = glm::cross(L, t1);
    // Vogel spiral, uniform in solid angle over the cone: cos(theta) uniform
    // in [cos r, 1] (1 - cos r = 2 sin^2(r/2) without cancellation), the
    // azimuth advancing by the golden angle. Deterministic and stratified.
    const double one_minus_cos_r = 2.0 * std::sin(0.5 * angular_radius) * std::sin(0.5 * angular_radius);
    const double golden_angle = kPi<double> * (3.0 - std::sqrt(5.0));
    double lit = 0.0;
    for (int k = 0; k < samples; ++k) {
        const double one_minus_cos = (k + 0.5) / samples * one_minus_cos_r;
        const double cos_theta = 1.0 - one_minus_cos;
        const double sin_theta = std::sqrt(std::max(0.0, one_minus_cos * (2.0 - one_minus_cos)));
        const double phi = golden_angle * k;
        const glm::dvec3 dir = cos_theta * L + sin_theta * (std::cos(phi) * t1 + std::sin(phi) * t2);
        lit += hard_visibility(field, uv, height, dir, height_scale);  // z <= 0: blocked
    }
    return lit / samples;
}

}  // namespace px::reference
