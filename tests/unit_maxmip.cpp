// Unit tests for the maxmip technique's CPU side: the maximum mip-map over
// the bilinearly filtered field (assets/max_mipmap.h) and the quadtree
// traversal that mirrors shaders_es/techniques/maxmip.frag
// (reference/maxmip_trace.h), checked against the exact reference tracer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "assets/heightfield.h"
#include "assets/max_mipmap.h"
#include "effects/technique.h"
#include "reference/maxmip_trace.h"
#include "reference/tracer.h"

namespace px {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The iteration budget (PX_MAX_SAMPLES for maxmip.frag) stated for 256-texel
// fields viewed at up to 89 degrees with the relief up to 0.1 tile deep
// (random rays over the test fields need at most 831; see the printed table).
// Each iteration descends a level, or crosses into the next node (solving a
// cell first at level 0) and ascends at most one level, so a ray entering C
// cells needs at most top + 2 C + 1 iterations, checked on every ray. Empty
// space costs far less (Tevs et al. 2008), but beside a thin tall feature the
// nodes shrink to single cells and a ray sliding along it pays per cell
// (MaxmipTrace.WorstCaseIsBoundedByTheCellsCrossed).
constexpr int kBudget = 1024;
constexpr double kScales[] = {0.05, 0.1};
constexpr double kHeightScale = 0.1;  // for the other tests
// Hit agreement with the exact reference, in texels of the base level.
constexpr double kTolerance = 1e-3;

HeightField generate(const FieldSpec& spec) {
    Result<HeightField> r = make_height_field(spec);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(r).value() : HeightField{};
}

MaxMipmap build(const HeightField& field) {
    Result<MaxMipmap> r = build_max_mipmap(field);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(r).value() : MaxMipmap{};
}

HeightField random_field(std::mt19937& rng, int w, int h) {
    HeightField f;
    f.width = w;
    f.height = h;
    f.texels.resize(static_cast<size_t>(w) * h);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::bernoulli_distribution sparse(0.1);
    // Mostly low with rare tall texels: isolated peaks are where a bound
    // taken from samples alone fails.
    for (float& t : f.texels) t = sparse(rng) ? unit(rng) : 0.2f * unit(rng);
    return reference::quantized_8bit(f);
}

// --- The pyramid ------------------------------------------------------------------

TEST(MaxMipmap, LevelZeroBoundsTheBilinearSurfaceOfEachCell) {
    std::mt19937 rng(1234);
    const int sizes[][2] = {{4, 4}, {8, 8}, {16, 4}, {2, 32}, {64, 64}, {1, 8}};
    long checked = 0;
    double tightest = 1.0;  // smallest slack seen: 0 shows the bound is attained
    for (const auto& s : sizes) {
        for (int repeat = 0; repeat < 4; ++repeat) {
            const HeightField f = random_field(rng, s[0], s[1]);
            const MaxMipmap m = build(f);
            ASSERT_EQ(m.width, s[0]);
            ASSERT_EQ(m.height, s[1]);
            std::uniform_int_distribution<int> cx(-2 * s[0], 3 * s[0]);
            std::uniform_int_distribution<int> cy(-2 * s[1], 3 * s[1]);
            std::uniform_real_distribution<double> frac(0.0, 1.0);
            for (int k = 0; k < 4000; ++k) {
                // A point in cell (i, j): texel space [i + 0.5, i + 1.5] x [j + 0.5, j + 1.5].
                const int i = cx(rng);
                const int j = cy(rng);
                const double x = i + 0.5 + frac(rng);
                const double y = j + 0.5 + frac(rng);
                const double surface = f.sample_bilinear(x / f.width, y / f.height);
                const double bound = m.max_height(0, i, j);
                ASSERT_LE(surface, bound + 1e-9) << "cell (" << i << ", " << j << ") of a " << f.width << "x"
                                                 << f.height << " field at (" << x << ", " << y << ")";
                tightest = std::min(tightest, bound - surface);
                ++checked;
            }
            // And at the corners themselves, where a sample-only bound is
            // already wrong for the cells beside a peak.
            for (int j = 0; j < f.height; ++j)
                for (int i = 0; i < f.width; ++i)
                    for (int dy = 0; dy < 2; ++dy)
                        for (int dx = 0; dx < 2; ++dx)
                            ASSERT_GE(m.max_height(0, i, j), f.at(i + dx, j + dy)) << i << "," << j;
        }
    }
    EXPECT_GT(checked, 0);
    EXPECT_LT(tightest, 0.05);  // the bound is not vacuous
}

TEST(MaxMipmap, EveryNodeBoundsItsChildrenAndShapesMatchTheMipChain) {
    std::mt19937 rng(99);
    const int sizes[][2] = {{32, 32}, {64, 8}, {4, 128}, {1, 1}, {2, 1}};
    for (const auto& s : sizes) {
        const HeightField f = random_field(rng, s[0], s[1]);
        const MaxMipmap m = build(f);
        int expected_levels = 1;
        while ((1 << (expected_levels - 1)) < std::max(s[0], s[1])) ++expected_levels;
        ASSERT_EQ(m.level_count(), expected_levels) << s[0] << "x" << s[1];
        for (int k = 0; k < m.level_count(); ++k) {
            const Image& img = m.levels[static_cast<size_t>(k)];
            EXPECT_EQ(img.width, std::max(1, s[0] >> k));
            EXPECT_EQ(img.height, std::max(1, s[1] >> k));
            EXPECT_EQ(img.pixels.size(), static_cast<size_t>(img.width) * img.height * img.channels);
        }
        EXPECT_EQ(m.levels.back().width, 1);
        EXPECT_EQ(m.levels.back().height, 1);
        for (int k = 1; k < m.level_count(); ++k) {
            const Image& parent = m.levels[static_cast<size_t>(k)];
            const Image& child = m.levels[static_cast<size_t>(k - 1)];
            for (int y = 0; y < parent.height; ++y)
                for (int x = 0; x < parent.width; ++x) {
                    int children_max = 0;
                    for (int cy = 0; cy < child.height; ++cy)
                        for (int cx = 0; cx < child.width; ++cx) {
                            // Child (cx, cy) belongs to parent (cx * pw / cw, cy * ph / ch).
                            if (cx * parent.width / child.width != x || cy * parent.height / child.height != y)
                                continue;
                            children_max = std::max(children_max, int{m.max_byte(k - 1, cx, cy)});
                        }
                    ASSERT_GE(int{m.max_byte(k, x, y)}, children_max) << "level " << k << " node " << x << "," << y;
                    // Tight as well: no looser than the children need.
                    ASSERT_EQ(int{m.max_byte(k, x, y)}, children_max) << "level " << k << " node " << x << "," << y;
                }
        }
        // The root bounds the whole field.
        const float top = *std::max_element(f.texels.begin(), f.texels.end());
        EXPECT_NEAR(m.max_height(m.level_count() - 1, 0, 0), top, 1e-6);
    }
}

TEST(MaxMipmap, LevelZeroStoresTheQuantisedCornerMax) {
    HeightField f;
    f.width = 4;
    f.height = 2;
    // Row 0 then row 1; one spike at (3, 1) so wrapping shows.
    const float a = 26.0f / 255.0f, b = 51.0f / 255.0f, c = 179.0f / 255.0f;
    f.texels = {0.0f, a, b, 0.0f, 0.0f, 0.0f, 0.0f, c};
    const MaxMipmap m = build(f);
    ASSERT_EQ(m.level_count(), 3);
    EXPECT_EQ(m.levels[0].channels, 1);
    // Cell (i, j) has corners (i..i+1, j..j+1), wrapped.
    EXPECT_EQ(m.max_byte(0, 0, 0), 26);
    EXPECT_EQ(m.max_byte(0, 1, 0), 51);
    EXPECT_EQ(m.max_byte(0, 2, 0), 179);  // (3, 1)
    EXPECT_EQ(m.max_byte(0, 3, 0), 179);  // corners x 3 and 0 (wrapped)
    EXPECT_EQ(m.max_byte(0, 3, 1), 179);  // rows 1 and 0 (wrapped)
    EXPECT_EQ(m.max_byte(0, 0, 1), 26);  // rows 1 and 0 (wrapped): (1, 0)
    EXPECT_EQ(m.max_byte(0, 1, 1), 51);
    // Level 1 is 2 x 1 (the height stops at 1), level 2 the root.
    EXPECT_EQ(m.levels[1].width, 2);
    EXPECT_EQ(m.levels[1].height, 1);
    EXPECT_EQ(m.max_byte(1, 0, 0), 51);
    EXPECT_EQ(m.max_byte(1, 1, 0), 179);
    EXPECT_EQ(m.max_byte(2, 0, 0), 179);
    EXPECT_FLOAT_EQ(m.max_height(2, 5, -3), 179.0f / 255.0f);
    // Node indices wrap (GL_REPEAT), negative ones too.
    EXPECT_EQ(m.max_byte(0, -1, 0), m.max_byte(0, 3, 0));
    EXPECT_EQ(m.max_byte(0, -3, -1), m.max_byte(0, 1, 1));
    EXPECT_EQ(m.max_byte(0, 6, 5), m.max_byte(0, 2, 1));
    EXPECT_EQ(m.max_byte(1, -1, 7), 179);
    EXPECT_EQ(m.max_byte(1, -2, 0), 51);
}

TEST(MaxMipmap, NonPowerOfTwoSizesAreErrorsNamingTheSize) {
    HeightField f;
    f.width = 300;
    f.height = 256;
    f.texels.assign(static_cast<size_t>(f.width) * f.height, 0.5f);
    Result<MaxMipmap> r = build_max_mipmap(f);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("300x256"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("power of two"), std::string::npos) << r.error().message;

    f.width = 64;
    f.height = 48;
    f.texels.assign(static_cast<size_t>(f.width) * f.height, 0.5f);
    Result<MaxMipmap> r2 = build_max_mipmap(f);
    ASSERT_FALSE(r2.ok());
    EXPECT_NE(r2.error().message.find("64x48"), std::string::npos) << r2.error().message;

    HeightField empty;
    EXPECT_FALSE(build_max_mipmap(empty).ok());
}

// --- The traversal against the exact reference ---------------------------------------

struct Agreement {
    long rays = 0;
    long disagreements = 0;
    long exhausted = 0;
    int max_iterations = 0;
    double max_error = 0.0;       // texels, against trace_view
    double max_walk_error = 0.0;  // texels, against first_hit on the walked float ray
    long line_hits = 0;      // reference hits on a raised texel's cells (lines field)
    double max_bound_use = 0.0;  // iterations / (top + 2 * cells entered + 1): must stay <= 1
    long ill_conditioned = 0;  // rays whose exact hit moves > kTolerance / 10 when the input is rounded to float
    std::string first_failures;
};

glm::dvec3 view_direction(double angle_deg, double azimuth) {
    const double a = angle_deg * kPi / 180.0;
    return {std::sin(a) * std::cos(azimuth), std::sin(a) * std::sin(azimuth), std::cos(a)};
}

// Inputs as the shader receives them: float values (highp uv, view vector).
// Through a volatile: GCC 12.2 at -O2 (SLP vectorizer) folds a plain
// double -> float -> double round trip of a vector pair away.
double as_float(double x) {
    volatile float f = static_cast<float>(x);
    return static_cast<double>(f);
}
glm::dvec2 as_float(glm::dvec2 v) { return {as_float(v.x), as_float(v.y)}; }
glm::dvec3 as_float(glm::dvec3 v) { return {as_float(v.x), as_float(v.y), as_float(v.z)}; }

// The maxmip hit (uv as the shader returns it) must be within kTolerance of
// the exact hit for the same input (trace_view). The traversal runs in
// float, like the shader: its ray (maxmip_view_ray) is the input rounded to
// float, and for rays nearly parallel to a feature's edge that rounding
// alone moves the exact hit along the ray by more than kTolerance. So:
//   walk error: maxmip against first_hit on the very float ray it walks,
//               within kTolerance always: the traversal itself is exact;
//   error:      against trace_view, within kTolerance plus the distance
//               between the exact hits of the double and the float ray
//               (the input's own conditioning, reported as ill-conditioned
//               when over kTolerance / 10).
//   walk_ulps:  extra allowance, in float ulps of the distance walked (the
//               walk's positions are floats relative to the entry cell, so
//               their rounding grows with it) and of the ray's run per unit
//               of height (a hit height off by one ulp is that far along the
//               ray); 0 for the usual walks of a few hundred texels, where
//               kTolerance covers both.
void compare_view(const HeightField& q, const MaxMipmap& m, glm::dvec2 uv_in, glm::dvec3 view_in,
                  double polygon_height, double height_scale, int budget, Agreement& a, double walk_ulps = 0.0) {
    const glm::dvec2 uv = as_float(uv_in);
    const glm::dvec3 view = as_float(view_in);
    const reference::ReliefHit truth = reference::trace_view(q, uv, view, height_scale, polygon_height);
    const reference::MaxmipHit got = reference::maxmip_trace_view(m, q, uv, view, height_scale, polygon_height, budget);
    const reference::Ray walked_ray = reference::maxmip_view_ray(m, uv, view, height_scale, polygon_height);
    const reference::Hit same_ray = reference::first_hit(q, walked_ray, 0.0, 1.0);
    const glm::dvec2 size(q.width, q.height);
    const glm::dvec2 truth_texels = truth.uv * size;
    const double error = glm::length(got.uv * size - truth_texels);
    const double walk_error = glm::length(glm::dvec2(got.position) - glm::dvec2(same_ray.position));
    const double conditioning = glm::length(glm::dvec2(same_ray.position) - truth_texels);
    ++a.rays;
    a.max_iterations = std::max(a.max_iterations, got.iterations);
    if (got.budget_exhausted) ++a.exhausted;
    a.max_error = std::max(a.max_error, error);
    a.max_walk_error = std::max(a.max_walk_error, walk_error);
    if (conditioning > 0.1 * kTolerance) ++a.ill_conditioned;
    if (truth.height > 0.0 && truth.height < 1.0) {
        // On a line's slope or top: the cells beside a raised texel.
        const int i = static_cast<int>(std::floor(truth_texels.x - 0.5));
        if (q.at(i, 0) > 0.0f || q.at(i + 1, 0) > 0.0f) ++a.line_hits;
    }
    // Iterations: each descends a level, or leaves a node across a cell
    // boundary (then ascends at most one level), so with C cells entered
    // before the hit, iterations <= top level + 2 C + 1 (see kBudget).
    const long bound = (m.level_count() - 1) + 2 * same_ray.cells_visited + 1;
    a.max_bound_use = std::max(a.max_bound_use, static_cast<double>(got.iterations) / static_cast<double>(bound));
    const double walked = glm::length(glm::dvec2(same_ray.position) - glm::dvec2(walked_ray.origin));
    const double run_per_height = glm::length(glm::dvec2(walked_ray.direction));  // direction.z = -1
    const double tolerance = kTolerance + walk_ulps * (walked + run_per_height) * 0x1p-23;
    const bool ok = same_ray.hit && got.hit && walk_error <= tolerance && error <= tolerance + conditioning &&
                    (got.budget_exhausted || got.iterations <= bound);
    if (!ok && ++a.disagreements <= 5) {
        std::ostringstream s;
        s.precision(17);
        s << "  uv (" << uv.x << ", " << uv.y << ") view (" << view.x << ", " << view.y << ", " << view.z
          << ") polygon " << polygon_height << " scale " << height_scale << ": reference (" << truth_texels.x
          << ", " << truth_texels.y << ", h " << truth.height << "), maxmip (" << got.uv.x * size.x << ", "
          << got.uv.y * size.y << ", h " << got.height << "): " << error << " texels; float ray: reference ("
          << same_ray.position.x << ", " << same_ray.position.y << "), walk error " << walk_error << "; "
          << got.iterations << " iterations (bound " << bound << ")"
          << (got.budget_exhausted ? " (budget ran out)" : "") << "\n";
        a.first_failures += s.str();
    }
}

struct FieldCase {
    const char* name;
    FieldSpec spec;
};

std::vector<FieldCase> agreement_fields() {
    std::vector<FieldCase> cases;
    FieldSpec lines;
    lines.kind = FieldKind::lines;
    lines.size = 256;
    lines.count = 16;
    lines.line_width = 1;
    cases.push_back({"lines(16, width 1)", lines});
    FieldSpec spike;
    spike.kind = FieldKind::spike;
    spike.size = 256;
    cases.push_back({"spike", spike});
    FieldSpec text;
    text.kind = FieldKind::text;
    text.size = 256;
    text.text = "PARALLAX";
    cases.push_back({"text PARALLAX", text});
    FieldSpec sine;
    sine.kind = FieldKind::sine;
    sine.size = 256;
    sine.frequency = 4.0f;
    cases.push_back({"sine", sine});
    FieldSpec bricks;
    bricks.kind = FieldKind::bricks;
    bricks.size = 256;
    bricks.count = 8;
    cases.push_back({"bricks", bricks});
    return cases;
}

constexpr double kAngles[] = {0.0, 30.0, 60.0, 75.0, 85.0, 89.0};

// Many rays (fixed seed) per field and angle, random uv over several tiles
// (wrap), random azimuth, the polygon at the top and half-way down.
TEST(MaxmipTrace, AgreesWithTheExactReferenceOnEveryFieldAndAngle) {
    constexpr int kRaysPerAngle = 1500;
    for (const double scale : kScales) {
        std::mt19937 rng(20240601);
        std::uniform_real_distribution<double> uv_dist(-3.0, 3.0);
        std::uniform_real_distribution<double> azimuth(0.0, 2.0 * kPi);
        std::printf("maxmip: relief %.2f deep, budget %d: max iterations per view angle (from the normal)\n", scale,
                    kBudget);
        std::vector<int> worst(std::size(kAngles), 0);
        long ill_conditioned = 0;
        long rays = 0;
        double max_walk_error = 0.0;
        double max_bound_use = 0.0;
        for (const FieldCase& c : agreement_fields()) {
            const HeightField q = reference::quantized_8bit(generate(c.spec));
            const MaxMipmap m = build(q);
            ASSERT_EQ(m.level_count(), 9);
            std::printf("  %-20s", c.name);
            for (size_t ai = 0; ai < std::size(kAngles); ++ai) {
                Agreement a;
                for (int r = 0; r < kRaysPerAngle; ++r) {
                    const glm::dvec2 uv(uv_dist(rng), uv_dist(rng));
                    const double polygon = r % 4 == 3 ? 0.5 : 1.0;
                    compare_view(q, m, uv, view_direction(kAngles[ai], azimuth(rng)), polygon, scale, kBudget, a);
                }
                std::printf(" %4.0f°:%4d", kAngles[ai], a.max_iterations);
                worst[ai] = std::max(worst[ai], a.max_iterations);
                ill_conditioned += a.ill_conditioned;
                rays += a.rays;
                max_walk_error = std::max(max_walk_error, a.max_walk_error);
                max_bound_use = std::max(max_bound_use, a.max_bound_use);
                EXPECT_EQ(a.disagreements, 0) << c.name << " at " << kAngles[ai] << " degrees, relief "
                                              << scale << ": " << a.disagreements << " of " << a.rays
                                              << " rays disagree (max error " << a.max_error << " texels)\n"
                                              << a.first_failures;
                EXPECT_EQ(a.exhausted, 0) << c.name << " at " << kAngles[ai] << " degrees";
                EXPECT_LE(a.max_iterations, kBudget);
            }
            std::printf("\n");
        }
        std::printf("  %-20s", "all fields");
        for (size_t ai = 0; ai < std::size(kAngles); ++ai) std::printf(" %4.0f°:%4d", kAngles[ai], worst[ai]);
        std::printf("\n  traversal error (float ray vs exact) max %.2g texels; %ld of %ld rays ill-conditioned at "
                    "float precision; iterations up to %.0f%% of top + 2 C + 1\n",
                    max_walk_error, ill_conditioned, rays, 100.0 * max_bound_use);
        // Ill-conditioned rays are the rare near-parallel ones, not a pattern.
        EXPECT_LT(ill_conditioned * 100, rays);
    }
}

// Past 89.1 degrees off the normal V.z < 1/64, where march.glsl clamps the
// divisor of the parallax vector. maxmip used to clamp there too, tracing a
// steeper ray than the camera's: 2 texels of mean error at 89 degrees on the
// bench (docs/accuracy.md, "At 89 degrees"). The exact ray must be traced up
// to the 89.9 degrees the bench measures, at the default budget
// (TechniqueOptions::max_steps), with the same agreement as everywhere else.
TEST(MaxmipTrace, RaysPastTheOldGrazingClampAreTheExactRay) {
    const int budget = TechniqueOptions{}.max_steps;
    constexpr int kRaysPerAngle = 400;
    std::mt19937 rng(89);
    std::uniform_real_distribution<double> uv_dist(-3.0, 3.0);
    std::uniform_real_distribution<double> azimuth(0.0, 2.0 * kPi);
    for (const double scale : kScales) {
        for (const FieldCase& c : agreement_fields()) {
            const HeightField q = reference::quantized_8bit(generate(c.spec));
            const MaxMipmap m = build(q);
            for (const double angle : {89.3, 89.6, 89.9}) {
                ASSERT_LT(std::cos(angle * kPi / 180.0), 1.0 / 64.0);
                Agreement a;
                double worst_direction = 0.0;
                for (int r = 0; r < kRaysPerAngle; ++r) {
                    const double polygon = r % 4 == 3 ? 0.5 : 1.0;
                    const glm::dvec2 uv(uv_dist(rng), uv_dist(rng));
                    const glm::dvec3 view = view_direction(angle, azimuth(rng));
                    // The ray walked must be the view ray rounded to float, not a
                    // clamped one: its direction within 2 ulps (float inputs; the
                    // scale product, V.z's rounding and the division, half an ulp
                    // each; the texel scale is a power of two, exact).
                    const glm::dvec2 exact(reference::view_ray(q, as_float(uv), as_float(view), scale, polygon).direction);
                    const glm::dvec2 got(reference::maxmip_view_ray(m, as_float(uv), as_float(view), scale, polygon).direction);
                    worst_direction = std::max(worst_direction, glm::length(got - exact) / glm::length(exact));
                    // 89.9 degrees runs up to ~15,000 texels per unit of height:
                    // 2 ulps (the position t * dir is rounded once by the product
                    // and once by the sum with the entry offset; the hit height
                    // once by t's update and once by the solve) of that is 0.0036
                    // texel, and as much again for the distance walked.
                    compare_view(q, m, uv, view, polygon, scale, budget, a, 2.0);
                }
                EXPECT_EQ(a.disagreements, 0) << c.name << " at " << angle << " degrees, relief " << scale << ": "
                                              << a.disagreements << " of " << a.rays << " rays disagree (max error "
                                              << a.max_error << " texels)\n"
                                              << a.first_failures;
                EXPECT_EQ(a.exhausted, 0) << c.name << " at " << angle << " degrees, relief " << scale
                                          << ": the budget of " << budget << " ran out";
                EXPECT_LE(worst_direction, 0x1p-22)
                    << c.name << " at " << angle << " degrees, relief " << scale
                    << ": the ray walked is not the view ray (relative direction error " << worst_direction << ")";
            }
        }
    }
}

// 1-texel lines crossed at grazing angles: the reference hits the lines
// (their cells are two texels of a tent profile, the thinnest feature the
// texture holds); the traversal must hit exactly the same line, never step
// over it, never stop at one the reference passes.
TEST(MaxmipTrace, NeverStepsOverAOneTexelLine) {
    FieldSpec spec;
    spec.kind = FieldKind::lines;
    spec.size = 256;
    spec.count = 4;
    spec.line_width = 1;
    const HeightField q = reference::quantized_8bit(generate(spec));
    const MaxMipmap m = build(q);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uv_dist(0.0, 1.0);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    Agreement a;
    for (double angle : {75.0, 85.0, 88.0, 89.0}) {
        for (int r = 0; r < 3000; ++r) {
            // Across the lines (azimuth near 0 or pi), mostly.
            const double az = (r % 2 == 0 ? 0.0 : kPi) + jitter(rng);
            compare_view(q, m, {uv_dist(rng), uv_dist(rng)}, view_direction(angle, az), 1.0, kHeightScale, kBudget, a);
        }
    }
    EXPECT_GT(a.line_hits, 1000) << "the rays should hit lines, or the test shows nothing";
    EXPECT_EQ(a.disagreements, 0) << a.disagreements << " of " << a.rays << " (max error " << a.max_error
                                  << " texels)\n"
                                  << a.first_failures;
    EXPECT_EQ(a.exhausted, 0);
    std::printf("maxmip: 1-texel lines: %ld of %ld rays hit a line, max %d iterations, max error %.2g texels\n",
                a.line_hits, a.rays, a.max_iterations, a.max_error);
}

// Rays starting exactly on cell boundaries and corners, moving along the
// axes and diagonals (exits exactly on boundaries, ties between x and y),
// and vertical rays: each must agree with the reference and terminate.
TEST(MaxmipTrace, BoundaryAlignedAndVerticalRays) {
    FieldSpec spec;
    spec.kind = FieldKind::spike;
    spec.size = 64;
    const HeightField spike = reference::quantized_8bit(generate(spec));
    spec.kind = FieldKind::lines;
    spec.count = 8;
    const HeightField lines = reference::quantized_8bit(generate(spec));
    spec.kind = FieldKind::sine;
    const HeightField sine = reference::quantized_8bit(generate(spec));
    Agreement a;
    for (const HeightField* f : {&spike, &lines, &sine}) {
        const MaxMipmap m = build(*f);
        for (int ty = 0; ty < 64; ty += 3)
            for (int tx = 0; tx < 64; tx += 5) {
                // Texel space x = i + 0.5 is a cell boundary; x = i the middle of one.
                for (double off : {0.5, 0.0}) {
                    const glm::dvec2 uv((tx + off) / 64.0, (ty + off) / 64.0);
                    for (int k = 0; k < 8; ++k) {
                        const double az = k * kPi / 4.0;
                        for (double angle : {0.0, 45.0, 80.0})
                            compare_view(*f, m, uv, view_direction(angle, az), 1.0, kHeightScale, kBudget, a);
                    }
                }
            }
    }
    EXPECT_EQ(a.disagreements, 0) << a.first_failures;
    EXPECT_EQ(a.exhausted, 0);
}

// The worst case of any quadtree walk: a grazing ray sliding along a
// 1-texel line, in the cells right beside it. Every node holding the ray
// also holds the line, so the walk goes cell by cell: the iterations grow
// with the cells crossed (and stay within top + 2 C + 1), which is why the
// budget has to grow with height_scale * tan(angle) * size.
TEST(MaxmipTrace, WorstCaseIsBoundedByTheCellsCrossed) {
    FieldSpec spec;
    spec.kind = FieldKind::lines;
    spec.size = 256;
    spec.count = 4;  // lines at texels 32, 96, 160, 224
    const HeightField q = reference::quantized_8bit(generate(spec));
    const MaxMipmap m = build(q);
    constexpr int kLargeBudget = 1 << 14;
    int worst = 0;
    long worst_cells = 0;
    Agreement a;
    for (const double scale : kScales) {
        for (const double angle : {85.0, 89.0}) {
            for (int k = 0; k < 40; ++k) {
                // Texel x 33.6: cell 33, beside the line's cells 31 and 32 (the
                // cells with texel 32 as a corner), seen from -v so the ray runs
                // along +v, parallel to the line to within 2e-4 rad.
                const glm::dvec2 uv(33.6 / 256.0, 0.5 + k / 97.0);
                const double az = -0.5 * kPi + (k % 5 - 2) * 1e-4;
                compare_view(q, m, uv, view_direction(angle, az), 1.0, scale, kLargeBudget, a);
                const reference::MaxmipHit got = reference::maxmip_trace_view(
                    m, q, as_float(uv), as_float(view_direction(angle, az)), scale, 1.0, kLargeBudget);
                const reference::Hit truth = reference::first_hit(
                    q, reference::maxmip_view_ray(m, as_float(uv), as_float(view_direction(angle, az)), scale, 1.0),
                    0.0, 1.0);
                if (got.iterations > worst) {
                    worst = got.iterations;
                    worst_cells = truth.cells_visited;
                }
            }
        }
    }
    EXPECT_EQ(a.disagreements, 0) << a.first_failures;
    EXPECT_EQ(a.exhausted, 0);
    EXPECT_LE(a.max_bound_use, 1.0);
    // It really is the bad case: hundreds of cells, walked one by one.
    EXPECT_GT(worst, 500);
    std::printf("maxmip: ray sliding beside a 1-texel line: up to %d iterations for %ld cells crossed "
                "(%.0f%% of the bound top + 2 C + 1)\n",
                worst, worst_cells, 100.0 * a.max_bound_use);
}

// The ray form (maxmip_first_hit) against first_hit, including rays that
// start above the relief's top and steep and shallow slopes.
TEST(MaxmipTrace, FirstHitAgreesWithReferenceFirstHit) {
    FieldSpec spec;
    spec.kind = FieldKind::text;
    spec.size = 128;
    spec.text = "ES";
    const HeightField q = reference::quantized_8bit(generate(spec));
    const MaxMipmap m = build(q);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> pos(-200.0, 300.0);
    std::uniform_real_distribution<double> dir(-60.0, 60.0);
    std::uniform_real_distribution<double> start(1.0, 1.5);
    int checked = 0;
    for (int r = 0; r < 2000; ++r) {
        reference::Ray ray;
        ray.origin = {pos(rng), pos(rng), start(rng)};
        ray.direction = {dir(rng), dir(rng), -0.5};
        const reference::Hit truth = reference::first_hit(q, ray, 0.0, ray.origin.z / 0.5);
        const reference::MaxmipHit got = reference::maxmip_first_hit(m, q, ray, kBudget);
        ASSERT_TRUE(truth.hit);
        ASSERT_TRUE(got.hit) << r;
        ASSERT_FALSE(got.budget_exhausted);
        const double error = glm::length(glm::dvec2(got.position) - glm::dvec2(truth.position));
        EXPECT_LE(error, kTolerance) << "ray " << r << ": reference (" << truth.position.x << ", " << truth.position.y
                                     << ", " << truth.position.z << "), maxmip (" << got.position.x << ", "
                                     << got.position.y << ", " << got.position.z << ")";
        EXPECT_NEAR(got.t, truth.t, 1e-4);
        ++checked;
    }
    EXPECT_EQ(checked, 2000);
    // A ray that does not descend has no hit.
    reference::Ray up;
    up.origin = {10, 10, 0.5};
    up.direction = {1, 0, 0.1};
    EXPECT_FALSE(reference::maxmip_first_hit(m, q, up, kBudget).hit);
}

// A budget too small to finish is reported, never silently taken as a hit,
// and the point returned is still above the surface (conservative).
TEST(MaxmipTrace, ExhaustedBudgetIsReported) {
    FieldSpec spec;
    spec.kind = FieldKind::lines;
    spec.size = 256;
    spec.count = 16;
    const HeightField q = reference::quantized_8bit(generate(spec));
    const MaxMipmap m = build(q);
    const reference::MaxmipHit got =
        reference::maxmip_trace_view(m, q, {0.3, 0.4}, view_direction(89.0, 0.1), kHeightScale, 1.0, 4);
    EXPECT_TRUE(got.budget_exhausted);
    EXPECT_FALSE(got.hit);
    EXPECT_EQ(got.iterations, 4);
    EXPECT_GE(got.height, q.sample_bilinear(got.uv.x, got.uv.y) - 1e-6);
}

}  // namespace
}  // namespace px
