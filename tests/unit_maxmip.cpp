// Unit tests for the maxmip technique's CPU side: the maximum mip-map over
// the bilinearly filtered field (assets/max_mipmap.h). The traversal itself
// is tested where it runs, on the GPU: tests/gpu_accuracy_tests.cpp and the
// stability catalogue (tests/stability/catalogue.jsonc) hold maxmip.frag to
// the exact reference, and its precision is emulated on the shader itself
// (src/emulation). The hand-written CPU mirror it replaced could drift from
// the shader; it did, by clamping the same way (docs/accuracy.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "parallaxes/assets/heightfield.h"
#include "parallaxes/assets/max_mipmap.h"
#include "parallaxes/effects/technique.h"
#include "parallaxes/reference/tracer.h"

namespace px {
namespace {

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


}  // namespace
}  // namespace px

namespace px {
namespace {

// GLSL ES 1.00's atlas holds the same pyramid: every node of every level at
// max_atlas_origin, no two levels overlapping, and each cell's four corner
// bytes (wrapping) in RGBA of its texel in the base block; square and
// non-square fields, both ways round.
TEST(MaxAtlas, HoldsEveryLevelAtItsOriginAndTheCornersOfEachCell) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (const std::pair<int, int>& size : {std::pair<int, int>{16, 16}, {64, 4}, {4, 64}, {1, 8}, {8, 1}, {32, 2}}) {
        const int w = size.first, h = size.second;  // not a structured binding: the lambda below captures them
        HeightField field;
        field.width = w;
        field.height = h;
        for (int i = 0; i < w * h; ++i) field.texels.push_back(unit(rng));
        const MaxMipmap pyramid = build(field);
        Result<MaxAtlas> atlas = build_max_atlas(field);
        ASSERT_TRUE(atlas.ok()) << atlas.error().message;
        const std::string where = std::to_string(w) + "x" + std::to_string(h);
        ASSERT_EQ(atlas->levels, pyramid.level_count()) << where;
        EXPECT_EQ(atlas->image.width, w + std::max(1, w / 2)) << where;
        std::vector<int> owner(static_cast<size_t>(atlas->image.width) * atlas->image.height, -1);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::uint8_t* t = atlas->image.texel(x, y);
                const auto byte = [&](int dx, int dy) {
                    return static_cast<int>(std::lround(field.at((x + dx) % w, (y + dy) % h) * 255.0f));
                };
                EXPECT_EQ(t[0], byte(0, 0)) << where;
                EXPECT_EQ(t[1], byte(1, 0)) << where;
                EXPECT_EQ(t[2], byte(0, 1)) << where;
                EXPECT_EQ(t[3], byte(1, 1)) << where;
                EXPECT_EQ(std::max({t[0], t[1], t[2], t[3]}), pyramid.max_byte(0, x, y)) << where;
                owner[static_cast<size_t>(y) * atlas->image.width + x] = 0;
            }
        for (int level = 1; level < pyramid.level_count(); ++level) {
            const Image& src = pyramid.levels[static_cast<size_t>(level)];
            const AtlasOrigin o = max_atlas_origin(w, h, level);
            for (int y = 0; y < src.height; ++y)
                for (int x = 0; x < src.width; ++x) {
                    ASSERT_LT(o.x + x, atlas->image.width) << where << " level " << level;
                    ASSERT_LT(o.y + y, atlas->image.height) << where << " level " << level;
                    int& who = owner[static_cast<size_t>(o.y + y) * atlas->image.width + o.x + x];
                    EXPECT_EQ(who, -1) << where << ": level " << level << " overlaps level " << who;
                    who = level;
                    EXPECT_EQ(atlas->image.texel(o.x + x, o.y + y)[0], pyramid.max_byte(level, x, y)) << where;
                }
        }
    }
}

}  // namespace
}  // namespace px
