// Unit tests for src/reference/tracer: the exact CPU reference against closed
// forms (flat, step, tent, sphere cap), against a dense brute-force march, and
// its shadow queries on the pit field.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <optional>
#include <random>
#include <vector>

#include "parallaxes/assets/heightfield.h"
#include "parallaxes/reference/tracer.h"

namespace px::reference {
namespace {

constexpr double kPi = 3.14159265358979323846;

HeightField field_of(const FieldSpec& spec) {
    Result<HeightField> f = make_height_field(spec);
    EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().message);
    return f.ok() ? std::move(f).value() : HeightField{};
}

HeightField field_of(FieldKind kind, int size) {
    FieldSpec s;
    s.kind = kind;
    s.size = size;
    return field_of(s);
}

// Unit vector toward the eye (or light) at `theta` from the normal, azimuth `phi`.
glm::dvec3 direction(double theta, double phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

glm::dvec2 parallax_of(glm::dvec3 v, double scale) { return scale * glm::dvec2(v.x, v.y) / v.z; }

// The surface as sample_bilinear (GL_LINEAR) sees it, at texel-space x, y.
double surface(const HeightField& f, double x, double y) {
    return f.sample_bilinear(x / f.width, y / f.height);
}

// Dense march: steps of 1e-4 texel along the ray's xy projection (1e-4 in t
// for near-vertical rays), bisection at the first sign change of z - S.
std::optional<double> brute_force_t(const HeightField& f, const Ray& r, double t_max) {
    const auto g = [&](double t) {
        const glm::dvec3 p = r.origin + t * r.direction;
        return p.z - surface(f, p.x, p.y);
    };
    if (g(0.0) <= 0.0) return 0.0;
    const double speed = std::hypot(r.direction.x, r.direction.y);
    const double dt = 1e-4 / std::max(speed, 1.0);
    double lo = 0.0;
    for (long k = 1;; ++k) {
        const double t = std::min(static_cast<double>(k) * dt, t_max);
        if (g(t) <= 0.0) {
            double hi = t;
            for (int it = 0; it < 80; ++it) {
                const double mid = 0.5 * (lo + hi);
                (g(mid) <= 0.0 ? hi : lo) = mid;
            }
            return hi;
        }
        if (t >= t_max) return std::nullopt;
        lo = t;
    }
}

TEST(ReferenceTracer, FlatFieldHitsAtItsLevel) {
    FieldSpec spec;
    spec.kind = FieldKind::flat;
    spec.size = 64;
    spec.level = 0.37f;
    const HeightField f = field_of(spec);
    const double c = static_cast<double>(spec.level);  // the float the texels hold
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int n = 0; n < 200; ++n) {
        const glm::dvec2 uv0(unit(rng) * 3.0 - 1.0, unit(rng) * 3.0 - 1.0);
        const glm::dvec3 v = direction(unit(rng) * 85.0 * kPi / 180.0, unit(rng) * 2.0 * kPi);
        const double scale = 0.02 + 0.1 * unit(rng);
        const double p = unit(rng) * 1.2;  // polygon below, inside and above the relief
        const ReliefHit h = trace_view(f, uv0, v, scale, p);
        const glm::dvec2 expect = uv0 + (c - p) * parallax_of(v, scale);
        EXPECT_NEAR(h.height, c, 1e-9);
        EXPECT_NEAR(h.uv.x, expect.x, 1e-9);
        EXPECT_NEAR(h.uv.y, expect.y, 1e-9);
    }
}

// One float ulp of the inputs: looking straight down at a flat field (at
// 0, the polygon at the top), a uv at 0.3 moves by 2^-25 and the hit with
// it; the view's turn by 2^-24 moves the hit by height_scale * 2^-24 only.
// At 89 degrees, a ray running along a one-texel ridge moves its hit along
// the ridge hundreds of times as far as it is shifted across it.
TEST(ReferenceTracer, Fp32InputFloorIsTheHitsMoveForOneUlp) {
    const HeightField flat = field_of(FieldKind::flat, 256);
    EXPECT_NEAR(fp32_input_floor(flat, {0.3, 0.3}, {0.0, 0.0, 1.0}, 0.05, 1.0), 256.0 * std::ldexp(1.0, -25), 1e-12);

    FieldSpec lines;
    lines.kind = FieldKind::lines;
    lines.size = 256;
    lines.count = 16;
    const HeightField f = field_of(lines);
    const double a = 89.0 * kPi / 180.0;
    // Medians: a ray that skims a ridge's top moves its hit by whole
    // ridges for one ulp (hit or miss), in either direction.
    std::vector<double> along, across;
    for (int i = 0; i < 1024 && along.size() < 33; ++i) {
        const glm::dvec2 uv(0.25 + i / 16384.0, 0.5);  // across 16 texels: a line and its ground
        const double h = f.sample_bilinear(uv.x, uv.y);
        if (!(h > 0.05 && h < 0.95)) continue;  // on a line's side, where the rays along it land
        along.push_back(fp32_input_floor(f, uv, {0.0, std::sin(a), std::cos(a)}, 0.05, 1.0));
        across.push_back(fp32_input_floor(f, uv, {std::sin(a), 0.0, std::cos(a)}, 0.05, 1.0));
    }
    std::sort(along.begin(), along.end());
    std::sort(across.begin(), across.end());
    ASSERT_EQ(along.size(), 33u);
    std::printf("median fp32 floor at 89 degrees: %.3g texel along the lines, %.3g across\n", along[16], across[16]);
    EXPECT_GT(along[16], 100.0 * across[16]);
}

// Texels 0 for x < k, 1 from k on: bilinear filtering turns the step into a
// ramp S = x - (k - 0.5) between the texel centres k - 0.5 and k + 0.5. The
// view ray from the -x side, at height H, is at x(H) = (u0 + (H - p) P) w
// with P < 0; it meets the ramp where H = x(H) - (k - 0.5):
// H = ((u0 - p P) w - k + 0.5) / (1 - P w).
TEST(ReferenceTracer, StepRampHitMatchesClosedForm) {
    const int n = 64, k = 32;
    HeightField f = field_of(FieldKind::flat, n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) f.ref(x, y) = x >= k ? 1.0f : 0.0f;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int checked = 0;
    for (int it = 0; it < 2000 && checked < 200; ++it) {
        const double theta = unit(rng) * 80.0 * kPi / 180.0;
        const glm::dvec3 v = direction(theta, kPi + (unit(rng) - 0.5) * 1.2);  // eye toward -x
        const double scale = 0.05;
        const double p = unit(rng);
        const glm::dvec2 P = parallax_of(v, scale);
        if (-P.x * n > 20.0) continue;  // stay clear of the wrap-around ramp at x = 0
        const glm::dvec2 uv0((k - 1.0 + 2.0 * unit(rng)) / n, unit(rng));
        const double H = ((uv0.x - p * P.x) * n - k + 0.5) / (1.0 - P.x * n);
        if (!(H > 0.0 && H < 1.0)) continue;
        const ReliefHit h = trace_view(f, uv0, v, scale, p);
        const glm::dvec2 expect = uv0 + (H - p) * P;
        EXPECT_NEAR(h.height, H, 1e-9);
        EXPECT_NEAR(h.uv.x, expect.x, 1e-9);
        EXPECT_NEAR(h.uv.y, expect.y, 1e-9);
        ++checked;
    }
    EXPECT_GE(checked, 100);
}

// A 1-texel line is a tent 1 - |x - xc| two texels wide. A ray skimming its
// tip (entering 0.01 below the apex) meets a sliver 0.02 texel wide: any
// fixed-step march misses it; the cell walk may not.
TEST(ReferenceTracer, SkimmingRayHitsOneTexelLineTip) {
    FieldSpec spec;
    spec.kind = FieldKind::lines;
    spec.size = 64;
    spec.count = 4;
    spec.line_width = 1;
    const HeightField f = field_of(spec);
    int xl = -1;
    for (int x = 0; x < f.width; ++x)
        if (f.at(x, 0) == 1.0f && x > 20) {
            xl = x;
            break;
        }
    ASSERT_GT(xl, 20);
    const double xc = xl + 0.5;
    for (const double slope : {0.0, 1e-4, 1e-3}) {
        // z = zs - slope t, x = xs + t; rising side of the tent: S = 1 + x - xc.
        const double xs = xc - 15.3, zs = 0.99 + slope * 14.3;
        Ray r{{xs, 7.25, zs}, {1.0, 0.0, -slope}};
        const Hit h = first_hit(f, r, 0.0, 30.0);
        ASSERT_TRUE(h.hit) << "slope " << slope;
        const double t = (zs - 1.0 - xs + xc) / (1.0 + slope);
        EXPECT_NEAR(h.t, t, 1e-9);
        EXPECT_NEAR(h.position.z, 1.0 + (xs + t) - xc, 1e-9);
        EXPECT_GT(h.position.z, 0.98);
        // The same ray through the walk in the -x direction from the other side.
        Ray back{{2.0 * xc - xs, 7.25, zs}, {-1.0, 0.0, -slope}};
        const Hit hb = first_hit(f, back, 0.0, 30.0);
        ASSERT_TRUE(hb.hit);
        EXPECT_NEAR(hb.position.x, 2.0 * xc - h.position.x, 1e-9);
    }
}

// Sphere of radius R = 0.4 tile centred 0.3 below the ground, relief 0.1
// deep: a cap whose top is height 1. Bound on |H_ref - H_sphere|: bilinear
// interpolation of a C2 function errs by at most (d^2/8)(max|f_xx| + max|f_yy|)
// (tensor product of two linear interpolations), d = 1/512 tile. Inside
// r <= 0.2 (+1 texel), |f_xx|, |f_yy| <= R^2 / (R^2 - r^2)^1.5 < 3.91, so the
// surface errs by < 3.8e-6 tile = 3.8e-5 in normalised height, plus float
// storage (< 1e-7). A vertical surface error e moves the hit height by
// e / (1 - dS/dH along the ray); rays with that factor above 10 are skipped,
// which leaves 3.8e-4 < 1e-3.
TEST(ReferenceTracer, SphereCapWithinBilinearError) {
    const int n = 512;
    const double scale = 0.1, R = 0.4, cz = -0.3;
    HeightField f = field_of(FieldKind::flat, n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double u = (x + 0.5) / n - 0.5, v = (y + 0.5) / n - 0.5;
            const double r2 = u * u + v * v;
            const double z = r2 < R * R ? std::sqrt(R * R - r2) + cz : 0.0;
            f.ref(x, y) = static_cast<float>(std::max(z, 0.0) / scale);
        }
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int checked = 0;
    for (int it = 0; it < 5000 && checked < 300; ++it) {
        const glm::dvec3 v = direction(unit(rng) * 70.0 * kPi / 180.0, unit(rng) * 2.0 * kPi);
        const glm::dvec2 P = parallax_of(v, scale);
        const double p = unit(rng);
        const glm::dvec2 uv0(0.25 + 0.5 * unit(rng), 0.25 + 0.5 * unit(rng));
        // |Q + H D|^2 = R^2 in tile units, Q = (uv0 - p P - centre, -cz), D = (P, scale).
        const glm::dvec3 Q(uv0 - p * P - glm::dvec2(0.5), -cz);
        const glm::dvec3 D(P, scale);
        const double a = glm::dot(D, D), b = 2.0 * glm::dot(Q, D), c = glm::dot(Q, Q) - R * R;
        const double disc = b * b - 4.0 * a * c;
        if (disc <= 0.0) continue;
        const double H = (-b + std::sqrt(disc)) / (2.0 * a);  // the higher root: first met descending
        if (!(H > 0.0 && H < 1.0)) continue;
        const glm::dvec2 at = uv0 + (H - p) * P - glm::dvec2(0.5);
        const double rr = glm::length(at);
        if (rr > 0.2) continue;
        // dS/dH along the ray: grad S (normalised per tile) . P.
        const glm::dvec2 grad = -at / (std::sqrt(R * R - rr * rr) * scale);
        const double rate = 1.0 - glm::dot(grad, P);
        if (!(rate > 0.1)) continue;
        const ReliefHit h = trace_view(f, uv0, v, scale, p);
        EXPECT_NEAR(h.height, H, 1e-3);
        EXPECT_NEAR(glm::length(h.uv - (uv0 + (H - p) * P)), 0.0, 1e-3 * glm::length(P) + 1e-12);
        ++checked;
    }
    EXPECT_GE(checked, 200);
}

TEST(ReferenceTracer, VerticalRayHitsFieldValueBelow) {
    FieldSpec spec;
    spec.kind = FieldKind::sine;
    spec.size = 64;
    const HeightField f = field_of(spec);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(-1.0, 2.0);
    for (int n = 0; n < 100; ++n) {
        const glm::dvec2 uv0(unit(rng), unit(rng));
        const ReliefHit h = trace_view(f, uv0, {0.0, 0.0, 1.0}, 0.1, 0.7);
        EXPECT_NEAR(h.height, f.sample_bilinear(uv0.x, uv0.y), 1e-12);
        EXPECT_EQ(h.uv.x, uv0.x);
        EXPECT_EQ(h.uv.y, uv0.y);
    }
    // Straight down on the spike's texel centre: its full height.
    const HeightField spike = field_of(FieldKind::spike, 16);
    const ReliefHit h = trace_view(spike, {8.5 / 16, 8.5 / 16}, {0.0, 0.0, 1.0}, 0.1, 1.0);
    EXPECT_NEAR(h.height, 1.0, 1e-12);
    // A vertical ray is a point in xy: one cell.
    const Hit one = first_hit(spike, Ray{{3.2, 4.7, 1.0}, {0.0, 0.0, -1.0}}, 0.0, 1.0);
    EXPECT_EQ(one.cells_visited, 1);
}

// Random view rays (fixed seed, up to 89 degrees from the normal) plus axis-
// aligned and diagonal rays starting exactly on cell boundaries, against the
// dense march. Returns how many hits were above the ground (z > 1e-6).
int compare_with_brute_force(const HeightField& f, double scale, unsigned seed, int rays) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Ray> list;
    for (int n = 0; n < rays; ++n) {
        const double theta = (n % 10 == 0 ? 89.0 : unit(rng) * 89.0) * kPi / 180.0;
        const glm::dvec3 v = direction(theta, unit(rng) * 2.0 * kPi);
        list.push_back(view_ray(f, {unit(rng), unit(rng)}, v, scale, unit(rng)));
    }
    for (int q = 0; q < 8; ++q) {
        const double phi = q * kPi / 4.0;
        const double x0 = 7.5 + q, y0 = 9.5 + 2 * q;  // texel centres = cell corners
        list.push_back(Ray{{x0, y0, 1.0}, {20.0 * std::round(std::cos(phi)), 20.0 * std::round(std::sin(phi)), -1.0}});
    }
    int raised = 0;
    for (const Ray& r : list) {
        const Hit h = first_hit(f, r, 0.0, 1.0);
        const std::optional<double> tb = brute_force_t(f, r, 1.0);
        EXPECT_EQ(h.hit, tb.has_value());
        if (!h.hit || !tb) continue;
        const glm::dvec3 pb = r.origin + *tb * r.direction;
        // 1e-4 texel in uv, i.e. the march's own resolution.
        EXPECT_NEAR(h.position.x, pb.x, 1e-4) << "ray origin " << r.origin.x << "," << r.origin.y;
        EXPECT_NEAR(h.position.y, pb.y, 1e-4) << "ray origin " << r.origin.x << "," << r.origin.y;
        if (pb.z > 1e-6) {
            ++raised;
            // Never miss a raised feature the march found.
            EXPECT_GT(h.position.z, 1e-6);
        }
    }
    return raised;
}

TEST(ReferenceTracer, AgreesWithBruteForceOnSine) {
    FieldSpec spec;
    spec.kind = FieldKind::sine;
    spec.size = 64;
    spec.frequency = 4;
    EXPECT_GT(compare_with_brute_force(field_of(spec), 0.05, 21, 150), 100);
}

TEST(ReferenceTracer, AgreesWithBruteForceOnText) {
    FieldSpec spec;
    spec.kind = FieldKind::text;
    spec.size = 128;
    spec.text = "ES";
    EXPECT_GT(compare_with_brute_force(field_of(spec), 0.05, 22, 150), 10);
}

TEST(ReferenceTracer, AgreesWithBruteForceOnOneTexelLines) {
    FieldSpec spec;
    spec.kind = FieldKind::lines;
    spec.size = 64;
    spec.count = 8;
    spec.line_width = 1;
    EXPECT_GT(compare_with_brute_force(field_of(spec), 0.05, 23, 150), 30);
}

// Amanatides-Woo visits 1 + (x boundaries crossed) + (y boundaries crossed).
TEST(ReferenceTracer, WalkVisitsExactlyTheCellsCrossed) {
    const HeightField f = field_of(FieldKind::flat, 16);  // level 1: ray from above to z = 1
    FieldSpec low;
    low.kind = FieldKind::flat;
    low.size = 16;
    low.level = 0.0f;
    const HeightField g = field_of(low);
    // x from 0.7 - 0.5 = 0.2 to 10.2 in cell units: cells 0..10.
    EXPECT_EQ(first_hit(g, Ray{{0.7, 0.7, 1.0}, {10.0, 0.0, -1.0}}, 0.0, 1.0).cells_visited, 11);
    EXPECT_EQ(first_hit(g, Ray{{0.7, 0.7, 1.0}, {-10.0, 0.0, -1.0}}, 0.0, 1.0).cells_visited, 11);
    // x: 0.2 -> 3.2 (3 crossings), y: 0.2 -> -1.8 (2 crossings).
    EXPECT_EQ(first_hit(g, Ray{{0.7, 0.7, 1.0}, {3.0, -2.0, -1.0}}, 0.0, 1.0).cells_visited, 6);
    // Starting under the surface: hit at t_min, one cell.
    const Hit under = first_hit(f, Ray{{5.0, 5.0, 0.5}, {3.0, 1.0, 1.0}}, 0.25, 2.0);
    EXPECT_TRUE(under.hit);
    EXPECT_EQ(under.t, 0.25);
    EXPECT_EQ(under.cells_visited, 1);
    // Level ray just above a flat top never hits; one exactly on it does at once.
    EXPECT_FALSE(first_hit(f, Ray{{0.0, 0.0, 1.0 + 1e-12}, {1.0, 0.3, 0.0}}, 0.0, 100.0).hit);
    EXPECT_TRUE(first_hit(f, Ray{{0.0, 0.0, 1.0}, {1.0, 0.3, 0.0}}, 0.0, 100.0).hit);
}

TEST(ReferenceTracer, OccludedIsStrictlyBelowOnly) {
    FieldSpec spec;
    spec.kind = FieldKind::flat;
    spec.size = 8;
    spec.level = 0.5f;
    const HeightField f = field_of(spec);
    // Along the surface: not strictly below.
    EXPECT_FALSE(occluded(f, Ray{{1.0, 1.0, 0.5}, {5.0, 2.0, 0.0}}, 0.0, 3.0));
    EXPECT_TRUE(occluded(f, Ray{{1.0, 1.0, 0.5 - 1e-6}, {5.0, 2.0, 0.0}}, 0.0, 3.0));
    // Rising out of the surface from below: below only at t < 0.1.
    const Ray r{{1.0, 1.0, 0.4}, {5.0, 2.0, 1.0}};
    EXPECT_TRUE(occluded(f, r, 0.0, 1.0));
    EXPECT_FALSE(occluded(f, r, 0.1, 1.0));
    EXPECT_FALSE(occluded(f, r, 0.1, 0.1));  // (t_min, t_max] empty
}

// A saddle cell (h00 = h11 = 0, h10 = h01 = 1): along its main diagonal
// a = b = s the patch is S = 2s - 2s^2, a dome peaking at 0.5 mid-cell, while
// both cell corners it joins are at 0. A level ray at z dips under it only
// inside the cell: neither endpoint shows it; the quadratic must.
TEST(ReferenceTracer, SaddleCellInteriorDip) {
    HeightField f = field_of(FieldKind::flat, 2);
    f.ref(0, 0) = 0.0f;
    f.ref(1, 0) = 1.0f;
    f.ref(0, 1) = 1.0f;
    f.ref(1, 1) = 0.0f;
    const auto diagonal = [](double z) { return Ray{{0.5, 0.5, z}, {1.0, 1.0, 0.0}}; };
    // 2s - 2s^2 = z at s = (1 - sqrt(1 - 2z)) / 2.
    const Hit h = first_hit(f, diagonal(0.45), 0.0, 1.0);
    ASSERT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 0.5 * (1.0 - std::sqrt(1.0 - 0.9)), 1e-12);
    EXPECT_FALSE(first_hit(f, diagonal(0.5 + 1e-12), 0.0, 1.0).hit);
    EXPECT_TRUE(occluded(f, diagonal(0.45), 0.0, 1.0));
    // Epsilon: a dip of 5e-10 is under the default 1e-9, one of 2e-9 is not.
    EXPECT_FALSE(occluded(f, diagonal(0.5 + 5e-10), 0.0, 1.0));
    EXPECT_FALSE(occluded(f, diagonal(0.5 - 5e-10), 0.0, 1.0));
    EXPECT_TRUE(occluded(f, diagonal(0.5 - 2e-9), 0.0, 1.0));
    EXPECT_TRUE(occluded(f, diagonal(0.5 - 5e-10), 0.0, 1.0, 1e-10));
}

// Pit field, 256 texels, radius 0.25: floor (0) for texels 64..191, top (1)
// elsewhere; the +x wall is the ramp x in [191.5, 192.5]. A light from +x at
// elevation e, relief depth s: the light ray rises k = tan(e) / (s w) per
// texel, so a floor point x_p is lit iff it clears the wall's top edge:
// (192.5 - x_p) k >= 1.
constexpr double kScale = 0.1;
constexpr double kElevation = 30.0 * kPi / 180.0;

glm::dvec3 light_from_plus_x(double elevation) { return {std::cos(elevation), 0.0, std::sin(elevation)}; }
glm::dvec2 pit_uv(double x) { return {x / 256.0, 0.5}; }
double pit_shadow_edge(double elevation) { return 192.5 - kScale * 256.0 / std::tan(elevation); }

TEST(ReferenceTracer, HardVisibilityInPit) {
    const HeightField f = field_of(FieldKind::pit, 256);
    const glm::dvec3 L = light_from_plus_x(kElevation);
    EXPECT_EQ(hard_visibility(f, pit_uv(185.0), 0.0, L, kScale), 0.0);  // under the wall
    EXPECT_EQ(hard_visibility(f, pit_uv(70.0), 0.0, L, kScale), 1.0);   // open floor
    EXPECT_EQ(hard_visibility(f, pit_uv(20.0), 1.0, L, kScale), 1.0);   // top
    EXPECT_EQ(hard_visibility(f, pit_uv(230.0), 1.0, L, kScale), 1.0);
    // Closed-form shadow edge, both sides.
    const double edge = pit_shadow_edge(kElevation);
    EXPECT_EQ(hard_visibility(f, pit_uv(edge + 0.01), 0.0, L, kScale), 0.0);
    EXPECT_EQ(hard_visibility(f, pit_uv(edge - 0.01), 0.0, L, kScale), 1.0);
    // At or below the horizon: dark, even on top.
    EXPECT_EQ(hard_visibility(f, pit_uv(20.0), 1.0, {0.99, 0.0, -0.1}, kScale), 0.0);
    EXPECT_EQ(hard_visibility(f, pit_uv(70.0), 0.0, {1.0, 0.0, 0.0}, kScale), 0.0);
    // A flat surface is lit by a light barely above its horizon.
    FieldSpec flat;
    flat.kind = FieldKind::flat;
    flat.size = 32;
    flat.level = 0.3f;
    const HeightField g = field_of(flat);
    EXPECT_EQ(hard_visibility(g, {0.41, 0.77}, 0.3f, glm::normalize(glm::dvec3(1, 1, 0.05)), kScale), 1.0);
    // A surface point found by trace_view is lit by the light it faces.
    FieldSpec sine;
    sine.kind = FieldKind::sine;
    sine.size = 64;
    const HeightField s = field_of(sine);
    const ReliefHit top = trace_view(s, {1.0 / 16, 1.0 / 16}, {0, 0, 1}, kScale, 1.0);  // a crest
    EXPECT_EQ(hard_visibility(s, top.uv, top.height, glm::normalize(glm::dvec3(0.2, 0.1, 1)), kScale), 1.0);
}

TEST(ReferenceTracer, SoftVisibilityPenumbra) {
    const HeightField f = field_of(FieldKind::pit, 256);
    const glm::dvec3 L = light_from_plus_x(kElevation);
    const double radius = 5.0 * kPi / 180.0;
    EXPECT_EQ(soft_visibility(f, pit_uv(100.0), 0.0, L, kScale, radius), 1.0);  // far from the wall
    EXPECT_EQ(soft_visibility(f, pit_uv(186.0), 0.0, L, kScale, radius), 0.0);  // deep in the shadow
    const double edge = soft_visibility(f, pit_uv(pit_shadow_edge(kElevation)), 0.0, L, kScale, radius);
    EXPECT_GT(edge, 0.0);
    EXPECT_LT(edge, 1.0);
    // Penumbra from x = edge(25 deg) to edge(35 deg): visibility never falls
    // as the point moves out of the shadow (toward -x), and spans 0..1.
    double previous = 0.0;
    for (double x = 165.0; x >= 125.0; x -= 2.5) {
        const double vis = soft_visibility(f, pit_uv(x), 0.0, L, kScale, radius);
        EXPECT_GE(vis, previous) << "x = " << x;
        previous = vis;
    }
    EXPECT_EQ(previous, 1.0);
    // Radius 0 is the hard test; a light disc partly below the horizon loses that part.
    EXPECT_EQ(soft_visibility(f, pit_uv(185.0), 0.0, L, kScale, 0.0), hard_visibility(f, pit_uv(185.0), 0.0, L, kScale));
    const double grazing = soft_visibility(f, pit_uv(20.0), 1.0, light_from_plus_x(0.0), kScale, radius);
    EXPECT_GT(grazing, 0.3);
    EXPECT_LT(grazing, 0.7);
}

TEST(ReferenceTracer, Quantized8BitIsMultiplesOf255) {
    FieldSpec spec;
    spec.kind = FieldKind::sine;
    spec.size = 32;
    const HeightField f = field_of(spec);
    const HeightField q = quantized_8bit(f);
    ASSERT_EQ(q.width, f.width);
    ASSERT_EQ(q.height, f.height);
    ASSERT_EQ(q.texels.size(), f.texels.size());
    int changed = 0;
    for (size_t i = 0; i < q.texels.size(); ++i) {
        const double k = static_cast<double>(q.texels[i]) * 255.0;
        EXPECT_NEAR(k, std::round(k), 1e-4);
        EXPECT_LE(std::abs(static_cast<double>(q.texels[i]) - f.texels[i]), 0.5 / 255.0 + 1e-7);
        changed += q.texels[i] != f.texels[i];
    }
    EXPECT_GT(changed, 0);
}

// 256 x 256 view rays over a 256-texel field. Timing is printed, not
// asserted (build types differ); the walk's cost is: each ray visits at most
// 3 + |dx| + |dy| cells over the t it travels.
TEST(ReferenceTracer, ImageOfRaysVisitsOnlyCrossedCells) {
    FieldSpec spec;
    spec.kind = FieldKind::text;
    spec.size = 256;
    spec.text = "PX";
    const HeightField f = field_of(spec);
    const int n = 256;
    long cells = 0;
    const auto start = std::chrono::steady_clock::now();
    for (int py = 0; py < n; ++py)
        for (int px_ = 0; px_ < n; ++px_) {
            const double theta = (py + 0.5) / n * 70.0 * kPi / 180.0;  // rows: normal to 70 degrees
            const glm::dvec3 v = direction(theta, 0.3 + px_ * 0.01);
            const Ray r = view_ray(f, {(px_ + 0.5) / n, (py + 0.5) / n}, v, 0.1, 1.0);
            const Hit h = first_hit(f, r, 0.0, 1.0);
            ASSERT_TRUE(h.hit);
            const double bound = 3.0 + h.t * (std::abs(r.direction.x) + std::abs(r.direction.y));
            ASSERT_LE(static_cast<double>(h.cells_visited), bound);
            cells += h.cells_visited;
        }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::cout << "[ reference ] 256x256 rays: " << ms << " ms, " << static_cast<double>(cells) / (n * n)
              << " cells per ray\n";
}

}  // namespace
}  // namespace px::reference
