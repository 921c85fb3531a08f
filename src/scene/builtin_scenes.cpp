// Scenes built into the program, written in C++ so they need no files. The
// scene's up axis is +z; planes lie in the xy plane with u along +x, v along +y.
#include "parallaxes/scene/scene.h"
#include "parallaxes/core/text.h"

#include <cmath>
#include <utility>

namespace px {

namespace {

// Unit vector at `azimuth_deg` around +z from +x, `elevation_deg` above the xy plane.
glm::vec3 spherical(float azimuth_deg, float elevation_deg) {
    const float a = glm::radians(azimuth_deg), e = glm::radians(elevation_deg);
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

// A directional light coming from the given direction: LightDesc::direction is
// the way the light travels, the opposite of where it comes from.
LightDesc sun(float from_azimuth_deg, float elevation_deg, float intensity, glm::vec3 color = glm::vec3(1.0f)) {
    LightDesc l;
    l.kind = LightKind::directional;
    l.direction = -spherical(from_azimuth_deg, elevation_deg);
    l.color = color;
    l.intensity = intensity;
    return l;
}

// A camera `distance` from `target`, seen from the given azimuth and elevation.
CameraDesc orbit(glm::vec3 target, float distance, float azimuth_deg, float elevation_deg) {
    CameraDesc c;
    c.target = target;
    c.position = target + distance * spherical(azimuth_deg, elevation_deg);
    return c;
}

TextureSource colour(glm::vec3 rgb) {
    TextureSource s;
    s.kind = TextureSource::Kind::color;
    s.color = rgb;
    return s;
}

TextureSource procedural(FieldSpec field) {
    TextureSource s;
    s.kind = TextureSource::Kind::procedural;
    s.field = std::move(field);
    return s;
}

FieldSpec field(FieldKind kind, int size = 256) {
    FieldSpec f;
    f.kind = kind;
    f.size = size;
    return f;
}

MaterialDesc material(std::string name, glm::vec3 albedo, FieldSpec height, float height_scale,
                      TechniqueOptions technique, glm::vec2 uv_scale = glm::vec2(1.0f)) {
    MaterialDesc m;
    m.name = std::move(name);
    m.albedo = colour(albedo);
    m.height = procedural(std::move(height));
    m.height_scale = height_scale;
    m.uv.scale = uv_scale;
    m.technique = technique;
    return m;
}

TechniqueOptions technique(Technique t, ShadowMode shadow = ShadowMode::none, int max_samples = 32) {
    TechniqueOptions o;
    o.technique = t;
    o.shadow = shadow;
    o.max_samples = max_samples;
    return o;
}

ObjectDesc object(std::string name, MeshDesc mesh, std::string material_name, glm::vec3 translate = glm::vec3(0.0f),
                  glm::vec3 rotate_deg = glm::vec3(0.0f)) {
    ObjectDesc o;
    o.name = std::move(name);
    o.mesh = mesh;
    o.material = std::move(material_name);
    o.transform.translate = translate;
    o.transform.rotate_deg = rotate_deg;
    return o;
}

MeshDesc plane(float size) {
    MeshDesc m;
    m.kind = MeshKind::plane;
    m.size = size;
    return m;
}

const glm::vec3 kBrickRed{0.58f, 0.27f, 0.19f};
const glm::vec3 kPaleStone{0.82f, 0.79f, 0.72f};

// Where parallax matters: a low camera looking across relief, with one low
// light raking from the side so joints and glyphs cast shadows. The first
// default scene; the texture bench's scene (`bench --textures`).
SceneDesc lettering_scene() {
    SceneDesc s;
    s.name = "lettering";
    // 40 degrees up, and lettering 0.015 deep (7.7 of its 512 texels): a
    // glyph's top moves about 9 texels across its base at this view, less
    // than a stroke is wide (512 / 48 = 10.7 texels), so no glyph hides its
    // neighbour and the word reads, while the bricks behind show the depth.
    s.camera = orbit({0.0f, -0.2f, 0.0f}, 2.9f, -90.0f, 40.0f);
    s.ambient = glm::vec3(0.10f);
    s.background = {0.05f, 0.06f, 0.09f};
    // From the left and slightly in front, 20 degrees up: vertical joints are
    // shadowed along their left walls, horizontal ones a little.
    LightDesc light = sun(235.0f, 22.0f, 2.2f, {1.0f, 0.95f, 0.88f});
    light.angular_radius_deg = 1.5f;
    s.lights = {light};

    TechniqueOptions pom = technique(Technique::pom, ShadowMode::soft, 32);
    pom.depth_write = true;  // the relief, not the polygon, meets the neighbouring plane
    FieldSpec bricks = field(FieldKind::bricks);
    FieldSpec text = field(FieldKind::text, 512);  // 8 glyphs across: 512 texels keep their edges crisp
    text.text = "PARALLAX";
    s.materials = {material("bricks", kBrickRed, bricks, 0.06f, pom, glm::vec2(3.0f)),
                   material("lettering", kPaleStone, text, 0.015f, pom)};
    // The lettering in front, the brick floor running away behind it.
    s.objects = {object("brick floor", plane(2.6f), "bricks", {0.0f, 1.25f, -0.001f}),
                 object("text slab", plane(2.0f), "lettering", {0.0f, -1.05f, 0.0f})};
    return s;
}

// A procedural albedo from the same field as the relief: colour `low` where
// the field is at 0, `high` at 1, with grain (ramp_image).
TextureSource ramp(const FieldSpec& f, glm::vec3 low, glm::vec3 high, float grain) {
    TextureSource s = procedural(f);
    s.low = low;
    s.high = high;
    s.grain = grain;
    return s;
}

// The first picture a user sees: a material study that should read as real
// at a glance. A brick pavement whose colour comes from its own relief
// (mortar below, brick faces above, grain), and a slate panel set flush in
// it with raised brass lettering, a bounded relief (its letters end at the
// panel, their outlines drawn); a warm sun 35 degrees up from the front
// left with a soft penumbra, a cool sky as the ambient term so shadows
// keep their colour, specular on brass and brick, four samples per pixel
// where the context offers them (`parallax render`'s default).
SceneDesc default_scene() {
    SceneDesc s;
    s.name = "default";
    s.camera = orbit({0.0f, 0.2f, 0.0f}, 2.9f, -90.0f, 36.0f);
    s.camera.fov_y_deg = 42.0f;
    s.ambient = glm::vec3(0.36f, 0.39f, 0.45f);  // sky: shadowed brick stays brick-coloured
    s.background = {0.62f, 0.69f, 0.78f};
    LightDesc light = sun(215.0f, 35.0f, 1.45f, {1.0f, 0.92f, 0.80f});
    light.angular_radius_deg = 2.5f;
    s.lights = {light};

    TechniqueOptions pom = technique(Technique::pom, ShadowMode::soft, 32);
    pom.depth_write = true;
    FieldSpec bricks = field(FieldKind::bricks);
    MaterialDesc pavement = material("pavement", kBrickRed, bricks, 0.05f, pom, glm::vec2(28.0f));
    pavement.albedo = ramp(bricks, {0.52f, 0.50f, 0.47f}, {0.60f, 0.33f, 0.25f}, 0.22f);
    pavement.specular = 0.12f;
    pavement.shininess = 20.0f;

    FieldSpec text = field(FieldKind::text, 512);
    text.text = "PARALLAX";
    MaterialDesc panel = material("brass lettering", kPaleStone, text, 0.025f, pom);
    panel.albedo = ramp(text, {0.27f, 0.29f, 0.32f}, {0.80f, 0.62f, 0.30f}, 0.08f);
    panel.specular = 0.55f;
    panel.shininess = 28.0f;
    panel.bounded = true;
    // The band of the tile the glyphs stand in, on a panel of its shape.
    panel.uv.scale = {1.0f, 0.2f};
    panel.uv.offset = {0.0f, 0.4f};

    // A bronze dome studded with bumps, set into the pavement behind the
    // panel (depth written, so the bricks meet it where their relief does):
    // its outline is the studs' (`silhouette`, the curved search).
    FieldSpec studs = field(FieldKind::hemispheres);
    studs.count = 2;
    MaterialDesc bronze = material("studded bronze", kPaleStone, studs, 0.06f, pom, glm::vec2(6.0f, 3.0f));
    bronze.albedo = ramp(studs, {0.20f, 0.15f, 0.10f}, {0.86f, 0.64f, 0.34f}, 0.06f);
    bronze.specular = 0.6f;
    bronze.shininess = 36.0f;
    bronze.silhouette = true;

    s.materials = {pavement, panel, bronze};
    MeshDesc sphere;
    sphere.kind = MeshKind::sphere;
    sphere.radius = 0.45f;
    ObjectDesc ball = object("dome", sphere, "studded bronze", {1.0f, 0.75f, -0.12f});
    ball.transform.rotate_deg = {0.0f, 0.0f, 20.0f};
    ObjectDesc ground = object("pavement", plane(12.0f), "pavement", {0.0f, 4.0f, -0.002f});
    // The panel's ground (the glyphs' height 0) lies on the pavement's
    // bricks; its polygon is at the glyphs' tops, 0.025 of its 2.2-unit tile.
    ObjectDesc plaque = object("panel", plane(2.2f), "brass lettering", {0.0f, -0.35f, 0.025f * 2.2f});
    plaque.transform.scale = {1.0f, 0.2f, 1.0f};
    s.objects = {ground, plaque, ball};
    return s;
}

// A material that declares effects: the planner chooses its technique.
MaterialDesc effects_material(std::string name, glm::vec3 albedo, FieldSpec height, float height_scale,
                              EffectRequest effects, glm::vec2 uv_scale = glm::vec2(1.0f)) {
    MaterialDesc m = material(std::move(name), albedo, std::move(height), height_scale, TechniqueOptions{}, uv_scale);
    m.effects = effects;
    return m;
}

EffectRequest parallax_within(float texels, ShadowMode shadow = ShadowMode::none, float shadow_error = 0.1f) {
    EffectRequest e;
    e.max_error_texels = texels;
    e.shadow = shadow;
    e.shadow_max_error = shadow_error;
    return e;
}

// Surfaces that call for different effects, every material declaring what
// it needs and the planner choosing (docs/planner.md): a brick floor running
// far away, a stone wall seen at a grazing angle, raised text close up under
// a low light, a flat painted panel, and a board leaning on a deep brick
// wall, whose relief it meets. Planes only, so the exact reference
// covers every surface.
SceneDesc showcase_scene() {
    SceneDesc s;
    s.name = "showcase";
    s.camera.position = {0.0f, -3.2f, 1.35f};
    s.camera.target = {0.25f, 2.5f, 0.75f};
    s.camera.fov_y_deg = 55.0f;
    s.ambient = glm::vec3(0.12f);
    s.background = {0.05f, 0.06f, 0.09f};
    // Low, from the left and behind the camera: it rakes across the text
    // panel, reaches the floor and the back wall, and is behind the grazing
    // wall on the right (which faces -x, away from it).
    LightDesc sun_light = sun(200.0f, 18.0f, 1.4f, {1.0f, 0.95f, 0.88f});
    sun_light.angular_radius_deg = 1.5f;
    s.lights = {sun_light};

    FieldSpec text = field(FieldKind::text, 256);
    text.text = "ES";
    FieldSpec waves = field(FieldKind::sine, 256);
    waves.frequency = 2.0f;
    EffectRequest floor = parallax_within(1.0f);
    EffectRequest side = parallax_within(0.75f);
    EffectRequest lettering = parallax_within(0.5f, ShadowMode::soft, 0.08f);
    EffectRequest back = parallax_within(1.0f, ShadowMode::hard, 0.1f);
    EffectRequest painted = parallax_within(1.0f);
    EffectRequest plain;
    plain.parallax = false;
    s.materials = {
        effects_material("floor", kBrickRed, field(FieldKind::bricks), 0.03f, floor, glm::vec2(4.4f, 9.2f)),
        effects_material("side wall", {0.45f, 0.47f, 0.5f}, waves, 0.04f, side, glm::vec2(2.0f)),
        effects_material("lettering", kPaleStone, text, 0.04f, lettering),
        effects_material("back wall", {0.62f, 0.36f, 0.26f}, field(FieldKind::bricks), 0.08f, back, glm::vec2(3.0f, 1.5f)),
        effects_material("paint", {0.25f, 0.45f, 0.62f}, field(FieldKind::flat), 0.0f, painted),
        effects_material("board", {0.55f, 0.5f, 0.45f}, field(FieldKind::flat), 0.0f, plain),
    };
    // The floor ends where the walls begin, and the walls stand 0.02 above
    // it: nothing meets another surface's relief but the board.
    ObjectDesc floor_object = object("floor", plane(1.0f), "floor", {0.0f, 2.4f, 0.0f});
    floor_object.transform.scale = {4.4f, 9.2f, 1.0f};
    s.objects = {
        floor_object,
        // Vertical planes: +z turned to face the camera's side.
        object("side wall", plane(4.0f), "side wall", {2.2f, 3.0f, 2.02f}, {0.0f, -90.0f, 0.0f}),
        object("text panel", plane(0.5f), "lettering", {-0.45f, -1.8f, 0.82f}, {72.0f, 0.0f, 20.0f}),
        object("back wall", plane(4.0f), "back wall", {0.0f, 7.0f, 2.02f}, {90.0f, 0.0f, 0.0f}),
        object("painted panel", plane(0.8f), "paint", {-1.4f, 1.5f, 0.9f}, {90.0f, 0.0f, -30.0f}),
        // A board leaning on the back wall, its top edge inside the wall's relief.
        object("board", plane(1.2f), "board", {0.6f, 6.95f, 1.0f}, {75.0f, 0.0f, 0.0f}),
    };
    return s;
}

SceneDesc bricks_scene() {
    SceneDesc s;
    s.name = "bricks";
    s.camera = orbit({0.0f, 0.0f, 0.0f}, 3.2f, -90.0f, 45.0f);
    s.lights = {sun(225.0f, 50.0f, 1.6f)};
    s.materials = {material("bricks", kBrickRed, field(FieldKind::bricks), 0.05f, technique(Technique::pom),
                            glm::vec2(2.0f))};
    s.objects = {object("wall", plane(2.4f), "bricks")};
    return s;
}

// A square pit seen from straight above and lit from -x at 25 degrees: the
// shadow of the -x wall covers the floor next to it (depth / tan 25 = 0.21 of
// the tile, of the pit's 0.5), and the rest of the floor is lit.
SceneDesc pit_scene() {
    SceneDesc s;
    s.name = "pit";
    s.camera.position = {0.0f, 0.0f, 2.3f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.up = {0.0f, 1.0f, 0.0f};  // +z would be parallel to the view
    s.ambient = glm::vec3(0.05f);
    s.lights = {sun(180.0f, 25.0f, 1.5f)};
    TechniqueOptions pom = technique(Technique::pom, ShadowMode::hard, 64);
    pom.min_samples = 16;
    pom.shadow_samples = 32;
    FieldSpec pit = field(FieldKind::pit);
    pit.radius = 0.25f;
    s.materials = {material("pit", {0.75f, 0.73f, 0.70f}, pit, 0.1f, pom)};
    s.objects = {object("ground", plane(2.0f), "pit")};
    return s;
}

// Curved meshes: the tangent frame turns across each surface, so a wrong
// frame shows as bumps that shift the wrong way. uv scales keep tiles square.
SceneDesc shapes_scene() {
    SceneDesc s;
    s.name = "shapes";
    s.camera = orbit({0.0f, 0.0f, 0.7f}, 5.0f, -90.0f, 22.0f);
    LightDesc fill;
    fill.kind = LightKind::point;
    fill.position = {0.0f, -1.8f, 2.5f};
    fill.color = {0.65f, 0.75f, 1.0f};
    fill.intensity = 0.35f;
    // Dim enough that the pale floor under both lights does not clip to white.
    s.lights = {sun(135.0f, 40.0f, 0.9f), fill};

    FieldSpec bumps = field(FieldKind::hemispheres);
    bumps.count = 2;
    FieldSpec cones = field(FieldKind::cones);
    cones.count = 2;
    FieldSpec waves = field(FieldKind::sine);
    waves.frequency = 2.0f;
    TechniqueOptions relief = technique(Technique::relief);
    s.materials = {
        material("bumps", {0.30f, 0.55f, 0.75f}, bumps, 0.04f, technique(Technique::pom, ShadowMode::hard),
                 {6.0f, 3.0f}),
        material("cones", {0.80f, 0.60f, 0.25f}, cones, 0.05f, relief, {6.0f, 2.0f}),
        material("waves", kPaleStone, waves, 0.03f, technique(Technique::steep), glm::vec2(3.0f)),
    };

    MeshDesc sphere;
    sphere.kind = MeshKind::sphere;
    sphere.radius = 0.9f;
    MeshDesc torus;
    torus.kind = MeshKind::torus;
    torus.radius = 0.8f;
    torus.tube_radius = 0.3f;
    s.objects = {
        object("sphere", sphere, "bumps", {-1.2f, 0.0f, 0.9f}),
        object("torus", torus, "cones", {1.2f, 0.0f, 1.05f}, {60.0f, 0.0f, 0.0f}),
        object("floor", plane(6.0f), "waves"),
    };
    return s;
}

struct Builtin {
    const char* name;
    SceneDesc (*build)();
};

constexpr Builtin kBuiltins[] = {
    {"default", default_scene},
    {"lettering", lettering_scene},
    {"bricks", bricks_scene},
    {"pit", pit_scene},
    {"shapes", shapes_scene},
    {"showcase", showcase_scene},
};

}  // namespace

std::vector<std::string> builtin_scene_names() {
    std::vector<std::string> names;
    for (const Builtin& b : kBuiltins) names.emplace_back(b.name);
    return names;
}

Result<SceneDesc> builtin_scene(const std::string& name) {
    for (const Builtin& b : kBuiltins)
        if (name == b.name) return b.build();
    std::string known;
    for (const Builtin& b : kBuiltins) known += (known.empty() ? "" : ", ") + std::string(b.name);
    return make_error("unknown built-in scene '" + echo(name) + "' (built-in: " + known + ")");
}

}  // namespace px
