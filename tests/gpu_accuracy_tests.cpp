// Accuracy against the exact CPU reference (src/reference/), measured on what
// the shader computed (its debug outputs), on both ES versions.
#include "gpu_fixture.h"

#include "profiling/bench.h"
#include "reference/reference_image.h"
#include "render/surface_capture.h"

namespace px::test {
namespace {

struct Measured {
    reference::ErrorMetrics error;
};

// Mean hit-uv error in texels of `technique` at `samples` on a bench scene.
reference::ErrorMetrics measure(const std::string& scene_name, double angle, Technique technique, int samples,
                                const reference::ReferenceImage& truth) {
    auto scene = profiling::bench_scene(scene_name, angle);
    EXPECT_TRUE(scene.ok());
    scene->materials[0].technique.technique = technique;
    scene->materials[0].technique.min_samples = scene->materials[0].technique.max_samples = samples;
    auto renderer = Renderer::create();
    EXPECT_TRUE(renderer.ok());
    Status loaded = (*renderer)->load(*scene);
    EXPECT_TRUE(loaded.ok()) << loaded.error().message;
    auto surfaces = capture_surfaces(**renderer, truth.surface.width, truth.surface.height);
    EXPECT_TRUE(surfaces.ok()) << surfaces.error().message;
    auto error = reference::compare_surfaces(*surfaces, truth.surface, truth.texture_width, truth.texture_height);
    EXPECT_TRUE(error.ok());
    return *error;
}

// POM and relief converge to the reference as the linear search gets finer,
// and reach it (0.1 texel mean) at the top sample count on a smooth field.
TEST(Accuracy, PomAndReliefConvergeToTheReferenceOnASmoothField) {
    const double angle = 75.0;
    auto scene = profiling::bench_scene("sine", angle);
    ASSERT_TRUE(scene.ok());
    auto truth = reference::render_reference(*scene, 128, 128);
    ASSERT_TRUE(truth.ok()) << truth.error().message;
    for (Technique t : {Technique::pom, Technique::relief}) {
        const double coarse = measure("sine", angle, t, 8, *truth).uv_error_mean;
        const double middle = measure("sine", angle, t, 32, *truth).uv_error_mean;
        const reference::ErrorMetrics fine = measure("sine", angle, t, 256, *truth);
        EXPECT_GT(coarse, middle) << technique_name(t) << ": 32 samples are no better than 8";
        EXPECT_GE(middle + 0.01, fine.uv_error_mean) << technique_name(t) << ": 256 samples are worse than 32";
        EXPECT_LE(fine.uv_error_mean, 0.1) << technique_name(t) << " at 256 samples misses the reference";
        EXPECT_GT(fine.pixels, 1000) << "the plane must cover the image";
    }
}

// Normal mapping ignores the relief: its error is the parallax it leaves out,
// far above what POM achieves on the same pixels.
TEST(Accuracy, NormalMappingErrorIsTheMissingParallax) {
    auto scene = profiling::bench_scene("sine", 60.0);
    ASSERT_TRUE(scene.ok());
    auto truth = reference::render_reference(*scene, 128, 128);
    ASSERT_TRUE(truth.ok());
    const double normal = measure("sine", 60.0, Technique::normal, 0, *truth).uv_error_mean;
    const double pom = measure("sine", 60.0, Technique::pom, 64, *truth).uv_error_mean;
    EXPECT_GT(normal, 10.0 * pom);
    EXPECT_GT(normal, 2.0);  // the sine relief is 0.08 tiles deep: ~35 texels of parallax at 60 degrees
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

// maxmip is exact: on every bench scene, thin raised text included, up to 85
// degrees off the normal, its mean hit error is within 0.1 texel of the
// reference (it solves each bilinear patch in closed form and skips only
// space the max pyramid proves empty). ES 3.0 only: on ES 2.0 the planner
// substitutes relief (tested in gpu_render_tests.cpp); ctest's gpu_es2 leaves
// this test out (tests/CMakeLists.txt) so that its skip does not mark the run.
TEST(Accuracy, MaxmipMeetsTheReferenceOnEveryBenchScene) {
    if (test_es_major() < 3) GTEST_SKIP() << "maxmip needs OpenGL ES 3.0; this run is ES 2.0";
    for (const std::string& scene_name : profiling::bench_scene_names()) {
        for (double angle : {0.0, 60.0, 85.0}) {
            auto scene = profiling::bench_scene(scene_name, angle);
            ASSERT_TRUE(scene.ok());
            auto truth = reference::render_reference(*scene, 96, 96);
            ASSERT_TRUE(truth.ok()) << truth.error().message;
            const reference::ErrorMetrics e = measure(scene_name, angle, Technique::maxmip, 0, *truth);
            EXPECT_LE(e.uv_error_mean, 0.1) << scene_name << " at " << angle << " degrees";
            EXPECT_GT(e.pixels, 500) << scene_name << " at " << angle << " degrees";
        }
    }
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

// maxmip at the grazing limit: 89 and 89.9 degrees, where V.z < 1/64 on the
// plane's far rows. A clamp of V.z there (march.glsl's, which maxmip used to
// share) traced a steeper ray than the camera's: 2 texels of mean error at
// 89 degrees on sine, all of it on the rows past the clamp (docs/accuracy.md,
// "At 89 degrees"). 127 pixels, an odd size: the middle row and column pass
// through the view target, so 89.9 degrees, whose plane spans 0.16 of the 45
// degrees of view (less than a row of 128), still covers a row of pixel
// centres, and the middle ray runs along the field's symmetry line, the
// costliest walk (2310 iterations on hemispheres).
//
// The bound, 0.05 texel, on the whole image and on every row (an error
// confined to rows is what the clamp left): the walk is exact to 1e-3 texel
// (tests/unit_maxmip.cpp); the rest is the rasteriser's input, the uv and
// view vector interpolated from vertices snapped to 1/256 pixel (llvmpipe's
// 8 subpixel bits): a pixel here spans 1.5 to 4.6 texels across the ray, so
// that moves a hit by at most 0.018 texel.
TEST(Accuracy, MaxmipMeetsTheReferenceAtGrazingAngles) {
    if (test_es_major() < 3) GTEST_SKIP() << "maxmip needs OpenGL ES 3.0; this run is ES 2.0";
    constexpr int kSize = 127;
    constexpr double kBound = 0.05;
    for (const std::string& scene_name : profiling::bench_scene_names()) {
        for (double angle : {89.0, 89.9}) {
            auto scene = profiling::bench_scene(scene_name, angle);
            ASSERT_TRUE(scene.ok());
            reference::ReferenceOptions reference_options;
            reference_options.shadow = profiling::bench_scene_shadow(scene_name);
            auto truth = reference::render_reference(*scene, kSize, kSize, reference_options);
            ASSERT_TRUE(truth.ok()) << truth.error().message;
            scene->materials[0].technique.technique = Technique::maxmip;
            scene->materials[0].technique.shadow = reference_options.shadow;
            auto renderer = Renderer::create();
            ASSERT_TRUE(renderer.ok());
            Status loaded = (*renderer)->load(*scene);
            ASSERT_TRUE(loaded.ok()) << loaded.error().message;
            auto surfaces = capture_surfaces(**renderer, kSize, kSize);
            ASSERT_TRUE(surfaces.ok()) << surfaces.error().message;
            const std::string where = scene_name + " at " + std::to_string(angle) + " degrees";
            auto whole = reference::compare_surfaces(*surfaces, truth->surface, truth->texture_width,
                                                     truth->texture_height);
            ASSERT_TRUE(whole.ok());
            EXPECT_LT(whole->uv_error_mean, kBound) << where << " (max " << whole->uv_error_max << " texels)";
            // 89 degrees covers 4 rows of 127 pixels, 89.9 one.
            EXPECT_GE(whole->pixels, angle < 89.5 ? 4 * kSize : kSize) << where;
            for (int y = 0; y < kSize; ++y) {
                SurfaceImage measured_row, truth_row;
                measured_row.width = truth_row.width = kSize;
                measured_row.height = truth_row.height = 1;
                measured_row.packing_bits = surfaces->packing_bits;
                for (int x = 0; x < kSize; ++x) {
                    measured_row.samples.push_back(surfaces->at(x, y));
                    truth_row.samples.push_back(truth->surface.at(x, y));
                }
                auto row = reference::compare_surfaces(measured_row, truth_row, truth->texture_width,
                                                       truth->texture_height);
                ASSERT_TRUE(row.ok());
                if (row->pixels > 0)
                    EXPECT_LT(row->uv_error_mean, kBound)
                        << where << ", row " << y << ": " << row->pixels << " pixels, max " << row->uv_error_max
                        << " texels, mean depth error " << row->depth_error_mean << " of the relief";
            }
        }
    }
}

}  // namespace
}  // namespace px::test
