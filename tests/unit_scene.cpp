// Scene description: JSON parsing, error messages, defaults, built-in scenes,
// loading, and the object transform.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "parallaxes/assets/heightfield.h"
#include "parallaxes/assets/image.h"
#include "parallaxes/scene/scene.h"

namespace px {
namespace {

namespace fs = std::filesystem;

constexpr const char* kOrigin = "test.json";

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
    if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

SceneDesc parse_ok(const std::string& text) {
    Result<SceneDesc> r = parse_scene(text, kOrigin);
    EXPECT_TRUE(r.ok()) << r.error().message;
    return r.ok() ? *r : SceneDesc{};
}

std::string parse_error(const std::string& text) {
    Result<SceneDesc> r = parse_scene(text, kOrigin);
    EXPECT_FALSE(r.ok()) << "parsed, but expected an error:\n" << text;
    if (r.ok()) return "";
    EXPECT_EQ(r.error().message.rfind(kOrigin, 0), 0u) << "error does not start with the origin: "
                                                         << r.error().message;
    return r.error().message;
}

// A valid document with `members` added at the top level.
std::string doc(const std::string& members) { return "{" + members + R"(, "objects": [{}]})"; }

// A valid document with one material "m" holding `fields`, used by one object.
std::string material_doc(const std::string& fields) {
    return R"({"materials": [{"name": "m")" + (fields.empty() ? "" : ", " + fields) +
           R"(}], "objects": [{"material": "m"}]})";
}

// A valid document with one object holding `fields`.
std::string object_doc(const std::string& fields) { return R"({"objects": [{)" + fields + "}]}"; }

void expect_vec(const glm::vec3& v, float x, float y, float z, float eps = 1e-6f) {
    EXPECT_NEAR(v.x, x, eps);
    EXPECT_NEAR(v.y, y, eps);
    EXPECT_NEAR(v.z, z, eps);
}

// Degrees above the horizon of a directional light (from its travel direction).
float light_elevation_deg(const LightDesc& l) {
    return glm::degrees(std::asin(-l.direction.z / glm::length(l.direction)));
}

float camera_elevation_deg(const CameraDesc& c) {
    const glm::vec3 to_camera = c.position - c.target;
    return glm::degrees(std::asin(to_camera.z / glm::length(to_camera)));
}

// --- Round trip ---------------------------------------------------------------------

constexpr const char* kComplete = R"json({
  "name": "demo",
  "camera": {"position": [1, -4, 2], "target": [0, 0, 0.5], "up": [0, 0, 1],
             "fov_y_deg": 40, "near": 0.1, "far": 20},
  "ambient": [0.1, 0.15, 0.2],
  "background": [0.2, 0.3, 0.4],
  "lights": [
    {"type": "directional", "direction": [1, 0, -1], "color": [1, 0.9, 0.8], "intensity": 2,
     "angular_radius_deg": 3},
    {"type": "point", "position": [0, 0, 3], "color": [0.5, 0.5, 1], "intensity": 0.5}
  ],
  "materials": [
    {"name": "bricks", "albedo": "textures/bricks.png",
     "height": {"file": "textures/bricks_depth.png", "convention": "depth"},
     "normal": {"file": "textures/bricks_n.png"},
     "height_scale": 0.08, "height_bias": -0.04, "pack_height_in_normal_alpha": false,
     "uv": {"scale": [2, 3], "offset": [0.25, 0.5], "rotation_deg": 90},
     "technique": "relief",
     "options": {"min_samples": 4, "max_samples": 48, "refine_steps": 6, "shadow": "soft",
                 "shadow_samples": 24, "depth_write": true, "lod": true, "lod_threshold": 4,
                 "lod_band": 2}},
    {"name": "sign", "albedo": {"color": [0.9, 0.8, 0.7]},
     "height": {"procedural": "text", "size": 512, "text": "HI 2"}, "uv": {"scale": 2}},
    {"name": "bumps", "height": {"procedural": "hemispheres", "size": 128, "count": 3},
     "technique": "steep", "options": {"shadow": "hard"}}
  ],
  "objects": [
    {"name": "floor", "mesh": {"type": "plane", "size": 4, "segments": 8},
     "transform": {"translate": [0, 0, -1], "rotate_deg": [0, 0, 45], "scale": 2}, "material": "bricks"},
    {"name": "ring", "mesh": {"type": "torus", "radius": 1.5, "tube_radius": 0.5},
     "transform": {"scale": [1, 2, 3]}, "material": "sign"},
    {"mesh": {"type": "sphere", "radius": 0.7}, "material": "bumps"}
  ]
})json";

TEST(SceneParse, CompleteExampleLandsEveryValue) {
    const SceneDesc s = parse_ok(kComplete);
    EXPECT_EQ(s.name, "demo");
    expect_vec(s.camera.position, 1, -4, 2);
    expect_vec(s.camera.target, 0, 0, 0.5f);
    expect_vec(s.camera.up, 0, 0, 1);
    EXPECT_FLOAT_EQ(s.camera.fov_y_deg, 40.0f);
    EXPECT_FLOAT_EQ(s.camera.near_plane, 0.1f);
    EXPECT_FLOAT_EQ(s.camera.far_plane, 20.0f);
    expect_vec(s.ambient, 0.1f, 0.15f, 0.2f);
    expect_vec(s.background, 0.2f, 0.3f, 0.4f);

    ASSERT_EQ(s.lights.size(), 2u);
    EXPECT_EQ(s.lights[0].kind, LightKind::directional);
    expect_vec(s.lights[0].direction, 1, 0, -1);
    expect_vec(s.lights[0].color, 1, 0.9f, 0.8f);
    EXPECT_FLOAT_EQ(s.lights[0].intensity, 2.0f);
    EXPECT_FLOAT_EQ(s.lights[0].angular_radius_deg, 3.0f);
    EXPECT_EQ(s.lights[1].kind, LightKind::point);
    expect_vec(s.lights[1].position, 0, 0, 3);
    EXPECT_FLOAT_EQ(s.lights[1].intensity, 0.5f);
    EXPECT_FLOAT_EQ(s.lights[1].angular_radius_deg, 2.0f);  // default

    ASSERT_EQ(s.materials.size(), 3u);  // no "default" added: every object names its material
    const MaterialDesc& b = s.materials[0];
    EXPECT_EQ(b.name, "bricks");
    EXPECT_EQ(b.albedo.kind, TextureSource::Kind::file);
    EXPECT_EQ(b.albedo.path, "textures/bricks.png");  // parse_scene keeps paths as written
    EXPECT_EQ(b.height.kind, TextureSource::Kind::file);
    EXPECT_EQ(b.height.path, "textures/bricks_depth.png");
    EXPECT_EQ(b.height.convention, HeightConvention::depth);
    EXPECT_EQ(b.normal.kind, TextureSource::Kind::file);
    EXPECT_EQ(b.normal.path, "textures/bricks_n.png");
    EXPECT_FLOAT_EQ(b.height_scale, 0.08f);
    ASSERT_TRUE(b.height_bias.has_value());
    EXPECT_FLOAT_EQ(b.bias(), -0.04f);
    EXPECT_FALSE(b.pack_height_in_normal_alpha);
    EXPECT_FLOAT_EQ(b.uv.scale.x, 2.0f);
    EXPECT_FLOAT_EQ(b.uv.scale.y, 3.0f);
    EXPECT_FLOAT_EQ(b.uv.offset.x, 0.25f);
    EXPECT_FLOAT_EQ(b.uv.offset.y, 0.5f);
    EXPECT_FLOAT_EQ(b.uv.rotation_deg, 90.0f);
    EXPECT_EQ(b.technique.technique, Technique::relief);
    EXPECT_EQ(b.technique.min_samples, 4);
    EXPECT_EQ(b.technique.max_samples, 48);
    EXPECT_EQ(b.technique.refine_steps, 6);
    EXPECT_EQ(b.technique.shadow, ShadowMode::soft);
    EXPECT_EQ(b.technique.shadow_samples, 24);
    EXPECT_TRUE(b.technique.depth_write);
    EXPECT_TRUE(b.technique.lod);
    EXPECT_FLOAT_EQ(b.technique.lod_threshold, 4.0f);
    EXPECT_FLOAT_EQ(b.technique.lod_band, 2.0f);

    const MaterialDesc& sign = s.materials[1];
    EXPECT_EQ(sign.albedo.kind, TextureSource::Kind::color);
    expect_vec(sign.albedo.color, 0.9f, 0.8f, 0.7f);
    EXPECT_EQ(sign.height.kind, TextureSource::Kind::procedural);
    EXPECT_EQ(sign.height.field.kind, FieldKind::text);
    EXPECT_EQ(sign.height.field.size, 512);
    EXPECT_EQ(sign.height.field.text, "HI 2");
    EXPECT_FLOAT_EQ(sign.uv.scale.x, 2.0f);  // one number scales both axes
    EXPECT_FLOAT_EQ(sign.uv.scale.y, 2.0f);
    EXPECT_FALSE(sign.height_bias.has_value());
    EXPECT_FLOAT_EQ(sign.bias(), -sign.height_scale);

    const MaterialDesc& bumps = s.materials[2];
    EXPECT_EQ(bumps.height.field.kind, FieldKind::hemispheres);
    EXPECT_EQ(bumps.height.field.size, 128);
    EXPECT_EQ(bumps.height.field.count, 3);
    EXPECT_EQ(bumps.technique.technique, Technique::steep);
    EXPECT_EQ(bumps.technique.shadow, ShadowMode::hard);

    ASSERT_EQ(s.objects.size(), 3u);
    const ObjectDesc& floor = s.objects[0];
    EXPECT_EQ(floor.name, "floor");
    EXPECT_EQ(floor.mesh.kind, MeshKind::plane);
    EXPECT_FLOAT_EQ(floor.mesh.size, 4.0f);
    EXPECT_EQ(floor.mesh.segments, 8);
    expect_vec(floor.transform.translate, 0, 0, -1);
    expect_vec(floor.transform.rotate_deg, 0, 0, 45);
    expect_vec(floor.transform.scale, 2, 2, 2);
    EXPECT_EQ(floor.material, "bricks");
    EXPECT_EQ(s.objects[1].mesh.kind, MeshKind::torus);
    EXPECT_FLOAT_EQ(s.objects[1].mesh.radius, 1.5f);
    EXPECT_FLOAT_EQ(s.objects[1].mesh.tube_radius, 0.5f);
    expect_vec(s.objects[1].transform.scale, 1, 2, 3);
    EXPECT_EQ(s.objects[2].mesh.kind, MeshKind::sphere);
    EXPECT_FLOAT_EQ(s.objects[2].mesh.radius, 0.7f);
    EXPECT_EQ(s.objects[2].name, "object2");  // generated name
    EXPECT_EQ(s.objects[2].material, "bumps");
    ASSERT_NE(s.find_material("sign"), nullptr);
    EXPECT_EQ(s.find_material("sign"), &s.materials[1]);
    EXPECT_EQ(s.find_material("nope"), nullptr);
}

TEST(SceneParse, CommentsAndIntegralFloatsAreAccepted) {
    const SceneDesc s = parse_ok(R"({
      // hand-written files may carry notes
      "materials": [{"name": "m", "options": {"max_samples": 32.0}}], /* 32.0 reads as 32 */
      "objects": [{"material": "m"}]
    })");
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].technique.max_samples, 32);
}

// --- Defaults -------------------------------------------------------------------------

TEST(SceneParse, DefaultsForAMinimalScene) {
    const SceneDesc s = parse_ok(R"({"objects": [{}]})");
    const CameraDesc defaults;
    expect_vec(s.camera.position, defaults.position.x, defaults.position.y, defaults.position.z);
    EXPECT_FLOAT_EQ(s.camera.fov_y_deg, 50.0f);
    EXPECT_FLOAT_EQ(s.camera.near_plane, 0.05f);
    EXPECT_FLOAT_EQ(s.camera.far_plane, 50.0f);
    expect_vec(s.ambient, 0.08f, 0.08f, 0.08f);

    ASSERT_EQ(s.lights.size(), 1u);  // missing lights: one directional light
    EXPECT_EQ(s.lights[0].kind, LightKind::directional);

    ASSERT_EQ(s.objects.size(), 1u);
    const ObjectDesc& o = s.objects[0];
    EXPECT_EQ(o.name, "object0");
    EXPECT_EQ(o.mesh.kind, MeshKind::plane);
    EXPECT_FLOAT_EQ(o.mesh.size, 2.0f);
    EXPECT_EQ(o.mesh.segments, 1);
    expect_vec(o.transform.scale, 1, 1, 1);
    EXPECT_EQ(o.material, "default");

    // The object's implicit material is supplied with the documented defaults.
    ASSERT_EQ(s.materials.size(), 1u);
    const MaterialDesc& m = s.materials[0];
    EXPECT_EQ(m.name, "default");
    EXPECT_EQ(m.albedo.kind, TextureSource::Kind::color);
    expect_vec(m.albedo.color, 0.8f, 0.8f, 0.8f);
    EXPECT_EQ(m.height.kind, TextureSource::Kind::procedural);
    EXPECT_EQ(m.height.field.kind, FieldKind::flat);
    EXPECT_FLOAT_EQ(m.height.field.level, 1.0f);
    EXPECT_EQ(m.normal.kind, TextureSource::Kind::none);  // derived from the height map
    EXPECT_EQ(m.technique.technique, Technique::pom);
    EXPECT_EQ(m.technique.shadow, ShadowMode::none);
    EXPECT_FLOAT_EQ(m.height_scale, 0.05f);
    EXPECT_FLOAT_EQ(m.bias(), -0.05f);
    EXPECT_TRUE(m.pack_height_in_normal_alpha);
    EXPECT_FLOAT_EQ(m.uv.scale.x, 1.0f);
}

TEST(SceneParse, MaterialDefaultsWhenOnlyNamed) {
    const SceneDesc s = parse_ok(material_doc(R"("height_scale": 0.1)"));
    ASSERT_EQ(s.materials.size(), 1u);
    const MaterialDesc& m = s.materials[0];
    EXPECT_EQ(m.albedo.kind, TextureSource::Kind::color);
    expect_vec(m.albedo.color, 0.8f, 0.8f, 0.8f);
    EXPECT_EQ(m.height.kind, TextureSource::Kind::procedural);
    EXPECT_EQ(m.height.field.kind, FieldKind::flat);
    EXPECT_EQ(m.normal.kind, TextureSource::Kind::none);
    EXPECT_FLOAT_EQ(m.bias(), -0.1f);  // follows the scale when not given
}

TEST(SceneParse, UnnamedMaterialIsTheDefaultOne) {
    const SceneDesc s = parse_ok(R"({"materials": [{"height_scale": 0.02}], "objects": [{}]})");
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].name, "default");
    EXPECT_FLOAT_EQ(s.materials[0].height_scale, 0.02f);
}

TEST(SceneParse, ExplicitEmptyLightsMeansNone) {
    EXPECT_TRUE(parse_ok(doc(R"("lights": [])")).lights.empty());
}

// --- Malformed JSON -------------------------------------------------------------------

TEST(SceneErrors, MalformedJsonGivesLineAndColumn) {
    // The second comma on line 3 is at column 19.
    const std::string message = parse_error("{\n  \"name\": \"x\",\n  \"objects\": [{}],,\n}");
    EXPECT_EQ(message.rfind("test.json:3:19: malformed JSON: ", 0), 0u) << message;
    EXPECT_TRUE(contains(message, "unexpected ','"));
}

TEST(SceneErrors, MalformedJsonColumnCountsCharactersNotBytes) {
    // "é" is two bytes: the stray comma is character 14, byte 15.
    const std::string message = parse_error("{\"name\": \"\xc3\xa9\",,}");
    EXPECT_EQ(message.rfind("test.json:1:14: malformed JSON", 0), 0u) << message;
}

TEST(SceneErrors, MalformedJsonAtEndOfInput) {
    const std::string message = parse_error(R"({"objects": [{}])");  // 16 characters, no closing brace
    EXPECT_EQ(message.rfind("test.json:1:17: malformed JSON: ", 0), 0u) << message;
    EXPECT_TRUE(contains(message, "end of input"));
}

TEST(SceneErrors, NumberOverflowIsLocated) {
    const std::string message = parse_error(R"({"camera": {"fov_y_deg": 1e999}, "objects": [{}]})");
    EXPECT_EQ(message.rfind("test.json:1:26: malformed JSON", 0), 0u) << message;
    EXPECT_TRUE(contains(message, "1e999"));
}

TEST(SceneErrors, DuplicateKeysAreErrors) {
    const std::string message =
        parse_error(material_doc(R"("height_scale": 0.1, "height_scale": 0.2)"));
    EXPECT_TRUE(contains(message, "duplicate field 'height_scale' in materials[0]"));
    EXPECT_TRUE(contains(parse_error(R"({"name": "a", "name": "b", "objects": [{}]})"),
                         "duplicate field 'name' at the top level"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"size": 1, "size": 2})")),
                         "duplicate field 'size' in objects[0].mesh"));
}

TEST(SceneErrors, TopLevelMustBeAnObject) {
    EXPECT_TRUE(contains(parse_error("[1, 2]"), "a scene must be a JSON object, got array of 2"));
}

// --- Types and shapes -----------------------------------------------------------------

TEST(SceneErrors, WrongTypesNameThePath) {
    const std::string two_materials =
        R"({"materials": [{"name": "a"}, {"name": "b", "options": {"max_samples": "64"}}],
            "objects": [{"material": "a"}]})";
    EXPECT_TRUE(contains(parse_error(two_materials),
                         "test.json: materials[1].options.max_samples: expected an integer, got string"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("options": {"min_samples": 2.5})")),
                         "materials[0].options.min_samples: expected an integer, got number 2.5"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("options": {"depth_write": 1})")),
                         "materials[0].options.depth_write: expected true or false, got integer 1"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("height_scale": "deep")")),
                         "materials[0].height_scale: expected a number, got string"));
    EXPECT_TRUE(contains(parse_error(doc(R"("camera": [0, 0, 1])")), "camera: expected an object, got array"));
    EXPECT_TRUE(contains(parse_error(doc(R"("lights": {"type": "point"})")), "lights: expected an array, got object"));
    EXPECT_TRUE(contains(parse_error(doc(R"("name": 7)")), "name: expected a string, got integer 7"));
    EXPECT_TRUE(contains(parse_error(R"({"objects": [{"material": null}]})"),
                         "objects[0].material: expected a string, got null"));
}

TEST(SceneErrors, WrongArrayLengthsAndElements) {
    EXPECT_TRUE(contains(parse_error(doc(R"("camera": {"position": [1, 2]})")),
                         "camera.position: expected an array of 3 numbers, got array of 2"));
    EXPECT_TRUE(contains(parse_error(doc(R"("camera": {"up": [0, 0, "1"]})")),
                         "camera.up[2]: expected a number, got string"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("uv": {"offset": [1, 2, 3]})")),
                         "materials[0].uv.offset: expected an array of 2 numbers, got array of 3"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("uv": {"scale": "big"})")),
                         "materials[0].uv.scale: expected a number or an array of 2 numbers"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("transform": {"scale": [1, 2]})")),
                         "objects[0].transform.scale: expected an array of 3 numbers"));
}

TEST(SceneErrors, NonFiniteNumbers) {
    // 1e39 is a finite double but overflows a float.
    EXPECT_TRUE(contains(parse_error(doc(R"("camera": {"far": 1e39})")),
                         "camera.far: expected a finite number"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("transform": {"translate": [0, -1e300, 0]})")),
                         "objects[0].transform.translate[1]: expected a finite number"));
}

TEST(SceneErrors, TextureSourceForms) {
    EXPECT_TRUE(contains(parse_error(material_doc(R"("albedo": 5)")),
                         "materials[0].albedo: expected a file path, or an object"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("albedo": {"file": "a.png", "color": [1, 1, 1]})")),
                         "materials[0].albedo: give one of"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("height": {"fiel": "h.png"})")),
                         "unknown field 'fiel' in materials[0].height (did you mean 'file'?)"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("height": {"size": 64})")),
                         "materials[0].height: needs one of \"file\", \"procedural\" or \"color\""));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("albedo": {"file": "a.png", "convention": "depth"})")),
                         "materials[0].albedo.convention: only a height map has a convention"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("height": {"file": "h.png", "convention": "up"})")),
                         "materials[0].height.convention: unknown height convention 'up'"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("albedo": {"color": [1, 0.5]})")),
                         "materials[0].albedo.color: expected an array of 3 numbers"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("height": {"procedural": "bricks", "text": 3})")),
                         "materials[0].height.text: expected a string"));
    // Asset packs' conventions: each key in the slot it belongs to, each value named.
    EXPECT_TRUE(contains(parse_error(material_doc(R"("height": {"file": "n.tga", "channel": "alpha"})")),
                         "materials[0].height.channel: \"alpha\" is not a channel"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("normal": {"file": "n.tga", "channel": "a"})")),
                         "materials[0].normal.channel: only a height map names a channel"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("height": {"file": "h.png", "green": "down"})")),
                         "materials[0].height.green: only a normal map has a green convention"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("normal": {"file": "n.png", "green": "-y"})")),
                         "materials[0].normal.green: \"-y\" is not \"up\""));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("normal": {"file": "n.png", "color_space": "linear"})")),
                         "materials[0].normal.color_space: only a colour texture (albedo) has a colour space"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("albedo": {"file": "a.png", "color_space": "gamma"})")),
                         "materials[0].albedo.color_space: \"gamma\" is not \"srgb\" or \"linear\""));
}

TEST(Scene, AssetPackConventionsAreRead) {
    const SceneDesc scene = parse_ok(material_doc(
        R"("albedo": {"file": "a.png", "color_space": "linear"},
           "height": {"file": "rock_norm.tga", "channel": "a", "convention": "depth"},
           "normal": {"file": "rock_norm.tga", "green": "down"})"));
    ASSERT_EQ(scene.materials.size(), 1u);
    const MaterialDesc& m = scene.materials[0];
    EXPECT_EQ(m.height.channel, TextureSource::Channel::a);
    EXPECT_EQ(m.height.convention, HeightConvention::depth);
    EXPECT_EQ(m.normal.green, TextureSource::Green::down);
    EXPECT_EQ(m.albedo.color_space, TextureSource::ColorSpace::linear);
    EXPECT_EQ(m.normal.channel, TextureSource::Channel::grey);
}

// --- Unknown fields and names -----------------------------------------------------------

TEST(SceneErrors, UnknownFieldsSuggestTheClosestKey) {
    EXPECT_TRUE(contains(parse_error(material_doc(R"("hieght_scale": 0.1)")),
                         "test.json: unknown field 'hieght_scale' in materials[0] (did you mean 'height_scale'?)"));
    EXPECT_TRUE(contains(parse_error(R"({"nmae": "x", "objects": [{}]})"),
                         "unknown field 'nmae' at the top level (did you mean 'name'?)"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("options": {"max_sample": 8})")),
                         "unknown field 'max_sample' in materials[0].options (did you mean 'max_samples'?)"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("transform": {"translat": [0, 0, 0]})")),
                         "in objects[0].transform (did you mean 'translate'?)"));
    EXPECT_TRUE(contains(parse_error(doc(R"("lights": [{}, {"colour": [1, 1, 1]}])")),
                         "unknown field 'colour' in lights[1] (did you mean 'color'?)"));
}

TEST(SceneErrors, NoSuggestionWhenNothingIsClose) {
    const std::string message = parse_error(doc(R"("camera": {"zoom": 2})"));
    EXPECT_TRUE(contains(message, "unknown field 'zoom' in camera"));
    EXPECT_FALSE(contains(message, "did you mean"));
}

TEST(SceneErrors, UnknownNamesListTheKnownOnes) {
    const std::string technique = parse_error(material_doc(R"("technique": "pomm")"));
    EXPECT_TRUE(contains(technique, "materials[0].technique: unknown technique 'pomm'"));
    EXPECT_TRUE(contains(technique, "relief"));  // the list of known techniques
    EXPECT_TRUE(contains(parse_error(material_doc(R"("options": {"shadow": "sof"})")),
                         "materials[0].options.shadow: unknown shadow mode 'sof' (known: none, hard, soft)"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"type": "cylindre"})")),
                         "objects[0].mesh.type: unknown mesh kind 'cylindre'"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"type": "cone"})")),
                         "(known: plane, cube, sphere, torus, cylinder)"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"type": "cube", "displaced": true})")),
                         "objects[0].mesh.displaced: a cube cannot be displaced"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"displaced": true, "vertices_per_texel": 0})")),
                         "objects[0].mesh.vertices_per_texel: must be within 1..8, got 0"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"displaced": true, "vertices_per_texel": 9})")),
                         "objects[0].mesh.vertices_per_texel: must be within 1..8, got 9"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"vertices_per_texel": 2})")),
                         "objects[0].mesh.vertices_per_texel: only a displaced mesh"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"displaced": true, "vertices_per_texel": 2.5})")),
                         "objects[0].mesh.vertices_per_texel"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("height": {"procedural": "brick"})")),
                         "materials[0].height.procedural: unknown field kind 'brick'"));
    EXPECT_TRUE(contains(parse_error(doc(R"("lights": [{"type": "spot"}])")),
                         "lights[0].type: unknown light type 'spot' (known: directional, point)"));
}

// --- Values out of range ----------------------------------------------------------------

TEST(SceneErrors, CameraRanges) {
    EXPECT_TRUE(contains(parse_error(doc(R"("camera": {"fov_y_deg": 0})")), "test.json: camera.fov_y_deg: must be within [1, 170]"));
    EXPECT_TRUE(contains(parse_error(doc(R"("camera": {"fov_y_deg": 180})")), "camera.fov_y_deg"));
    EXPECT_TRUE(contains(parse_error(doc(R"("camera": {"near": 0})")), "camera.near: must be within [0.0001, 100000]"));
    EXPECT_TRUE(contains(parse_error(doc(R"("camera": {"near": 1, "far": 1})")),
                         "camera.far: must be greater than near (1), at most 10^6 times near and at most 200000, got 1"));
    EXPECT_TRUE(contains(parse_error(doc(R"("camera": {"position": [0, 0, 5], "target": [0, 0, 0]})")),
                         "camera.up: must be non-zero and not parallel"));
    EXPECT_TRUE(contains(parse_error(doc(R"("camera": {"position": [1, 1, 1], "target": [1, 1, 1]})")),
                         "camera.target: must differ"));
}

TEST(SceneErrors, MaterialRanges) {
    EXPECT_TRUE(contains(parse_error(material_doc(R"("height_scale": -0.01)")),
                         "materials[0].height_scale: must be within [0, 4] tiles, got -0.01"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("uv": {"scale": [1, 0]})")),
                         "materials[0].uv.scale: components must be non-zero with magnitudes within [1/16384, 16384]"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("uv": {"scale": 0})")), "materials[0].uv.scale"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("albedo": {"color": [1.5, 0, 0]})")),
                         "materials[0].albedo.color: components must be within [0, 1]"));
    // A procedural albedo's colour ramp, in range, and on an albedo only.
    {
        const SceneDesc s = parse_ok(material_doc(
            R"("albedo": {"procedural": "bricks", "low": [0.5, 0.5, 0.45], "high": [0.6, 0.3, 0.2], "grain": 0.2})"));
        ASSERT_EQ(s.materials.size(), 1u);
        EXPECT_EQ(s.materials[0].albedo.low, glm::vec3(0.5f, 0.5f, 0.45f));
        EXPECT_EQ(s.materials[0].albedo.high, glm::vec3(0.6f, 0.3f, 0.2f));
        EXPECT_FLOAT_EQ(s.materials[0].albedo.grain, 0.2f);
    }
    EXPECT_TRUE(contains(parse_error(material_doc(R"("albedo": {"procedural": "bricks", "high": [1.2, 0, 0]})")),
                         "materials[0].albedo.high: components must be within [0, 1]"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("albedo": {"procedural": "bricks", "grain": -0.1})")),
                         "materials[0].albedo.grain: must be within [0, 1]"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("height": {"procedural": "bricks", "low": [0.5, 0.5, 0.5]})")),
                         "materials[0].height: low, high and grain colour a procedural albedo"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("albedo": {"color": [0.5, 0.5, 0.5], "grain": 0.1})")),
                         "materials[0].albedo"));
    // Non-power-of-two sizes are fine (resampled where a context needs it).
    EXPECT_TRUE(parse_scene(material_doc(R"("height": {"procedural": "bricks", "size": 300})"), kOrigin).ok());
    EXPECT_TRUE(contains(parse_error(material_doc(R"("height": {"procedural": "bricks", "size": 0})")),
                         "materials[0].height: field 'bricks': size must be in 1..4096, got 0"));
    // The generator's own rules (even brick rows) are reported at the source's path.
    EXPECT_TRUE(contains(parse_error(material_doc(R"("height": {"procedural": "bricks", "count": 3})")),
                         "materials[0].height: "));
    const std::string glyph = parse_error(material_doc(R"("height": {"procedural": "text", "text": "hi"})"));
    EXPECT_TRUE(contains(glyph, "materials[0].height: "));
    EXPECT_TRUE(contains(glyph, "'h'"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("albedo": "")")), "materials[0].albedo: the file path is empty"));
}

TEST(SceneErrors, TechniqueOptionsGoThroughValidateOptions) {
    const std::string message = parse_error(material_doc(R"("options": {"min_samples": 16, "max_samples": 8})"));
    EXPECT_TRUE(contains(message, "test.json: materials[0].options: max_samples (8) must not be below min_samples (16)"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("options": {"max_samples": 1000})")),
                         "materials[0].options: max_samples 1000 exceeds the limit"));
    EXPECT_TRUE(contains(parse_error(material_doc(R"("options": {"shadow_samples": 0})")),
                         "materials[0].options: shadow_samples"));
}

TEST(SceneErrors, LightRanges) {
    EXPECT_TRUE(contains(parse_error(doc(R"("lights": [{"direction": [0, 0, 0]}])")),
                         "lights[0].direction: must be a non-zero vector (length at least 1e-6"));
    EXPECT_TRUE(contains(parse_error(doc(R"("lights": [{}, {"intensity": -1}])")), "lights[1].intensity"));
    EXPECT_TRUE(contains(parse_error(doc(R"("lights": [{"angular_radius_deg": 90}])")),
                         "lights[0].angular_radius_deg"));
    EXPECT_TRUE(contains(parse_error(doc(R"("lights": [{"color": [1, -1, 1]}])")), "lights[0].color"));
}

TEST(SceneErrors, ObjectRanges) {
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"size": 0})")),
                         "objects[0].mesh.size: must be within [0.0001, 10000], got 0"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"segments": 0})")), "objects[0].mesh.segments"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"type": "sphere", "radius": -1})")),
                         "objects[0].mesh.radius"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"type": "torus", "radius": 1, "tube_radius": 1})")),
                         "objects[0].mesh.tube_radius: must be less than radius"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("transform": {"scale": [1, 0, 1]})")),
                         "objects[0].transform.scale: components must be non-zero with magnitudes within [0.0001, 10000]"));
}

TEST(SceneErrors, DuplicateMaterialNames) {
    const std::string message = parse_error(
        R"({"materials": [{"name": "bricks"}, {"name": "bricks"}], "objects": [{"material": "bricks"}]})");
    EXPECT_TRUE(contains(message, "test.json: materials[1].name: duplicate material name 'bricks' (also materials[0])"));
}

TEST(SceneErrors, AtLeastOneObject) {
    EXPECT_TRUE(contains(parse_error(R"({"objects": []})"), "test.json: objects: a scene needs at least one object"));
    EXPECT_TRUE(contains(parse_error(R"({"name": "empty"})"), "objects: a scene needs at least one object"));
}

TEST(SceneErrors, UnknownMaterialReferenceListsTheMaterials) {
    const std::string message = parse_error(
        R"({"materials": [{"name": "bricks"}, {"name": "stone"}], "objects": [{"material": "brick"}]})");
    EXPECT_TRUE(contains(message, "test.json: objects[0].material: no material named 'brick' (materials: bricks, stone)"));
}

TEST(SceneErrors, FirstErrorWins) {
    // Two problems: the earlier one in reading order is reported.
    const std::string message = parse_error(doc(R"("camera": {"fov_y_deg": "wide"}, "ambient": "dark")"));
    EXPECT_TRUE(contains(message, "camera.fov_y_deg"));
    EXPECT_FALSE(contains(message, "ambient"));
}

// --- validate_scene on scenes built in code ----------------------------------------------

TEST(SceneValidate, HandBuiltScene) {
    SceneDesc s;
    ObjectDesc o;
    o.material = "x";
    s.objects.push_back(o);
    Status st = validate_scene(s);
    ASSERT_FALSE(st.ok());
    EXPECT_TRUE(contains(st.error().message, "objects[0].material: no material named 'x' (the scene defines none)"));

    MaterialDesc m;
    m.name = "x";
    s.materials.push_back(m);
    EXPECT_TRUE(validate_scene(s).ok()) << validate_scene(s).error().message;

    s.materials[0].height_scale = std::nanf("");
    st = validate_scene(s);
    ASSERT_FALSE(st.ok());
    EXPECT_TRUE(contains(st.error().message, "materials[0].height_scale"));
}

// --- Built-in scenes ----------------------------------------------------------------------

TEST(BuiltinScenes, AllLoadValidateAndBuildTheirFields) {
    const std::vector<std::string> names = builtin_scene_names();
    for (const char* required : {"default", "bricks", "pit", "shapes"})
        EXPECT_NE(std::find(names.begin(), names.end(), required), names.end()) << required;
    for (const std::string& name : names) {
        SCOPED_TRACE(name);
        Result<SceneDesc> s = builtin_scene(name);
        ASSERT_TRUE(s.ok()) << s.error().message;
        EXPECT_EQ(s->name, name);
        Status st = validate_scene(*s);
        EXPECT_TRUE(st.ok()) << st.error().message;
        EXPECT_FALSE(s->objects.empty());
        for (const MaterialDesc& m : s->materials)
            if (m.height.kind == TextureSource::Kind::procedural) {
                Result<HeightField> f = make_height_field(m.height.field);
                EXPECT_TRUE(f.ok()) << m.name << ": " << f.error().message;
            }
        Result<SceneDesc> by_name = load_scene(name);
        ASSERT_TRUE(by_name.ok()) << by_name.error().message;
        EXPECT_EQ(by_name->objects.size(), s->objects.size());
    }
}

TEST(BuiltinScenes, UnknownNameListsTheBuiltins) {
    Result<SceneDesc> s = builtin_scene("nope");
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.error().message, "'nope'"));
    EXPECT_TRUE(contains(s.error().message, "default, lettering, bricks, pit, shapes"));
}

// The first default scene, kept as `lettering` (the texture bench's).
TEST(BuiltinScenes, LetteringShowsParallaxAtALowAngle) {
    Result<SceneDesc> s = builtin_scene("lettering");
    ASSERT_TRUE(s.ok());
    const float cam = camera_elevation_deg(s->camera);
    // Low enough that parallax shows, high enough that the lettering reads.
    EXPECT_GE(cam, 30.0f);
    EXPECT_LE(cam, 50.0f);
    ASSERT_EQ(s->lights.size(), 1u);
    EXPECT_EQ(s->lights[0].kind, LightKind::directional);
    // A low, raking light: joints and glyphs cast shadows.
    EXPECT_LE(light_elevation_deg(s->lights[0]), 30.0f);
    EXPECT_GE(light_elevation_deg(s->lights[0]), 10.0f);
    // Partly from the side, so shadows fall across the view, not only along it.
    EXPECT_GT(std::abs(s->lights[0].direction.x), 0.3f);

    bool bricks = false, text = false;
    for (const ObjectDesc& o : s->objects) {
        const MaterialDesc* m = s->find_material(o.material);
        ASSERT_NE(m, nullptr);
        EXPECT_EQ(m->technique.technique, Technique::pom);
        EXPECT_EQ(m->technique.shadow, ShadowMode::soft);
        EXPECT_EQ(m->technique.max_samples, 32);
        EXPECT_TRUE(m->technique.depth_write);
        EXPECT_EQ(m->albedo.kind, TextureSource::Kind::color);
        if (m->height.field.kind == FieldKind::bricks) {
            bricks = true;
            EXPECT_GT(m->uv.scale.x, 1.0f);  // tiled: many bricks
            EXPECT_GT(m->albedo.color.r, m->albedo.color.b);  // red-brown
        }
        if (m->height.field.kind == FieldKind::bricks) EXPECT_NEAR(m->height_scale, 0.06f, 0.01f);
        if (m->height.field.kind == FieldKind::text) {
            text = true;
            EXPECT_EQ(m->height.field.text, "PARALLAX");
            // Readable: at the camera's view angle a glyph's top moves less
            // than a stroke's width (8 glyphs of 6 font columns), so no glyph
            // hides its neighbour (the earlier default's moved a whole glyph).
            const double depth_texels = m->height_scale * m->height.field.size;
            const double shift = depth_texels * std::tan(glm::radians(90.0 - cam));
            EXPECT_LT(shift, m->height.field.size / 48.0);
            EXPECT_GT(shift, 0.5 * m->height.field.size / 48.0);  // and the relief still shows
        }
    }
    EXPECT_TRUE(bricks);
    EXPECT_TRUE(text);
}

// The default scene is a material study (issue 25): colour from the same
// relief as the height, shadows that keep colour (a sky ambient, not near
// black), specular, a bounded relief whose outline is drawn, soft shadows.
TEST(BuiltinScenes, DefaultIsAMaterialStudy) {
    Result<SceneDesc> s = builtin_scene("default");
    ASSERT_TRUE(s.ok());
    const float cam = camera_elevation_deg(s->camera);
    EXPECT_GE(cam, 25.0f);
    EXPECT_LE(cam, 50.0f);
    EXPECT_GE(s->ambient.r + s->ambient.g + s->ambient.b, 0.9f);  // a sky, not 0.1
    EXPECT_GT(s->ambient.b, s->ambient.r);                        // cool against a warm sun
    ASSERT_EQ(s->lights.size(), 1u);
    EXPECT_GT(s->lights[0].angular_radius_deg, 1.0f);  // a penumbra
    bool bounded = false;
    for (const MaterialDesc& m : s->materials) {
        SCOPED_TRACE(m.name);
        EXPECT_EQ(m.technique.shadow, ShadowMode::soft);
        EXPECT_GT(m.specular, 0.0f);
        // Albedo from the very field that is the relief, through a ramp.
        ASSERT_EQ(m.albedo.kind, TextureSource::Kind::procedural);
        EXPECT_EQ(m.albedo.field.kind, m.height.field.kind);
        EXPECT_EQ(m.albedo.field.size, m.height.field.size);
        EXPECT_EQ(m.albedo.field.text, m.height.field.text);
        EXPECT_NE(m.albedo.low, m.albedo.high);
        bounded = bounded || m.bounded;
    }
    EXPECT_TRUE(bounded);
}

TEST(BuiltinScenes, BricksAtFortyFiveDegreesWithoutShadows) {
    Result<SceneDesc> s = builtin_scene("bricks");
    ASSERT_TRUE(s.ok());
    EXPECT_NEAR(camera_elevation_deg(s->camera), 45.0f, 2.0f);
    ASSERT_EQ(s->objects.size(), 1u);
    const MaterialDesc* m = s->find_material(s->objects[0].material);
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(m->height.field.kind, FieldKind::bricks);
    EXPECT_EQ(m->technique.technique, Technique::pom);
    EXPECT_EQ(m->technique.shadow, ShadowMode::none);
}

// Marches from a point on the pit floor towards the light through the height
// field, in tile units (the plane maps uv 0..1 onto its full width, +u = +x).
bool pit_floor_shadowed(const SceneDesc& s, const MaterialDesc& m, const HeightField& f, double u0, double v0) {
    const glm::vec3 to_light = -glm::normalize(s.lights[0].direction);
    const double du = to_light.x / to_light.z / m.uv.scale.x, dv = to_light.y / to_light.z / m.uv.scale.y;
    const int steps = 400;
    for (int i = 1; i <= steps; ++i) {
        const double rise = m.height_scale * static_cast<double>(i) / steps;  // above the floor, in tile units
        const double surface = f.sample_bilinear(u0 + du * rise, v0 + dv * rise) * m.height_scale;
        if (surface > rise + 1e-4) return true;
    }
    return false;
}

TEST(BuiltinScenes, PitFloorNextToTheLitWallIsInShadow) {
    Result<SceneDesc> s = builtin_scene("pit");
    ASSERT_TRUE(s.ok());
    // Straight above.
    EXPECT_NEAR(camera_elevation_deg(s->camera), 90.0f, 0.5f);
    ASSERT_EQ(s->lights.size(), 1u);
    EXPECT_NEAR(light_elevation_deg(s->lights[0]), 25.0f, 2.0f);
    ASSERT_EQ(s->objects.size(), 1u);
    EXPECT_EQ(s->objects[0].mesh.kind, MeshKind::plane);
    const MaterialDesc* m = s->find_material(s->objects[0].material);
    ASSERT_NE(m, nullptr);
    ASSERT_EQ(m->height.field.kind, FieldKind::pit);
    EXPECT_EQ(m->technique.technique, Technique::pom);
    EXPECT_EQ(m->technique.shadow, ShadowMode::hard);

    Result<HeightField> f = make_height_field(m->height.field);
    ASSERT_TRUE(f.ok()) << f.error().message;
    const double r = m->height.field.radius;
    // The wall the light comes over is on the side opposite its travel.
    const double dir = s->lights[0].direction.x > 0 ? 1.0 : -1.0;
    const double near_wall = 0.5 - dir * (r - 0.03), far_wall = 0.5 + dir * (r - 0.03);
    EXPECT_TRUE(pit_floor_shadowed(*s, *m, *f, near_wall, 0.5));
    EXPECT_FALSE(pit_floor_shadowed(*s, *m, *f, far_wall, 0.5));
}

TEST(BuiltinScenes, ShapesUseCurvedMeshes) {
    Result<SceneDesc> s = builtin_scene("shapes");
    ASSERT_TRUE(s.ok());
    bool sphere = false, torus = false;
    for (const ObjectDesc& o : s->objects) {
        const MaterialDesc* m = s->find_material(o.material);
        ASSERT_NE(m, nullptr);
        const FieldKind k = m->height.field.kind;
        if (o.mesh.kind == MeshKind::sphere) sphere = k == FieldKind::hemispheres || k == FieldKind::cones;
        if (o.mesh.kind == MeshKind::torus) torus = k == FieldKind::hemispheres || k == FieldKind::cones;
    }
    EXPECT_TRUE(sphere);
    EXPECT_TRUE(torus);
}

// --- Loading files ------------------------------------------------------------------------

class SceneFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("px_unit_scene_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "textures");
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string write(const std::string& name, const std::string& text) {
        const fs::path p = dir_ / name;
        std::ofstream(p) << text;
        return p.string();
    }

    fs::path dir_;
};

TEST_F(SceneFiles, LoadsAndResolvesTexturePathsAgainstTheFileFolder) {
    fs::create_directories(dir_ / "textures");
    ASSERT_TRUE(write_png((dir_ / "textures" / "albedo.png").string(), make_solid_image(4, 4, 10, 20, 30)).ok());
    const std::string path = write("my_scene.json", R"({"materials": [{"name": "m", "albedo": "textures/albedo.png"}],
                                                      "objects": [{"material": "m"}]})");
    Result<SceneDesc> s = load_scene(path);
    ASSERT_TRUE(s.ok()) << s.error().message;
    EXPECT_EQ(fs::path(s->base_dir), fs::absolute(dir_).lexically_normal());
    EXPECT_EQ(s->name, "my_scene");  // the file's stem when the scene has no name
    EXPECT_EQ(fs::path(s->materials[0].albedo.path), (fs::absolute(dir_) / "textures" / "albedo.png").lexically_normal());
}

TEST_F(SceneFiles, MissingTextureNamesTheField) {
    const std::string path = write("s.json", R"({"materials": [{"name": "m", "height": {"file": "missing.png"}}],
                                               "objects": [{"material": "m"}]})");
    Result<SceneDesc> s = load_scene_file(path);
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.error().message, path + ": materials[0].height: no such texture file 'missing.png'"));
}

TEST_F(SceneFiles, ErrorsCarryTheFilePath) {
    const std::string path = write("bad.json", "{\n  \"objects\": [{\"mesh\": {\"type\": \"cone\"}}]\n}\n");
    Result<SceneDesc> s = load_scene(path);
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.error().message, path + ": objects[0].mesh.type: unknown mesh kind 'cone'"));

    const std::string broken = write("broken.json", "{\n  \"objects\": [{}]\n  \"name\": \"x\"\n}\n");
    Result<SceneDesc> b = load_scene(broken);
    ASSERT_FALSE(b.ok());
    EXPECT_TRUE(contains(b.error().message, broken + ":3:"));
}

TEST_F(SceneFiles, AFileWithoutTheJsonExtensionStillLoads) {
    const std::string path = write("scene.txt", R"({"objects": [{}]})");
    Result<SceneDesc> s = load_scene(path);
    EXPECT_TRUE(s.ok()) << s.error().message;
}

TEST_F(SceneFiles, UnreadablePathsGiveTheReason) {
    const std::string missing = (dir_ / "nope.json").string();
    Result<SceneDesc> s = load_scene(missing);
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.error().message, missing));
    EXPECT_TRUE(contains(s.error().message, "No such file or directory"));

    Result<SceneDesc> d = load_scene_file(dir_.string());
    ASSERT_FALSE(d.ok());
    EXPECT_TRUE(contains(d.error().message, "it is a folder"));
}

TEST(SceneLoad, UnknownNameListsTheBuiltinScenes) {
    Result<SceneDesc> s = load_scene("no_such_scene");
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.error().message, "unknown scene 'no_such_scene'"));
    EXPECT_TRUE(contains(s.error().message, "default, lettering, bricks, pit, shapes"));
}

#ifdef PX_SOURCE_DIR
// The complete example in docs/scene-format.md must stay a valid scene.
TEST(SceneDocs, ExampleParses) {
    std::ifstream in(std::string(PX_SOURCE_DIR) + "/docs/scene-format.md");
    ASSERT_TRUE(in) << "docs/scene-format.md not found";
    std::stringstream text;
    text << in.rdbuf();
    const std::string md = text.str();
    const std::size_t start = md.find("```json\n");
    ASSERT_NE(start, std::string::npos);
    const std::size_t end = md.find("```", start + 8);
    ASSERT_NE(end, std::string::npos);
    const SceneDesc s = parse_ok(md.substr(start + 8, end - start - 8));
    EXPECT_FALSE(s.objects.empty());
}
#endif

// --- Transform ------------------------------------------------------------------------------

glm::vec3 apply(const glm::mat4& m, glm::vec3 p, float w = 1.0f) { return glm::vec3(m * glm::vec4(p, w)); }

TEST(TransformDesc, TranslateRotateScale) {
    TransformDesc t;
    t.translate = {1.0f, 2.0f, 3.0f};
    t.rotate_deg = {0.0f, 0.0f, 90.0f};
    t.scale = {2.0f, 1.0f, 1.0f};
    // Scaled first (x by 2), then turned 90 degrees about z, then moved.
    expect_vec(apply(t.matrix(), {1, 0, 0}), 1, 4, 3, 1e-5f);
    expect_vec(apply(t.matrix(), {0, 1, 0}), 0, 2, 3, 1e-5f);
    EXPECT_EQ(TransformDesc{}.matrix(), glm::mat4(1.0f));
}

TEST(TransformDesc, RotatesAboutXThenYThenZ) {
    TransformDesc t;
    t.rotate_deg = {90.0f, 90.0f, 0.0f};
    // Rx(90) takes +y to +z, then Ry(90) takes +z to +x. (Ry first would leave +z.)
    expect_vec(apply(t.matrix(), {0, 1, 0}, 0.0f), 1, 0, 0, 1e-5f);
    t.rotate_deg = {0.0f, 90.0f, 90.0f};
    // Ry(90): +z -> +x; Rz(90): +x -> +y.
    expect_vec(apply(t.matrix(), {0, 0, 1}, 0.0f), 0, 1, 0, 1e-5f);
}

}  // namespace
}  // namespace px

namespace px {
namespace {

// The lighting constants are material fields that the renderer and the
// reference both read (docs/scene-format.md).
TEST(SceneParse, LightingConstantsAreMaterialFields) {
    Result<SceneDesc> s = parse_scene(
        R"({"materials": [{"name": "m", "specular": 0.5, "shininess": 8}], "objects": [{"material": "m"}]})", "t.json");
    ASSERT_TRUE(s.ok()) << s.error().message;
    EXPECT_FLOAT_EQ(s->materials[0].specular, 0.5f);
    EXPECT_FLOAT_EQ(s->materials[0].shininess, 8.0f);
    const MaterialDesc defaults;
    EXPECT_FLOAT_EQ(defaults.specular, 0.25f);
    EXPECT_FLOAT_EQ(defaults.shininess, 32.0f);
    Result<SceneDesc> typo = parse_scene(
        R"({"materials": [{"name": "m", "shinines": 8}], "objects": [{"material": "m"}]})", "t.json");
    ASSERT_FALSE(typo.ok());
    EXPECT_NE(typo.error().message.find("did you mean 'shininess'"), std::string::npos) << typo.error().message;
    Result<SceneDesc> range = parse_scene(
        R"({"materials": [{"name": "m", "shininess": 0}], "objects": [{"material": "m"}]})", "t.json");
    ASSERT_FALSE(range.ok());
    EXPECT_NE(range.error().message.find("materials[0].shininess: must be within [1, 1024]"), std::string::npos)
        << range.error().message;
}

// "bounded": a tile or a decal, whose silhouette the traced techniques draw.
TEST(SceneParse, BoundedIsABooleanMaterialField) {
    Result<SceneDesc> s = parse_scene(
        R"({"materials": [{"name": "m", "bounded": true}, {"name": "n"}], "objects": [{"material": "m"}]})", "t.json");
    ASSERT_TRUE(s.ok()) << s.error().message;
    EXPECT_TRUE(s->materials[0].bounded);
    EXPECT_FALSE(s->materials[1].bounded);
    Result<SceneDesc> text = parse_scene(
        R"({"materials": [{"name": "m", "bounded": "yes"}], "objects": [{"material": "m"}]})", "t.json");
    ASSERT_FALSE(text.ok());
    EXPECT_NE(text.error().message.find("materials[0].bounded"), std::string::npos) << text.error().message;
    Result<SceneDesc> typo = parse_scene(
        R"({"materials": [{"name": "m", "bonded": true}], "objects": [{"material": "m"}]})", "t.json");
    ASSERT_FALSE(typo.ok());
    EXPECT_NE(typo.error().message.find("did you mean 'bounded'"), std::string::npos) << typo.error().message;
    // A sphere's uv edges are seams, not bounds: refused, naming the object.
    Result<SceneDesc> sphere = parse_scene(
        R"({"materials": [{"name": "m", "bounded": true}], "objects": [{"material": "m", "mesh": {"type": "sphere"}}]})",
        "t.json");
    ASSERT_FALSE(sphere.ok());
    EXPECT_NE(sphere.error().message.find("objects[0].material"), std::string::npos) << sphere.error().message;
    EXPECT_NE(sphere.error().message.find("seams"), std::string::npos) << sphere.error().message;
    // An open cylinder's ends are bounds along v (u wraps around it): accepted.
    Result<SceneDesc> tube = parse_scene(
        R"({"materials": [{"name": "m", "bounded": true}], "objects": [{"material": "m", "mesh": {"type": "cylinder"}}]})",
        "t.json");
    EXPECT_TRUE(tube.ok()) << tube.error().message;
}

// "silhouette": a curved mesh's own outline, drawn by the linear searches.
TEST(SceneParse, SilhouetteIsABooleanMaterialFieldForTheSearches) {
    Result<SceneDesc> s = parse_scene(
        R"({"materials": [{"name": "m", "silhouette": true, "technique": "pom"}], "objects": [{"material": "m", "mesh": {"type": "torus"}}]})",
        "t.json");
    ASSERT_TRUE(s.ok()) << s.error().message;
    EXPECT_TRUE(s->materials[0].silhouette);
    Result<SceneDesc> text = parse_scene(
        R"({"materials": [{"name": "m", "silhouette": 1}], "objects": [{"material": "m"}]})", "t.json");
    ASSERT_FALSE(text.ok());
    EXPECT_NE(text.error().message.find("materials[0].silhouette"), std::string::npos) << text.error().message;
    // The exact walk has no curved march: refused, naming the field.
    Result<SceneDesc> walk = parse_scene(
        R"({"materials": [{"name": "m", "silhouette": true, "technique": "maxmip"}], "objects": [{"material": "m", "mesh": {"type": "sphere"}}]})",
        "t.json");
    ASSERT_FALSE(walk.ok());
    EXPECT_NE(walk.error().message.find("materials[0].silhouette"), std::string::npos) << walk.error().message;
    EXPECT_NE(walk.error().message.find("maxmip"), std::string::npos) << walk.error().message;
}

// A texture source in no known form still gets a did-you-mean from the keys
// that any of its forms reads.
TEST(SceneErrors, SourceInNoFormSuggestsAKeyOfAnyForm) {
    Result<SceneDesc> s = parse_scene(
        R"({"materials": [{"name": "m", "height": {"procedurl": "sine"}}], "objects": [{"material": "m"}]})", "t.json");
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("did you mean 'procedural'"), std::string::npos) << s.error().message;
    Result<SceneDesc> known = parse_scene(
        R"({"materials": [{"name": "m", "height": {"size": 64}}], "objects": [{"material": "m"}]})", "t.json");
    ASSERT_FALSE(known.ok());
    EXPECT_NE(known.error().message.find("needs one of"), std::string::npos) << known.error().message;
}

}  // namespace
}  // namespace px

namespace px {
namespace {

// An authored plane frame: any direction, zero and parallel ones included,
// lands as given (surface.vert and the reference fall back); absent, the
// fields stay empty and the plane keeps +u, +z.
TEST(SceneParse, AuthoredPlaneFrameLandsAsGiven) {
    const SceneDesc s = parse_ok(object_doc(R"("mesh": {"type": "plane", "tangent": [1, 0, 0.5], "normal": [0, 0, 0]})"));
    ASSERT_EQ(s.objects.size(), 1u);
    ASSERT_TRUE(s.objects[0].mesh.tangent.has_value());
    ASSERT_TRUE(s.objects[0].mesh.normal.has_value());
    EXPECT_EQ(*s.objects[0].mesh.tangent, glm::vec3(1.0f, 0.0f, 0.5f));
    EXPECT_EQ(*s.objects[0].mesh.normal, glm::vec3(0.0f));
    const SceneDesc parallel = parse_ok(object_doc(R"("mesh": {"tangent": [0, 0, 1]})"));
    EXPECT_EQ(*parallel.objects[0].mesh.tangent, glm::vec3(0.0f, 0.0f, 1.0f));
    EXPECT_FALSE(parallel.objects[0].mesh.normal.has_value());
    const SceneDesc plain = parse_ok(object_doc(R"("mesh": {"type": "plane"})"));
    EXPECT_FALSE(plain.objects[0].mesh.tangent.has_value());
    EXPECT_FALSE(plain.objects[0].mesh.normal.has_value());
    // make_plane gives every vertex the authored vectors, w +1.
    const Mesh mesh = make_plane(2.0f, 2, glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(0.0f));
    for (const Vertex& v : mesh.vertices) {
        EXPECT_EQ(v.tangent, glm::vec4(0.0f, 0.0f, 1.0f, 1.0f));
        EXPECT_EQ(v.normal, glm::vec3(0.0f));
    }
}

TEST(SceneErrors, AuthoredPlaneFrameErrorsNameThePath) {
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"tangent": [1, 0]})")),
                         "objects[0].mesh.tangent: expected an array of 3 numbers, got array of 2"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"normal": [0, "z", 1]})")),
                         "objects[0].mesh.normal[1]: expected a number, got string"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"normal": [0, 0, 1e39]})")),
                         "objects[0].mesh.normal[2]: expected a finite number"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"tangent": [2e5, 0, 0]})")),
                         "objects[0].mesh.tangent: components must be within ±100000, got"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"type": "cube", "normal": [0, 0, 1]})")),
                         "objects[0].mesh.normal: only a plane takes an authored frame"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"displaced": true, "tangent": [1, 0, 0]})")),
                         "objects[0].mesh.tangent: a displaced plane keeps the plane's frame"));
    EXPECT_TRUE(contains(parse_error(object_doc(R"("mesh": {"tangnet": [1, 0, 0]})")), "tangent"));
}

}  // namespace
}  // namespace px

namespace px {
namespace {

// The mesh a bounded relief is drawn on (build_widened_mesh) and its length
// (drawn_length_scale) say the same: a plane wider on each side and an open
// cylinder longer at each end by bounded_margin; nothing else is widened
// (a sphere's and torus's uv edges are seams, a displaced mesh is geometry,
// an unbounded or flat material has no margin).
TEST(SceneWidenedMesh, PlanesAndCylindersOfBoundedReliefsOnly) {
    MaterialDesc m;
    m.bounded = true;
    m.height_scale = 0.05f;
    const double margin = bounded_margin(m);
    ASSERT_GT(margin, 0.0);
    const auto extent = [](const Mesh& mesh, int axis) {
        float lo = 1e30f, hi = -1e30f;
        for (const Vertex& v : mesh.vertices) {
            lo = std::min(lo, v.position[axis]);
            hi = std::max(hi, v.position[axis]);
        }
        return static_cast<double>(hi - lo);
    };
    MeshDesc plane;
    plane.kind = MeshKind::plane;
    plane.size = 2.0f;
    const std::optional<Mesh> wide_plane = build_widened_mesh(plane, m);
    ASSERT_TRUE(wide_plane.has_value());
    EXPECT_NEAR(drawn_length_scale(plane, m), 1.0 + 2.0 * margin, 1e-12);
    EXPECT_NEAR(extent(*wide_plane, 0), plane.size * drawn_length_scale(plane, m), 1e-5);
    EXPECT_NEAR(extent(*wide_plane, 1), plane.size * drawn_length_scale(plane, m), 1e-5);
    MeshDesc tube;
    tube.kind = MeshKind::cylinder;
    tube.size = 1.5f;
    tube.radius = 0.5f;
    const std::optional<Mesh> wide_tube = build_widened_mesh(tube, m);
    ASSERT_TRUE(wide_tube.has_value());
    EXPECT_NEAR(extent(*wide_tube, 2), tube.size * drawn_length_scale(tube, m), 1e-5);  // along its axis
    EXPECT_NEAR(extent(*wide_tube, 0), 2.0 * tube.radius, 1e-5);                         // not around it
    for (MeshKind kind : {MeshKind::sphere, MeshKind::torus, MeshKind::cube}) {
        MeshDesc d;
        d.kind = kind;
        EXPECT_FALSE(build_widened_mesh(d, m).has_value()) << mesh_kind_name(kind);
        EXPECT_EQ(drawn_length_scale(d, m), 1.0) << mesh_kind_name(kind);
    }
    MeshDesc displaced = plane;
    displaced.displaced = true;
    EXPECT_FALSE(build_widened_mesh(displaced, m).has_value());
    EXPECT_EQ(drawn_length_scale(displaced, m), 1.0);
    MaterialDesc unbounded = m;
    unbounded.bounded = false;
    EXPECT_FALSE(build_widened_mesh(plane, unbounded).has_value());
    EXPECT_EQ(drawn_length_scale(tube, unbounded), 1.0);
}

}  // namespace
}  // namespace px
