// The effect planner without GL: effect requests in scene files, relief
// features, the cost table's format, and the planner's decisions on a small
// hand-written table (so that each rule is tested on numbers the test states).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "parallaxes/planner/cost_table.h"
#include "parallaxes/planner/planner.h"
#include "parallaxes/planner/relief.h"
#include "parallaxes/planner/search_model.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/scene/scene.h"

namespace px {
namespace {

Caps es3_caps() {
    Caps c;
    c.es_major = 3;
    c.version = "OpenGL ES 3.0 test";
    return c;
}

Caps es2_caps(bool frag_depth, bool derivatives) {
    Caps c;
    c.es_major = 2;
    c.version = "OpenGL ES 2.0 test";
    if (frag_depth) c.extensions.insert("GL_EXT_frag_depth");
    if (derivatives) c.extensions.insert("GL_OES_standard_derivatives");
    return c;
}

// --- Scene format ------------------------------------------------------------

std::string scene_with_material(const std::string& material) {
    return R"({"materials": [)" + material + R"(], "objects": [{"name": "o", "material": "m"}]})";
}

TEST(EffectsFormat, ReadsEveryEffect) {
    Result<SceneDesc> s = parse_scene(scene_with_material(R"({"name": "m", "effects": {
        "parallax": {"max_error_texels": 0.5}, "shadow": {"mode": "soft", "max_error": 0.05},
        "depth_correction": "on", "lod_fade": {"mode": "off", "threshold": 4, "band": 2}}})"),
                                      "t.json");
    ASSERT_TRUE(s.ok()) << s.error().message;
    ASSERT_TRUE(s->materials[0].effects.has_value());
    const EffectRequest& e = *s->materials[0].effects;
    EXPECT_TRUE(e.parallax);
    EXPECT_FLOAT_EQ(e.max_error_texels, 0.5f);
    EXPECT_EQ(e.shadow, ShadowMode::soft);
    EXPECT_FLOAT_EQ(e.shadow_max_error, 0.05f);
    EXPECT_EQ(e.depth_correction, EffectSwitch::on);
    EXPECT_EQ(e.lod_fade, EffectSwitch::off);
    EXPECT_FLOAT_EQ(e.lod_threshold, 4.0f);
    EXPECT_FLOAT_EQ(e.lod_band, 2.0f);
    // Strings for the short forms.
    s = parse_scene(scene_with_material(R"({"name": "m", "effects": {"parallax": "off", "lod_fade": "auto"}})"), "t.json");
    ASSERT_TRUE(s.ok()) << s.error().message;
    EXPECT_FALSE(s->materials[0].effects->parallax);
}

void expect_error(const std::string& material, const std::string& fragment) {
    Result<SceneDesc> s = parse_scene(scene_with_material(material), "t.json");
    ASSERT_FALSE(s.ok()) << "accepted: " << material;
    EXPECT_NE(s.error().message.find(fragment), std::string::npos) << s.error().message;
}

TEST(EffectsFormat, RefusesUnknownContradictoryAndOutOfRange) {
    expect_error(R"({"name": "m", "effects": {"paralax": {}}})", "materials[0].effects");
    expect_error(R"({"name": "m", "effects": {"paralax": {}}})", "did you mean 'parallax'");
    expect_error(R"({"name": "m", "effects": {"parallax": {"max_error": 1}}})", "materials[0].effects.parallax");
    expect_error(R"({"name": "m", "technique": "pom", "effects": {}})", "materials[0].effects: a material declares effects or names a technique, not both");
    expect_error(R"({"name": "m", "options": {"max_samples": 8}, "effects": {}})", "not both");
    expect_error(R"({"name": "m", "effects": {"parallax": "off", "shadow": "hard"}})",
                 "materials[0].effects.shadow: \"hard\" contradicts \"parallax\": \"off\"");
    expect_error(R"({"name": "m", "effects": {"parallax": "off", "depth_correction": "on"}})",
                 "materials[0].effects.depth_correction");
    expect_error(R"({"name": "m", "effects": {"parallax": "on"}})", "materials[0].effects.parallax: expected \"off\" or an object");
    expect_error(R"({"name": "m", "effects": {"parallax": {"max_error_texels": 0}}})",
                 "materials[0].effects.parallax.max_error_texels: must be within");
    expect_error(R"({"name": "m", "effects": {"parallax": {"max_error_texels": -1}}})", "max_error_texels");
    expect_error(R"({"name": "m", "effects": {"shadow": {"mode": "soft", "max_error": 2}}})", "materials[0].effects.shadow.max_error");
    expect_error(R"({"name": "m", "effects": {"shadow": "blurry"}})", "materials[0].effects.shadow");
    expect_error(R"({"name": "m", "effects": {"depth_correction": "maybe"}})", "materials[0].effects.depth_correction");
    expect_error(R"({"name": "m", "effects": {"lod_fade": {"band": 0}}})", "materials[0].effects.lod_fade.band");
}

// --- Relief features ---------------------------------------------------------

HeightField field_of(FieldKind kind, int size = 128, int count = 4) {
    FieldSpec spec;
    spec.kind = kind;
    spec.size = size;
    spec.count = count;
    Result<HeightField> f = make_height_field(spec);
    EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().message);
    return quantized_8bit(*f);
}

TEST(ReliefFeatures, MeasuresDepthSteepnessAndThinnestFeature) {
    const ReliefFeatures lines = measure_relief(field_of(FieldKind::lines, 128, 8), 0.05);
    EXPECT_DOUBLE_EQ(lines.thinnest_texels, 1.0);
    EXPECT_NEAR(lines.steepness, 1.0, 1e-6);
    EXPECT_NEAR(lines.depth_texels, 0.05 * 128, 1e-6);
    const ReliefFeatures sine = measure_relief(field_of(FieldKind::sine), 0.05);
    EXPECT_GT(sine.thinnest_texels, 8.0);
    EXPECT_LT(sine.steepness, 0.2);
    const ReliefFeatures flat = measure_relief(field_of(FieldKind::flat), 0.05);
    EXPECT_EQ(flat.range, 0.0);
    EXPECT_EQ(flat.depth_texels, 0.0);
    EXPECT_NE(lines.field_hash, sine.field_hash);
    EXPECT_EQ(lines.field_hash, measure_relief(field_of(FieldKind::lines, 128, 8), 0.1).field_hash);
}

// --- Cost table ----------------------------------------------------------------

TEST(CostTable, BuiltInParsesAndRoundTrips) {
    Result<const CostTable*> table = builtin_cost_table();
    ASSERT_TRUE(table.ok()) << table.error().message;
    EXPECT_FALSE((*table)->rows.empty());
    EXPECT_FALSE((*table)->renderer.empty());
    Result<CostTable> again = parse_cost_table(cost_table_json(**table), "again");
    ASSERT_TRUE(again.ok()) << again.error().message;
    EXPECT_EQ(again->rows.size(), (*table)->rows.size());
    EXPECT_EQ(again->reliefs.size(), (*table)->reliefs.size());
}

TEST(CostTable, RefusesBrokenTables) {
    const std::string head = R"({"date": "d", "renderer": "r", "version": "v", "command": "c",
        "reliefs": [{"name": "x", "depth_texels": 10, "steepness": 1, "thinnest_texels": 1, "range": 1}], "rows": [)";
    auto refused = [&](const std::string& rows, const std::string& fragment) {
        Result<CostTable> t = parse_cost_table(head + rows + "]}", "t.json");
        ASSERT_FALSE(t.ok()) << rows;
        EXPECT_NE(t.error().message.find(fragment), std::string::npos) << t.error().message;
    };
    refused(R"([1, 0, "pom", 8, "none", 0, 1, 0, 1])", "rows[0][0]: not a relief index");
    refused(R"([0, 95, "pom", 8, "none", 0, 1, 0, 1])", "rows[0][1]");
    refused(R"([0, 0, "bogus", 8, "none", 0, 1, 0, 1])", "rows[0][2]");
    refused(R"([0, 0, "pom", 8, "none", 0, -1, 0, 1])", "rows[0][6]: negative");
    refused(R"([0, 0, "pom", 8, "none", 0, 1, 0, 0])", "rows[0][8]");
    refused(R"([0, 0, "pom"])", "rows[0]: expected");
    // Absurd values are not measurements: refused on reading, never planned with.
    refused(R"([0, 0, "pom", 8, "none", 0, 1e300, 0, 1])", "rows[0][6]: a hit error over 1e6 texels");
    refused(R"([0, 0, "pom", 8, "soft", 4, 1, 1.5, 1])", "rows[0][7]: a visibility difference over 1");
    refused(R"([0, 0, "pom", 8, "none", 0, 1, 0, 1e300])", "rows[0][8]: a cost over 10000");
    EXPECT_FALSE(parse_cost_table("not json", "t.json").ok());
    // What the costs are (a GPU-priced table's `prices`): a string, kept.
    const std::string one_row = R"([0, 0, "pom", 8, "none", 0, 1, 0, 1]]})";
    Result<CostTable> priced = parse_cost_table(
        std::string(head).insert(1, R"("prices": "Mali-G57 cycles per pixel", )") + one_row, "t.json");
    ASSERT_TRUE(priced.ok()) << priced.error().message;
    EXPECT_EQ(priced->prices, "Mali-G57 cycles per pixel");
    Result<CostTable> again = parse_cost_table(cost_table_json(*priced), "again");
    ASSERT_TRUE(again.ok()) << again.error().message;
    EXPECT_EQ(again->prices, priced->prices);
    Result<CostTable> bad = parse_cost_table(std::string(head).insert(1, R"("prices": 3, )") + one_row, "t.json");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("t.json: prices: expected a string"), std::string::npos) << bad.error().message;
}

// --- Planner decisions, on a table stated here --------------------------------

// One relief (depth 10 texels, thin features); normal mapping's error grows
// with the angle, POM at 8 samples is cheap and rough, at 32 dear and fine;
// shadows at 8 and 32 samples.
CostTable small_table() {
    CostTable t;
    t.date = "test";
    t.renderer = "test";
    t.reliefs.push_back({"lines", ReliefFeatures{256, 256, 10.0, 1.0, 1.0, 1.0, 0}});
    for (double a : {0.0, 45.0, 89.0}) {
        const double grow = 1.0 + a / 10.0;
        t.rows.push_back({0, a, Technique::normal, 0, ShadowMode::none, 0, 2.0 * grow, 0.0, 1.0});
        t.rows.push_back({0, a, Technique::offset_limited, 0, ShadowMode::none, 0, 1.5 * grow, 0.0, 1.1});
        t.rows.push_back({0, a, Technique::pom, 8, ShadowMode::none, 0, 0.4 * grow, 0.0, 1.5});
        t.rows.push_back({0, a, Technique::pom, 32, ShadowMode::none, 0, 0.05 * grow, 0.0, 3.0});
        t.rows.push_back({0, a, Technique::pom, 32, ShadowMode::hard, 8, 0.05 * grow, 0.2, 3.5});
        t.rows.push_back({0, a, Technique::pom, 32, ShadowMode::hard, 32, 0.05 * grow, 0.02, 5.0});
    }
    return t;
}

// A 2-unit plane seen from `angle_deg` off its normal at `distance`, with a
// 1-texel-lines relief `height_scale` deep and one light `light_elevation`
// degrees above the plane.
SceneDesc plane_scene(double angle_deg, float distance, float height_scale, EffectRequest effects,
                      float light_elevation = 40.0f, int segments = 16) {
    SceneDesc s;
    s.name = "t";
    const double a = glm::radians(angle_deg);
    s.camera.position = glm::vec3(0.0f, static_cast<float>(-distance * std::sin(a)), static_cast<float>(distance * std::cos(a)));
    s.camera.target = glm::vec3(0.0f);
    s.camera.up = angle_deg < 1.0 ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
    LightDesc light;
    const float e = glm::radians(light_elevation);
    light.direction = -glm::vec3(std::cos(e), 0.0f, std::sin(e));
    s.lights = {light};
    MaterialDesc m;
    m.name = "m";
    m.height.kind = TextureSource::Kind::procedural;
    m.height.field.kind = FieldKind::lines;
    m.height.field.size = 256;
    m.height.field.count = 8;
    m.height_scale = height_scale;
    m.effects = effects;
    s.materials = {m};
    ObjectDesc o;
    o.name = "plane";
    o.material = "m";
    o.mesh.size = 2.0f;
    o.mesh.segments = segments;
    s.objects = {o};
    return s;
}

// Planned on `table` alone (the search model, which would predict hits from
// the relief itself, left out: these tests state the table's numbers), or
// with the search model where `search_model` is true.
Result<std::vector<ObjectPlan>> plan_of(const SceneDesc& scene, const Caps& caps, const CostTable& table, int size = 256,
                                        bool search_model = false) {
    std::vector<MaterialRelief> reliefs;
    for (const MaterialDesc& m : scene.materials) {
        Result<MaterialImages> images = build_material_images(m, "");
        if (!images) return images.error();
        reliefs.push_back(material_relief(quantized_8bit(images->field), m));
        if (!search_model) reliefs.back().search.reset();
    }
    PlannerOptions options;
    options.table = &table;
    Result<std::unique_ptr<ScenePlanner>> planner = ScenePlanner::create(scene, caps, reliefs, options);
    if (!planner) return planner.error();
    return (*planner)->plan(scene.camera, size, size);
}

bool has_note(const ObjectPlan& p, const std::string& fragment) {
    for (const std::string& n : p.notes)
        if (n.find(fragment) != std::string::npos) return true;
    return false;
}

// A parallax request of `texels`, without the LOD fade (which would move
// the choice on far pixels).
EffectRequest within(float texels) {
    EffectRequest r;
    r.max_error_texels = texels;
    r.lod_fade = EffectSwitch::off;
    return r;
}

TEST(Planner, ChoosesTheCheapestCandidateWithinTheTarget) {
    const CostTable table = small_table();
    EffectRequest loose;
    loose.max_error_texels = 2.0f;
    loose.lod_fade = EffectSwitch::off;
    Result<std::vector<ObjectPlan>> p = plan_of(plane_scene(20.0, 2.5f, 0.04f, loose), es3_caps(), table);
    ASSERT_TRUE(p.ok()) << p.error().message;
    // pom x8 predicts 0.4 * (1 + ~2) * 10.24 / 10 ~ 1.2 texels at ~20 degrees: within 2, cheaper than x32.
    EXPECT_EQ((*p)[0].key.technique, Technique::pom);
    EXPECT_EQ((*p)[0].key.max_samples, 8);
    EXPECT_LE((*p)[0].predicted_error, 2.0);
    EXPECT_EQ((*p)[0].options.min_samples, 8);  // the table measured min = max

    EffectRequest tight = loose;
    tight.max_error_texels = 0.5f;
    p = plan_of(plane_scene(20.0, 2.5f, 0.04f, tight), es3_caps(), table);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_EQ((*p)[0].key.max_samples, 32);
    EXPECT_GT((*p)[0].predicted_cost, 2.0);
}

TEST(Planner, ImpossibleTargetNamesTheObjectAndTheField) {
    EffectRequest e;
    e.max_error_texels = 0.01f;
    Result<std::vector<ObjectPlan>> p = plan_of(plane_scene(60.0, 2.5f, 0.04f, e), es3_caps(), small_table());
    ASSERT_FALSE(p.ok());
    EXPECT_NE(p.error().message.find("object 'plane' (material 'm')"), std::string::npos) << p.error().message;
    EXPECT_NE(p.error().message.find("materials[0].effects.parallax.max_error_texels"), std::string::npos)
        << p.error().message;
    EXPECT_NE(p.error().message.find("best: pom x32"), std::string::npos) << p.error().message;

    EffectRequest shadow;
    shadow.max_error_texels = 2.0f;
    shadow.shadow = ShadowMode::hard;
    shadow.shadow_max_error = 0.001f;
    p = plan_of(plane_scene(20.0, 2.5f, 0.04f, shadow), es3_caps(), small_table());
    ASSERT_FALSE(p.ok());
    EXPECT_NE(p.error().message.find("materials[0].effects.shadow.max_error"), std::string::npos) << p.error().message;
}

TEST(Planner, DropsEffectsThatCannotMatterAndSaysWhy) {
    const CostTable table = small_table();
    EffectRequest e;
    e.max_error_texels = 2.0f;
    e.shadow = ShadowMode::hard;
    e.shadow_max_error = 0.1f;
    e.depth_correction = EffectSwitch::on;
    // Height scale 0: normal mapping, and the shadow goes with the relief.
    Result<std::vector<ObjectPlan>> p = plan_of(plane_scene(20.0, 2.5f, 0.0f, e), es3_caps(), table);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_EQ((*p)[0].key.technique, Technique::normal);
    EXPECT_TRUE(has_note((*p)[0], "height_scale is 0")) << (*p)[0].notes.front();
    EXPECT_TRUE(has_note((*p)[0], "shadow=hard dropped"));

    // A light below the horizon: no shadow ray, the fewer-samples variant.
    p = plan_of(plane_scene(20.0, 2.5f, 0.04f, e, -10.0f), es3_caps(), table);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_EQ((*p)[0].key.shadow, ShadowMode::none);
    EXPECT_TRUE(has_note((*p)[0], "below its horizon"));
    // A light above it: the shadow, at the fewest samples within 0.1 (32: 8 leaves 0.2).
    p = plan_of(plane_scene(20.0, 2.5f, 0.04f, e, 30.0f), es3_caps(), table);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_EQ((*p)[0].key.shadow, ShadowMode::hard);
    EXPECT_EQ((*p)[0].key.shadow_samples, 32);
    EXPECT_TRUE((*p)[0].key.depth_write);
    // No light at all.
    SceneDesc dark = plane_scene(20.0, 2.5f, 0.04f, e);
    dark.lights.clear();
    p = plan_of(dark, es3_caps(), table);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_EQ((*p)[0].key.shadow, ShadowMode::none);
    EXPECT_TRUE(has_note((*p)[0], "no light"));
    // ES 2.0 without GL_EXT_frag_depth: depth output dropped, with the reason.
    p = plan_of(plane_scene(20.0, 2.5f, 0.04f, e), es2_caps(false, true), table);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_FALSE((*p)[0].key.depth_write);
    EXPECT_TRUE(has_note((*p)[0], "lacks GL_EXT_frag_depth"));
    p = plan_of(plane_scene(20.0, 2.5f, 0.04f, e), es2_caps(true, true), table);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_TRUE((*p)[0].key.depth_write);
}

TEST(Planner, DepthCorrectionOnlyWhereAnotherSurfaceMeetsTheRelief) {
    EffectRequest e;
    e.max_error_texels = 2.0f;
    SceneDesc s = plane_scene(30.0, 3.0f, 0.04f, e);
    MaterialDesc plain = s.materials[0];
    plain.name = "plain";
    plain.height_scale = 0.0f;
    s.materials.push_back(plain);
    ObjectDesc board;
    board.name = "board";
    board.material = "plain";
    board.mesh.size = 0.5f;
    board.transform.rotate_deg = {90.0f, 0.0f, 0.0f};  // upright, facing -y
    board.transform.translate = {0.0f, 0.0f, 0.2f};     // its lower edge 0.05 into the relief
    s.objects.push_back(board);
    Result<std::vector<ObjectPlan>> p = plan_of(s, es3_caps(), small_table());
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_TRUE((*p)[0].key.depth_write);
    EXPECT_TRUE(has_note((*p)[0], "object 'board' meets this surface's relief"));
    // Lifted clear of the relief: no depth written.
    s.objects[1].transform.translate.z = 0.35f;
    p = plan_of(s, es3_caps(), small_table());
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_FALSE((*p)[0].key.depth_write);
    EXPECT_TRUE(has_note((*p)[0], "no other object meets"));
}

TEST(Planner, PerVertexViewOnlyWhereTheTrianglesAreSmallEnough) {
    // The whitepaper's saving on one 4-unit quad seen from 2 units puts the
    // relief far off; on a 64x64 grid it adds almost nothing.
    const CostTable table = small_table();
    EffectRequest e;
    e.max_error_texels = 2.0f;
    e.lod_fade = EffectSwitch::off;
    SceneDesc one_quad = plane_scene(40.0, 2.0f, 0.04f, e, 40.0f, 1);
    one_quad.objects[0].mesh.size = 4.0f;
    Result<std::vector<ObjectPlan>> p = plan_of(one_quad, es3_caps(), table);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_GT((*p)[0].view.per_vertex_view_error, 1.0);
    EXPECT_TRUE((*p)[0].key.exact_view);
    SceneDesc grid = one_quad;
    grid.objects[0].mesh.segments = 64;
    p = plan_of(grid, es3_caps(), table);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_LT((*p)[0].view.per_vertex_view_error, 0.05);
    EXPECT_FALSE((*p)[0].key.exact_view);
}

TEST(Planner, FarSurfacesPastTheLodThresholdGetNormalMapping) {
    EffectRequest e;
    e.max_error_texels = 1.0f;
    e.lod_fade = EffectSwitch::on;
    // 2 units across at 300 units: a few pixels for 256 texels, mip ~7.
    SceneDesc far = plane_scene(10.0, 300.0f, 0.04f, e);
    far.camera.far_plane = 1000.0f;
    Result<std::vector<ObjectPlan>> p = plan_of(far, es3_caps(), small_table());
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_EQ((*p)[0].key.technique, Technique::normal);
    EXPECT_TRUE(has_note((*p)[0], "past the lod_fade threshold"));
    // Without derivatives (ES 2.0 lacking GL_OES_standard_derivatives) LOD cannot run.
    p = plan_of(far, es2_caps(true, false), small_table());
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_FALSE((*p)[0].key.lod);
    EXPECT_TRUE(has_note((*p)[0], "lacks GL_OES_standard_derivatives"));
}

TEST(Planner, ExplicitTechniquesKeepTheirOwnPlan) {
    SceneDesc s = plane_scene(30.0, 3.0f, 0.04f, EffectRequest{});
    s.materials[0].effects.reset();
    s.materials[0].technique.technique = Technique::relief;
    Result<std::vector<ObjectPlan>> p = plan_of(s, es3_caps(), small_table());
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_FALSE((*p)[0].planned);
    EXPECT_EQ((*p)[0].key.technique, Technique::relief);
}

// What a context cannot draw, one rule for both planners: maxmip runs on
// ES 2.0 (its pyramid as one atlas 1.5 times the field's width, which must
// fit GL_MAX_TEXTURE_SIZE) and without fragment highp (kept, and said); a
// field that is not a power of two each way, or an atlas too wide, gets the
// fallback, and the note says which.
TEST(Planner, MaxmipRunsOnEsTwoWhereItsAtlasFits) {
    Caps es2 = es2_caps(false, true);
    es2.max_texture_size = 2048;
    EXPECT_EQ(why_technique_cannot_run(Technique::maxmip, es2, 1024, 1024), "");
    EXPECT_EQ(why_technique_cannot_run(Technique::maxmip, es2, 0, 0), "");
    const std::string too_wide = why_technique_cannot_run(Technique::maxmip, es2, 2048, 512);
    EXPECT_NE(too_wide.find("3072 texels wide, over this context's GL_MAX_TEXTURE_SIZE of 2048"), std::string::npos)
        << too_wide;
    Caps es3 = es3_caps();
    es3.max_texture_size = 2048;
    EXPECT_EQ(why_technique_cannot_run(Technique::maxmip, es3, 2048, 512), "") << "ES 3.0 uploads mip levels";
    EXPECT_NE(why_technique_cannot_run(Technique::maxmip, es3, 96, 64).find("not a power of two"), std::string::npos);
    EXPECT_EQ(why_technique_cannot_run(Technique::pom, es2, 96, 64), "");

    MaterialDesc m;
    m.technique.technique = Technique::maxmip;
    m.height_scale = 0.05f;
    Result<VariantPlan> wide = plan_variant(m, es2, 2048, 512);
    ASSERT_TRUE(wide.ok());
    EXPECT_EQ(wide->key.technique, technique_info(Technique::maxmip).fallback);
    ASSERT_FALSE(wide->notes.empty());
    EXPECT_NE(wide->notes[0].find("GL_MAX_TEXTURE_SIZE"), std::string::npos) << wide->notes[0];
    Result<VariantPlan> fits = plan_variant(m, es2, 512, 512);
    ASSERT_TRUE(fits.ok());
    EXPECT_EQ(fits->key.technique, Technique::maxmip);
    EXPECT_TRUE(fits->notes.empty()) << fits->notes[0];
    es2.fragment_highp = false;
    Result<VariantPlan> mediump = plan_variant(m, es2, 512, 512);
    ASSERT_TRUE(mediump.ok());
    EXPECT_EQ(mediump->key.technique, Technique::maxmip);
    EXPECT_TRUE(mediump->key.no_fragment_highp);
    ASSERT_FALSE(mediump->notes.empty());
    EXPECT_NE(mediump->notes[0].find("no longer exact"), std::string::npos) << mediump->notes[0];
}

// The plane scene's relief as the planner measures it, predicted from a
// stated table (its search model left out).
MaterialRelief stated_relief(const SceneDesc& scene) {
    Result<MaterialImages> images = build_material_images(scene.materials[0], "");
    EXPECT_TRUE(images.ok());
    if (!images) return {};
    MaterialRelief relief = material_relief(quantized_8bit(images->field), scene.materials[0]);
    relief.search.reset();  // against the stated table, not the search model
    return relief;
}

// small_table() as a calibration of `relief`.
CostTable calibration_of(const MaterialRelief& relief) {
    CostTable calibration = small_table();
    calibration.date = "calibrated";
    calibration.reliefs[0].features = relief.features;
    return calibration;
}

TEST(Planner, CalibrationReplacesTheGenericTable) {
    EffectRequest e;
    e.max_error_texels = 2.0f;
    e.lod_fade = EffectSwitch::off;
    const SceneDesc scene = plane_scene(20.0, 2.5f, 0.04f, e);
    const MaterialRelief relief = stated_relief(scene);
    // A calibration of this very relief in which pom x8 is far worse.
    CostTable calibration = calibration_of(relief);
    for (CostSample& s : calibration.rows)
        if (s.technique == Technique::pom && s.samples == 8) s.error_p95 *= 10.0;
    PlannerOptions options;
    const CostTable generic = small_table();
    options.table = &generic;
    options.calibrations = std::make_shared<const std::vector<CostTable>>(std::vector<CostTable>{calibration});
    Result<std::unique_ptr<ScenePlanner>> planner = ScenePlanner::create(scene, es3_caps(), {relief}, options);
    ASSERT_TRUE(planner.ok()) << planner.error().message;
    Result<std::vector<ObjectPlan>> p = (*planner)->plan(scene.camera, 256, 256);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_EQ((*p)[0].key.max_samples, 32);
    ASSERT_TRUE((*p)[0].generic_key.has_value());
    EXPECT_EQ((*p)[0].generic_key->max_samples, 8);
    EXPECT_NE((*p)[0].prediction_source.find("calibrated"), std::string::npos);
}

// A generic table priced otherwise than by frame time (a GPU compiler's
// cycles: `bench --planner-table --gpu`) prices every candidate, a timed
// calibration's too: its times are this renderer's, in another unit.
TEST(Planner, AGpuPricedTablePricesATimedCalibration) {
    EffectRequest e;
    e.max_error_texels = 5.0f;  // offset limiting (4.5 texels here) and POM both reach it
    e.lod_fade = EffectSwitch::off;
    const SceneDesc scene = plane_scene(20.0, 2.5f, 0.04f, e);
    const MaterialRelief relief = stated_relief(scene);
    // Timed on this renderer: POM x8 cheaper than offset limiting.
    CostTable calibration = calibration_of(relief);
    for (CostSample& s : calibration.rows) {
        if (s.technique == Technique::offset_limited) s.cost = 3.5;
        if (s.technique == Technique::pom && s.shadow == ShadowMode::none) s.cost = s.samples == 8 ? 1.2 : 4.0;
    }
    const auto plan_with = [&](const std::string& prices) {
        CostTable generic = small_table();  // offset limiting 1.1, POM x8 1.5
        generic.prices = prices;
        PlannerOptions options;
        options.table = &generic;
        options.calibrations = std::make_shared<const std::vector<CostTable>>(std::vector<CostTable>{calibration});
        Result<std::unique_ptr<ScenePlanner>> planner = ScenePlanner::create(scene, es3_caps(), {relief}, options);
        EXPECT_TRUE(planner.ok()) << planner.error().message;
        Result<std::vector<ObjectPlan>> p = (*planner)->plan(scene.camera, 256, 256);
        EXPECT_TRUE(p.ok()) << p.error().message;
        return (*p)[0];
    };
    const ObjectPlan timed = plan_with("");
    EXPECT_EQ(timed.key.technique, Technique::pom) << "the calibration's own times: " << timed.prediction_source;
    const ObjectPlan gpu = plan_with("Mali-G57 (Valhall) cycles per pixel");
    EXPECT_EQ(gpu.key.technique, Technique::offset_limited) << "the GPU table's prices: " << gpu.prediction_source;
    EXPECT_NE(gpu.prediction_source.find("calibrated"), std::string::npos) << gpu.prediction_source;
    EXPECT_NE(gpu.prediction_source.find("costs from table"), std::string::npos) << gpu.prediction_source;
    EXPECT_NEAR(gpu.predicted_cost, 1.1, 1e-9);
}

// The same through the lookup a host gives (PlannerOptions::find_calibration):
// asked once per material with a relief, with that relief; what it finds is
// used, and why it found nothing usable is the plan's note.
TEST(Planner, CalibrationsAreLookedUpPerMaterial) {
    EffectRequest e;
    e.max_error_texels = 2.0f;
    e.lod_fade = EffectSwitch::off;
    const SceneDesc scene = plane_scene(20.0, 2.5f, 0.04f, e);
    const MaterialRelief relief = stated_relief(scene);
    CostTable calibration = calibration_of(relief);
    for (CostSample& s : calibration.rows)
        if (s.technique == Technique::pom && s.samples == 8) s.error_p95 *= 10.0;
    const CostTable generic = small_table();
    std::vector<std::uint64_t> asked;
    auto plan_with = [&](bool found) {
        PlannerOptions options;
        options.table = &generic;
        options.find_calibration = [&](const ReliefFeatures& f, std::string& note) -> std::optional<CostTable> {
            asked.push_back(f.field_hash);
            if (found) return calibration;
            note = "calibration not used: broken.json: not a JSON object";
            return std::nullopt;
        };
        Result<std::unique_ptr<ScenePlanner>> planner = ScenePlanner::create(scene, es3_caps(), {relief}, options);
        EXPECT_TRUE(planner.ok()) << planner.error().message;
        Result<std::vector<ObjectPlan>> p = (*planner)->plan(scene.camera, 256, 256);
        EXPECT_TRUE(p.ok()) << p.error().message;
        return (*p)[0];
    };
    const ObjectPlan used = plan_with(true);
    ASSERT_EQ(asked.size(), 1u);
    EXPECT_EQ(asked[0], relief.features.field_hash);
    EXPECT_EQ(used.key.max_samples, 32);
    EXPECT_NE(used.prediction_source.find("calibrated"), std::string::npos) << used.prediction_source;
    const ObjectPlan without = plan_with(false);
    EXPECT_EQ(without.key.max_samples, 8);
    EXPECT_EQ(without.prediction_source.find("calibrated"), std::string::npos) << without.prediction_source;
    EXPECT_NE(std::find(without.notes.begin(), without.notes.end(), "calibration not used: broken.json: not a JSON object"),
              without.notes.end());

    // Two materials on one height map at two depths are two reliefs: each
    // is asked for (the showcase's floor and back wall share their bricks).
    SceneDesc two = scene;
    MaterialDesc deeper = two.materials[0];
    deeper.name = "deeper";
    deeper.height_scale *= 2.0f;
    two.materials.push_back(deeper);
    ObjectDesc second = two.objects[0];
    second.name = "second";
    second.material = "deeper";
    two.objects.push_back(second);
    SceneDesc deeper_scene = scene;
    deeper_scene.materials[0] = deeper;
    const MaterialRelief deeper_relief = stated_relief(deeper_scene);
    ASSERT_EQ(deeper_relief.features.field_hash, relief.features.field_hash);
    std::vector<double> depths;
    PlannerOptions options;
    options.table = &generic;
    options.find_calibration = [&](const ReliefFeatures& f, std::string&) -> std::optional<CostTable> {
        depths.push_back(f.depth_texels);
        return std::nullopt;
    };
    ASSERT_TRUE(ScenePlanner::create(two, es3_caps(), {relief, deeper_relief}, options).ok());
    ASSERT_EQ(depths.size(), 2u);
    EXPECT_NEAR(depths[1], 2.0 * depths[0], 1e-3 * depths[1]);
}

// A calibration knows what it measured: the view angles it was run at and
// the renderer it timed. A view past its angles, or another renderer, plans
// without it, and the note says which and why.
TEST(Planner, ACalibrationIsUsedOnlyWhereItMeasured) {
    EffectRequest e;
    e.max_error_texels = 2.0f;
    e.lod_fade = EffectSwitch::off;
    auto plan_with = [&](double view_angle, double calibrated_up_to, const std::string& renderer) {
        const SceneDesc scene = plane_scene(view_angle, 2.5f, 0.04f, e);
        Result<MaterialImages> images = build_material_images(scene.materials[0], "");
        EXPECT_TRUE(images.ok());
        MaterialRelief relief = material_relief(quantized_8bit(images->field), scene.materials[0]);
        relief.search.reset();
        CostTable calibration = small_table();
        calibration.date = "calibrated";
        calibration.renderer = renderer;
        calibration.reliefs[0].features = relief.features;
        std::vector<CostSample> kept;
        for (const CostSample& s : calibration.rows)
            if (s.angle_deg <= calibrated_up_to) kept.push_back(s);
        calibration.rows = kept;
        PlannerOptions options;
        const CostTable generic = small_table();
        options.table = &generic;
        options.calibrations = std::make_shared<const std::vector<CostTable>>(std::vector<CostTable>{calibration});
        Caps caps = es3_caps();
        caps.renderer = "llvmpipe (test)";
        Result<std::unique_ptr<ScenePlanner>> planner = ScenePlanner::create(scene, caps, {relief}, options);
        EXPECT_TRUE(planner.ok()) << planner.error().message;
        Result<std::vector<ObjectPlan>> p = (*planner)->plan(scene.camera, 256, 256);
        EXPECT_TRUE(p.ok()) << p.error().message;
        return p ? (*p)[0] : ObjectPlan{};
    };
    const ObjectPlan inside = plan_with(20.0, 89.0, "llvmpipe (test)");
    EXPECT_NE(inside.prediction_source.find("calibrated"), std::string::npos) << inside.prediction_source;
    const ObjectPlan past = plan_with(60.0, 45.0, "llvmpipe (test)");
    EXPECT_EQ(past.prediction_source.find("calibrated"), std::string::npos) << past.prediction_source;
    EXPECT_TRUE(has_note(past, "measured view angles up to 45.0 degrees; this view reaches"));
    const ObjectPlan elsewhere = plan_with(20.0, 89.0, "Mali-G78");
    EXPECT_EQ(elsewhere.prediction_source.find("calibrated"), std::string::npos) << elsewhere.prediction_source;
    EXPECT_TRUE(has_note(elsewhere, "was measured on 'Mali-G78', not this renderer ('llvmpipe (test)')"));
}

// A calibration that measured errors only ("costs": "table", the default of
// `plan --calibrate`) is priced from the generic table: whatever costs its
// rows hold, the plan's predicted cost is the table's, and its errors still
// decide. The same file with measured costs is priced by its own rows.
TEST(Planner, AnUntimedCalibrationIsPricedFromTheGenericTable) {
    EffectRequest e;
    e.max_error_texels = 2.0f;
    e.lod_fade = EffectSwitch::off;
    const SceneDesc scene = plane_scene(20.0, 2.5f, 0.04f, e);
    Result<MaterialImages> images = build_material_images(scene.materials[0], "");
    ASSERT_TRUE(images.ok());
    MaterialRelief relief = material_relief(quantized_8bit(images->field), scene.materials[0]);
    relief.search.reset();
    const CostTable generic = small_table();
    CostTable calibration = small_table();
    calibration.date = "calibrated";
    calibration.reliefs[0].features = relief.features;
    for (CostSample& s : calibration.rows) {
        if (s.technique == Technique::pom && s.samples == 8) s.error_p95 *= 10.0;  // errors decide: POM x32
        if (s.technique != Technique::normal) s.cost *= 7.0;                         // not timings, if untimed
    }
    auto plan_with = [&](const CostTable& c) {
        PlannerOptions options;
        options.table = &generic;
        options.calibrations = std::make_shared<const std::vector<CostTable>>(std::vector<CostTable>{c});
        Result<std::unique_ptr<ScenePlanner>> planner = ScenePlanner::create(scene, es3_caps(), {relief}, options);
        EXPECT_TRUE(planner.ok()) << planner.error().message;
        Result<std::vector<ObjectPlan>> p = (*planner)->plan(scene.camera, 256, 256);
        EXPECT_TRUE(p.ok()) << p.error().message;
        return p ? (*p)[0] : ObjectPlan{};
    };
    const ObjectPlan timed = plan_with(calibration);
    CostTable untimed = calibration;
    untimed.costs_measured = false;
    const ObjectPlan priced = plan_with(untimed);
    EXPECT_EQ(timed.key.max_samples, 32);
    EXPECT_EQ(priced.key.max_samples, 32);
    ASSERT_GT(priced.predicted_cost, 0.0);
    EXPECT_NEAR(timed.predicted_cost / priced.predicted_cost, 7.0, 0.7);
    EXPECT_NE(priced.prediction_source.find("errors measured, costs from table"), std::string::npos)
        << priced.prediction_source;
    EXPECT_EQ(timed.prediction_source.find("costs from table"), std::string::npos) << timed.prediction_source;
    // The file says which it is, and reads back the same.
    Result<CostTable> back = parse_cost_table(cost_table_json(untimed), "untimed.json");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_FALSE(back->costs_measured);
    back = parse_cost_table(cost_table_json(calibration), "timed.json");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_TRUE(back->costs_measured);
}

TEST(Planner, ACalibrationWithNothingToPlanWithFallsBackToTheGenericTable) {
    EffectRequest e;
    e.max_error_texels = 2.0f;
    const SceneDesc scene = plane_scene(20.0, 2.5f, 0.04f, e);
    Result<MaterialImages> images = build_material_images(scene.materials[0], "");
    ASSERT_TRUE(images.ok());
    MaterialRelief relief = material_relief(quantized_8bit(images->field), scene.materials[0]);
    relief.search.reset();  // against the stated table, not the search model
    // A cache file that matches the relief but holds only shadow rows.
    CostTable calibration = small_table();
    calibration.reliefs[0].features = relief.features;
    calibration.rows.erase(std::remove_if(calibration.rows.begin(), calibration.rows.end(),
                                          [](const CostSample& s) { return s.shadow == ShadowMode::none; }),
                           calibration.rows.end());
    PlannerOptions options;
    const CostTable generic = small_table();
    options.table = &generic;
    options.calibrations = std::make_shared<const std::vector<CostTable>>(std::vector<CostTable>{calibration});
    Result<std::unique_ptr<ScenePlanner>> planner = ScenePlanner::create(scene, es3_caps(), {relief}, options);
    ASSERT_TRUE(planner.ok());
    Result<std::vector<ObjectPlan>> p = (*planner)->plan(scene.camera, 128, 128);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_TRUE(has_note((*p)[0], "holds no normal-mapping row to plan with: the planner predicts without it"));
    EXPECT_EQ((*p)[0].prediction_source.find("calibrated"), std::string::npos) << (*p)[0].prediction_source;

    // Normal mapping alone: nothing that traces the relief.
    CostTable only_normal = small_table();
    only_normal.reliefs[0].features = relief.features;
    only_normal.rows.erase(std::remove_if(only_normal.rows.begin(), only_normal.rows.end(),
                                          [](const CostSample& s) { return s.technique != Technique::normal; }),
                           only_normal.rows.end());
    options.calibrations = std::make_shared<const std::vector<CostTable>>(std::vector<CostTable>{only_normal});
    planner = ScenePlanner::create(scene, es3_caps(), {relief}, options);
    ASSERT_TRUE(planner.ok());
    p = (*planner)->plan(scene.camera, 128, 128);
    ASSERT_TRUE(p.ok()) << p.error().message;
    EXPECT_TRUE(has_note((*p)[0], "holds no technique that traces the relief"));
}

// Many sample counts of one technique (a forged or runaway calibration):
// every count still costs at least what every smaller one does at each
// angle (the running maximum), and the table is read and planned with.
TEST(Planner, ManySampleCountsKeepCostsMonotoneInSamples) {
    CostTable t = small_table();
    std::vector<double> noisy_cost = {3.0, 1.2, 2.5, 1.1, 4.0, 0.9};
    for (int n = 1; n <= 3000; ++n)
        for (double a : {0.0, 45.0, 89.0})
            t.rows.push_back({0, a, Technique::steep, n, ShadowMode::none, 0, 8.0 / n, 0.0,
                              noisy_cost[static_cast<size_t>(n) % noisy_cost.size()]});
    Result<CostTable> back = parse_cost_table(cost_table_json(t), "test");
    ASSERT_TRUE(back.ok()) << back.error().message;
    Result<std::vector<ObjectPlan>> p = plan_of(plane_scene(20.0, 2.5f, 0.04f, within(2.0f)), es3_caps(), *back);
    ASSERT_TRUE(p.ok()) << p.error().message;
    // steep at n samples costs at least the most any smaller count cost:
    // from 5 samples on at least 4.0 (steep x4's), dearer than pom x8's 1.5,
    // so no steep count of 5 or more can win on a noisy low timing (0.9).
    const ObjectPlan& plan = (*p)[0];
    EXPECT_FALSE(plan.key.technique == Technique::steep && plan.key.max_samples >= 5) << plan.key.describe();
    EXPECT_GE(plan.predicted_cost, 1.0) << plan.key.describe();
    EXPECT_LE(plan.predicted_error, 2.0);
    // Past the bounds, refused by name.
    CostTable huge = small_table();
    huge.rows.resize(kMaxCostTableRows + 1, huge.rows[0]);
    Result<CostTable> refused = parse_cost_table(cost_table_json(huge), "huge.json");
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("more than the 20000"), std::string::npos) << refused.error().message;
}

// A single quad far bigger than the view (a 100-unit ground seen from a
// metre up): every precomputed survey point of it lies outside the view.
// Surveyed on its visible part, it gets the decision a tessellated
// ground gets, and the pixels it reports are the image's, not more.
TEST(PlannerSurvey, ABigSingleQuadIsPlannedLikeATessellatedOne) {
    const CostTable table = small_table();
    const EffectRequest request = within(1.0f);
    for (int segments : {1, 4, 32}) {
        SCOPED_TRACE(segments);
        SceneDesc s = plane_scene(70.0, 2.0f, 0.04f, request, 40.0f, segments);
        s.objects[0].mesh.size = 100.0f;
        s.materials[0].uv.scale = glm::vec2(50.0f);  // a tile per 2 units, as on the small plane
        Result<std::vector<ObjectPlan>> p = plan_of(s, es3_caps(), table, 512);
        ASSERT_TRUE(p.ok()) << p.error().message;
        const ObjectPlan& plan = (*p)[0];
        EXPECT_TRUE(plan.view.visible);
        EXPECT_GT(plan.view.pixels, 0.3 * 512 * 512);
        EXPECT_LE(plan.view.pixels, 512.0 * 512.0 * 1.0001);
        EXPECT_NE(plan.key.technique, Technique::normal) << plan.key.describe();
        EXPECT_EQ(plan.key.technique, Technique::pom) << plan.key.describe();
        EXPECT_GE(plan.view.angle_max_deg, 70.0);
    }
}

// The step-over bound: a linear search whose step along the ray passes the
// relief's narrowest feature is predicted at least that step off, whatever
// the table relief measured. Two reliefs alike but for their lines' width:
// the narrow one may not be given the cheaper search.
TEST(PlannerPrediction, ALinearSearchThatStepsOverTheNarrowestFeatureIsNotTrusted) {
    const CostTable table = small_table();
    const EffectRequest request = within(4.0f);
    auto plan_for = [&](int line_width) {
        SceneDesc s = plane_scene(60.0, 2.5f, 0.08f, request);
        s.materials[0].height.field.line_width = line_width;
        Result<std::vector<ObjectPlan>> p = plan_of(s, es3_caps(), table);
        EXPECT_TRUE(p.ok()) << p.error().message;
        return p ? (*p)[0] : ObjectPlan{};
    };
    const ObjectPlan narrow = plan_for(1), wide = plan_for(12);
    SCOPED_TRACE("narrow: " + narrow.key.describe() + ", wide: " + wide.key.describe());
    EXPECT_GE(narrow.predicted_cost, wide.predicted_cost);
    EXPECT_GE(narrow.key.max_samples, wide.key.max_samples);
    EXPECT_GT(narrow.predicted_error, wide.predicted_error);
}

// Explanations that are true: a pick made against the hit target a shadow
// tightened says that target, not the one asked; a calibrated plan names
// the generic choice as it would be drawn (a relief search refines).
TEST(PlannerExplanations, TheTargetUsedAndTheGenericChoiceAsDrawn) {
    const CostTable table = small_table();
    EffectRequest shadowed = within(4.0f);
    shadowed.shadow = ShadowMode::hard;
    shadowed.shadow_max_error = 0.5f;
    Result<std::vector<ObjectPlan>> p = plan_of(plane_scene(20.0, 2.5f, 0.04f, shadowed), es3_caps(), table);
    ASSERT_TRUE(p.ok()) << p.error().message;
    const ObjectPlan& plan = (*p)[0];
    ASSERT_TRUE(has_note(plan, "hit target tightened")) << plan.key.describe();
    EXPECT_TRUE(has_note(plan, "(the hit target tightened for the shadow; asked 4)"));
    EXPECT_FALSE(has_note(plan, "predicted within 4 texels"));

    // Generic: relief x8 the cheapest within 2; the calibration of this
    // relief finds it far worse.
    CostTable generic = small_table();
    for (double a : {0.0, 45.0, 89.0})
        generic.rows.push_back({0, a, Technique::relief, 8, ShadowMode::none, 0, 0.3 * (1.0 + a / 10.0), 0.0, 1.3});
    const SceneDesc scene = plane_scene(20.0, 2.5f, 0.04f, within(2.0f));
    Result<MaterialImages> images = build_material_images(scene.materials[0], "");
    ASSERT_TRUE(images.ok());
    MaterialRelief relief = material_relief(quantized_8bit(images->field), scene.materials[0]);
    relief.search.reset();  // against the stated table, not the search model
    CostTable calibration = generic;
    calibration.date = "calibrated";
    calibration.reliefs[0].features = relief.features;
    for (CostSample& s : calibration.rows)
        if (s.technique == Technique::relief) s.error_p95 *= 10.0;
    PlannerOptions options;
    options.table = &generic;
    options.calibrations = std::make_shared<const std::vector<CostTable>>(std::vector<CostTable>{calibration});
    Result<std::unique_ptr<ScenePlanner>> planner = ScenePlanner::create(scene, es3_caps(), {relief}, options);
    ASSERT_TRUE(planner.ok()) << planner.error().message;
    Result<std::vector<ObjectPlan>> calibrated = (*planner)->plan(scene.camera, 256, 256);
    ASSERT_TRUE(calibrated.ok()) << calibrated.error().message;
    ASSERT_TRUE((*calibrated)[0].generic_key.has_value()) << (*calibrated)[0].key.describe();
    EXPECT_EQ((*calibrated)[0].generic_key->technique, Technique::relief);
    EXPECT_GT((*calibrated)[0].generic_key->refine_steps, 0) << (*calibrated)[0].generic_key->describe();
    EXPECT_NE((*calibrated)[0].key.technique, Technique::relief);
}

// Shadows by what they can change: a gentle relief under a light steeper
// than any of its slopes cannot shadow itself, so the shadow is dropped and
// the note says why; under a low light it is kept.
TEST(PlannerShadows, ALightAboveEverySlopeDropsTheShadow) {
    const CostTable table = small_table();
    EffectRequest request = within(4.0f);
    request.shadow = ShadowMode::hard;
    request.shadow_max_error = 0.5f;
    auto plan_under = [&](float light_elevation) {
        SceneDesc s = plane_scene(20.0, 2.5f, 0.01f, request, light_elevation);
        s.materials[0].height.field.kind = FieldKind::sine;
        s.materials[0].height.field.frequency = 2;
        Result<std::vector<ObjectPlan>> p = plan_of(s, es3_caps(), table);
        EXPECT_TRUE(p.ok()) << p.error().message;
        return p ? (*p)[0] : ObjectPlan{};
    };
    const ObjectPlan high = plan_under(60.0f), low = plan_under(3.0f);
    EXPECT_EQ(high.key.shadow, ShadowMode::none) << high.key.describe();
    EXPECT_TRUE(has_note(high, "nothing on it can cast a shadow"));
    EXPECT_EQ(low.key.shadow, ShadowMode::hard) << low.key.describe();
    EXPECT_FALSE(has_note(low, "nothing on it can cast a shadow"));
}

// --- The search model: hits predicted from the relief itself -----------------

HeightField flat_field(int size, float level) {
    HeightField f;
    f.width = f.height = size;
    f.texels.assign(static_cast<size_t>(size) * size, level);
    return f;
}

// On a flat field at half depth every quantity has a closed form: the exact
// hit is at height 0.5, so normal mapping is off by 0.5 |P| and offset
// limiting (which scales the offset by V.z) by 0.5 (1 - cos) |P|, with
// |P| = scale * width * tan(angle); parallax's single fetch is exact there,
// and a linear search whose samples land on 0.5 is exact too.
TEST(SearchModel, AFlatFieldGivesTheClosedFormErrors) {
    const HeightField field = flat_field(64, 0.5f);
    const double angle = 60.0, scale = 0.05;
    const double theta = glm::radians(angle);
    std::vector<SearchRay> rays;
    for (int k = 0; k < 16; ++k) {
        const double phi = 0.4 * k;
        rays.push_back({glm::dvec2(0.03 * k, 0.05 * k),
                        glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta))});
    }
    const std::vector<int> samples{4, 6};
    const std::vector<SearchCurve> order = search_candidates(samples);
    const std::vector<double> e = simulate_rays(field, scale, 1.0, rays, samples, 5).front();
    ASSERT_EQ(e.size(), order.size());
    auto error_of = [&](Technique t, int n) {
        for (size_t i = 0; i < order.size(); ++i)
            if (order[i].technique == t && order[i].samples == n) return e[i];
        ADD_FAILURE() << "no curve " << technique_name(t) << " " << n;
        return -1.0;
    };
    const double p = scale * 64 * std::tan(theta);
    EXPECT_NEAR(error_of(Technique::normal, 0), 0.5 * p, 1e-6);
    EXPECT_NEAR(error_of(Technique::offset_limited, 0), 0.5 * (1.0 - std::cos(theta)) * p, 1e-6);
    EXPECT_NEAR(error_of(Technique::parallax, 0), 0.0, 1e-6);
    EXPECT_NEAR(error_of(Technique::steep, 4), 0.0, 1e-6);  // samples at 1, 0.75, 0.5
    // Six samples fall at 1, 5/6, 4/6, 3/6: steep stops on 0.5 exactly too;
    // at 1/3 steps (three samples) it would stop at 1/3, 1/6 |P| off.
    EXPECT_NEAR(error_of(Technique::steep, 6), 0.0, 1e-6);
    EXPECT_NEAR(error_of(Technique::pom, 4), 0.0, 1e-6);
    EXPECT_NEAR(error_of(Technique::maxmip, 0), 0.0, 1e-12);
    const std::vector<double> three = simulate_rays(field, scale, 1.0, rays, {3}, 5).front();
    const std::vector<SearchCurve> order3 = search_candidates({3});
    for (size_t i = 0; i < order3.size(); ++i)
        if (order3[i].technique == Technique::steep) EXPECT_NEAR(three[i], p / 6.0, 1e-6);
}

// 16 lines 3 texels wide along y on a 128-texel tile, as the GPU samples it (8-bit).
HeightField three_texel_lines() {
    FieldSpec spec;
    spec.kind = FieldKind::lines;
    spec.size = 128;
    spec.count = 16;
    spec.line_width = 3;
    Result<HeightField> field = make_height_field(spec);
    EXPECT_TRUE(field.ok()) << field.error().message;
    return field.ok() ? quantized_8bit(*field) : HeightField{};
}

// A search that steps over thin features: 3-texel flat-topped lines 8
// texels apart, seen low. Few samples stride past the lines (errors of
// many texels), many do not; the model sees it from the field, with no
// table relief to match. (1-texel lines are a bilinear tent whose tip a ray
// can graze near the top between any two samples: even 256 samples leave a
// few rays texels off there, as the exact reference sees it.)
TEST(SearchModel, StepsOverThinLinesWithFewSamplesOnly) {
    const HeightField field = three_texel_lines();
    ASSERT_GT(field.width, 0);
    SearchModelOptions o;
    o.angles = {0, 75};
    o.samples = {4, 256};
    o.rays = 256;
    const SearchModel m = simulate_searches(field, 0.08, 1.0, o);
    const SearchCurve* coarse = m.find(Technique::pom, 4);
    const SearchCurve* fine = m.find(Technique::pom, 256);
    ASSERT_TRUE(coarse && fine);
    EXPECT_GT(coarse->error[1], 3.0);  // steps of 0.08 * 128 * tan 75 / 4 = 9.6 texels over 3-texel lines
    EXPECT_LT(fine->error[1], 0.5);
    EXPECT_LT(fine->error[0], 1e-3);
    // Deterministic.
    const SearchModel again = simulate_searches(field, 0.08, 1.0, o);
    EXPECT_EQ(again.find(Technique::pom, 4)->error, coarse->error);
}

// Azimuth sectors: the view's direction folded by both mirror axes.
TEST(SearchModel, SectorsFoldTheAzimuthByBothMirrorAxes) {
    EXPECT_EQ(search_sector(1.0, 0.0), 0);
    EXPECT_EQ(search_sector(-1.0, 0.0), 0);
    EXPECT_EQ(search_sector(0.0, 1.0), kSearchSectors - 1);
    EXPECT_EQ(search_sector(0.0, -1.0), kSearchSectors - 1);
    for (double x : {0.3, -0.3})
        for (double y : {0.8, -0.8}) EXPECT_EQ(search_sector(x, y), search_sector(0.3, 0.8)) << x << " " << y;
    EXPECT_EQ(search_sector(1.0, 1.0), kSearchSectors / 2);
    EXPECT_EQ(search_sector(0.0, 0.0), 0);
    EXPECT_EQ(search_sector(std::nan(""), 1.0), 0);
}

// Lines along y (FieldKind::lines) are stepped over by a view across them
// (along x, sector 0), never by one along them (the last sector): the
// model keeps the two apart where the pooled curve mixes them.
TEST(SearchModel, LinesSeenAlongThemAreNotSteppedOver) {
    const HeightField field = three_texel_lines();
    ASSERT_GT(field.width, 0);
    SearchModelOptions o;
    o.angles = {75};
    o.samples = {4};
    o.rays = 128;
    const SearchModel m = simulate_searches(field, 0.08, 1.0, o);
    const SearchCurve* pom = m.find(Technique::pom, 4);
    ASSERT_TRUE(pom);
    ASSERT_EQ(pom->sector_levels.size(), 1u);
    ASSERT_EQ(pom->sector_levels[0].size(), static_cast<size_t>(kSearchSectors));
    const double across = pom->sector_levels[0][0][5], along = pom->sector_levels[0][kSearchSectors - 1][5];
    EXPECT_GT(across, 3.0);          // steps of 9.6 texels over 3-texel lines
    EXPECT_LT(along, 0.5 * across);  // within 15 degrees of the lines: steps of at most 2.5 texels across
    EXPECT_GT(pom->error[0], along);  // the pooled p95 holds the across rays' misses
    // Exactly along a line the height never changes: no search misses.
    std::vector<SearchRay> rays;
    for (int i = 0; i < 64; ++i)
        rays.push_back({glm::dvec2((i + 0.5) / 64.0, 0.37), glm::dvec3(0.0, std::sin(glm::radians(75.0)), std::cos(glm::radians(75.0)))});
    const std::vector<std::vector<double>> exact = simulate_rays(field, 0.08, 1.0, rays, {4}, 5);
    const std::vector<SearchCurve> order = search_candidates({4});
    for (size_t c = 0; c < order.size(); ++c)
        if (order[c].technique == Technique::pom) EXPECT_LT(exact[0][c], 0.05);
}

// The planner with the search model: its prediction comes from the relief
// itself (the source says so), it offers the single-fetch techniques too,
// and a shallow relief with a loose target gets one of them where the
// table alone (thin 1-texel lines) would pay for a search.
TEST(SearchModel, PlansFromTheReliefAndOffersSingleFetchCandidates) {
    const CostTable table = small_table();
    SceneDesc s = plane_scene(30.0, 2.5f, 0.02f, within(2.0f));
    s.materials[0].height.field.kind = FieldKind::sine;
    s.materials[0].height.field.frequency = 2;
    Result<std::vector<ObjectPlan>> with = plan_of(s, es3_caps(), table, 256, true);
    ASSERT_TRUE(with.ok()) << with.error().message;
    const ObjectPlan& p = (*with)[0];
    EXPECT_NE(p.prediction_source.find("search model on this relief"), std::string::npos) << p.prediction_source;
    EXPECT_TRUE(p.key.technique == Technique::offset_limited || p.key.technique == Technique::parallax)
        << p.key.describe();
    EXPECT_LE(p.predicted_error, 2.0);
    Result<std::vector<ObjectPlan>> without = plan_of(s, es3_caps(), table, 256, false);
    ASSERT_TRUE(without.ok()) << without.error().message;
    EXPECT_NE((*without)[0].prediction_source.find("table"), std::string::npos);
}

// The margin: a tail of misses just past 5 % of the rays (the p97 far above
// the p95) is predicted at the tail, since the GPU's p95 may land anywhere
// up to it; a smooth distribution gets its scaled p95 and the floor.
TEST(SearchModel, TheMarginCoversATailPastThePercentile) {
    const SearchMargin m = search_margin(Technique::pom);
    EXPECT_GE(m.scale, 1.0);
    EXPECT_GE(m.floor, 0.0);
    EXPECT_DOUBLE_EQ(predicted_with_margin(Technique::pom, 0.02, 5.4), 5.4 + m.floor);
    EXPECT_DOUBLE_EQ(predicted_with_margin(Technique::pom, 1.0, 1.01), m.scale * 1.0 + m.floor);
    EXPECT_DOUBLE_EQ(predicted_with_margin(Technique::maxmip, 0.0, 0.0), search_margin(Technique::maxmip).floor);
}

// A bounded tile's outline is on screen unless every pixel's ray stays
// inside its bounds: seen whole it is; filling the view from close above it
// is not, unless the relief's depth carries a corner's ray past an edge, or
// the view reaches past the tile.
TEST(BoundedOutline, OnScreenUnlessEveryRayStaysInsideTheTile) {
    const auto view_of = [](glm::vec3 eye, glm::vec3 target, float fov_deg) {
        CameraDesc c;
        c.position = eye;
        c.target = target;
        c.up = glm::vec3(0.0f, 1.0f, 0.0f);
        c.fov_y_deg = fov_deg;
        return PlanView::from_camera(c, 256, 256);
    };
    const glm::mat4 identity(1.0f);
    // A 2-unit tile seen whole from 3.6 units away: on screen.
    const PlanView whole = view_of({0.0f, -1.8f, 3.1f}, {0.0f, 0.0f, 0.0f}, 40.0f);
    EXPECT_TRUE(bounded_outline_on_screen(identity, 2.0f, 0.3, whole.view, whole.projection));
    // Straight down from 0.5 units, 40 degrees: the view spans 0.36 units of
    // the tile's 2 along each axis. A shallow relief keeps every ray inside;
    // a deep one does not (9 units deep: a corner's ray, its tangent 0.51,
    // is carried 4.6 units sideways).
    const PlanView close = view_of({0.0f, 0.0f, 0.5f}, {0.0f, 0.0f, 0.0f}, 40.0f);
    EXPECT_FALSE(bounded_outline_on_screen(identity, 2.0f, 0.05, close.view, close.projection));
    EXPECT_TRUE(bounded_outline_on_screen(identity, 2.0f, 9.0, close.view, close.projection));
    // The same view over a tile moved so that its edge is in view.
    EXPECT_TRUE(bounded_outline_on_screen(glm::translate(identity, glm::vec3(0.9f, 0.0f, 0.0f)), 2.0f, 0.05,
                                          close.view, close.projection));
    // Seen from below (its back) or with the tile behind the eye: on screen
    // (the check says false only when it is sure).
    const PlanView below = view_of({0.0f, 0.0f, -0.5f}, {0.0f, 0.0f, 0.0f}, 40.0f);
    EXPECT_TRUE(bounded_outline_on_screen(identity, 2.0f, 0.05, below.view, below.projection));
    const PlanView away = view_of({0.0f, 0.0f, 0.5f}, {0.0f, 0.0f, 1.0f}, 40.0f);
    EXPECT_TRUE(bounded_outline_on_screen(identity, 2.0f, 0.05, away.view, away.projection));
}

// A curved mesh's contour is on screen unless the mesh is out of view or,
// for a sphere, every viewport corner's ray meets it (shrunk by the relief).
TEST(CurvedOutline, OnScreenUnlessOutOfViewOrFillingIt) {
    const auto view_of = [](glm::vec3 eye, glm::vec3 target, float fov_deg) {
        CameraDesc c;
        c.position = eye;
        c.target = target;
        c.up = glm::vec3(0.0f, 0.0f, 1.0f);
        c.fov_y_deg = fov_deg;
        return PlanView::from_camera(c, 256, 256);
    };
    const glm::mat4 identity(1.0f);
    const PlanView whole = view_of({0.0f, -3.4f, 0.0f}, {0.0f, 0.0f, 0.0f}, 40.0f);
    EXPECT_TRUE(curved_outline_on_screen(identity, MeshKind::sphere, 1.0f, 0.3f, 2.0f, 0.05, whole.view, whole.projection));
    // 0.1 above a unit sphere, 40 degrees: every corner meets it.
    const PlanView close = view_of({0.0f, -1.1f, 0.0f}, {0.0f, 0.0f, 0.0f}, 40.0f);
    EXPECT_FALSE(curved_outline_on_screen(identity, MeshKind::sphere, 1.0f, 0.3f, 2.0f, 0.05, close.view, close.projection));
    // A relief deep enough that the corners pass the shrunk sphere (they
    // pass 1.1 sin(27.2 degrees) = 0.50 from its centre).
    EXPECT_TRUE(curved_outline_on_screen(identity, MeshKind::sphere, 1.0f, 0.3f, 2.0f, 0.6, close.view, close.projection));
    // A torus or cylinder in view: only the view volume is tested.
    EXPECT_TRUE(curved_outline_on_screen(identity, MeshKind::torus, 1.0f, 0.3f, 2.0f, 0.05, close.view, close.projection));
    // Behind the camera, or far to the side: off screen.
    const glm::mat4 behind = glm::translate(identity, glm::vec3(0.0f, -8.0f, 0.0f));
    EXPECT_FALSE(curved_outline_on_screen(behind, MeshKind::sphere, 1.0f, 0.3f, 2.0f, 0.05, whole.view, whole.projection));
    const glm::mat4 aside = glm::translate(identity, glm::vec3(20.0f, 0.0f, 0.0f));
    EXPECT_FALSE(curved_outline_on_screen(aside, MeshKind::cylinder, 1.0f, 0.3f, 2.0f, 0.05, whole.view, whole.projection));
    // Its edge in view: on screen.
    const glm::mat4 edge = glm::translate(identity, glm::vec3(1.6f, 0.0f, 0.0f));
    EXPECT_TRUE(curved_outline_on_screen(edge, MeshKind::sphere, 1.0f, 0.3f, 2.0f, 0.05, whole.view, whole.projection));
}

}  // namespace
}  // namespace px
