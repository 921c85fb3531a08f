// Rendering behaviour on surfaceless Mesa, run once with an OpenGL ES 2.0
// context and once with ES 3.0 (PX_TEST_ES). Each test states the property
// of the techniques it checks; tolerances are in 8-bit levels.
#include "gpu_fixture.h"

#include "parallaxes/assets/color.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <set>

#include "parallaxes/reference/reference_image.h"
#include "parallaxes/render/offscreen_target.h"
#include "parallaxes/render/surface_capture.h"

namespace px::test {
namespace {

// The catalogue's techniques with every bit of `flags` that this context's
// ES version runs (the technique table is the one list of them).
std::vector<Technique> techniques_with(std::uint32_t flags) {
    std::vector<Technique> out;
    for (const TechniqueInfo& info : technique_table())
        if ((info.options & flags) == flags && info.min_es_major <= test_es_major()) out.push_back(info.id);
    return out;
}
// Every technique that offsets or traces by height, and those that search
// along the view ray with a sample count.
const std::vector<Technique> kParallaxTechniques = techniques_with(kOptHeight);
const std::vector<Technique> kMarchTechniques = techniques_with(kOptSamples);

// A flat green plane parallel to the test plane at height z, drawn after it:
// it shows wherever the relief's written depth lies behind z.
void add_probe_plane(SceneDesc& scene, float z) {
    MaterialDesc material;
    material.name = "probe";
    material.albedo.kind = TextureSource::Kind::color;
    material.albedo.color = glm::vec3(0.0f, 1.0f, 0.0f);
    material.height_scale = 0.0f;
    material.technique.technique = Technique::flat;
    scene.materials.push_back(material);
    ObjectDesc probe;
    probe.name = "probe";
    probe.mesh.kind = MeshKind::plane;
    probe.mesh.size = 2.0f;
    probe.transform.translate = glm::vec3(0.0f, 0.0f, z);
    probe.material = "probe";
    scene.objects.push_back(probe);
}

// A square pit (half-width 0.25 tiles) `depth` tiles deep in a flat top.
PlaneScene pit_scene(Technique technique, float depth) {
    PlaneScene p;
    p.field.kind = FieldKind::pit;
    p.field.size = 128;
    p.field.radius = 0.25f;
    p.height_scale = depth;
    p.technique = technique;
    return p;
}

PlaneScene bricks_scene() {
    PlaneScene p;
    p.field.kind = FieldKind::bricks;
    p.field.size = 128;
    p.field.count = 4;
    return p;
}

// Multisampled offscreen targets: on ES 3.0 four samples change only the
// pixels along the polygon's edges (a plane turned 30 degrees, so its edges
// cross the pixel grid), each to a blend of what the single-sampled image
// shows on either side; on ES 2.0 the target falls back to one sample and
// says why.
TEST(OffscreenTarget, MultisamplingBlendsOnlyTheEdges) {
    SceneDesc scene = builtin_scene("bricks").value();
    scene.objects[0].transform.rotate_deg = glm::vec3(0.0f, 0.0f, 30.0f);
    scene.objects[0].transform.scale = glm::vec3(0.6f);
    auto renderer = Renderer::create();
    ASSERT_TRUE(renderer.ok());
    ASSERT_TRUE((*renderer)->load(scene).ok());
    std::vector<Image> images;
    for (int samples : {1, 4}) {
        auto target = OffscreenTarget::create(96, 96, samples);
        ASSERT_TRUE(target.ok()) << target.error().message;
        if (samples == 4 && test_es_major() < 3) {
            EXPECT_EQ(target->samples(), 1);
            EXPECT_NE(target->sampling_note().find("no multisampled renderbuffers"), std::string::npos)
                << target->sampling_note();
            return;
        }
        EXPECT_EQ(target->samples(), samples);
        EXPECT_TRUE(target->sampling_note().empty()) << target->sampling_note();
        ASSERT_TRUE((*renderer)->draw(target->target()).ok());
        auto image = target->read_pixels();
        ASSERT_TRUE(image.ok()) << image.error().message;
        images.push_back(std::move(*image));
    }
    const Image& one = images[0];
    const Image& four = images[1];
    auto background = [&](const Image& im, int x, int y) {
        const std::uint8_t* p = im.texel(x, y);
        const glm::vec3 b = scene.background * 255.0f;
        return std::abs(p[0] - b.r) <= 1 && std::abs(p[1] - b.g) <= 1 && std::abs(p[2] - b.b) <= 1;
    };
    long edge_pixels = 0, changed = 0, changed_inside = 0;
    for (int y = 1; y < 95; ++y)
        for (int x = 1; x < 95; ++x) {
            bool mixed = false;
            for (int d = 0; d < 4; ++d) {
                const int nx = x + (d == 0) - (d == 1), ny = y + (d == 2) - (d == 3);
                mixed = mixed || background(one, nx, ny) != background(one, x, y);
            }
            edge_pixels += mixed;
            const bool differs = std::memcmp(one.texel(x, y), four.texel(x, y), 3) != 0;
            changed += differs;
            if (differs && !mixed && !background(one, x, y)) {
                // Inside the polygon samples at one position shade once: the same pixel.
                bool near_edge = false;
                for (int dy = -2; dy <= 2; ++dy)
                    for (int dx = -2; dx <= 2; ++dx)
                        near_edge = near_edge || (x + dx >= 0 && x + dx < 96 && y + dy >= 0 && y + dy < 96 &&
                                                  background(one, x + dx, y + dy));
                changed_inside += !near_edge;
            }
        }
    EXPECT_GT(edge_pixels, 100);
    // edge_pixels counts both sides of each crossing; the edge runs through
    // about one of the two, and some it only grazes.
    EXPECT_GT(changed, edge_pixels / 4);
    EXPECT_EQ(changed_inside, 0);
}

TEST(Context, IsTheRequestedEsVersion) {
    const Caps caps = query_caps();
    EXPECT_EQ(caps.es_major, test_es_major()) << caps.version;
    // Mesa makes exactly the version asked for (MESA_GLES_VERSION_OVERRIDE,
    // set by the platform). Other drivers may make a later minor version,
    // which EGL allows as backward compatible (NVIDIA 580 makes ES 3.2 for
    // 3.0): the shaders stay GLSL ES 3.00, checked strictly by glslang.
    if (caps.version.find("Mesa") != std::string::npos)
        EXPECT_EQ(caps.es_minor, 0) << "asked for a true ES " << test_es_major() << ".0 context, got " << caps.version;
    if (test_es_major() == 2) EXPECT_NE(caps.glsl_version.find("1.0"), std::string::npos) << caps.glsl_version;
}

// Every technique, with every option it has switched on, compiles, links and
// draws without a GL error, and draws the plane (not just the background).
TEST(Techniques, EachRendersWithoutGlErrors) {
    for (const TechniqueInfo& info : technique_table()) {
        PlaneScene p = bricks_scene();
        p.technique = info.id;
        p.view_angle_deg = 50.0f;
        p.options.shadow = ShadowMode::soft;
        p.options.depth_write = true;
        p.options.lod = true;
        const SceneDesc scene = p.build();
        const Rendered r = render(scene);
        ASSERT_EQ(r.reports.size(), 1u) << info.name;
        if (info.min_es_major > test_es_major()) {
            // Not on this context: the planner draws the table's fallback and says why.
            EXPECT_EQ(r.reports[0].variant.technique, info.fallback) << info.name;
            ASSERT_FALSE(r.reports[0].notes.empty()) << info.name;
            EXPECT_NE(r.reports[0].notes[0].find("needs OpenGL ES 3.0"), std::string::npos) << r.reports[0].notes[0];
        } else {
            EXPECT_EQ(r.reports[0].variant.technique, info.id);
        }
        EXPECT_EQ(r.reports[0].variant.es_major, test_es_major());
        EXPECT_EQ(r.reports[0].variant.depth_write, (info.options & kOptDepth) != 0) << info.name;
        // The plane covers the centre of the image; the background is near black.
        EXPECT_GT(luminance(r.image, 64, 64, 4), 20.0) << info.name << ": the plane was not drawn";
    }
}

// maxmip runs on OpenGL ES 2.0 (GLSL ES 1.00, its pyramid in one atlas).
// Without fragment highp it is no longer exact, but it stays the most
// accurate technique there (docs/stability.md, nohighp): the planner keeps
// it and says so.
TEST(Techniques, MaxmipWithoutFragmentHighpIsKeptAndSaysSo) {
    if (test_es_major() >= 3) GTEST_SKIP() << "OpenGL ES 3.0 guarantees fragment highp";
    PlaneScene p = bricks_scene();
    p.technique = Technique::maxmip;
    p.view_angle_deg = 50.0f;
    const SceneDesc scene = p.build();
    const Rendered with_highp = render(scene);
    ASSERT_EQ(with_highp.reports.size(), 1u);
    EXPECT_EQ(with_highp.reports[0].variant.technique, Technique::maxmip);
    EXPECT_TRUE(with_highp.reports[0].notes.empty()) << with_highp.reports[0].notes[0];
    const Rendered without = render(scene, 128, true);
    ASSERT_EQ(without.reports.size(), 1u);
    EXPECT_EQ(without.reports[0].variant.technique, Technique::maxmip);
    EXPECT_TRUE(without.reports[0].variant.no_fragment_highp);
    ASSERT_FALSE(without.reports[0].notes.empty());
    EXPECT_NE(without.reports[0].notes[0].find("lacks GL_FRAGMENT_PRECISION_HIGH"), std::string::npos)
        << without.reports[0].notes[0];
    // It draws the plane (not a hang, not black).
    EXPECT_GT(luminance(without.image, 64, 64, 4), 20.0);
}

// With a flat height field there is nothing to see through: every parallax
// technique must give the normal-mapping image, with the relief's top on the
// polygon (level 1, default bias) and with the polygon mid-relief (level
// 128/255, exact in 8 bits, bias -level * scale). 32 samples put one of
// steep's layers on 0.5, within 1/255 of the surface.
TEST(Techniques, FlatHeightFieldMatchesNormalMapping) {
    for (float level : {1.0f, 128.0f / 255.0f}) {
        PlaneScene p;
        p.field.kind = FieldKind::flat;
        p.field.size = 64;
        p.field.level = level;
        p.height_bias = -level * p.height_scale;
        p.view_angle_deg = 70.0f;  // grazing: offsets would be large if any
        p.options.shadow = ShadowMode::hard;
        p.options.min_samples = p.options.max_samples = 32;
        p.technique = Technique::normal;
        const Image reference = render(p.build()).image;
        for (Technique t : kParallaxTechniques) {
            p.technique = t;
            const ImageDiff d = compare(render(p.build()).image, reference);
            // Bound: steep's layer at 0.5 sits 1/510 under the stored 128/255;
            // times the parallax vector at 70 degrees (0.08 * tan 70 = 0.22)
            // that is 0.00043 uv, times the albedo's steepest slope (127 * 2 pi
            // * 8 levels per uv) 2.7 levels; +1 for rounding.
            EXPECT_LE(d.max, 4) << technique_name(t) << " at level " << level;
        }
    }
}

// Viewed straight on (a narrow field of view along the normal), V.xy is
// about zero and so are the offsets: the image is the normal-mapping one.
// At the image centre V is the normal; elsewhere it is within 0.5 degrees,
// where a 0.08-deep relief still shifts uv by up to 0.0007 (4 levels on the
// sine albedo's steepest slope), so the whole image is held to a small mean.
TEST(Techniques, OffsetsVanishStraightOn) {
    PlaneScene p = bricks_scene();
    p.view_angle_deg = 0.0f;
    p.distance = 60.0f;
    p.fov_deg = 1.0f;  // V within 0.5 degrees of the normal: offsets under 0.2 texel
    p.technique = Technique::normal;
    auto build = [&p]() {
        SceneDesc s = p.build();
        s.camera.far_plane = 100.0f;
        return s;
    };
    const Image reference = render(build()).image;
    for (Technique t : kParallaxTechniques) {
        p.technique = t;
        const Image image = render(build()).image;
        const ImageDiff d = compare(image, reference);
        EXPECT_LT(d.mean, 1.5) << technique_name(t);
        for (int y = 61; y <= 66; ++y)
            for (int x = 61; x <= 66; ++x)
                for (int c = 0; c < 3; ++c)
                    EXPECT_LE(std::abs(int(image.texel(x, y)[c]) - int(reference.texel(x, y)[c])), 2)
                        << technique_name(t) << " at the centre pixel " << x << "," << y;
    }
}

// At a grazing view the marched techniques see the bricks' sides and hide the
// mortar behind them: the image must differ clearly from normal mapping.
TEST(Techniques, MarchingDiffersFromNormalMappingAtGrazingView) {
    PlaneScene p = bricks_scene();
    p.view_angle_deg = 75.0f;
    p.distance = 2.5f;
    p.technique = Technique::normal;
    const Image reference = render(p.build()).image;
    for (Technique t : kMarchTechniques) {
        p.technique = t;
        const ImageDiff d = compare(render(p.build()).image, reference);
        EXPECT_GT(d.mean, 4.0) << technique_name(t) << " looks like normal mapping at 75 degrees";
    }
}

// Mip-level LOD (Tatarchuk 2005): past the threshold the technique becomes
// normal mapping; far below it, it is the full technique.
TEST(Lod, ThresholdSwitchesBetweenFullEffectAndNormalMapping) {
    PlaneScene p = bricks_scene();
    p.field.size = 512;  // 4 texels per pixel or more: minified (mip > 1) everywhere in view
    p.view_angle_deg = 65.0f;
    p.technique = Technique::normal;
    const Image normal_mapping = render(p.build()).image;
    for (Technique t : kParallaxTechniques) {
        p.technique = t;
        p.options.lod = false;
        const Image full = render(p.build()).image;
        p.options.lod = true;
        p.options.lod_threshold = 1.0f;  // every pixel is past mip level 1
        p.options.lod_band = 0.5f;
        const Rendered past = render(p.build());
        ASSERT_TRUE(past.reports[0].variant.lod) << technique_name(t);
        // The LOD variant is a different program: Mesa rounds its mediump
        // (fp16) arithmetic in another order, which moves a few pixels on
        // brick edges (measured: mean 0.14, max 18 levels); the mean holds
        // the rest to "the same image".
        const ImageDiff to_normal = compare(past.image, normal_mapping);
        EXPECT_LT(to_normal.mean, 0.25) << technique_name(t) << " past the threshold";
        EXPECT_LE(to_normal.max, 32) << technique_name(t) << " past the threshold";
        p.options.lod_threshold = 20.0f;  // no pixel reaches mip level 19
        p.options.lod_band = 1.0f;
        const ImageDiff to_full = compare(render(p.build()).image, full);
        EXPECT_LT(to_full.mean, 0.25) << technique_name(t) << " below the threshold";
        EXPECT_LE(to_full.max, 32) << technique_name(t) << " below the threshold";
        EXPECT_GT(compare(full, normal_mapping).mean, 1.0) << technique_name(t) << ": the test needs visible parallax";
    }
}

// The view ray goes the right way: seen from -y at 60 degrees, a ray entering
// a pit just past its near edge travels on (+v) to the pit floor, while one
// entering just before its far edge meets the far wall near the top. A probe
// plane halfway down the pit shows only where the hit is deeper than it; a
// reversed offset would swap the two.
TEST(Depth, ViewRayTravelsAwayFromTheViewer) {
    for (Technique t : kMarchTechniques) {
        PlaneScene p = pit_scene(t, 0.1f);
        p.options.depth_write = true;
        p.options.min_samples = p.options.max_samples = 64;
        p.view_angle_deg = 60.0f;
        p.textured_albedo = false;
        SceneDesc scene = p.build();
        add_probe_plane(scene, -0.1f);  // half of 0.1 tiles x 2 units per tile
        const Rendered r = render(scene, 256);
        auto greenness = [&](float v) {
            const glm::vec2 px = project(scene, glm::vec3(0.0f, (v - 0.5f) * 2.0f, 0.0f), 256);
            const std::uint8_t* c = r.image.texel(int(px.x), int(px.y));
            return int(c[1]) - int(c[0]);
        };
        // Near edge at v = 0.25: the ray from v = 0.28 reaches the floor at
        // v = 0.28 + 0.1 tan 60 = 0.45, inside the pit.
        EXPECT_GT(greenness(0.28f), 100) << technique_name(t) << ": the ray past the near edge did not reach the floor";
        // Far edge at v = 0.75: the ray from v = 0.73 meets the far wall 0.012 deep.
        EXPECT_LT(greenness(0.73f), 10) << technique_name(t) << ": the ray before the far edge went deep";
    }
}

// The debug outputs carry what the shader computed: on a flat relief at the
// polygon, seen straight on, the hit is the polygon's own uv at height 1;
// with the relief 0.1 deep under it, the hit moves by -0.1 * V.xy / V.z.
TEST(DebugOutput, CapturesHitUvHeightAndVisibility) {
    for (float level : {1.0f, 0.0f}) {
        PlaneScene p;
        p.field.kind = FieldKind::flat;
        p.field.size = 64;
        p.field.level = level;
        p.height_scale = 0.1f;
        p.technique = Technique::pom;
        p.view_angle_deg = 0.0f;
        p.options.shadow = ShadowMode::hard;
        const SceneDesc scene = p.build();
        auto renderer = Renderer::create();
        ASSERT_TRUE(renderer.ok());
        ASSERT_TRUE((*renderer)->load(scene).ok());
        auto surfaces = capture_surfaces(**renderer, 128, 128);
        ASSERT_TRUE(surfaces.ok()) << surfaces.error().message;
        EXPECT_FALSE(surfaces->at(0, 0).covered) << "the corner shows background";
        // World point (0.4, 0.2) is polygon uv (0.7, 0.6); from the camera at
        // (0, 0, 3) the view vector there is (-0.4, -0.2, 3) / |.|.
        const glm::vec2 px = project(scene, glm::vec3(0.4f, 0.2f, 0.0f), 128);
        const SurfaceSample& s = surfaces->at(int(px.x), int(px.y));
        ASSERT_TRUE(s.covered);
        const glm::dvec2 expected = level == 1.0f ? glm::dvec2(0.7, 0.6)
                                                  : glm::dvec2(0.7, 0.6) - 0.1 * glm::dvec2(-0.4, -0.2) / 3.0;
        // Half a pixel of the 128-pixel view spans 0.004 uv; allow that.
        EXPECT_NEAR(s.uv.x, expected.x, 0.006) << "level " << level;
        EXPECT_NEAR(s.uv.y, expected.y, 0.006) << "level " << level;
        EXPECT_NEAR(s.height, level, 1.0 / 256.0);
        EXPECT_NEAR(s.visibility, 1.0, 1e-3) << "a flat relief casts no shadow";
    }
}

// After a context loss the renderer forgets its GL objects without touching
// GL, and loads again.
TEST(HostIntegration, AbandonThenReload) {
    auto renderer = Renderer::create();
    ASSERT_TRUE(renderer.ok());
    const SceneDesc scene = bricks_scene().build();
    ASSERT_TRUE((*renderer)->load(scene).ok());
    (*renderer)->abandon();
    EXPECT_EQ((*renderer)->program_count(), 0u);
    EXPECT_FALSE((*renderer)->draw(RenderTarget{0, 8, 8}).ok()) << "drawing with nothing loaded must be an error";
    ASSERT_TRUE((*renderer)->load(scene).ok());
    auto target = OffscreenTarget::create(32, 32);
    ASSERT_TRUE(target.ok());
    ASSERT_TRUE((*renderer)->draw(target->target()).ok());
}

// Written depth follows the height field: a probe plane placed halfway down a
// pit, drawn after the relief, shows through only where the traced surface is
// deeper than the probe (the pit) and nowhere when depth is not written.
TEST(Depth, WrittenDepthFollowsTheHeightField) {
    for (Technique t : kMarchTechniques) {
        for (bool depth_write : {true, false}) {
            PlaneScene p = pit_scene(t, 0.2f);  // the pit is 0.2 tiles = 0.4 world units deep
            p.options.depth_write = depth_write;
            p.view_angle_deg = 20.0f;
            p.textured_albedo = false;
            SceneDesc scene = p.build();
            add_probe_plane(scene, -0.2f);  // half the pit's depth

            const Rendered r = render(scene);
            auto greenness = [&](glm::vec3 world) {
                const glm::vec2 px = project(scene, world, 128);
                const std::uint8_t* c = r.image.texel(int(px.x), int(px.y));
                return int(c[1]) - int(c[0]);
            };
            // Pit centre (uv 0.5, 0.5) and the flat top (uv 0.1, 0.5).
            const int pit = greenness(glm::vec3(0.0f, 0.0f, 0.0f));
            const int top = greenness(glm::vec3(-0.8f, 0.0f, 0.0f));
            EXPECT_LT(top, 10) << technique_name(t) << ": probe seen through the relief's top";
            if (depth_write)
                EXPECT_GT(pit, 100) << technique_name(t) << ": the pit's written depth is not behind the probe";
            else
                EXPECT_LT(pit, 10) << technique_name(t) << ": without depth write the polygon must hide the probe";
        }
    }
}

// A pit under a low light: the floor next to the wall that faces away from
// the light is dark with self-shadowing (hard and soft) and lit without.
TEST(Shadows, PitUnderLowLightIsDarkOnlyWithSelfShadowing) {
    for (Technique t : kMarchTechniques) {
        PlaneScene p = pit_scene(t, 0.1f);
        p.view_angle_deg = 0.0f;
        p.light_elevation_deg = 25.0f;  // shadow 0.1 / tan(25) = 0.21 tiles long
        p.textured_albedo = false;
        const SceneDesc lit_scene = p.build();
        // Pit floor at uv (0.68, 0.5): 0.07 tiles from the wall toward the light.
        const glm::vec2 probe = project(lit_scene, glm::vec3(0.36f, 0.0f, 0.0f), 128);
        const double lit = luminance(render(lit_scene).image, int(probe.x), int(probe.y));
        for (ShadowMode mode : {ShadowMode::hard, ShadowMode::soft}) {
            p.options.shadow = mode;
            const double shadowed = luminance(render(p.build()).image, int(probe.x), int(probe.y));
            // Compared as light (the image is encoded for an sRGB display).
            EXPECT_LT(srgb_to_linear(shadowed / 255.0), 0.4 * srgb_to_linear(lit / 255.0))
                << technique_name(t) << " shadow=" << shadow_mode_name(mode) << ": lit " << lit << ", shadowed "
                << shadowed;
        }
        // The flat top, in the open, stays lit with shadows on.
        p.options.shadow = ShadowMode::hard;
        const glm::vec2 open = project(lit_scene, glm::vec3(-0.8f, 0.0f, 0.0f), 128);
        const Image with_shadows = render(p.build()).image;
        EXPECT_GT(srgb_to_linear(luminance(with_shadows, int(open.x), int(open.y)) / 255.0),
                  0.8 * srgb_to_linear(lit / 255.0))
            << technique_name(t);
    }
}

// A light on or below the polygon's plane cannot light its surface, whatever
// the normal map says: a bevel facing a light 5 degrees under the horizon has
// N.L > 0, but the light is behind the polygon. Shadows off (the shadow ray's
// horizon test is not what keeps it dark), every technique, and the exact
// reference's shading (surface_main.glsl's mirror) the same. What is left is
// ambient * albedo in linear light: 0.08 times the albedo 0.8 (byte 204, sRGB:
// 0.604 linear) = 0.0483, shown as 62 of 255 on an sRGB display; one more
// allows the 8-bit rounding of that (and mediump's 1e-3 relative error, a
// tenth of a level there). Before: 12 to 28 % of the surface was lit from
// under the polygon.
TEST(Lighting, LightOnOrBelowTheHorizonLightsNothingButAmbient) {
    const int kAmbientLevel = linear_to_srgb8(0.08 * srgb_to_linear(204 / 255.0)) + 1;
    for (const TechniqueInfo& info : technique_table()) {
        if (info.min_es_major > test_es_major()) continue;
        for (float elevation : {-5.0f, 0.0f}) {
            PlaneScene p = bricks_scene();
            p.technique = info.id;
            p.view_angle_deg = 40.0f;
            p.light_elevation_deg = elevation;
            p.textured_albedo = false;
            SceneDesc scene = p.build();
            scene.materials[0].specular = 1.0f;  // a lit highlight could not hide
            const Image image = render(scene).image;
            ASSERT_EQ(image.pixels.size(), 128u * 128u * 4u);
            long lit = 0, drawn = 0;
            for (size_t i = 0; i < image.pixels.size(); i += 4) {
                const int level = std::max({image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]});
                if (level > 12) ++drawn;  // the background is (5, 5, 8)
                if (level > kAmbientLevel) ++lit;
            }
            EXPECT_GT(drawn, 128 * 128 / 4) << info.name << ": the plane was not drawn";
            EXPECT_EQ(lit, 0) << info.name << " with the light " << elevation << " degrees up: " << lit << " of "
                              << drawn << " pixels (" << 100.0 * lit / std::max(drawn, 1L)
                              << " %) lit beyond ambient";
            if (info.id == Technique::pom) {
                auto truth = reference::render_reference(scene, 128, 128);
                ASSERT_TRUE(truth.ok()) << truth.error().message;
                long reference_lit = 0;
                for (size_t i = 0; i < truth->color.pixels.size(); i += 4)
                    if (std::max({truth->color.pixels[i], truth->color.pixels[i + 1], truth->color.pixels[i + 2]}) >
                        kAmbientLevel)
                        ++reference_lit;
                EXPECT_EQ(reference_lit, 0) << "the reference with the light " << elevation << " degrees up";
            }
        }
    }
}

// A curved mesh's uv need not be square on the surface: a uv sphere's u runs
// round the equator (2 pi r), its v pole to pole (pi r), so a material scaled
// 6 x 3 on it has square tiles, and round bumps stay round. Shading must
// then see the texture at the surface's proportions: a light 45 degrees
// from the east lights the equator's front as one 45 degrees from the north
// does (the scene turned a quarter round the view axis), in mean and in the
// bumps' contrast. It did not: the lights' and the view's texture frame was
// the material's uv matrix alone, diag(6, 3) / sqrt(18), so the east light
// arrived 35 degrees up and the north one 55 (measured before the fix, ES
// 3.0: mean luminance 115 from the east against 162 from the north, the
// bumps' deviation 1.3 times as strong), for every technique, and the
// shadow rays stepped uv without the mesh's stretch.
TEST(Lighting, ASquareMaterialOnAStretchedUvShadesTheSameFromEachSide) {
    const auto lit_by = [](Technique technique, glm::vec3 to_light) {
        SceneDesc s;
        s.camera.position = {0.0f, -3.4f, 0.0f};
        s.camera.target = {0.0f, 0.0f, 0.0f};
        s.camera.up = {0.0f, 0.0f, 1.0f};
        s.camera.fov_y_deg = 14.0f;  // the front of the equator, +-20 degrees of the sphere
        MaterialDesc m;
        m.name = "bumps";
        m.height.kind = TextureSource::Kind::procedural;
        m.height.field.kind = FieldKind::hemispheres;
        m.height.field.count = 2;
        m.height.field.size = 128;
        m.height_scale = 0.05f;
        m.uv.scale = {6.0f, 3.0f};
        m.specular = 0.0f;
        m.technique.technique = technique;
        s.materials = {m};
        ObjectDesc o;
        o.name = "sphere";
        o.material = "bumps";
        o.mesh.kind = MeshKind::sphere;
        o.mesh.radius = 0.9f;
        s.objects = {o};
        LightDesc l;
        l.direction = -glm::normalize(to_light);
        l.angular_radius_deg = 0.0f;
        s.lights = {l};
        s.ambient = glm::vec3(0.0f);
        EXPECT_TRUE(validate_scene(s).ok());
        return render(s).image;
    };
    // Mean and standard deviation of the luminance over the middle half.
    struct Stats {
        double mean = 0.0, deviation = 0.0;
    };
    const auto stats = [](const Image& image) {
        double sum = 0.0, sum2 = 0.0;
        long n = 0;
        for (int y = 32; y < 96; ++y)
            for (int x = 32; x < 96; ++x) {
                const double v = luminance(image, x, y, 0);
                sum += v;
                sum2 += v * v;
                ++n;
            }
        const double mean = sum / n;
        return Stats{mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean))};
    };
    const double c = std::sqrt(0.5);
    for (Technique technique : {Technique::normal, Technique::pom}) {
        SCOPED_TRACE(technique_name(technique));
        const Stats east = stats(lit_by(technique, {c, -c, 0.0f}));
        const Stats north = stats(lit_by(technique, {0.0f, -c, c}));
        std::printf("%s: lit from the east mean %.1f, deviation %.1f; from the north %.1f, %.1f\n",
                    technique_name(technique), east.mean, east.deviation, north.mean, north.deviation);
        EXPECT_GT(east.deviation, 3.0) << "the bumps do not show";
        EXPECT_NEAR(east.mean / north.mean, 1.0, 0.05);
        EXPECT_NEAR(east.deviation / north.deviation, 1.0, 0.15);
    }
}

// A whole-tile uv offset changes no texel (GL_REPEAT), so it must change
// nothing drawn, up to kMaxUvOffset (core/limits.h), for every technique. It
// did: at offset 1000 steep's colour lost the relief (26 levels mean, its
// march uv demoted to fp16 by Mesa's mediump lowering) and every technique's
// hit moved by fp32's 2^-14-tile grid there (up to 0.83 texel on steep, 0.3
// on pom and maxmip). The bound is exact equality: the renderer hands the
// shader only the offset's fraction, and k + 0.25 (|k| <= 1023) is exact in
// fp32 with an exact difference (Sterbenz), so the draws are the same draws.
TEST(UvOffset, WholeTilesChangeNothingForEveryTechnique) {
    const glm::vec2 base(0.25f, 0.5f);
    for (const TechniqueInfo& info : technique_table()) {
        if (info.min_es_major > test_es_major()) continue;
        PlaneScene p = bricks_scene();
        p.technique = info.id;
        p.view_angle_deg = 50.0f;
        SceneDesc scene = p.build();
        auto draw = [&](glm::vec2 tiles) {
            SceneDesc s = scene;
            s.materials[0].uv.offset = base + tiles;
            auto renderer = Renderer::create();
            EXPECT_TRUE(renderer.ok());
            Status loaded = (*renderer)->load(s);
            EXPECT_TRUE(loaded.ok()) << loaded.error().message;
            auto surfaces = capture_surfaces(**renderer, 128, 128);
            EXPECT_TRUE(surfaces.ok()) << surfaces.error().message;
            return std::make_pair(*surfaces, render(s).image);
        };
        const auto [surface0, color0] = draw(glm::vec2(0.0f));
        for (const glm::vec2 tiles : {glm::vec2(100.0f), glm::vec2(1000.0f), glm::vec2(-1023.0f, 1023.0f)}) {
            const auto [surface, color] = draw(tiles);
            double worst = 0.0, worst_height = 0.0;
            long covered = 0;
            for (size_t i = 0; i < surface.samples.size(); ++i) {
                const SurfaceSample& a = surface.samples[i];
                const SurfaceSample& b = surface0.samples[i];
                ASSERT_EQ(a.covered, b.covered);
                if (!a.covered) continue;
                ++covered;
                glm::dvec2 d = a.uv - b.uv;
                d -= glm::round(d);  // modulo the tile
                worst = std::max(worst, glm::length(d) * 128.0);
                worst_height = std::max(worst_height, std::abs(a.height - b.height));
            }
            EXPECT_GT(covered, 128 * 128 / 4) << info.name;
            EXPECT_EQ(worst, 0.0) << info.name << " at offset " << tiles.x << ", " << tiles.y
                                  << " tiles: the hit moved by up to " << worst << " texels";
            EXPECT_EQ(worst_height, 0.0) << info.name << " at offset " << tiles.x << ", " << tiles.y;
            const ImageDiff diff = compare(color, color0);
            EXPECT_EQ(diff.max, 0) << info.name << " at offset " << tiles.x << ", " << tiles.y
                                   << " tiles: colour differs by " << diff.mean << " levels mean, " << diff.max
                                   << " max";
        }
    }
}

// The renderer draws into a framebuffer the host app owns (not 0, not made by
// platform/) and puts back the state it changed.
TEST(HostIntegration, DrawsIntoTheHostFramebufferAndRestoresState) {
    auto host_target = OffscreenTarget::create(64, 64);  // stands in for the app's FBO
    ASSERT_TRUE(host_target.ok()) << host_target.error().message;
    auto other = OffscreenTarget::create(32, 32);
    ASSERT_TRUE(other.ok());
    // Host state before the draw: another framebuffer bound, its own viewport.
    glBindFramebuffer(GL_FRAMEBUFFER, other->target().framebuffer);
    glViewport(1, 2, 3, 4);
    glDisable(GL_DEPTH_TEST);

    auto renderer = Renderer::create();
    ASSERT_TRUE(renderer.ok());
    PlaneScene p = bricks_scene();
    ASSERT_TRUE((*renderer)->load(p.build()).ok());
    Status s = (*renderer)->draw(host_target->target());
    ASSERT_TRUE(s.ok()) << s.error().message;

    GLint bound = 0, viewport[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &bound);
    glGetIntegerv(GL_VIEWPORT, viewport);
    EXPECT_EQ(GLuint(bound), other->target().framebuffer);
    EXPECT_EQ(viewport[0], 1);
    EXPECT_EQ(viewport[3], 4);
    EXPECT_FALSE(glIsEnabled(GL_DEPTH_TEST));
    auto image = host_target->read_pixels();
    ASSERT_TRUE(image.ok());
    EXPECT_GT(luminance(*image, 32, 32, 3), 20.0) << "nothing drawn into the host framebuffer";
}

TEST(Errors, IncompleteTargetIsReportedNotDrawn) {
    auto renderer = Renderer::create();
    ASSERT_TRUE(renderer.ok());
    ASSERT_TRUE((*renderer)->load(bricks_scene().build()).ok());
    FramebufferHandle empty = make_framebuffer();  // no attachments
    Status s = (*renderer)->draw(RenderTarget{empty.get(), 64, 64});
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("incomplete"), std::string::npos) << s.error().message;
}

TEST(Errors, MissingTextureFileNamesTheFileAndMaterial) {
    auto renderer = Renderer::create(reading_files());
    ASSERT_TRUE(renderer.ok());
    SceneDesc scene = bricks_scene().build();
    scene.materials[0].albedo.kind = TextureSource::Kind::file;
    scene.materials[0].albedo.path = "/nonexistent/albedo.png";
    Status s = (*renderer)->load(scene);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("/nonexistent/albedo.png"), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find("surface"), std::string::npos) << s.error().message;
}

// Without RendererOptions::texture_files a scene that names a file is
// refused before anything is read or uploaded, naming the JSON path, the
// material and the file, and saying what to set.
TEST(Errors, FilesWithoutReadersAreRefusedNamingTheFile) {
    auto renderer = Renderer::create();
    ASSERT_TRUE(renderer.ok());
    SceneDesc scene = bricks_scene().build();
    scene.materials[0].height.kind = TextureSource::Kind::file;
    scene.materials[0].height.path = "relief.ktx";
    Status s = (*renderer)->load(scene);
    ASSERT_FALSE(s.ok());
    for (const char* part : {"materials[0].height", "surface", "relief.ktx", "texture_files"})
        EXPECT_NE(s.error().message.find(part), std::string::npos) << part << ": " << s.error().message;
    EXPECT_EQ((*renderer)->prepared(), nullptr);
}

// A shader that fails to compile reports the stage, the driver's log, the
// offending line and the variant's defines.
TEST(Errors, ShaderCompileFailureCarriesLogLineAndDefines) {
    VariantSources sources;
    sources.vertex.text = test_es_major() >= 3 ? "#version 300 es\nvoid main() { gl_Position = vec4(0.0); }\n"
                                               : "#version 100\nvoid main() { gl_Position = vec4(0.0); }\n";
    sources.fragment.text = (test_es_major() >= 3 ? std::string("#version 300 es\n") : std::string("#version 100\n")) +
                            "precision mediump float;\nvoid main() {\n  undeclared_name = 1.0;\n}\n";
    sources.fragment.defines_summary = "PX_TEST_DEFINE=7";
    VariantKey key;
    key.technique = Technique::normal;
    key.es_major = static_cast<std::uint8_t>(test_es_major());
    auto program = build_program(sources, key);
    ASSERT_FALSE(program.ok());
    const std::string& m = program.error().message;
    EXPECT_NE(m.find("fragment shader of variant '" + key.describe() + "'"), std::string::npos) << m;
    EXPECT_NE(m.find("PX_TEST_DEFINE=7"), std::string::npos) << m;
    EXPECT_NE(m.find("undeclared_name"), std::string::npos) << m;
    EXPECT_NE(m.find("4 |"), std::string::npos) << "the offending source line is quoted: " << m;
}

// The real sources of a variant with one line of the fragment stage edited.
VariantSources edited_sources(const VariantKey& key, const std::string& from, const std::string& to) {
    Result<VariantSources> sources = assemble_variant(key);
    EXPECT_TRUE(sources.ok()) << (sources.ok() ? "" : sources.error().message);
    VariantSources s = std::move(*sources);
    const size_t at = s.fragment.text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) s.fragment.text.replace(at, from.size(), to);
    return s;
}

VariantKey pom_key() {
    VariantKey key;
    key.technique = Technique::pom;
    key.es_major = static_cast<std::uint8_t>(test_es_major());
    key.max_samples = 16;
    return key;
}

// The typed interface: a uniform the variant needs and the program lacks (a
// misspelt declaration) is an error when the program is built, naming the
// uniform and the variant's defines, not a silent -1 at draw time.
TEST(ShaderInterface, MissingNeededUniformFailsTheBuild) {
    const VariantKey key = pom_key();
    // Unedited, the variant builds: the control.
    Result<VariantSources> good = assemble_variant(key);
    ASSERT_TRUE(good.ok());
    ASSERT_TRUE(build_program(*good, key).ok());

    VariantSources s = edited_sources(key, "uniform mediump float u_specular;", "uniform mediump float u_specularity;");
    // Its uses too, so that the program compiles and links without it.
    for (size_t at; (at = s.fragment.text.find("u_specular ")) != std::string::npos;)
        s.fragment.text.replace(at, 11, "u_specularity ");
    auto program = build_program(s, key);
    ASSERT_FALSE(program.ok());
    const std::string& m = program.error().message;
    EXPECT_NE(m.find("needs uniform 'u_specular'"), std::string::npos) << m;
    EXPECT_NE(m.find("PX_TECH_POM"), std::string::npos) << "names the defines: " << m;
}

// The other way round: an active uniform that the interface does not list
// would never be set, and one declared with another type than the
// interface's would be set wrongly; both fail the build.
TEST(ShaderInterface, UnlistedOrMistypedUniformFailsTheBuild) {
    const VariantKey key = pom_key();
    VariantSources unlisted = edited_sources(key, "uniform mediump float u_specular;",
                                             "uniform mediump float u_specular;\nuniform mediump float u_gloss;");
    const size_t use = unlisted.fragment.text.find("u_specular *");
    ASSERT_NE(use, std::string::npos);
    unlisted.fragment.text.replace(use, 12, "u_specular * u_gloss *");
    auto a = build_program(unlisted, key);
    ASSERT_FALSE(a.ok());
    EXPECT_NE(a.error().message.find("uniform 'u_gloss'"), std::string::npos) << a.error().message;

    VariantSources mistyped =
        edited_sources(key, "uniform mediump float u_shininess;", "uniform mediump int u_shininess;");
    const size_t exponent = mistyped.fragment.text.find(", u_shininess)");
    ASSERT_NE(exponent, std::string::npos);
    mistyped.fragment.text.replace(exponent, 14, ", float(u_shininess))");
    auto b = build_program(mistyped, key);
    ASSERT_FALSE(b.ok());
    EXPECT_NE(b.error().message.find("uniform 'u_shininess' is declared with another type"), std::string::npos)
        << b.error().message;
}

// Every variant the program can build (the shader-validation set) builds on
// this context with its interface complete: the table's "needed" rules match
// what the shaders really use.
TEST(ShaderInterface, EveryVariantBuildsWithItsInterface) {
    int built = 0;
    for (const VariantKey& key : enumerate_variants(test_es_major())) {
        Result<VariantSources> sources = assemble_variant(key);
        ASSERT_TRUE(sources.ok()) << key.describe();
        auto program = build_program(*sources, key);
        EXPECT_TRUE(program.ok()) << (program.ok() ? "" : program.error().message);
        ++built;
    }
    EXPECT_GT(built, 100);
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

std::string joined_notes(const DrawReport& r) {
    std::string out;
    for (const std::string& n : r.notes) out += n + "\n";
    return out;
}

// `parallax render default --technique T` refused every technique but the
// linear searches ("materials[2].silhouette: a curved silhouette is drawn by
// the linear searches ..."): the first scene a newcomer sees. An override
// draws every material with its technique, and the plan says what it
// dropped (the dome's curved silhouette, the panel's bounded outline, the
// shadows), whichever planner the renderer has (the effect planner, or none:
// the named-technique planner). A material that names such a technique
// itself is still refused, naming the field.
TEST(Overrides, EveryTechniqueDrawsTheDefaultSceneAndSaysWhatItDropped) {
    Result<SceneDesc> scene = builtin_scene("default");
    ASSERT_TRUE(scene.ok());
    for (const bool with_effect_planner : {false, true}) {
        for (const TechniqueInfo& info : technique_table()) {
            SCOPED_TRACE(std::string(info.name) + (with_effect_planner ? ", effect planner" : ", named planner"));
            SceneDesc s = *scene;
            (void)force_technique(s, info.id);
            ASSERT_TRUE(validate_scene(s).ok()) << validate_scene(s).error().message;
            RendererOptions options;
            options.effect_planner = with_effect_planner ? effect_planner : nullptr;
            auto renderer = Renderer::create(options);
            ASSERT_TRUE(renderer.ok()) << renderer.error().message;
            auto target = OffscreenTarget::create(64, 64);
            ASSERT_TRUE(target.ok());
            Status loaded = (*renderer)->load(s);
            ASSERT_TRUE(loaded.ok()) << loaded.error().message;
            Status drawn = (*renderer)->draw(target->target());
            ASSERT_TRUE(drawn.ok()) << drawn.error().message;
            const std::vector<DrawReport>& reports = (*renderer)->reports();
            ASSERT_EQ(reports.size(), s.objects.size());
            const bool searches = (info.options & kOptSamples) != 0;
            const bool traces = (info.options & kOptHeight) != 0;
            for (const DrawReport& r : reports) {
                const std::string notes = joined_notes(r);
                if (r.object == "dome") {
                    EXPECT_EQ(r.variant.curved, searches) << r.variant.describe();
                    EXPECT_EQ(notes.find("silhouette not drawn: " + std::string(info.name)) != std::string::npos,
                              !searches)
                        << notes;
                    if (info.id == Technique::maxmip) EXPECT_NE(notes.find("does not yet"), std::string::npos) << notes;
                }
                if (r.object == "panel") {
                    EXPECT_EQ(notes.find("bounded outline not drawn") != std::string::npos, !traces) << notes;
                    if (!traces) EXPECT_FALSE(r.variant.bounded) << r.variant.describe();
                }
                if (!(info.options & kOptShadow))
                    EXPECT_NE(notes.find("shadow=soft ignored"), std::string::npos) << notes;
            }
            // Something was drawn: a textured scene, not a cleared target.
            auto image = target->read_pixels();
            ASSERT_TRUE(image.ok());
            std::set<std::uint32_t> colours;
            for (size_t p = 0; p + 2 < image->pixels.size(); p += static_cast<size_t>(image->channels))
                colours.insert(std::uint32_t{image->pixels[p]} << 16 | std::uint32_t{image->pixels[p + 1]} << 8 |
                               image->pixels[p + 2]);
            EXPECT_GT(colours.size(), 100u);
        }
    }
    // Authored, not forced: still refused, naming the field.
    SceneDesc authored = *scene;
    for (MaterialDesc& m : authored.materials)
        if (m.silhouette) m.technique.technique = Technique::normal;
    Status refused = validate_scene(authored);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find(".silhouette"), std::string::npos) << refused.error().message;
}

}  // namespace
}  // namespace px::test

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    ::testing::AddGlobalTestEnvironment(new px::test::GpuEnvironment);
    return RUN_ALL_TESTS();
}
