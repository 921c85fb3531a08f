// Accuracy against the exact CPU reference (src/reference/), measured on what
// the shader computed (its debug outputs), on both ES versions.
#include "gpu_fixture.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <utility>
#include <vector>

#include "parallaxes/profiling/measurement/bench.h"
#include "parallaxes/profiling/measurement/stability.h"
#include "parallaxes/profiling/measurement/work.h"
#include "parallaxes/reference/reference_image.h"
#include "parallaxes/render/surface_capture.h"
#include "parallaxes/scene/material_images.h"

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
// space the max pyramid proves empty). On both contexts: GLSL ES 1.00 walks
// the same pyramid from one atlas (assets/max_mipmap.h build_max_atlas).
TEST(Accuracy, MaxmipMeetsTheReferenceOnEveryBenchScene) {
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

namespace px::test {
namespace {

struct ImpliedDepth {
    double height = 0.0;  // where the exact view ray passes over the hit uv (0 bottom, 1 top)
    long pixels = 0;
};

// One 4-unit quad (one segment, so the vertex stage runs only at its
// corners), seen from 2 units at 35 degrees, a flat field at level 0 0.08
// deep under it: every view ray must reach the bottom, height 0. The shader
// reports height 0 whatever ray it walked (the field is flat), so the depth
// is read from the hit uv instead: with uv0 the pixel's polygon uv (normal
// mapping's hit) and p = uv0 - reference hit (the exact ray's shift from the
// polygon down to the bottom), a hit uv0 - D p lies on the exact ray at
// height 1 - D. D is fitted over the pixels whose shift is at least 4 texels.
ImpliedDepth implied_depth(Technique technique, const TechniqueOptions& options) {
    PlaneScene p;
    p.field.kind = FieldKind::flat;
    p.field.level = 0.0f;
    p.field.size = 256;
    p.technique = technique;
    p.options = options;
    p.view_angle_deg = 35.0f;
    p.distance = 2.0f;
    p.fov_deg = 60.0f;
    SceneDesc scene = p.build();
    scene.objects[0].mesh.size = 4.0f;
    scene.objects[0].mesh.segments = 1;
    constexpr int kSize = 96;
    auto capture = [&](Technique t) {
        SceneDesc s = scene;
        s.materials[0].technique.technique = t;
        auto renderer = Renderer::create();
        EXPECT_TRUE(renderer.ok());
        Status loaded = (*renderer)->load(s);
        EXPECT_TRUE(loaded.ok()) << loaded.error().message;
        auto surfaces = capture_surfaces(**renderer, kSize, kSize);
        EXPECT_TRUE(surfaces.ok()) << surfaces.error().message;
        return *surfaces;
    };
    const SurfaceImage polygon = capture(Technique::normal);
    const SurfaceImage hit = capture(technique);
    auto truth = reference::render_reference(scene, kSize, kSize);
    EXPECT_TRUE(truth.ok());
    const glm::dvec2 texels(256.0);
    auto wrapped = [](glm::dvec2 d) { return d - glm::round(d); };  // ES 2.0 reads uvs modulo the tile
    double along = 0.0, squared = 0.0;
    ImpliedDepth out;
    for (size_t i = 0; i < hit.samples.size(); ++i) {
        const SurfaceSample& h = hit.samples[i];
        const SurfaceSample& uv0 = polygon.samples[i];
        const SurfaceSample& t = truth->surface.samples[i];
        if (!h.covered || !uv0.covered || !t.covered) continue;
        const glm::dvec2 shift = wrapped(uv0.uv - t.uv) * texels;
        if (glm::length(shift) < 4.0) continue;
        along += glm::dot(wrapped(uv0.uv - h.uv) * texels, shift);
        squared += glm::dot(shift, shift);
        ++out.pixels;
    }
    out.height = squared > 0.0 ? 1.0 - along / squared : 1.0;
    return out;
}

// The default view vector is the exact one (interpolated unnormalised in
// highp, normalised per fragment) for every technique that reads height; the
// PowerVR whitepaper's per-vertex normalisation is an opt-in
// (`"exact_view": false`), and this shows what it costs on a big polygon.
//
// Bound at the default, 0.005 of the relief depth: the reference and the GPU
// share nothing but the scene, so the GPU's uv0 carries the rasteriser's
// vertex snap (1/256 pixel, here 7e-5 units of the 4-unit quad: 0.0045
// texel), which over shifts of at least 4 texels is 0.0011 of the depth; the
// interpolated view vector's direction moves by 3.5e-5 (relative) over that
// snap, fp32 adds 1e-6 and the ES 2.0 packing 24 bits of a tile (1.5e-5
// texel). 0.005 is twice their sum, rounded up. The linear techniques land
// on the bottom exactly (steep's last layer is height 0; pom and relief
// interpolate onto it; parallax reads the flat field's true height);
// offset limiting drops V.z by design, so it is not among them.
TEST(Accuracy, ExactViewIsTheDefaultAndPlacesTheReliefAtItsDepth) {
    constexpr double kBound = 0.005;
    EXPECT_TRUE(TechniqueOptions{}.exact_view);
    for (Technique t : {Technique::parallax, Technique::steep, Technique::pom, Technique::relief, Technique::maxmip}) {
        if (technique_info(t).min_es_major > test_es_major()) continue;
        TechniqueOptions options;
        options.min_samples = options.max_samples = 64;
        const ImpliedDepth exact = implied_depth(t, options);
        EXPECT_GT(exact.pixels, 1000) << technique_name(t);
        EXPECT_NEAR(exact.height, 0.0, kBound) << technique_name(t) << " at the default view vector: the level-0 "
                                               << "field shows at height " << exact.height << " of the relief";
        if (technique_info(t).always_exact_view) continue;
        options.exact_view = false;
        const ImpliedDepth per_vertex = implied_depth(t, options);
        // What the opt-in costs: measurably off, far past the exact path's bound.
        EXPECT_GT(per_vertex.height, 10.0 * kBound)
            << technique_name(t) << " with the per-vertex view vector: the level-0 field shows at height "
            << per_vertex.height;
        std::printf("%s: the level-0 field shows at height %.4f with the exact view vector, %.4f per vertex\n",
                    technique_name(t), exact.height, per_vertex.height);
    }
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

// The displaced plane (real geometry, drawn with normal mapping as the bench
// draws displaced_mesh) at uv scale `uv_scale`, against the exact reference
// of the same scene: the mean hit-uv error in texels.
reference::ErrorMetrics displaced_error(const std::string& scene_name, double angle, float uv_scale) {
    auto scene = profiling::bench_scene(scene_name, angle);
    EXPECT_TRUE(scene.ok());
    scene->materials[0].uv.scale = glm::vec2(uv_scale);
    constexpr int kSize = 128;
    auto truth = reference::render_reference(*scene, kSize, kSize);  // pom marks the plane as relief
    EXPECT_TRUE(truth.ok()) << truth.error().message;
    scene->materials[0].technique.technique = Technique::normal;
    scene->objects[0].mesh.displaced = true;
    auto renderer = Renderer::create();
    EXPECT_TRUE(renderer.ok());
    Status loaded = (*renderer)->load(*scene);
    EXPECT_TRUE(loaded.ok()) << loaded.error().message;
    auto surfaces = capture_surfaces(**renderer, kSize, kSize);
    EXPECT_TRUE(surfaces.ok()) << surfaces.error().message;
    // Normal mapping reports the polygon's height; the mesh's is the field's at its uv (as the bench).
    auto images = build_material_images(scene->materials[0], scene->base_dir);
    EXPECT_TRUE(images.ok());
    const HeightField field = quantized_8bit(images->field);
    for (SurfaceSample& s : surfaces->samples)
        if (s.covered) s.height = field.sample_bilinear(s.uv.x, s.uv.y);
    auto error = reference::compare_surfaces(*surfaces, truth->surface, truth->texture_width, truth->texture_height);
    EXPECT_TRUE(error.ok());
    return *error;
}

// The displaced baseline follows the material's uv transform: at uv scale 2
// and 3 the relief lies under the tiles the shading shows. It used to place
// one tile of relief across the plane under s x s tiles of shading: errors
// of the parallax's size (tens of texels at 60 degrees on sine).
//
// The bound, s times the scale-1 error: the grid is the same lattice in
// texel space at every scale (one vertex per texel of uv'), and each pixel's
// view vector in the texture frame does not depend on the scale, so a ray's
// geometry error (the triangulated field against the bilinear one) is the
// same function of where it enters the tile; only the share of pixels at
// the relief's silhouettes, where a small geometry error switches the
// surface hit, grows with the tiles across the image, s times. Fields with
// round features only (sine, hemispheres): a brick edge parallel to the
// pixel rows puts a whole row (1% of the image) in or out of its half-texel
// band at once, a sampling accident that no per-ray argument bounds.
TEST(Accuracy, DisplacedMeshFollowsTheUvScale) {
    for (const auto& [scene_name, angle] : {std::pair<std::string, double>{"sine", 60.0}, {"hemispheres", 45.0}}) {
        const reference::ErrorMetrics one = displaced_error(scene_name, angle, 1.0f);
        EXPECT_GT(one.pixels, 1000) << scene_name;
        for (float s : {2.0f, 3.0f}) {
            const reference::ErrorMetrics e = displaced_error(scene_name, angle, s);
            EXPECT_GT(e.pixels, 1000) << scene_name << " at uv scale " << s;
            EXPECT_LE(e.uv_error_mean, s * one.uv_error_mean)
                << scene_name << " at " << angle << " degrees, uv scale " << s << ": " << e.uv_error_mean
                << " texels against " << one.uv_error_mean << " at scale 1";
            std::printf("displaced %s at %.0f degrees: uv scale 1 %.4f texels (p95 %.3f, max %.2f, wrong %.4f), "
                        "%.0f: %.4f (p95 %.3f, max %.2f, wrong %.4f)\n",
                        scene_name.c_str(), angle, one.uv_error_mean, one.uv_error_p95, one.uv_error_max,
                        one.wrong_surface_share, s, e.uv_error_mean, e.uv_error_p95, e.uv_error_max,
                        e.wrong_surface_share);
        }
    }
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

struct AuthoredFrame {
    const char* what;
    std::optional<glm::vec3> tangent, normal;
};

// What one draw of `scene` computed: its debug surfaces and its colour.
struct Drawn {
    SurfaceImage surfaces;
    Image color;
};

Drawn draw_scene(const SceneDesc& scene, int size) {
    Drawn out;
    auto renderer = Renderer::create();
    EXPECT_TRUE(renderer.ok());
    Status loaded = (*renderer)->load(scene);
    EXPECT_TRUE(loaded.ok()) << loaded.error().message;
    auto surfaces = capture_surfaces(**renderer, size, size);
    EXPECT_TRUE(surfaces.ok()) << surfaces.error().message;
    if (surfaces.ok()) out.surfaces = std::move(*surfaces);
    out.color = render(scene, size).image;
    return out;
}

// Covered pixels whose hit uv, height or visibility is not finite (a NaN
// frame in the vertex stage reaches all three through the view vector).
long non_finite_pixels(const SurfaceImage& s) {
    long n = 0;
    for (const SurfaceSample& p : s.samples)
        if (p.covered && !(std::isfinite(p.uv.x) && std::isfinite(p.uv.y) && std::isfinite(p.height) &&
                           std::isfinite(p.visibility)))
            ++n;
    return n;
}

// A plane's authored frame may be degenerate (zero normal, zero tangent, a
// tangent along the normal) or skewed; surface.vert falls back to, or
// Gram-Schmidts onto, the default frame (+u, +z) in every such case here,
// and the exact reference applies the same rule. Every technique this ES
// version runs: no NaN/Inf in the debug outputs, the same hits and colour as
// the default frame, and the same error against the reference.
//
// Bounds. The fallback and Gram-Schmidt frames are the default one up to
// fp32 rounding (1e-7 relative; [1, 0, 0.5] - n 0.5 is exact), which moves a
// hit by 1e-7 of its parallax (under 40 texels at 60 degrees): 4e-6 texel.
// A march's step may still flip where a sample lands on a crossing; 1e-3
// texel of mean over the ~5000 covered pixels lets one pixel in 1000 jump a
// texel, and stays 100 times under the techniques' own errors. The colour:
// the same frame up to rounding is at most one unit of 8 bits apart.
// maxmip is exact, so it also keeps Accuracy's bound of 0.1 texel to the
// reference (MaxmipMeetsTheReferenceOnEveryBenchScene).
TEST(Accuracy, DegenerateAuthoredFramesFallBackToAUsableFrame) {
    constexpr int kSize = 96;
    constexpr double kSameHits = 1e-3;
    const std::vector<AuthoredFrame> frames = {
        {"normal [0, 0, 0]", std::nullopt, glm::vec3(0.0f)},
        {"tangent [0, 0, 0]", glm::vec3(0.0f), std::nullopt},
        {"tangent [0, 0, 1] along the normal", glm::vec3(0.0f, 0.0f, 1.0f), std::nullopt},
        {"skewed tangent [1, 0, 0.5]", glm::vec3(1.0f, 0.0f, 0.5f), std::nullopt},
    };
    auto base = profiling::bench_scene("sine", 60.0);
    ASSERT_TRUE(base.ok());
    auto with_frame = [&](const AuthoredFrame* f) {
        SceneDesc s = *base;
        if (f) {
            s.objects[0].mesh.tangent = f->tangent;
            s.objects[0].mesh.normal = f->normal;
        }
        return s;
    };
    auto default_truth = reference::render_reference(with_frame(nullptr), kSize, kSize);
    ASSERT_TRUE(default_truth.ok()) << default_truth.error().message;
    std::vector<reference::ReferenceImage> truths;
    for (const AuthoredFrame& f : frames) {
        auto truth = reference::render_reference(with_frame(&f), kSize, kSize);
        ASSERT_TRUE(truth.ok()) << f.what << ": " << truth.error().message;
        // The reference's own frame falls back to the default one too.
        auto same = reference::compare_surfaces(truth->surface, default_truth->surface, truth->texture_width,
                                                truth->texture_height);
        ASSERT_TRUE(same.ok());
        EXPECT_LT(same->uv_error_mean, 1e-9) << f.what << ": the reference's frame is not the default one";
        truths.push_back(std::move(*truth));
    }
    for (const TechniqueInfo& info : technique_table()) {
        if (info.min_es_major > test_es_major()) continue;
        auto set_technique = [&](SceneDesc s) {
            s.materials[0].technique.technique = info.id;
            if (info.options & kOptSamples)  // the march techniques at Accuracy's 64 samples
                s.materials[0].technique.min_samples = s.materials[0].technique.max_samples = 64;
            return s;
        };
        const Drawn plain = draw_scene(set_technique(with_frame(nullptr)), kSize);
        ASSERT_EQ(non_finite_pixels(plain.surfaces), 0) << info.name << " with the default frame";
        const bool traced = (info.options & kOptHeight) != 0;
        double plain_error = 0.0;
        if (traced) {
            auto e = reference::compare_surfaces(plain.surfaces, default_truth->surface, default_truth->texture_width,
                                                 default_truth->texture_height);
            ASSERT_TRUE(e.ok());
            plain_error = e->uv_error_mean;
        }
        for (size_t i = 0; i < frames.size(); ++i) {
            const std::string where = std::string(info.name) + ", " + frames[i].what;
            const Drawn d = draw_scene(set_technique(with_frame(&frames[i])), kSize);
            long covered = 0;
            for (const SurfaceSample& p : d.surfaces.samples) covered += p.covered ? 1 : 0;
            EXPECT_GT(covered, 1000) << where;
            EXPECT_EQ(non_finite_pixels(d.surfaces), 0) << where << ": non-finite debug outputs";
            auto same = reference::compare_surfaces(d.surfaces, plain.surfaces, truths[i].texture_width,
                                                    truths[i].texture_height);
            ASSERT_TRUE(same.ok());
            EXPECT_LE(same->uv_error_mean, kSameHits) << where << ": hits differ from the default frame's";
            EXPECT_LE(compare(d.color, plain.color).max, 1) << where << ": colour differs from the default frame's";
            if (!traced) continue;
            auto e = reference::compare_surfaces(d.surfaces, truths[i].surface, truths[i].texture_width,
                                                 truths[i].texture_height);
            ASSERT_TRUE(e.ok());
            EXPECT_GT(e->pixels, 1000) << where;
            EXPECT_NEAR(e->uv_error_mean, plain_error, kSameHits) << where << " against the reference";
            if (info.id == Technique::maxmip) EXPECT_LE(e->uv_error_mean, 0.1) << where << " against the reference";
        }
    }
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

struct CompositeCase {
    reference::ObjectError wall, board;
};

// The GPU's capture of `scene` (depth_write on the wall or not) against the
// reference, per object.
CompositeCase composite_case(SceneDesc scene, bool depth_write, const reference::ReferenceImage& truth) {
    scene.materials[0].technique.depth_write = depth_write;
    auto renderer = Renderer::create();
    EXPECT_TRUE(renderer.ok());
    Status loaded = (*renderer)->load(scene);
    EXPECT_TRUE(loaded.ok()) << loaded.error().message;
    auto surfaces = capture_surfaces(**renderer, truth.surface.width, truth.surface.height);
    EXPECT_TRUE(surfaces.ok()) << surfaces.error().message;
    CompositeCase c;
    auto wall = reference::compare_object(*surfaces, truth, 0);
    auto board = reference::compare_object(*surfaces, truth, 1);
    EXPECT_TRUE(wall.ok() && board.ok());
    if (wall.ok()) c.wall = *wall;
    if (board.ok()) c.board = *board;
    return c;
}

// The reference's depth compositing against the GPU's depth_write: a sine
// relief (0.2 units deep; pom, 64 samples, 45 degrees off the normal)
// pierced at mid-depth by a board whose relief is flat at its top (so it is
// its polygon), its uv offset by half a tile so that wherever one object
// shows instead of the other, the uv is off by many texels. Composited, the
// board shows where the relief's hit is behind it and the relief where it is
// in front; drawn with depth_write, the GPU agrees but for a few pixels
// along the contour where they cross (2 of 5514 of the board's). Without
// depth_write the wall's polygon hides the board: the board's pixels inside
// the wall show the wall (the error depth correction removes), and the plain
// reference, the nearest polygon, agrees with that image instead. Bounds:
// agreement to 1% of an object's pixels off by more than a texel (the
// contour moves with the depth's scale: 2% too deep a relief in the
// reference puts 2.3% of the board's pixels off), disagreement past 25%.
TEST(Accuracy, DepthWriteMatchesTheCompositedReference) {
    PlaneScene plane;
    plane.field.kind = FieldKind::sine;
    plane.field.size = 64;
    plane.field.frequency = 2.0f;
    plane.height_scale = 0.1f;  // 2 units per tile: 0.2 deep
    plane.technique = Technique::pom;
    plane.options.min_samples = plane.options.max_samples = 64;
    plane.view_angle_deg = 45.0f;
    SceneDesc scene = plane.build();
    MaterialDesc board;
    board.name = "board";
    board.technique.technique = Technique::pom;
    board.height.kind = TextureSource::Kind::procedural;
    board.height.field.kind = FieldKind::flat;
    board.height.field.level = 1.0f;
    board.height.field.size = 16;
    board.uv.offset = glm::vec2(0.5f);
    board.albedo.kind = TextureSource::Kind::color;
    board.albedo.color = glm::vec3(0.9f, 0.2f, 0.1f);
    scene.materials.push_back(board);
    ObjectDesc o;
    o.name = "board";
    o.mesh.size = 4.0f;
    o.transform.translate = glm::vec3(0.0f, 0.0f, -0.1f);
    o.material = "board";
    scene.objects.push_back(o);

    constexpr int kSize = 96;
    reference::ReferenceOptions options;
    auto plain = reference::render_reference(scene, kSize, kSize, options);
    options.depth_composite = true;
    auto composited = reference::render_reference(scene, kSize, kSize, options);
    ASSERT_TRUE(plain.ok() && composited.ok());

    const CompositeCase corrected = composite_case(scene, true, *composited);
    const CompositeCase uncorrected = composite_case(scene, false, *composited);
    const CompositeCase uncorrected_plain = composite_case(scene, false, *plain);
    for (const auto& [name, c] : {std::pair<const char*, const CompositeCase&>{"depth_write", corrected},
                                  {"no depth_write", uncorrected},
                                  {"no depth_write against the plain reference", uncorrected_plain}})
        std::printf("%s: wall %ld px (%ld missing), %.4f off by a texel, mean %.4f texels (%.4f of the level), max %.2f; "
                    "board %ld px, %.4f off by a texel, max %.2f\n",
                    name, c.wall.pixels, c.wall.pixels_missing, c.wall.wrong_surface_share, c.wall.base_error_mean,
                    c.wall.level_error_mean, c.wall.base_error_max, c.board.pixels, c.board.wrong_surface_share,
                    c.board.base_error_max);

    EXPECT_GT(corrected.wall.pixels, 1000);
    EXPECT_GT(corrected.board.pixels, 1000);
    EXPECT_EQ(corrected.wall.pixels_missing + corrected.board.pixels_missing, 0);  // the board fills the view
    EXPECT_LT(corrected.wall.wrong_surface_share, 0.01);
    EXPECT_LT(corrected.board.wrong_surface_share, 0.01);
    EXPECT_GT(uncorrected.board.wrong_surface_share, 0.25);
    EXPECT_LT(uncorrected_plain.wall.wrong_surface_share, 0.01);
    EXPECT_LT(uncorrected_plain.board.wrong_surface_share, 0.01);
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

// The exact walk counts its own work (include/parallaxes/profiling/measurement/work.h), on both
// contexts (ES 2.0 through the 24-bit packed passes). Every iteration reads
// one texel (a node's max, or on ES 2.0 a cell's four corners at once) and
// ends in at least one patch solve (4 reads of the height map on ES 3.0), so
// fetches >= iterations (+ 3 on ES 3.0) at every pixel, hence at the median.
// Looking down, the walk starts where the ray's descent spans two nodes a
// side (level 4 here, the perspective's rays being off vertical by up to
// 8 cells over the relief), not at the root (level 8: 9 iterations at the
// least from there); at 85 degrees it walks further. A renderer made
// without the counting is refused, not misread as counts.
TEST(Work, BucketsArePowersOfTwo) {
    EXPECT_EQ(profiling::work_bucket(0), 0u);
    EXPECT_EQ(profiling::work_bucket(1), 0u);
    EXPECT_EQ(profiling::work_bucket(2), 1u);
    EXPECT_EQ(profiling::work_bucket(3), 1u);
    EXPECT_EQ(profiling::work_bucket(4), 2u);
    EXPECT_EQ(profiling::work_bucket(4095), 11u);
    EXPECT_EQ(profiling::work_bucket(4096), 12u);
    EXPECT_EQ(profiling::work_bucket(1e9), 12u);
}

TEST(Work, TheExactWalkCountsItsIterations) {
    std::vector<profiling::WorkStats> at;
    for (double angle : {0.0, 85.0}) {
        auto scene = profiling::bench_scene("sine", angle);
        ASSERT_TRUE(scene.ok());
        scene->materials[0].technique.technique = Technique::maxmip;
        RendererOptions options;
        options.get_proc_address = platform::HeadlessContext::proc_loader();
        options.effect_planner = effect_planner;
        options.count_work = true;
        auto renderer = Renderer::create(options);
        ASSERT_TRUE(renderer.ok());
        ASSERT_TRUE((*renderer)->load(*scene).ok());
        auto work = profiling::measure_work(**renderer, 64, 64);
        ASSERT_TRUE(work.ok()) << work.error().message;
        EXPECT_GT(work->pixels, 500u) << angle;
        at.push_back(*work);
    }
    const double solve_extra = test_es_major() >= 3 ? 3.0 : 0.0;
    for (const profiling::WorkStats& w : at) EXPECT_GE(w.fetches_median, w.iterations_median + solve_extra);
    EXPECT_GE(at[0].iterations_median, 1.0);
    EXPECT_LT(at[0].iterations_median, 9.0);
    EXPECT_GT(at[1].iterations_median, at[0].iterations_median);
    EXPECT_GE(at[1].iterations_max, at[1].iterations_p99);

    auto scene = profiling::bench_scene("sine", 60.0);
    ASSERT_TRUE(scene.ok());
    scene->materials[0].technique.technique = Technique::maxmip;
    RendererOptions plain;
    plain.get_proc_address = platform::HeadlessContext::proc_loader();
    plain.effect_planner = effect_planner;
    auto renderer = Renderer::create(plain);
    ASSERT_TRUE(renderer.ok());
    ASSERT_TRUE((*renderer)->load(*scene).ok());
    auto misread = profiling::measure_work(**renderer, 64, 64);
    ASSERT_FALSE(misread.ok());
    EXPECT_NE(misread.error().message.find("count_work"), std::string::npos) << misread.error().message;
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

// Every technique that reads height hands its ray back (the bench's own-ray
// column measures each): the program links (the trace and its uniforms stay
// live behind the captured ray), and the parallax vector read back is the
// view's (uv shift per unit height: toward the camera on -y, height_scale
// * tan(60 degrees) long at the image centre).
TEST(ExactTracing, EveryTracedTechniqueHandsBackItsRay) {
    if (test_es_major() < 3) GTEST_SKIP() << "ES 2.0 has no float read-back for the captured rays";
    auto scene = profiling::bench_scene("sine", 60.0);
    ASSERT_TRUE(scene.ok());
    for (const TechniqueInfo& info : technique_table()) {
        if (!(info.options & kOptHeight)) continue;
        SCOPED_TRACE(info.name);
        scene->materials[0].technique.technique = info.id;
        RendererOptions options;
        options.get_proc_address = platform::HeadlessContext::proc_loader();
        options.effect_planner = effect_planner;
        options.capture_ray = true;
        auto renderer = Renderer::create(options);
        ASSERT_TRUE(renderer.ok());
        Status loaded = (*renderer)->load(*scene);
        ASSERT_TRUE(loaded.ok()) << loaded.error().message;
        auto rays = capture_surfaces(**renderer, 32, 32);
        ASSERT_TRUE(rays.ok()) << rays.error().message;
        const SurfaceSample& centre = rays->at(16, 16);
        ASSERT_TRUE(centre.covered);
        // parallax.x: the camera looks along +y (pixel 16 is half a pixel off
        // the centre); parallax.y toward the camera, on -v.
        EXPECT_NEAR(centre.height, 0.0, 0.005);
        EXPECT_NEAR(centre.visibility, -0.08 * std::tan(glm::radians(60.0)), 0.01);
    }
}

// The exact walk against the exact reference of the ray each pixel handed it
// (its fp32 uv and parallax vector, read back with capture_ray): at 89
// degrees on the one-texel lines and on sine, within the 2e-3 texel
// (p95) and far under the error against the camera's exact ray. That error
// (4e-3 texel p95 on lines at 89 degrees, docs/exact_tracing.md) is the
// rasterised inputs' share: where a ray runs along a ridge, a sideways shift
// of the ray's origin moves the hit hundreds of times as far along it.
// A renderer drawing hits (capture_ray off) reads as rays whose traces are
// texels away: the check can fail.
TEST(ExactTracing, TheWalkIsExactOnTheRayItIsHanded) {
    if (test_es_major() < 3) GTEST_SKIP() << "ES 2.0 has no float read-back for the captured rays";
    constexpr int kSize = 192;
    for (const char* scene_name : {"lines", "sine"}) {
        auto scene = profiling::bench_scene(scene_name, 89.0);
        ASSERT_TRUE(scene.ok());
        scene->materials[0].technique.technique = Technique::maxmip;
        scene->materials[0].technique.exact_view = true;
        auto images = build_material_images(scene->materials[0], scene->base_dir);
        ASSERT_TRUE(images.ok());
        std::vector<SurfaceImage> captured;
        for (bool capture_ray : {false, true}) {
            RendererOptions options;
            options.get_proc_address = platform::HeadlessContext::proc_loader();
            options.effect_planner = effect_planner;
            options.capture_ray = capture_ray;
            auto renderer = Renderer::create(options);
            ASSERT_TRUE(renderer.ok());
            Status loaded = (*renderer)->load(*scene);
            ASSERT_TRUE(loaded.ok()) << loaded.error().message;
            ASSERT_TRUE(captures_floats((*renderer)->caps()));
            auto surfaces = capture_surfaces(**renderer, kSize, kSize);
            ASSERT_TRUE(surfaces.ok()) << surfaces.error().message;
            captured.push_back(std::move(*surfaces));
        }
        const double polygon_height = scene->materials[0].polygon_height();
        auto own = profiling::own_ray_errors(images->traced, captured[0], captured[1], polygon_height);
        ASSERT_TRUE(own.ok()) << own.error().message;
        ASSERT_GT(own->size(), 300u) << scene_name;
        const double own_p95 = reference::nearest_rank_p95(*own);
        EXPECT_LT(own_p95, 2e-3) << scene_name;

        auto truth = reference::render_reference(*scene, kSize, kSize);
        ASSERT_TRUE(truth.ok()) << truth.error().message;
        auto camera = reference::compare_surfaces(captured[0], truth->surface, truth->texture_width, truth->texture_height);
        ASSERT_TRUE(camera.ok());
        EXPECT_GT(camera->uv_error_p95, 4.0 * own_p95) << scene_name;
        std::printf("%s at 89 degrees: hit error p95 %.3g texel against the camera's ray, %.3g against its own\n",
                    scene_name, camera->uv_error_p95, own_p95);

        // Hits read as rays: their traces land texels away.
        auto misread = profiling::own_ray_errors(images->traced, captured[0], captured[0], polygon_height);
        ASSERT_TRUE(misread.ok());
        EXPECT_GT(reference::nearest_rank_p95(*misread), 1.0) << scene_name;
    }
}

// The stability catalogue holds the exact tracer to its bound on the rays it
// was handed, where they read back (StabilityRow::own_error_mean): a GPU's
// rasteriser hands it inputs further off the camera's ray than the bound's
// fp32 terms allow (docs/exact_tracing.md). The other techniques, and
// maxmip without a float read-back, stay judged on the camera's rays.
TEST(ExactTracing, TheStabilityCatalogueJudgesTheWalkOnItsOwnRays) {
    if (test_es_major() < 3) GTEST_SKIP() << "ES 2.0 has no float read-back for the captured rays";
    auto catalogue = profiling::parse_catalogue(profiling::embedded_catalogue_text(), "catalogue");
    ASSERT_TRUE(catalogue.ok()) << catalogue.error().message;
    profiling::StabilityOptions options;
    options.cases_pattern = "grazing_text";
    options.image_size = 128;
    options.renderer_options = [](const std::string& precision, int) -> Result<RendererOptions> {
        if (precision != "native") return make_error("native only here");
        RendererOptions o;
        o.get_proc_address = platform::HeadlessContext::proc_loader();
        o.effect_planner = effect_planner;
        return o;
    };
    auto rows = profiling::run_stability(*catalogue, options, nullptr);
    ASSERT_TRUE(rows.ok()) << rows.error().message;
    bool saw_maxmip = false;
    for (const profiling::StabilityRow& r : *rows) {
        if (r.technique != "maxmip") {
            EXPECT_LT(r.own_error_mean, 0.0) << r.technique;
            continue;
        }
        saw_maxmip = true;
        ASSERT_GT(r.pixels, 300);
        ASSERT_GE(r.own_error_mean, 0.0);
        // Its own rays' traces are closer to its hits than the camera's are.
        EXPECT_LT(r.own_error_mean, 0.5 * r.error_mean);
        EXPECT_LT(r.own_error_max, 2e-3);
        EXPECT_EQ(r.verdict, "pass") << r.reasons;
    }
    EXPECT_TRUE(saw_maxmip);
}

}  // namespace
}  // namespace px::test
