// Silhouettes of bounded reliefs (MaterialDesc::bounded, PX_BOUNDED): a tile
// whose traced rays leave its mesh uv [0, 1]^2 shows what lies behind, so
// its outline is the relief's, not the polygon's. Checked against the relief
// drawn as real geometry (a displaced mesh: the contour truth) and against
// the exact reference, which applies the same bounds.
#include "gpu_fixture.h"

#include <cmath>
#include <cstdio>
#include <utility>

#include "parallaxes/core/numeric.h"
#include "parallaxes/emulation/precision.h"
#include "parallaxes/planner/planner.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/reference/metrics.h"
#include "parallaxes/reference/reference_image.h"
#include "parallaxes/render/surface_capture.h"

namespace px::test {
namespace {

constexpr int kSize = 192;

// A bricks tile seen at `angle` degrees, deep enough that its mortar shows
// through at the far edge.
PlaneScene tile(double angle, Technique technique) {
    PlaneScene p;
    p.field.kind = FieldKind::bricks;
    p.field.size = 128;
    p.height_scale = 0.15f;
    p.view_angle_deg = static_cast<float>(angle);
    p.distance = 3.6f;
    p.technique = technique;
    p.options.min_samples = p.options.max_samples = 64;
    return p;
}

SurfaceImage surfaces_of(const SceneDesc& scene, const RendererOptions& options = {}) {
    auto renderer = Renderer::create(options);
    EXPECT_TRUE(renderer.ok());
    if (!renderer.ok()) return {};
    Status loaded = (*renderer)->load(scene);
    EXPECT_TRUE(loaded.ok()) << loaded.error().message;
    auto s = capture_surfaces(**renderer, kSize, kSize);
    EXPECT_TRUE(s.ok()) << s.error().message;
    return s.ok() ? std::move(*s) : SurfaceImage{};
}

// The tile as real geometry, displaced by the relief: `per_texel` vertices
// per texel along each side (2: a vertex on every texel centre, the
// bilinear patches' corners, and one between; one vertex per texel puts
// them on texel corners, and its triangles cut across the bricks' walls).
SurfaceImage displaced(double angle, int per_texel = 2) {
    SceneDesc s = tile(angle, Technique::normal).build();
    s.objects[0].mesh.displaced = true;
    s.objects[0].mesh.vertices_per_texel = per_texel;
    return surfaces_of(s);
}

// The bounded tile at `angle` as the exact reference draws it (maxmip's
// scene; the reference traces the relief exactly, whatever the technique).
SurfaceImage bounded_reference(double angle) {
    SceneDesc exact = tile(angle, Technique::maxmip).build();
    exact.materials[0].bounded = true;
    auto reference = reference::render_reference(exact, kSize, kSize);
    EXPECT_TRUE(reference.ok()) << reference.error().message;
    return reference.ok() ? std::move(reference->surface) : SurfaceImage{};
}

reference::ContourError contour(const SurfaceImage& measured, const SurfaceImage& truth) {
    auto e = reference::compare_contours(measured, truth);
    EXPECT_TRUE(e.ok()) << e.error().message;
    return e.ok() ? *e : reference::ContourError{};
}

// A planner for a scene of one material, on this test's context.
Result<std::unique_ptr<ScenePlanner>> one_material_planner(const SceneDesc& scene,
                                                           const Caps& caps = Caps::full(test_es_major())) {
    Result<MaterialImages> images = build_material_images(scene.materials[0], scene.base_dir);
    if (!images) return images.error();
    return ScenePlanner::create(scene, caps, {material_relief(quantized_8bit(images->field), scene.materials[0])});
}

// A plan's notes, one per line.
std::string notes_of(const ObjectPlan& p) {
    std::string all;
    for (const std::string& n : p.notes) all += n + "\n";
    return all;
}

// The exact reference applies the same bounds (a ray that leaves the tile
// before meeting the relief shows the background): the GPU's outline is the
// reference's, to a few pixels along a contour of hundreds, where the tile
// without bounds shows phantom relief (the next tile's) along its far edge.
TEST(Silhouettes, ABoundedTileHasTheReferencesOutline) {
    for (double angle : {45.0, 75.0}) {
        for (Technique t : {Technique::maxmip, Technique::pom}) {
            SceneDesc bounded = tile(angle, t).build();
            bounded.materials[0].bounded = true;
            auto truth = reference::render_reference(bounded, kSize, kSize);
            ASSERT_TRUE(truth.ok()) << truth.error().message;
            const reference::ContourError with = contour(surfaces_of(bounded), truth->surface);
            const reference::ContourError without = contour(surfaces_of(tile(angle, t).build()), truth->surface);
            SCOPED_TRACE(std::string(technique_name(t)) + " at " + std::to_string(angle) + " degrees");
            std::printf("%s at %.0f deg against the reference: contour %ld px, %ld mismatched bounded, %ld open\n",
                        technique_name(t), angle, with.contour, with.mismatched, without.mismatched);
            ASSERT_GT(with.contour, 300);
            // Measured (llvmpipe, 192 pixels, ES 2.0 and 3.0 alike): maxmip
            // 0 pixels at both angles; POM x64 0 at 45 degrees, 8 of 408 at
            // 75 (its search's own error, at brick corners near the edge).
            EXPECT_LE(with.share(), t == Technique::maxmip ? 0.005 : 0.03) << with.mismatched << " of " << with.contour;
            EXPECT_GT(without.share(), 1.0) << without.mismatched << " of " << with.contour;
        }
    }
}

// Against the relief drawn as real geometry (the displaced tile, 2 vertices
// per texel): bounds remove what the tile drew where the geometry shows
// nothing (phantom relief past its far edge), and the wider polygon draws
// the band along the near edge where the relief, under the polygon, shows
// past the polygon's own outline (rays that come in through the tile's
// side). The displaced tile is converged: the exact reference differs from
// it by at most 1 pixel, where one vertex per texel differs by 3 to 5 % of
// the contour (its triangles cut across the bricks' walls). maxmip, exact,
// meets the goal (at most 1 % of the contour); the linear searches
// are within their own error against the exact reference (POM x64: 8 pixels
// at 75 degrees, ABoundedTileHasTheReferencesOutline).
TEST(Silhouettes, ABoundedTileHasTheOutlineOfItsReliefAsGeometry) {
    for (double angle : {45.0, 60.0, 75.0}) {
        const SurfaceImage truth = displaced(angle);
        const SurfaceImage exact = bounded_reference(angle);
        const reference::ContourError mesh_error = contour(exact, truth);
        const reference::ContourError coarse_error = contour(exact, displaced(angle, 1));
        std::printf("at %.0f deg the exact reference against the displaced tile: %ld of %ld px at 2 vertices per "
                    "texel, %ld at 1\n",
                    angle, mesh_error.mismatched, mesh_error.contour, coarse_error.mismatched);
        EXPECT_LE(mesh_error.mismatched * 100, mesh_error.contour) << "the displaced reference has not converged";
        EXPECT_GT(coarse_error.mismatched * 100, coarse_error.contour) << "one vertex per texel was not coarser";
        for (Technique t : {Technique::maxmip, Technique::pom, Technique::relief, Technique::steep}) {
            SceneDesc bounded = tile(angle, t).build();
            bounded.materials[0].bounded = true;
            const reference::ContourError with = contour(surfaces_of(bounded), truth);
            const reference::ContourError without = contour(surfaces_of(tile(angle, t).build()), truth);
            std::printf("%s at %.0f deg: contour %ld px; bounded: %ld drawn only, %ld truth only; open: %ld drawn only, "
                        "%ld truth only\n",
                        technique_name(t), angle, with.contour, with.measured_only, with.mismatched - with.measured_only,
                        without.measured_only, without.mismatched - without.measured_only);
            SCOPED_TRACE(std::string(technique_name(t)) + " at " + std::to_string(angle) + " degrees");
            // Measured (llvmpipe, 192 pixels, 2026-12-05): maxmip 0, 0 and 1
            // pixels at 45, 60 and 75 degrees; POM x64 0, 4 and 9, relief x64
            // 0, 2 and 7, steep x64 (it stops at its first sample under the
            // surface) 4, 8 and 17, all truth only; open, 866 to 1858 drawn
            // only and 2332 to 4801 truth only.
            const double limit = t == Technique::maxmip ? 0.01 : t == Technique::steep ? 0.05 : 0.03;
            EXPECT_LE(with.share(), limit) << with.mismatched << " of " << with.contour;
            EXPECT_GT(without.mismatched - without.measured_only, with.contour);
            EXPECT_GT(without.measured_only, with.contour);
        }
    }
}

// Toward grazing a ray comes into the tile through its side far beyond the
// wider polygon's reach (at 89 degrees it crosses the polygon's plane 57
// relief depths out, the polygon reaches 5.7): the tile's side walls
// (make_tile_walls) start those traces where the ray comes in. Against the
// displaced tile (2 vertices per texel): maxmip 1 pixel of 434 and 422 at 85
// and 89 degrees (0.2 %), POM x64 17 and 43 (3.9 and 10.2 %: its linear
// search steps over the near bricks' edges seen nearly edge-on); 2026-12-05.
// Without the walls, 778 % at 89 (the near bricks' faces, 3273 pixels, not
// drawn).
TEST(Silhouettes, ABoundedTileKeepsItsSideTowardGrazing) {
    for (double angle : {85.0, 89.0}) {
        SCOPED_TRACE(std::to_string(angle) + " degrees");
        const SurfaceImage truth = displaced(angle);
        const SurfaceImage exact = bounded_reference(angle);
        const reference::ContourError reference_error = contour(exact, truth);
        std::printf("the exact reference at %.0f deg against the geometry: contour %ld px, %ld mismatched\n", angle,
                    reference_error.contour, reference_error.mismatched);
        EXPECT_LE(reference_error.share(), 0.01);
        for (Technique t : {Technique::maxmip, Technique::pom}) {
            SceneDesc bounded = tile(angle, t).build();
            bounded.materials[0].bounded = true;
            const SurfaceImage drawn = surfaces_of(bounded);
            const reference::ContourError e = contour(drawn, truth);
            const reference::ContourError r = contour(drawn, exact);
            std::printf("%s at %.0f deg against the geometry: contour %ld px, %ld geometry only, %ld drawn only; "
                        "against the exact reference %ld\n",
                        technique_name(t), angle, e.contour, e.mismatched - e.measured_only, e.measured_only,
                        r.mismatched);
            EXPECT_GT(e.contour, 300);
            EXPECT_LE(e.share(), t == Technique::maxmip ? 0.01 : 0.12) << technique_name(t);
            if (t == Technique::maxmip) EXPECT_LE(r.share(), 0.005);
        }
    }
}

// A single fetch (parallax, offset_limited) has no ray to start part way
// down: it draws no fragment outside the tile, and inside it stays bounded.
TEST(Silhouettes, SingleFetchesDrawNothingOutsideTheTile) {
    SceneDesc open = tile(60.0, Technique::parallax).build();
    SceneDesc bounded = open;
    bounded.materials[0].bounded = true;
    const SurfaceImage a = surfaces_of(open), b = surfaces_of(bounded);
    long drawn_open = 0, drawn_bounded = 0, bounded_only = 0;
    for (size_t i = 0; i < a.samples.size() && i < b.samples.size(); ++i) {
        drawn_open += a.samples[i].covered;
        drawn_bounded += b.samples[i].covered;
        bounded_only += b.samples[i].covered && !a.samples[i].covered;
    }
    EXPECT_EQ(bounded_only, 0);
    EXPECT_GT(drawn_bounded, drawn_open / 2);
}

// The planner keeps a bounded tile's discard only where its outline can be
// on screen, and says which: seen whole, the tile is bounded; filling the
// view from close above, its discard is left out.
TEST(Silhouettes, ThePlannerDropsTheDiscardWhereNoOutlineIsOnScreen) {
    SceneDesc scene = tile(60.0, Technique::pom).build();
    scene.materials[0].bounded = true;
    scene.materials[0].effects.emplace().max_error_texels = 0.5;
    Result<std::unique_ptr<ScenePlanner>> planner = one_material_planner(scene);
    ASSERT_TRUE(planner.ok()) << planner.error().message;
    auto whole = (*planner)->plan(scene.camera, kSize, kSize);
    ASSERT_TRUE(whole.ok()) << whole.error().message;
    EXPECT_TRUE(whole->at(0).key.bounded) << whole->at(0).key.describe();
    EXPECT_NE(notes_of(whole->at(0)).find("outline can be on screen"), std::string::npos) << notes_of(whole->at(0));
    CameraDesc close;
    close.position = glm::vec3(0.0f, 0.0f, 0.5f);
    close.target = glm::vec3(0.0f);
    close.up = glm::vec3(0.0f, 1.0f, 0.0f);
    close.fov_y_deg = 40.0f;
    auto inside = (*planner)->plan(close, kSize, kSize);
    ASSERT_TRUE(inside.ok()) << inside.error().message;
    EXPECT_FALSE(inside->at(0).key.bounded) << inside->at(0).key.describe();
    EXPECT_NE(notes_of(inside->at(0)).find("silhouette off"), std::string::npos) << notes_of(inside->at(0));
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

// A sphere, cylinder or torus under hemispherical bumps, seen from
// `elevation` degrees above its equator (the torus tilted 60 degrees).
SceneDesc curved_scene(MeshKind kind, double elevation, Technique technique, bool silhouette) {
    SceneDesc s;
    const double e = elevation * kPi<double> / 180.0;
    s.camera.position = {0.0f, static_cast<float>(-3.4 * std::cos(e)), static_cast<float>(3.4 * std::sin(e))};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.up = std::fabs(elevation) > 80.0 ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f);
    s.camera.fov_y_deg = 40.0f;
    MaterialDesc m;
    m.name = "bumps";
    m.height.kind = TextureSource::Kind::procedural;
    m.height.field.kind = FieldKind::hemispheres;
    m.height.field.count = 2;
    m.height.field.size = 128;
    m.height_scale = 0.05f;
    m.uv.scale = kind == MeshKind::torus ? glm::vec2(6.0f, 2.0f) : glm::vec2(6.0f, 3.0f);
    m.technique.technique = technique;
    m.technique.max_samples = 64;
    m.silhouette = silhouette;
    s.materials = {m};
    ObjectDesc o;
    o.name = "shape";
    o.material = "bumps";
    o.mesh.kind = kind;
    o.mesh.radius = kind == MeshKind::torus ? 1.0f : 0.9f;
    o.mesh.tube_radius = 0.4f;
    o.mesh.size = 1.8f;
    if (kind == MeshKind::torus) o.transform.rotate_deg = {60.0f, 0.0f, 0.0f};
    s.objects = {o};
    return s;
}

// Curved meshes as real geometry (make_displaced_curved): the reference for
// their silhouettes. A sphere, a cylinder and a torus of hemispherical bumps
// 0.05 tiles deep: displaced, their outline follows the bumps, so it leaves
// the smooth mesh's by more than 1 % of the contour; drawn with POM, the
// outline is the smooth mesh's to the pixel (without "silhouette": the
// relief ends at the polygon's edge), and what it misses against the
// displaced reference is printed (docs/silhouettes.md).
TEST(Silhouettes, DisplacedCurvedMeshesAreTheContourReference) {
    for (MeshKind kind : {MeshKind::sphere, MeshKind::cylinder, MeshKind::torus}) {
        SCOPED_TRACE(mesh_kind_name(kind));
        SceneDesc s = curved_scene(kind, 0.0, Technique::pom, false);
        s.camera.position = {0.0f, -3.4f, 0.8f};
        ASSERT_TRUE(validate_scene(s).ok());

        const SurfaceImage pom = surfaces_of(s);
        s.materials[0].technique.technique = Technique::normal;
        const SurfaceImage smooth = surfaces_of(s);
        s.objects[0].mesh.displaced = true;
        const SurfaceImage geometry = surfaces_of(s);

        const reference::ContourError relief_outline = contour(smooth, geometry);
        EXPECT_GT(relief_outline.contour, 200);
        EXPECT_GT(relief_outline.share(), 0.01);
        const reference::ContourError pom_vs_polygon = contour(pom, smooth);
        EXPECT_EQ(pom_vs_polygon.mismatched, 0);
        const reference::ContourError pom_vs_geometry = contour(pom, geometry);
        std::printf("%s: contour %ld px; POM (the smooth outline) mismatches %.1f %% of it, %ld px drawn outside\n",
                    mesh_kind_name(kind), pom_vs_geometry.contour, 100.0 * pom_vs_geometry.share(),
                    pom_vs_geometry.measured_only);
    }
}

// The three images a curved silhouette is judged by: the scene as given,
// the smooth outline (silhouette and bounds off: the polygon's), and the
// relief drawn as real geometry (the displaced reference).
struct CurvedImages {
    SurfaceImage with, smooth, geometry;
};
CurvedImages curved_images(SceneDesc s) {
    CurvedImages images;
    images.with = surfaces_of(s);
    s.materials[0].silhouette = false;
    s.materials[0].bounded = false;
    images.smooth = surfaces_of(s);
    s.objects[0].mesh.displaced = true;
    images.geometry = surfaces_of(s);
    return images;
}

// The displaced reference is fine enough to judge a 1 % goal: with the
// relief sampled twice as finely (a 256-texel field of the same bumps, so
// twice the vertices along u and v), the displaced sphere's and torus's
// contours move by at most 2 % of their length (measured 1.0 and 1.5 % at
// 30 degrees, docs/silhouettes.md). What the curved silhouette misses
// against it is the parallax trace's, not the reference's. The same
// geometry on either context: measured once, the ES 2.0 entry leaves it out
// (tests/CMakeLists.txt).
TEST(Silhouettes, TheDisplacedReferenceHasConverged) {
    for (MeshKind kind : {MeshKind::sphere, MeshKind::torus}) {
        SCOPED_TRACE(mesh_kind_name(kind));
        SceneDesc s = curved_scene(kind, 30.0, Technique::pom, false);
        s.objects[0].mesh.displaced = true;
        ASSERT_TRUE(validate_scene(s).ok());
        const SurfaceImage coarse = surfaces_of(s);
        s.materials[0].height.field.size *= 2;
        const SurfaceImage fine = surfaces_of(s);
        const reference::ContourError e = contour(coarse, fine);
        std::printf("%s at 30: contour %ld px; the reference against itself at twice the density: %.1f %%\n",
                    mesh_kind_name(kind), e.contour, 100.0 * e.share());
        EXPECT_GT(e.contour, 300);
        EXPECT_LT(e.share(), 0.02);
    }
}

// Curved silhouettes (MaterialDesc::silhouette, PX_CURVED): the search
// traces each mesh's own shape (PX_SHAPE: the sphere's, torus's or
// cylinder's uv and normal height at every sample of the mesh-space ray), so
// the outline is the relief's, measured against the relief drawn as real
// geometry (contour pixels covered in one image only, over the contour's
// length).
//  - A relief all at its bottom (flat at 0): the true outline is the mesh
//    shrunk by the relief's depth, whatever the uv: the shape search finds
//    it to 0.0 to 0.5 % of the contour (the smooth outline misses it by 350
//    to 500 %; the fitted quadric, before the shape search, by 2.6 to 35 %).
//  - Hemispherical bumps on a sphere, a torus and an open cylinder: the
//    sphere and torus to 0.0 to 1.5 % (2026-12-05; the quadric 8.3 to
//    19.2 %), within the reference's own 1.0 to 1.5 % against itself at
//    twice the density (TheDisplacedReferenceHasConverged). The
//    cylinder's ends are its uv bounds along v: its material is bounded,
//    and its relief a sheet with no thickness that ends there. The search
//    samples its ray on the tube's length only, and the rays that come onto
//    it through an end are traced from the end's plane by the rim caps
//    (make_tube_rim_caps): seen from above the open end, the relief on the
//    far wall's outside stands past the rim, and the near rim's bumps show
//    from above (0.4 to 0.7 % at 30 to 89 degrees, 2026-12-05; 6.1 and
//    56.1 % at 30 and 60 degrees traced through a wider tube, 34 % at 75
//    with the far wall's inside traced instead of caps).
TEST(Silhouettes, CurvedSilhouettesFollowTheDisplacedOutline) {
    const auto measure = [](const SceneDesc& s, double* with_share, double* without_share) {
        const CurvedImages images = curved_images(s);
        const reference::ContourError on = contour(images.with, images.geometry);
        const reference::ContourError off = contour(images.smooth, images.geometry);
        *with_share = on.share();
        *without_share = off.share();
        return on;
    };
    for (MeshKind kind : {MeshKind::sphere, MeshKind::torus}) {
        for (double elevation : {0.0, 30.0, 60.0}) {
            SCOPED_TRACE(std::string("flat ") + mesh_kind_name(kind) + " at " + std::to_string(elevation));
            SceneDesc s = curved_scene(kind, elevation, Technique::pom, true);
            s.materials[0].height.field.kind = FieldKind::flat;
            s.materials[0].height.field.level = 0.0f;
            ASSERT_TRUE(validate_scene(s).ok());
            double on = 0.0, off = 0.0;
            const reference::ContourError e = measure(s, &on, &off);
            std::printf("flat %s at %.0f: contour %ld px; mismatched with silhouette %.1f %% (%ld outside), without %.1f %%\n",
                        mesh_kind_name(kind), elevation, e.contour, 100.0 * on, e.measured_only, 100.0 * off);
            EXPECT_GT(off, 2.0);
            EXPECT_LT(on, 0.01);
        }
    }
    double mean = 0.0;  // the sphere's and torus's views
    double tube_mean = 0.0;
    const std::vector<double> views = {0.0, 30.0, 60.0, 75.0, 85.0, 89.0};
    const std::vector<double> tube_views = {0.0, 30.0, 60.0, 75.0, 89.0};
    for (MeshKind kind : {MeshKind::sphere, MeshKind::torus, MeshKind::cylinder}) {
        for (double elevation : kind == MeshKind::cylinder ? tube_views : views) {
            SCOPED_TRACE(std::string(mesh_kind_name(kind)) + " at " + std::to_string(elevation));
            SceneDesc s = curved_scene(kind, elevation, Technique::pom, true);
            s.materials[0].bounded = kind == MeshKind::cylinder;  // its ends
            ASSERT_TRUE(validate_scene(s).ok());
            double on = 0.0, off = 0.0;
            const reference::ContourError e = measure(s, &on, &off);
            std::printf("%s at %.0f: contour %ld px; mismatched with silhouette %.1f %% (%ld outside), without %.1f %%\n",
                        mesh_kind_name(kind), elevation, e.contour, 100.0 * on, e.measured_only, 100.0 * off);
            EXPECT_LT(on, 0.5 * off);
            // Each view within twice the reference's own noise, and the
            // issue's 1 % on the mean (measured 0.5 % on the sphere's and
            // torus's twelve views, 0.0 to 1.6 % each; 0.3 % on the tube).
            EXPECT_LT(on, 0.025);
            if (kind == MeshKind::cylinder) tube_mean += on / static_cast<double>(tube_views.size());
            else mean += on / (2.0 * static_cast<double>(views.size()));
        }
    }
    EXPECT_LT(mean, 0.01) << "the sphere's and torus's mean contour mismatch";
    EXPECT_LT(tube_mean, 0.01) << "the open tube's mean contour mismatch";
}

// LOD (Tatarchuk's fade to normal mapping past a mip level) fades the
// shading only: at the contour the view grazes and the uv's footprint is
// largest, so a LOD that skipped the trace there drew the smooth outline
// (the sphere's and torus's bumps rows 43.6 to 117.4 % of the contour with
// LOD, 0.0 to 1.5 % without it; 2026-12-05).
TEST(Silhouettes, LodKeepsTheCurvedSilhouette) {
    for (MeshKind kind : {MeshKind::sphere, MeshKind::torus}) {
        SCOPED_TRACE(mesh_kind_name(kind));
        SceneDesc s = curved_scene(kind, 30.0, Technique::pom, true);
        s.materials[0].technique.lod = true;
        ASSERT_TRUE(validate_scene(s).ok());
        const CurvedImages images = curved_images(s);
        const reference::ContourError e = contour(images.with, images.geometry);
        std::printf("%s at 30 with LOD: contour %ld px; mismatched %.1f %%\n", mesh_kind_name(kind), e.contour,
                    100.0 * e.share());
        EXPECT_GT(e.contour, 300);
        EXPECT_LT(e.share(), 0.025);
    }
}

// A shallow relief (1e-6 tiles deep, or 4000 x 2000 tiles of 0.05 around
// the mesh) lies thousands of relief depths under the drawn polygon (the
// chords' sag): the shape search starts at the model's entry, not at the
// fragment, or its whole range passes above the relief and the whole
// object is discarded (2026-12-05: 0 and 2806 of the sphere's 16400
// pixels drawn). Drawn, its outline is the smooth mesh's.
TEST(Silhouettes, AShallowReliefKeepsItsObject) {
    for (MeshKind kind : {MeshKind::sphere, MeshKind::torus}) {
        for (int shallow = 0; shallow < 2; ++shallow) {
            SCOPED_TRACE(std::string(mesh_kind_name(kind)) + (shallow ? " 1e-6 deep" : " 4000 tiles"));
            SceneDesc s = curved_scene(kind, 30.0, Technique::pom, true);
            if (shallow) s.materials[0].height_scale = 1e-6f;
            else s.materials[0].uv.scale = glm::vec2(4000.0f, 2000.0f);
            ASSERT_TRUE(validate_scene(s).ok());
            const SurfaceImage traced = surfaces_of(s);
            s.materials[0].silhouette = false;
            const SurfaceImage plain = surfaces_of(s);
            ASSERT_EQ(traced.samples.size(), plain.samples.size());
            long with = 0, smooth = 0;
            for (size_t i = 0; i < traced.samples.size(); ++i) {
                with += traced.samples[i].covered;
                smooth += plain.samples[i].covered;
            }
            std::printf("%s: %ld pixels drawn with the silhouette, %ld without\n",
                        shallow ? "1e-6 deep" : "4000 tiles", with, smooth);
            EXPECT_GT(smooth, 10000);
            EXPECT_NEAR(static_cast<double>(with), static_cast<double>(smooth), 0.01 * static_cast<double>(smooth));
        }
    }
}

// The curved relief's polygon is drawn out past its chords (Mesh::chord_sag,
// the shell in surface.vert), so that it covers the smooth surface's
// outline: with the relief all at its top (the polygon's height, nothing
// below it), the curved silhouette's outline is the smooth sphere's and
// torus's (the displaced mesh, built fine, with nothing to displace), not
// the coarse polygon's, which lies inside it by its chords' sag.
TEST(Silhouettes, CurvedSilhouettesCoverTheSmoothOutlineNotTheChords) {
    for (MeshKind kind : {MeshKind::sphere, MeshKind::torus}) {
        for (double elevation : {0.0, 30.0, 60.0}) {
            SCOPED_TRACE(std::string(mesh_kind_name(kind)) + " at " + std::to_string(elevation));
            SceneDesc s = curved_scene(kind, elevation, Technique::pom, true);
            s.materials[0].height.field.kind = FieldKind::flat;
            s.materials[0].height.field.level = 1.0f;
            ASSERT_TRUE(validate_scene(s).ok());
            const CurvedImages images = curved_images(s);  // geometry: the smooth surface, built fine
            const reference::ContourError on = contour(images.with, images.geometry);
            const reference::ContourError chords = contour(images.smooth, images.geometry);
            std::printf("%s at %.0f, relief at its top: contour %ld px; the curved silhouette mismatches %.1f %% "
                        "(%ld px outside), the polygon %.1f %% (%ld px inside)\n",
                        mesh_kind_name(kind), elevation, on.contour, 100.0 * on.share(), on.measured_only,
                        100.0 * chords.share(), chords.mismatched - chords.measured_only);
            EXPECT_LT(on.share(), 0.5 * chords.share());
        }
    }
}

// Curved silhouettes at the mobile precisions (src/emulation, GLSL ES 3.00
// only: the Emulation suite, left out of the ES 2.0 entry): the bend, the
// ray's quadratic height and the march emulated in strict fp16 for every
// mediump value, and on the ES 2.0 variant without fragment highp (every
// fragment float fp16). The bumpy sphere and bounded tube at 30 degrees
// keep their outline: no pixel's hit is NaN or infinite, and the contour
// mismatch against the displaced mesh stays under 5 % (docs/silhouettes.md
// has the figures).
TEST(Emulation, CurvedSilhouettesKeepTheirOutlineAtMobilePrecisions) {
  for (MeshKind kind : {MeshKind::sphere, MeshKind::cylinder}) {
    SCOPED_TRACE(mesh_kind_name(kind));
    SceneDesc s = curved_scene(kind, 30.0, Technique::pom, true);
    s.materials[0].bounded = kind == MeshKind::cylinder;  // its ends
    ASSERT_TRUE(validate_scene(s).ok());
    SceneDesc smooth_scene = s;
    smooth_scene.materials[0].silhouette = false;
    smooth_scene.materials[0].bounded = false;
    SceneDesc geometry_scene = smooth_scene;
    geometry_scene.objects[0].mesh.displaced = true;
    const SurfaceImage geometry = surfaces_of(geometry_scene);
    const double smooth = contour(surfaces_of(smooth_scene), geometry).share();
    const SurfaceImage full = surfaces_of(s);
    const double native = contour(full, geometry).share();
    struct Case {
        const char* name;
        emulation::PrecisionProfile profile;
        bool es2;
    };
    for (const Case& c : {Case{"fp16", emulation::PrecisionProfile::fp16, false},
                          Case{"fp16, ES 2.0 variant", emulation::PrecisionProfile::fp16, true},
                          Case{"nohighp, ES 2.0 variant", emulation::PrecisionProfile::nohighp, true}}) {
        SCOPED_TRACE(c.name);
        RendererOptions options;
        const emulation::PrecisionProfile profile = c.profile;
        options.shader_transform = [profile](const std::string& source, ShaderStage stage) {
            return emulation::emulate_precision(source, stage, profile);
        };
        options.emulate_es2 = c.es2;
        options.emulate_no_fragment_highp = c.profile == emulation::PrecisionProfile::nohighp;
        const SurfaceImage emulated = surfaces_of(s, options);
        ASSERT_EQ(emulated.samples.size(), geometry.samples.size());
        long covered = 0, non_finite = 0, both = 0;
        double moved = 0.0;  // hit uv against full precision's, texels (the emulation is at work)
        for (size_t i = 0; i < emulated.samples.size(); ++i) {
            const SurfaceSample& p = emulated.samples[i];
            if (!p.covered) continue;
            ++covered;
            non_finite += !(std::isfinite(p.uv.x) && std::isfinite(p.uv.y) && std::isfinite(p.height));
            if (!full.samples[i].covered) continue;
            ++both;
            moved += glm::length(p.uv - full.samples[i].uv) * s.materials[0].height.field.size;
        }
        const double share = contour(emulated, geometry).share();
        std::printf("curved %s at 30 deg, %s: contour mismatch %.1f %% (full precision %.1f %%, smooth outline "
                    "%.1f %%), %ld of %ld pixels not finite, hits %.3g texels from full precision's (mean)\n",
                    mesh_kind_name(kind), c.name, 100.0 * share, 100.0 * native, 100.0 * smooth, non_finite, covered,
                    both > 0 ? moved / static_cast<double>(both) : 0.0);
        EXPECT_GT(covered, 5000);
        EXPECT_EQ(non_finite, 0);
        EXPECT_LT(share, 0.5 * smooth);
        // The shape search, drawn on every context: without fragment highp
        // it measured 2.2 % (sphere) and 1.8 % (tube), where the fitted
        // quadric, drawn there until 2026-12-05, measured 20.8 and 8.4 %.
        EXPECT_LT(share, 0.05);
    }
  }
}

// Bounds change only where a ray leaves them: on a bounded cube, a face's
// hits are the unbounded cube's wherever both draw (the side walls' height,
// v_wall_height, is a plane's: a cube vertex's z is not a height above its
// face, and with the walls' scale set for cubes too every face's hits moved).
TEST(Silhouettes, BoundsMoveNoHitOnACube) {
    // The curved meshes' scene with a cube in place of the mesh (any relief
    // would do: what is asserted is that bounds change no hit).
    SceneDesc open = curved_scene(MeshKind::cube, 40.0, Technique::pom, false);
    open.objects[0].mesh.size = 1.6f;
    SceneDesc bounded = open;
    bounded.materials[0].bounded = true;
    ASSERT_TRUE(validate_scene(bounded).ok());
    const SurfaceImage a = surfaces_of(open), b = surfaces_of(bounded);
    ASSERT_EQ(a.samples.size(), b.samples.size());
    long both = 0, moved = 0;
    for (size_t i = 0; i < a.samples.size(); ++i) {
        if (!a.samples[i].covered || !b.samples[i].covered) continue;
        ++both;
        moved += glm::length(a.samples[i].uv - b.samples[i].uv) > 1e-4;
    }
    std::printf("bounded cube: %ld pixels drawn by both, %ld with another hit\n", both, moved);
    EXPECT_GT(both, 5000);
    EXPECT_LT(moved, both / 100);
}

// Techniques without a trace (normal mapping, flat) shade the polygon: a
// bounded tile drawn with them is the tile itself, not the wider polygon
// that traced techniques draw to catch rays coming in through its side
// (that polygon, unbounded, would show the next tiles of the texture); the
// same for a bounded tube's ends.
TEST(Silhouettes, UntracedTechniquesDrawTheBoundedReliefsOwnPolygon) {
    for (Technique t : {Technique::normal, Technique::flat}) {
        SCOPED_TRACE(technique_info(t).name);
        SceneDesc open = tile(60.0, t).build();
        SceneDesc bounded = open;
        bounded.materials[0].bounded = true;
        SceneDesc tube = curved_scene(MeshKind::cylinder, 30.0, t, false);
        SceneDesc bounded_tube = tube;
        bounded_tube.materials[0].bounded = true;
        for (const auto& [a_scene, b_scene] : {std::pair<const SceneDesc*, const SceneDesc*>{&open, &bounded},
                                               std::pair<const SceneDesc*, const SceneDesc*>{&tube, &bounded_tube}}) {
            const SurfaceImage a = surfaces_of(*a_scene), b = surfaces_of(*b_scene);
            ASSERT_EQ(a.samples.size(), b.samples.size());
            long drawn = 0, differ = 0;
            for (size_t i = 0; i < a.samples.size(); ++i) {
                drawn += a.samples[i].covered;
                differ += a.samples[i].covered != b.samples[i].covered;
            }
            EXPECT_GT(drawn, 1000);
            EXPECT_EQ(differ, 0);
        }
    }
}

// The planner keeps a curved silhouette where the object's contour can be
// on screen, picks a search that can draw it for a planned material, and
// leaves it out (saying so) where the sphere fills the view.
TEST(Silhouettes, ThePlannerDrawsCurvedSilhouettesWhereTheContourIsOnScreen) {
    SceneDesc scene = curved_scene(MeshKind::sphere, 30.0, Technique::pom, true);
    scene.materials[0].effects.emplace().max_error_texels = 4.0f;
    Result<std::unique_ptr<ScenePlanner>> planner = one_material_planner(scene);
    ASSERT_TRUE(planner.ok()) << planner.error().message;
    auto whole = (*planner)->plan(scene.camera, kSize, kSize);
    ASSERT_TRUE(whole.ok()) << whole.error().message;
    EXPECT_TRUE(whole->at(0).key.curved) << whole->at(0).key.describe();
    EXPECT_TRUE(technique_info(whole->at(0).key.technique).options & kOptSamples) << whole->at(0).key.describe();
    EXPECT_NE(notes_of(whole->at(0)).find("contour can be on screen"), std::string::npos) << notes_of(whole->at(0));
    // The exact search of the sphere's own shape, on an ES 2.0 GPU without
    // fragment highp too (it beats the fitted quadric there: 2.2 against
    // 20.8 % at strict fp16, Emulation.CurvedSilhouettesKeepTheirOutline...);
    // the plan says which search it draws.
    EXPECT_EQ(whole->at(0).key.shape, kShapeSphere) << whole->at(0).key.describe();
    EXPECT_NE(notes_of(whole->at(0)).find("the mesh's own shape"), std::string::npos) << notes_of(whole->at(0));
    Caps mali = Caps::full(2);
    mali.fragment_highp = false;
    Result<std::unique_ptr<ScenePlanner>> low = one_material_planner(scene, mali);
    ASSERT_TRUE(low.ok()) << low.error().message;
    auto mobile = (*low)->plan(scene.camera, kSize, kSize);
    ASSERT_TRUE(mobile.ok()) << mobile.error().message;
    EXPECT_TRUE(mobile->at(0).key.curved) << mobile->at(0).key.describe();
    EXPECT_TRUE(mobile->at(0).key.no_fragment_highp) << mobile->at(0).key.describe();
    EXPECT_EQ(mobile->at(0).key.shape, kShapeSphere) << mobile->at(0).key.describe();
    EXPECT_NE(notes_of(mobile->at(0)).find("the mesh's own shape"), std::string::npos) << notes_of(mobile->at(0));
    CameraDesc close;  // 0.1 above the 0.9 sphere, looking at it: all relief
    close.position = glm::vec3(0.0f, -1.0f, 0.0f);
    close.target = glm::vec3(0.0f);
    close.up = glm::vec3(0.0f, 0.0f, 1.0f);
    close.fov_y_deg = 40.0f;
    auto inside = (*planner)->plan(close, kSize, kSize);
    ASSERT_TRUE(inside.ok()) << inside.error().message;
    EXPECT_FALSE(inside->at(0).key.curved) << inside->at(0).key.describe();
    EXPECT_NE(notes_of(inside->at(0)).find("silhouette off"), std::string::npos) << notes_of(inside->at(0));
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

// The first object's plan for `scene` at its camera: as the renderer draws
// a material that names its technique, and (`planned`) as the planner
// chooses for the same material asking for effects instead.
ObjectPlan named_plan(const SceneDesc& scene) {
    auto renderer = Renderer::create();
    EXPECT_TRUE(renderer.ok());
    if (!renderer.ok()) return {};
    Status loaded = (*renderer)->load(scene);
    EXPECT_TRUE(loaded.ok()) << loaded.error().message;
    auto plans = loaded.ok() ? (*renderer)->plan_view(scene.camera, kSize, kSize)
                             : Result<std::vector<ObjectPlan>>(loaded.error());
    EXPECT_TRUE(plans.ok() && !plans->empty());
    return plans.ok() && !plans->empty() ? plans->at(0) : ObjectPlan{};
}
ObjectPlan planned_plan(SceneDesc scene) {
    scene.materials[0].effects.emplace().max_error_texels = 4.0f;
    Result<std::unique_ptr<ScenePlanner>> planner = one_material_planner(scene);
    EXPECT_TRUE(planner.ok()) << planner.error().message;
    if (!planner.ok()) return {};
    auto plan = (*planner)->plan(scene.camera, kSize, kSize);
    EXPECT_TRUE(plan.ok() && !plan->empty());
    return plan.ok() && !plan->empty() ? plan->at(0) : ObjectPlan{};
}

// A relief as deep below the polygon as the shape's smallest radius (a
// torus's tube, a sphere's centre) has no outline to trace: displaced, the
// surface folds through the axis (relief_folds_through). The curved search
// drew a scatter of lobes there (a torus 0.46 units deep on a 0.4 tube:
// 59.6 % of the contour against the folded mesh, 2049 % at twice the
// depth; 2026-12-05): the silhouette is turned off, the smooth outline
// drawn, and the plan says why, for a named technique and a planned one.
TEST(Silhouettes, AReliefThroughTheAxisDrawsTheSmoothOutline) {
    for (MeshKind kind : {MeshKind::torus, MeshKind::sphere}) {
        SCOPED_TRACE(mesh_kind_name(kind));
        SceneDesc deep = curved_scene(kind, 30.0, Technique::pom, true);
        deep.materials[0].height_scale = kind == MeshKind::torus ? 0.5f : 2.0f;
        ASSERT_TRUE(validate_scene(deep).ok());
        const ObjectPlan named = named_plan(deep);
        EXPECT_FALSE(named.key.curved) << named.key.describe();
        EXPECT_NE(notes_of(named).find(kind == MeshKind::torus ? "through the torus's tube" : "through the sphere's centre"),
                  std::string::npos)
            << notes_of(named);
        SceneDesc smooth = deep;
        smooth.materials[0].silhouette = false;
        const reference::ContourError e = contour(surfaces_of(deep), surfaces_of(smooth));
        EXPECT_GT(e.contour, 300);
        EXPECT_EQ(e.mismatched, 0);

        // Planned: the same decision, said the same way.
        const ObjectPlan planned = planned_plan(deep);
        EXPECT_FALSE(planned.key.curved) << planned.key.describe();
        EXPECT_NE(notes_of(planned).find("silhouette off: the relief reaches"), std::string::npos) << notes_of(planned);

        // Shallower than the radius, the silhouette is drawn.
        SceneDesc shallow = deep;
        shallow.materials[0].height_scale = kind == MeshKind::torus ? 0.2f : 0.4f;
        EXPECT_TRUE(named_plan(shallow).key.curved);
        EXPECT_TRUE(planned_plan(shallow).key.curved);
    }
}

// A tube with a silhouette but no bounds is drawn as a window into a
// longer tube: its open ends keep the smooth rim's outline (108 to 233 % of
// the contour against the displaced tube where they are in view, 0.4 to
// 0.7 % bounded; docs/silhouettes.md), and the plan says so, named or
// planned.
TEST(Silhouettes, AnUnboundedTubeSaysItsEndsAreOpen) {
    for (bool bounded : {false, true}) {
        SCOPED_TRACE(bounded ? "bounded" : "not bounded");
        SceneDesc s = curved_scene(MeshKind::cylinder, 60.0, Technique::pom, true);
        s.materials[0].bounded = bounded;
        const ObjectPlan named = named_plan(s);
        EXPECT_TRUE(named.key.curved) << named.key.describe();
        EXPECT_EQ(notes_of(named).find("open ends") != std::string::npos, !bounded) << notes_of(named);
        const ObjectPlan planned = planned_plan(s);
        EXPECT_EQ(notes_of(planned).find("open ends") != std::string::npos, !bounded) << notes_of(planned);
    }
}

// A bounded tile under a rotated, scaled and offset uv transform, or a
// rotated object: its edges cut through the bricks, and a ray that comes in
// through the tile's side meets a brick's cut face exactly at the edge.
// Its uv, rounded (the transform's products, the march's fp16 start height
// 1 - px_start_t), fell just off the tile every other pixel and was
// discarded: against the exact reference 32 to 191 % of the contour for
// maxmip, up to 783 pixels of 393 for POM x64 (2026-12-05). Now maxmip
// mismatches 0 or 1 pixel, the linear searches a few percent at 85 and 89
// degrees (their own search's error; POM x64 up to 45 of 384 at 89).
TEST(Silhouettes, ABoundedTileUnderAUvTransformKeepsItsCutFaces) {
    for (int variant = 1; variant < 4; ++variant) {
        for (double angle : {60.0, 85.0, 89.0}) {
            SceneDesc s = tile(angle, Technique::maxmip).build();
            s.materials[0].bounded = true;
            if (variant & 1) {
                s.materials[0].uv.scale = {1.5f, 1.5f};
                s.materials[0].uv.rotation_deg = 30.0f;
                s.materials[0].uv.offset = {0.3f, 0.1f};
            } else {
                s.materials[0].uv.scale = {2.0f, 1.0f};
            }
            if (variant & 2) s.objects[0].transform.rotate_deg = {0.0f, 0.0f, 35.0f};
            auto reference = reference::render_reference(s, kSize, kSize);
            ASSERT_TRUE(reference.ok()) << reference.error().message;
            for (Technique t : {Technique::maxmip, Technique::pom, Technique::relief, Technique::steep}) {
                SCOPED_TRACE(std::string(technique_name(t)) + ", variant " + std::to_string(variant) + ", " +
                             std::to_string(angle) + " degrees");
                s.materials[0].technique.technique = t;
                const reference::ContourError r = contour(surfaces_of(s), reference->surface);
                std::printf("uv variant %d, %s at %.0f deg: contour %ld px, drawn only %ld, reference only %ld\n",
                            variant, technique_name(t), angle, r.contour, r.measured_only,
                            r.mismatched - r.measured_only);
                EXPECT_GT(r.contour, 300);
                EXPECT_LE(r.share(), t == Technique::maxmip ? 0.005 : 0.15);
            }
        }
    }
}

}  // namespace
}  // namespace px::test
