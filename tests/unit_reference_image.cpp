// Unit tests for src/reference: the error metrics on hand-made surface
// images with known answers, and the exact reference image of plane scenes
// checked against geometry computed independently here.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "parallaxes/reference/metrics.h"
#include "parallaxes/assets/color.h"
#include "parallaxes/reference/reference_image.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/scene/scene.h"

namespace px::reference {
namespace {

// --- helpers -------------------------------------------------------------------

SurfaceImage surface(int w, int h) {
    SurfaceImage s;
    s.width = w;
    s.height = h;
    s.samples.assign(static_cast<size_t>(w) * h, SurfaceSample{});
    return s;
}

SurfaceSample& at(SurfaceImage& s, int x, int y) { return s.samples[static_cast<size_t>(y) * s.width + x]; }
SurfaceSample& at(ReferenceImage& r, int x, int y) { return at(r.surface, x, y); }

Image rgba(int w, int h, std::uint8_t value) { return make_solid_image(w, h, value, value, value); }

// One plane (2 x 2 unless changed) under a pom material whose height is a
// procedural field; a camera looking at it obliquely.
SceneDesc plane_scene(FieldSpec field, float height_scale) {
    SceneDesc s;
    s.name = "test";
    MaterialDesc m;
    m.name = "relief";
    m.height.kind = TextureSource::Kind::procedural;
    m.height.field = field;
    m.height_scale = height_scale;
    m.technique.technique = Technique::pom;
    s.materials.push_back(m);
    ObjectDesc o;
    o.name = "floor";
    o.mesh.kind = MeshKind::plane;
    o.mesh.size = 2.0f;
    o.material = "relief";
    s.objects.push_back(o);
    s.camera.position = glm::vec3(0.7f, -2.2f, 1.6f);
    s.camera.target = glm::vec3(0.1f, 0.2f, 0.0f);
    s.camera.up = glm::vec3(0.0f, 0.0f, 1.0f);
    LightDesc light;
    light.direction = glm::vec3(-0.3f, -0.2f, -1.0f);
    s.lights.push_back(light);
    return s;
}

FieldSpec flat_field(float level, int size = 16) {
    FieldSpec f;
    f.kind = FieldKind::flat;
    f.level = level;
    f.size = size;
    return f;
}

ReferenceImage render_ok(const SceneDesc& scene, int w, int h, const ReferenceOptions& options = {}) {
    Result<ReferenceImage> r = render_reference(scene, w, h, options);
    EXPECT_TRUE(r.ok()) << r.error().message;
    return r.ok() ? std::move(*r) : ReferenceImage{};
}

// Where a world point lands on screen, in pixel coordinates whose integers
// are pixel centres: the forward projection, independent of the reference's
// inverse (ray) construction.
glm::dvec2 project_to_pixel(const CameraDesc& cam, int w, int h, glm::dvec3 world) {
    const glm::dmat4 view = glm::lookAt(glm::dvec3(cam.position), glm::dvec3(cam.target), glm::dvec3(cam.up));
    const glm::dmat4 projection = glm::perspective(glm::radians(static_cast<double>(cam.fov_y_deg)),
                                                   static_cast<double>(w) / h, static_cast<double>(cam.near_plane),
                                                   static_cast<double>(cam.far_plane));
    const glm::dvec4 clip = projection * view * glm::dvec4(world, 1.0);
    const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
    return (ndc + 1.0) * 0.5 * glm::dvec2(w, h) - 0.5;
}

// --- metrics -----------------------------------------------------------------------

TEST(Metrics, ConstantHalfTexelOffset) {
    const int tex = 64;
    SurfaceImage truth = surface(4, 3), measured = surface(4, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) {
            SurfaceSample s;
            s.covered = true;
            s.uv = glm::dvec2(0.1 * x + 0.03, 0.2 * y + 0.07);
            at(truth, x, y) = s;
            s.uv += glm::dvec2(0.3, 0.4) / static_cast<double>(tex);  // a 3-4-5 triangle: 0.5 texel long
            at(measured, x, y) = s;
        }
    Result<ErrorMetrics> m = compare_surfaces(measured, truth, tex, tex);
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->pixels, 12);
    EXPECT_NEAR(m->uv_error_mean, 0.5, 1e-9);
    EXPECT_NEAR(m->uv_error_p95, 0.5, 1e-9);
    EXPECT_NEAR(m->uv_error_max, 0.5, 1e-9);
    EXPECT_EQ(m->wrong_surface_share, 0.0);
    EXPECT_EQ(m->depth_error_mean, 0.0);
    EXPECT_EQ(m->shadow_disagreement, 0.0);
}

TEST(Metrics, UvErrorWrapsAroundTheTile) {
    SurfaceImage truth = surface(3, 1), measured = surface(3, 1);
    for (SurfaceSample* s : {&truth.samples[0], &measured.samples[0], &truth.samples[1], &measured.samples[1],
                             &truth.samples[2], &measured.samples[2]})
        s->covered = true;
    truth.samples[0].uv = glm::dvec2(0.001, 0.5);
    measured.samples[0].uv = glm::dvec2(0.999, 0.5);  // 0.002 tiles the short way, not 0.998
    truth.samples[1].uv = glm::dvec2(0.25, 0.75);
    measured.samples[1].uv = glm::dvec2(3.25, -1.25);  // whole tiles apart: the same texel
    truth.samples[2].uv = glm::dvec2(0.5, 0.9995);
    measured.samples[2].uv = glm::dvec2(0.5, -7.9995);  // 0.001 the short way, across tiles in v
    Result<ErrorMetrics> m = compare_surfaces(measured, truth, 1000, 2000);
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->pixels, 3);
    EXPECT_NEAR(m->uv_error_max, 2.0, 1e-6);  // 0.002 * 1000 texels (u), and 0.001 * 2000 (v)
    EXPECT_NEAR(m->uv_error_mean, 4.0 / 3.0, 1e-6);
    EXPECT_NEAR(m->wrong_surface_share, 2.0 / 3.0, 1e-12);
}

TEST(Metrics, OnlyPixelsCoveredInBothCountAndErrorsAreKnown) {
    const int tex = 100;
    SurfaceImage truth = surface(10, 2), measured = surface(10, 2);
    for (int x = 0; x < 10; ++x) {
        // Row 0: covered in both; half of them 2 texels off in v.
        SurfaceSample t;
        t.covered = true;
        t.uv = glm::dvec2(0.5, 0.5);
        t.height = 0.25;
        t.visibility = 1.0;
        SurfaceSample s = t;
        if (x % 2 == 0) s.uv.y += 2.0 / tex;
        s.height = x < 5 ? 0.25 : 0.75;
        s.visibility = x < 8 ? 1.0 : 0.0;
        at(truth, x, 0) = t;
        at(measured, x, 0) = s;
        // Row 1: wildly different, but covered in one image only.
        SurfaceSample far = t;
        far.uv = glm::dvec2(0.1, 0.9);
        far.height = 0.0;
        far.visibility = 0.0;
        at(truth, x, 1) = t;
        at(measured, x, 1) = far;
        at(x % 2 ? truth : measured, x, 1).covered = false;
    }
    Result<ErrorMetrics> m = compare_surfaces(measured, truth, tex, tex);
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->pixels, 10);
    EXPECT_NEAR(m->uv_error_mean, 1.0, 1e-9);
    EXPECT_NEAR(m->uv_error_p95, 2.0, 1e-9);
    EXPECT_NEAR(m->uv_error_max, 2.0, 1e-9);
    EXPECT_NEAR(m->wrong_surface_share, 0.5, 1e-12);
    EXPECT_NEAR(m->depth_error_mean, 0.25, 1e-12);
    EXPECT_NEAR(m->depth_error_max, 0.5, 1e-12);
    EXPECT_NEAR(m->shadow_disagreement, 0.2, 1e-12);
}

TEST(Metrics, P95IsTheNinetyFifthPercentile) {
    // Errors 1..100 texels: nearest-rank p95 is 95.
    SurfaceImage truth = surface(100, 1), measured = surface(100, 1);
    for (int x = 0; x < 100; ++x) {
        at(truth, x, 0).covered = at(measured, x, 0).covered = true;
        at(measured, x, 0).uv = glm::dvec2((x + 1) / 1000.0, 0.0);
    }
    Result<ErrorMetrics> m = compare_surfaces(measured, truth, 1000, 1000);
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_NEAR(m->uv_error_p95, 95.0, 1e-9);
    EXPECT_NEAR(m->uv_error_mean, 50.5, 1e-9);
}

TEST(Metrics, MismatchedSizesAreAnError) {
    Result<ErrorMetrics> m = compare_surfaces(surface(4, 4), surface(4, 5), 64, 64);
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.error().message.find("4x5"), std::string::npos) << m.error().message;
    EXPECT_FALSE(compare_surfaces(surface(4, 4), surface(4, 4), 0, 64).ok());
}

// compare_object on a hand-made reference: object 1 owns the left half, of
// which one pixel is uncovered by the GPU; object 0 (no height: the
// reference does not cover it) owns the right half, which the GPU covers.
TEST(Metrics, CompareObjectCountsAndScalesPerObject) {
    const int w = 8, h = 2;
    ReferenceImage truth;
    truth.surface = surface(w, h);
    truth.object_index.assign(static_cast<size_t>(w) * h, 0);
    truth.texels_per_pixel.assign(static_cast<size_t>(w) * h, 0.5);
    truth.object_texture_size = {glm::ivec2(0), glm::ivec2(100, 50)};
    SurfaceImage measured = surface(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w / 2; ++x) {
            const size_t i = static_cast<size_t>(y) * w + x;
            truth.object_index[i] = 1;
            truth.texels_per_pixel[i] = x < 2 ? 0.5 : 4.0;  // magnified on the left, minified by 4 on the right
            at(truth, x, y).covered = true;
            at(truth, x, y).uv = glm::dvec2(0.995, 0.5);
            at(truth, x, y).visibility = 1.0;
            at(measured, x, y) = at(truth, x, y);
            // 2 texels off in v (0.04 * 50) for x < 2; 1 texel in u across the tile edge for x >= 2.
            if (x < 2) at(measured, x, y).uv.y += 0.04;
            else at(measured, x, y).uv.x = 1.005;
            if (y == 1) at(measured, x, y).visibility = 0.5;
        }
    at(measured, 3, 1).covered = false;  // missing
    for (int y = 0; y < h; ++y)
        for (int x = w / 2; x < w; ++x) at(measured, x, y).covered = true;  // the GPU reports every object
    Result<ObjectError> e = compare_object(measured, truth, 1);
    ASSERT_TRUE(e.ok()) << e.error().message;
    EXPECT_EQ(e->reference_pixels, 8);
    EXPECT_EQ(e->pixels, 7);
    EXPECT_EQ(e->pixels_missing, 1);
    // Errors: four of 2 texels, three of 1.
    EXPECT_NEAR(e->base_error_mean, 11.0 / 7.0, 1e-9);
    EXPECT_NEAR(e->base_error_p95, 2.0, 1e-9);
    EXPECT_NEAR(e->base_error_max, 2.0, 1e-9);
    EXPECT_NEAR(e->wrong_surface_share, 4.0 / 7.0, 1e-12);  // the 2-texel ones
    // Level: the 2s over max(1, 0.5) stay 2, the 1s over 4 are 0.25.
    EXPECT_NEAR(e->level_error_mean, (4 * 2.0 + 3 * 0.25) / 7.0, 1e-9);
    EXPECT_NEAR(e->level_error_p95, 2.0, 1e-9);
    EXPECT_NEAR(e->level_error_max, 2.0, 1e-9);
    EXPECT_NEAR(e->visibility_error_mean, 0.5 * 3.0 / 7.0, 1e-9);

    Result<ObjectError> flat = compare_object(measured, truth, 0);
    ASSERT_TRUE(flat.ok()) << flat.error().message;
    EXPECT_EQ(flat->reference_pixels, 8);
    EXPECT_EQ(flat->pixels, 0);  // nothing of the reference's to compare with
    EXPECT_EQ(flat->pixels_missing, 0);
    EXPECT_EQ(flat->base_error_max, 0.0);

    EXPECT_FALSE(compare_object(measured, truth, 2).ok());
    EXPECT_FALSE(compare_object(measured, truth, -1).ok());
    EXPECT_FALSE(compare_object(surface(w, h + 1), truth, 1).ok());
    truth.object_index.pop_back();
    Result<ObjectError> short_index = compare_object(measured, truth, 1);
    ASSERT_FALSE(short_index.ok());
    EXPECT_NE(short_index.error().message.find("8x2"), std::string::npos) << short_index.error().message;
}

TEST(Metrics, PsnrIdenticalIs99) {
    SurfaceImage mask = surface(8, 8);
    for (SurfaceSample& s : mask.samples) s.covered = true;
    EXPECT_EQ(color_psnr(rgba(8, 8, 77), rgba(8, 8, 77), mask), 99.0);
}

TEST(Metrics, PsnrOfAKnownError) {
    SurfaceImage mask = surface(8, 8);
    Image truth = rgba(8, 8, 100), measured = rgba(8, 8, 100);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            mask.samples[static_cast<size_t>(y) * 8 + x].covered = y < 4;
            if (y < 4)
                measured.texel(x, y)[1] = 110;  // green 10 off: MSE over RGB = 100 / 3
            else
                measured.texel(x, y)[0] = 0;    // outside the mask: ignored
        }
    const double expected = 10.0 * std::log10(255.0 * 255.0 * 3.0 / 100.0);  // 32.68 dB
    EXPECT_NEAR(color_psnr(measured, truth, mask), expected, 1e-9);
    // Alpha is not colour.
    for (int y = 0; y < 4; ++y) measured.texel(0, y)[3] = 0;
    EXPECT_NEAR(color_psnr(measured, truth, mask), expected, 1e-9);
    EXPECT_TRUE(std::isnan(color_psnr(rgba(8, 7, 0), truth, mask)));
}

// --- reference image -------------------------------------------------------------

// At level 1 the relief top is the polygon: every hit is where the pixel's
// ray meets the plane. Projecting that uv's plane point forward must land on
// the pixel centre.
TEST(ReferenceImage, FlatTopHitsThePolygonUnderThePixel) {
    SceneDesc scene = plane_scene(flat_field(1.0f), 0.1f);
    scene.objects[0].transform.translate = glm::vec3(0.2f, -0.1f, 0.15f);
    scene.objects[0].transform.rotate_deg = glm::vec3(20.0f, -10.0f, 35.0f);
    const int w = 40, h = 30;
    ReferenceImage r = render_ok(scene, w, h);
    ASSERT_EQ(r.surface.width, w);
    EXPECT_EQ(r.texture_width, 16);
    const glm::dmat4 model(scene.objects[0].transform.matrix());
    int covered = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const SurfaceSample& s = r.surface.at(x, y);
            if (!s.covered) continue;
            ++covered;
            EXPECT_NEAR(s.height, 1.0, 1e-9);
            const glm::dvec3 object((s.uv - 0.5) * 2.0, 0.0);  // size 2, uv 0..1
            const glm::dvec2 p = project_to_pixel(scene.camera, w, h, glm::dvec3(model * glm::dvec4(object, 1.0)));
            EXPECT_NEAR(p.x, x, 1e-6) << "pixel " << x << "," << y;
            EXPECT_NEAR(p.y, y, 1e-6) << "pixel " << x << "," << y;
        }
    EXPECT_GT(covered, w * h / 4);
    EXPECT_LT(covered, w * h);  // the plane's edges are in view
}

// The material's uv transform is uv' = R(rotation) S(scale) uv + offset.
TEST(ReferenceImage, UvTransformAppliesToThePolygonUv) {
    SceneDesc plain = plane_scene(flat_field(1.0f), 0.1f);
    SceneDesc mapped = plain;
    mapped.materials[0].uv.scale = glm::vec2(2.0f, 3.0f);
    mapped.materials[0].uv.rotation_deg = 30.0f;
    mapped.materials[0].uv.offset = glm::vec2(0.25f, -0.5f);
    const ReferenceImage a = render_ok(plain, 24, 24);
    const ReferenceImage b = render_ok(mapped, 24, 24);
    const double c = std::cos(glm::radians(30.0)), s = std::sin(glm::radians(30.0));
    int covered = 0;
    for (int i = 0; i < 24 * 24; ++i) {
        ASSERT_EQ(a.surface.samples[i].covered, b.surface.samples[i].covered);
        if (!a.surface.samples[i].covered) continue;
        ++covered;
        const glm::dvec2 uv = a.surface.samples[i].uv;
        const glm::dvec2 expected(c * 2.0 * uv.x - s * 3.0 * uv.y + 0.25, s * 2.0 * uv.x + c * 3.0 * uv.y - 0.5);
        EXPECT_NEAR(b.surface.samples[i].uv.x, expected.x, 1e-6);
        EXPECT_NEAR(b.surface.samples[i].uv.y, expected.y, 1e-6);
    }
    EXPECT_GT(covered, 0);
}

// At level 0 under a polygon at the top, the view ray descends the whole
// relief depth s: it shifts uv by exactly -s * V.xy / V.z (V toward the eye,
// here in the untransformed plane's frame t = x, b = y, n = z).
TEST(ReferenceImage, FlatBottomShiftsByTheParallaxOffset) {
    const float scale = 0.08f;
    SceneDesc top = plane_scene(flat_field(1.0f), scale);
    SceneDesc bottom = plane_scene(flat_field(0.0f), scale);
    const int w = 32, h = 32;
    const ReferenceImage polygon = render_ok(top, w, h);
    const ReferenceImage relief = render_ok(bottom, w, h);
    const glm::dvec3 eye(top.camera.position);
    int checked = 0;
    for (int y = 3; y < h; y += 7)
        for (int x = 2; x < w; x += 5) {
            const SurfaceSample& p = polygon.surface.at(x, y);
            const SurfaceSample& q = relief.surface.at(x, y);
            ASSERT_EQ(p.covered, q.covered);
            if (!p.covered) continue;
            ++checked;
            const glm::dvec3 world((p.uv - 0.5) * 2.0, 0.0);
            const glm::dvec3 v = glm::normalize(eye - world);
            const glm::dvec2 expected = p.uv - static_cast<double>(scale) * glm::dvec2(v) / v.z;
            EXPECT_NEAR(q.uv.x, expected.x, 1e-6) << "pixel " << x << "," << y;
            EXPECT_NEAR(q.uv.y, expected.y, 1e-6) << "pixel " << x << "," << y;
            EXPECT_NEAR(q.height, 0.0, 1e-9);
        }
    EXPECT_GE(checked, 5);
}

// A square pit seen from above, lit from +u at about 14 degrees: the floor
// beside the far (+u) wall, which faces away from the light, is in the
// rim's shadow; the floor beside the near wall and the open top are lit.
TEST(ReferenceImage, PitHardShadows) {
    FieldSpec pit;
    pit.kind = FieldKind::pit;
    pit.size = 64;
    pit.radius = 0.25f;
    SceneDesc scene = plane_scene(pit, 0.1f);
    scene.camera.position = glm::vec3(0.0f, 0.0f, 3.0f);
    scene.camera.target = glm::vec3(0.0f);
    scene.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
    scene.lights[0].direction = glm::vec3(-1.0f, 0.0f, -0.25f);  // travels toward -u: the light is at +u
    scene.lights[0].angular_radius_deg = 0.0f;
    ReferenceOptions options;
    options.shadow = ShadowMode::hard;
    const ReferenceImage r = render_ok(scene, 96, 96, options);
    // Floor (0 for u in [16.5, 47.5] / 64): the ray toward the light rises a
    // relief depth over 0.4 tiles, so the rim at u = 0.758 hides u > 0.358.
    int shadowed_floor = 0, lit_floor = 0, top = 0;
    for (const SurfaceSample& s : r.surface.samples) {
        if (!s.covered) continue;
        const double u = s.uv.x - std::floor(s.uv.x), v = s.uv.y - std::floor(s.uv.y);
        const bool mid_v = v > 0.35 && v < 0.65;
        if (s.height < 1e-6 && mid_v && u > 0.6 && u < 0.73) {
            EXPECT_EQ(s.visibility, 0.0) << "floor at u " << u << " v " << v;
            ++shadowed_floor;
        } else if (s.height < 1e-6 && mid_v && u > 0.27 && u < 0.34) {
            EXPECT_EQ(s.visibility, 1.0) << "floor at u " << u << " v " << v;
            ++lit_floor;
        } else if (s.height > 1.0 - 1e-9 && (u < 0.2 || u > 0.8 || v < 0.2 || v > 0.8)) {
            EXPECT_EQ(s.visibility, 1.0) << "top at u " << u << " v " << v;
            ++top;
        }
    }
    EXPECT_GT(shadowed_floor, 10);
    EXPECT_GT(lit_floor, 4);
    EXPECT_GT(top, 100);
}

TEST(ReferenceImage, NonPlaneMeshIsAnErrorNamingTheObject) {
    SceneDesc scene = plane_scene(flat_field(1.0f), 0.05f);
    ObjectDesc ball;
    ball.name = "the_ball";
    ball.mesh.kind = MeshKind::sphere;
    ball.material = "relief";
    scene.objects.push_back(ball);
    Result<ReferenceImage> r = render_reference(scene, 8, 8, {});
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("the_ball"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("sphere"), std::string::npos) << r.error().message;
}

// Back faces are culled as on the GPU: a plane turned over shows nothing.
TEST(ReferenceImage, BackFacesAreCulled) {
    SceneDesc scene = plane_scene(flat_field(1.0f), 0.05f);
    scene.objects[0].transform.rotate_deg = glm::vec3(180.0f, 0.0f, 0.0f);
    const ReferenceImage r = render_ok(scene, 16, 16);
    const std::uint8_t bg = static_cast<std::uint8_t>(std::lround(scene.background.r * 255.0f));
    for (const SurfaceSample& s : r.surface.samples) EXPECT_FALSE(s.covered);
    EXPECT_EQ(r.color.texel(8, 8)[0], bg);
}

// The nearest plane wins whatever the draw order, and a material that does
// not read height (normal mapping) leaves its pixels uncovered.
TEST(ReferenceImage, NearestPlaneWinsAndOnlyHeightReadersAreCovered) {
    SceneDesc scene = plane_scene(flat_field(1.0f), 0.05f);
    scene.camera.position = glm::vec3(0.0f, 0.0f, 3.0f);
    scene.camera.target = glm::vec3(0.0f);
    scene.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
    MaterialDesc lid;
    lid.name = "lid";
    lid.technique.technique = Technique::normal;
    lid.albedo.kind = TextureSource::Kind::color;
    lid.albedo.color = glm::vec3(1.0f, 0.0f, 0.0f);
    scene.materials.push_back(lid);
    ObjectDesc above;
    above.name = "above";
    above.mesh.size = 0.5f;
    above.transform.translate = glm::vec3(0.0f, 0.0f, 0.5f);
    above.material = "lid";
    scene.objects.insert(scene.objects.begin(), above);  // drawn first, still in front
    const ReferenceImage r = render_ok(scene, 33, 33);
    EXPECT_FALSE(r.surface.at(16, 16).covered);
    EXPECT_GT(r.color.texel(16, 16)[0], 2 * r.color.texel(16, 16)[1]);  // the red lid
    EXPECT_TRUE(r.surface.at(16, 8).covered);  // the floor around it
    EXPECT_EQ(r.texture_width, 16);           // the floor's field, the first height reader
}

// px_shade by hand at the centre pixel of a flat, level-1 plane: ambient *
// albedo + light * (albedo N.L + 0.25 (N.H)^32), with the eye near the
// light's mirror direction so the specular term matters.
TEST(ReferenceImage, ColourOfAFlatSurfaceMatchesTheLightingModel) {
    SceneDesc scene = plane_scene(flat_field(1.0f), 0.05f);
    scene.objects[0].mesh.size = 1.0f;
    scene.materials[0].albedo.kind = TextureSource::Kind::color;
    scene.materials[0].albedo.color = glm::vec3(0.6f, 0.4f, 0.2f);
    scene.ambient = glm::vec3(0.1f, 0.05f, 0.02f);
    scene.lights[0].direction = glm::vec3(-0.3f, -0.2f, -1.0f);
    scene.lights[0].color = glm::vec3(1.0f, 0.9f, 0.8f);
    scene.lights[0].intensity = 0.7f;
    scene.camera.position = glm::vec3(-0.63f, -0.4f, 2.0f);
    scene.camera.target = glm::vec3(0.0f);
    const int w = 33, h = 33;
    const ReferenceImage r = render_ok(scene, w, h);
    const SurfaceSample& s = r.surface.at(16, 16);
    ASSERT_TRUE(s.covered);

    Result<MaterialImages> images = build_material_images(scene.materials[0], "");
    ASSERT_TRUE(images.ok()) << images.error().message;
    const std::uint8_t* n8 = images->normal.texel(0, 0);  // flat: every texel alike
    const std::uint8_t* a8 = images->albedo.texel(0, 0);
    const glm::dvec3 n = glm::normalize(glm::dvec3(n8[0], n8[1], n8[2]) / 255.0 * 2.0 - 1.0);
    // The albedo colour is sRGB: lit after decoding, shown encoded.
    ASSERT_TRUE(images->albedo_srgb);
    const glm::dvec3 albedo(srgb_to_linear(a8[0] / 255.0), srgb_to_linear(a8[1] / 255.0), srgb_to_linear(a8[2] / 255.0));
    const glm::dvec3 world((s.uv - 0.5) * 1.0, 0.0);
    const glm::dvec3 v = glm::normalize(glm::dvec3(scene.camera.position) - world);
    const glm::dvec3 l = glm::normalize(-glm::dvec3(scene.lights[0].direction));
    const double n_dot_l = glm::dot(n, l);
    const double specular = 0.25 * std::pow(glm::dot(n, glm::normalize(l + v)), 32.0);
    ASSERT_GT(specular, 0.2);  // near the mirror direction
    const glm::dvec3 light = glm::dvec3(scene.lights[0].color) * 0.7;
    const glm::dvec3 expected =
        glm::dvec3(scene.ambient) * albedo + light * (albedo * n_dot_l + glm::dvec3(specular));
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(r.color.texel(16, 16)[c], linear_to_srgb(expected[c]) * 255.0, 0.5 + 1e-6) << "channel " << c;
    EXPECT_EQ(r.color.texel(16, 16)[3], 255);
    // With a linear output, the linear light itself.
    ReferenceOptions linear;
    linear.srgb_output = false;
    auto raw = render_reference(scene, w, h, linear);
    ASSERT_TRUE(raw.ok());
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(raw->color.texel(16, 16)[c], std::min(expected[c], 1.0) * 255.0, 0.5 + 1e-6) << "channel " << c;
    // A corner pixel misses the 1 x 1 plane: background.
    EXPECT_FALSE(r.surface.at(0, 0).covered);
    for (int c = 0; c < 3; ++c)
        EXPECT_EQ(r.color.texel(0, 0)[c], static_cast<std::uint8_t>(std::lround(scene.background[c] * 255.0f)));
}

// The accuracy benchmark's size with soft shadows: every visibility is a
// share, and both the lit top and the shadowed grooves appear.
TEST(ReferenceImage, SoftShadowsOnBricks) {
    FieldSpec bricks;
    bricks.kind = FieldKind::bricks;
    bricks.size = 256;
    SceneDesc scene = plane_scene(bricks, 0.06f);
    scene.lights[0].direction = glm::vec3(-1.0f, -0.5f, -0.5f);
    scene.lights[0].angular_radius_deg = 3.0f;
    ReferenceOptions options;
    options.shadow = ShadowMode::soft;
    options.soft_samples = 64;
    const auto start = std::chrono::steady_clock::now();
    const ReferenceImage r = render_ok(scene, 128, 128, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    RecordProperty("seconds", std::to_string(seconds));
    int partial = 0, dark = 0, lit = 0;
    for (const SurfaceSample& s : r.surface.samples) {
        if (!s.covered) continue;
        ASSERT_GE(s.visibility, 0.0);
        ASSERT_LE(s.visibility, 1.0);
        if (s.visibility == 0.0) ++dark;
        else if (s.visibility == 1.0) ++lit;
        else ++partial;
    }
    EXPECT_GT(dark, 0);
    EXPECT_GT(lit, 0);
    EXPECT_GT(partial, 0);
}

// --- depth compositing, object index, footprint -------------------------------------

// A wall (object 0) whose relief lies under its polygon, seen from `eye`,
// and a parallel board (object 1, normal mapping: no height read) `board_z`
// in front of (> 0) or behind (< 0) the wall's polygon, twice the wall's
// size so that it is behind every wall pixel.
SceneDesc wall_and_board(FieldSpec field, float board_z, glm::vec3 eye) {
    SceneDesc scene = plane_scene(field, 0.1f);  // 2 x 2: 2 world units per tile, the relief 0.2 deep
    scene.objects[0].name = "wall";
    scene.camera.position = eye;
    scene.camera.target = glm::vec3(0.0f);
    scene.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
    MaterialDesc board;
    board.name = "board";
    board.technique.technique = Technique::normal;
    scene.materials.push_back(board);
    ObjectDesc o;
    o.name = "board";
    o.mesh.size = 4.0f;
    o.transform.translate = glm::vec3(0.0f, 0.0f, board_z);
    o.material = "board";
    scene.objects.push_back(o);
    return scene;
}

ReferenceOptions composite_on() {
    ReferenceOptions o;
    o.depth_composite = true;
    return o;
}

// A board through the middle of the wall's relief (a pit: floor 0, rim 1):
// composited, the board hides the pit floor (hit behind it) and the rim
// hides the board; without compositing the wall's polygon wins everywhere.
TEST(ReferenceImage, DepthCompositeBoardPiercingTheRelief) {
    FieldSpec pit;
    pit.kind = FieldKind::pit;
    pit.size = 32;
    pit.radius = 0.25f;
    const SceneDesc scene = wall_and_board(pit, -0.1f, glm::vec3(0.3f, -0.2f, 3.0f));  // board at height 0.5
    const int w = 64, h = 64;
    const ReferenceImage off = render_ok(scene, w, h);
    const ReferenceImage on = render_ok(scene, w, h, composite_on());
    int board = 0, rim = 0;
    for (size_t i = 0; i < off.object_index.size(); ++i) {
        const int o = off.object_index[i];
        ASSERT_TRUE(o == 0 || o == 1) << i;  // the board fills the view
        ASSERT_EQ(on.object_index[i] == -1, o == -1);
        if (o != 0) {
            EXPECT_EQ(on.object_index[i], 1);  // outside the wall: the board either way
            continue;
        }
        // Off, the wall's trace is there whatever is behind its polygon.
        const double hit = off.surface.samples[i].height;
        if (std::fabs(hit - 0.5) < 0.05) continue;  // the pit's walls, near the board
        if (hit < 0.5) {
            EXPECT_EQ(on.object_index[i], 1) << "pixel " << i << " hit height " << hit;
            EXPECT_FALSE(on.surface.samples[i].covered);  // the board reads no height
            ++board;
        } else {
            EXPECT_EQ(on.object_index[i], 0) << "pixel " << i << " hit height " << hit;
            EXPECT_EQ(on.surface.samples[i].uv, off.surface.samples[i].uv);  // the same trace
            ++rim;
        }
    }
    EXPECT_GT(board, 100);
    EXPECT_GT(rim, 100);
}

// The hit's distance along an oblique ray: the relief's floor lies 0.2
// under the polygon (flat field at 0), so a board just in front of the
// floor shows at every wall pixel and one just behind it at none. Off
// axis, this needs the depth over the view cosine.
TEST(ReferenceImage, DepthCompositeHitDepthAlongAnObliqueRay) {
    const glm::vec3 eye(1.6f, -1.1f, 1.4f);
    for (const float board_z : {-0.19f, -0.21f}) {
        const SceneDesc scene = wall_and_board(flat_field(0.0f), board_z, eye);
        const ReferenceImage off = render_ok(scene, 64, 64);
        const ReferenceImage on = render_ok(scene, 64, 64, composite_on());
        int wall = 0;
        for (size_t i = 0; i < off.object_index.size(); ++i) {
            if (off.object_index[i] != 0) continue;
            ++wall;
            EXPECT_EQ(on.object_index[i], board_z > -0.2f ? 1 : 0) << "board at " << board_z << " pixel " << i;
        }
        EXPECT_GT(wall, 500);
    }
}

// A relief that rises over its polygon (bias 0: [0, 0.2] above it, flat at
// its top): composited, it hides a board 0.1 in front of its polygon at
// every pixel where the ray meets the wall (as alone), though the board's
// polygon is the nearer one (what the plain reference shows everywhere); a
// board 0.3 in front hides it. The candidate bound must reach above the
// polygon, or the board, nearer than the wall's polygon, wins untraced.
TEST(ReferenceImage, DepthCompositeReliefAboveItsPolygon) {
    const glm::vec3 eye(0.4f, -0.3f, 3.0f);
    SceneDesc alone = wall_and_board(flat_field(1.0f), 0.1f, eye);
    alone.materials[0].height_bias = 0.0f;
    alone.objects.pop_back();
    const ReferenceImage wall = render_ok(alone, 64, 64);
    for (const float board_z : {0.1f, 0.3f}) {
        SceneDesc scene = wall_and_board(flat_field(1.0f), board_z, eye);
        scene.materials[0].height_bias = 0.0f;
        const ReferenceImage off = render_ok(scene, 64, 64);
        const ReferenceImage on = render_ok(scene, 64, 64, composite_on());
        int wall_pixels = 0;
        for (size_t i = 0; i < off.object_index.size(); ++i) {
            EXPECT_EQ(off.object_index[i], 1);  // the board's polygon is nearer everywhere
            const bool on_wall = wall.object_index[i] == 0;
            wall_pixels += on_wall ? 1 : 0;
            EXPECT_EQ(on.object_index[i], on_wall && board_z < 0.2f ? 0 : 1) << "board at " << board_z << " pixel " << i;
        }
        EXPECT_GT(wall_pixels, 500);
    }
}

// One plane: compositing changes nothing, bit for bit (the winner keeps
// its trace), and the object index and footprint are the same too.
TEST(ReferenceImage, DepthCompositeOfOnePlaneIsBitIdentical) {
    FieldSpec pit;
    pit.kind = FieldKind::pit;
    pit.size = 32;
    const SceneDesc scene = plane_scene(pit, 0.1f);
    ReferenceOptions plain;
    plain.shadow = ShadowMode::hard;
    ReferenceOptions composited = plain;
    composited.depth_composite = true;
    const ReferenceImage a = render_ok(scene, 64, 64, plain);
    const ReferenceImage b = render_ok(scene, 64, 64, composited);
    ASSERT_EQ(a.surface.samples.size(), b.surface.samples.size());
    int covered = 0;
    for (size_t i = 0; i < a.surface.samples.size(); ++i) {
        const SurfaceSample& p = a.surface.samples[i];
        const SurfaceSample& q = b.surface.samples[i];
        ASSERT_EQ(p.covered, q.covered);
        covered += p.covered ? 1 : 0;
        EXPECT_EQ(std::memcmp(&p.uv, &q.uv, sizeof p.uv), 0) << i;
        EXPECT_EQ(std::memcmp(&p.height, &q.height, sizeof p.height), 0) << i;
        EXPECT_EQ(std::memcmp(&p.visibility, &q.visibility, sizeof p.visibility), 0) << i;
        EXPECT_EQ(std::memcmp(&a.view_ts[i], &b.view_ts[i], sizeof a.view_ts[i]), 0) << i;
        EXPECT_EQ(std::memcmp(&a.entry_uv[i], &b.entry_uv[i], sizeof a.entry_uv[i]), 0) << i;
        EXPECT_EQ(a.object_index[i], p.covered ? 0 : -1);
        EXPECT_EQ(a.object_index[i], b.object_index[i]);
        EXPECT_EQ(a.texels_per_pixel[i], b.texels_per_pixel[i]);
    }
    EXPECT_GT(covered, 1000);
    EXPECT_EQ(a.color.pixels, b.color.pixels);
    ASSERT_EQ(a.object_texture_size.size(), 1u);
    EXPECT_EQ(a.object_texture_size[0], glm::ivec2(32, 32));
}

// Footprint: a plane square to the view axis at distance D spans
// 2 D tan(fov/2) / H world units per pixel (the same everywhere: the
// mapping is affine), times texels per world unit (field size times uv
// scale over the mesh size). Tilted by theta about its x axis, the centre
// pixel (odd size: on the axis) sees v stretched by 1 / cos(theta).
TEST(ReferenceImage, TexelsPerPixelMatchesTheFootprint) {
    const int n = 65;
    const double distance = 3.0;
    SceneDesc scene = plane_scene(flat_field(1.0f, 64), 0.05f);
    scene.materials[0].uv.scale = glm::vec2(2.0f);
    scene.camera.position = glm::vec3(0.0f, 0.0f, static_cast<float>(distance));
    scene.camera.target = glm::vec3(0.0f);
    scene.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
    const double texels_per_unit = 64.0 * 2.0 / 2.0;
    const double units_per_pixel =
        2.0 * distance * std::tan(glm::radians(static_cast<double>(scene.camera.fov_y_deg)) / 2.0) / n;
    const double square = texels_per_unit * units_per_pixel;
    const ReferenceImage r = render_ok(scene, n, n);
    ASSERT_EQ(r.object_texture_size.size(), 1u);
    EXPECT_EQ(r.object_texture_size[0], glm::ivec2(64, 64));
    int covered = 0;
    for (size_t i = 0; i < r.texels_per_pixel.size(); ++i) {
        if (r.object_index[i] != 0) {
            EXPECT_EQ(r.texels_per_pixel[i], 0.0);
            continue;
        }
        ++covered;
        EXPECT_NEAR(r.texels_per_pixel[i], square, 1e-6 * square) << i;
    }
    EXPECT_GT(covered, n * n / 2);

    for (const double degrees : {45.0, 60.0}) {
        SceneDesc tilted = scene;
        tilted.objects[0].transform.rotate_deg = glm::vec3(static_cast<float>(degrees), 0.0f, 0.0f);
        const ReferenceImage t = render_ok(tilted, n, n);
        const size_t centre = static_cast<size_t>(n / 2) * n + n / 2;
        ASSERT_EQ(t.object_index[centre], 0);
        // Central differences: exact to second order in the pixel angle (1.5e-4 at 60 degrees).
        const double expected = square / std::cos(glm::radians(degrees));
        EXPECT_NEAR(t.texels_per_pixel[centre], expected, 1e-3 * expected)
            << degrees << " degrees";
    }
}

}  // namespace
}  // namespace px::reference
