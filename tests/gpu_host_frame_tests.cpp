// The renderer as part of a host's scene (issue 19): the host's own content,
// mesh, depth buffer and sub-viewport, the host's camera and transforms per
// frame, one preparation shared, and a renderer that refuses another
// context instead of crashing in the driver.
#include "gpu_fixture.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "parallaxes/core/counters.h"
#include "parallaxes/gl/handles.h"
#include "parallaxes/reference/reference_image.h"
#include "parallaxes/scene/mesh.h"
#include "parallaxes/scene/prepared_scene.h"

namespace px::test {
namespace {

// The host's own shader: flat green, GLSL ES 1.00 (runs on ES 2.0 and 3.x).
const char* kHostVertex =
    "attribute vec3 a_position;\n"
    "uniform mat4 u_mvp;\n"
    "void main() { gl_Position = u_mvp * vec4(a_position, 1.0); }\n";
const char* kHostFragment =
    "precision mediump float;\n"
    "void main() { gl_FragColor = vec4(0.0, 1.0, 0.0, 1.0); }\n";

GLuint compile(GLenum type, const char* source) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    EXPECT_TRUE(ok) << "the test's own shader";
    return s;
}

// The host's own fixed-function state, whatever earlier tests of this
// process left set (a host sets what its draws need).
void host_defaults() {
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glDepthRangef(0.0f, 1.0f);
    if (test_es_major() >= 3) glBindVertexArray(0);
}

// The host's mesh: a quad standing upright across the floor (y = 0.2,
// facing the camera), from z = -1 to 1, so that it pierces the relief.
ObjectDesc host_quad_object() {
    ObjectDesc o;
    o.name = "host quad";
    o.material = "host green";
    o.mesh.size = 2.0f;
    o.transform.rotate_deg = {90.0f, 0.0f, 0.0f};
    o.transform.translate = {0.0f, 0.2f, 0.0f};
    return o;
}

SceneDesc floor_scene(bool depth_write) {
    PlaneScene p;
    p.field.kind = FieldKind::bricks;
    p.field.size = 128;
    p.height_scale = 0.1f;
    p.technique = Technique::pom;
    p.options.depth_write = depth_write;
    p.options.max_samples = 64;
    SceneDesc s = p.build();
    s.camera.position = {0.0f, -2.4f, 1.1f};
    s.camera.target = {0.0f, 0.3f, -0.1f};
    s.camera.fov_y_deg = 40.0f;
    return s;
}

struct HostPicture {
    Image image;
    int width = 0, height = 0;
    Viewport viewport;
};

// The host: fills its framebuffer blue (depth 1), draws its quad in the
// viewport with its own program, then has the library draw the floor into
// the same viewport with the same camera, depth-tested against the quad.
HostPicture draw_as_host(bool depth_write) {
    HostPicture out;
    out.width = 160;
    out.height = 128;
    out.viewport = Viewport{24, 16, 112, 96};
    auto target = OffscreenTarget::create(out.width, out.height);
    EXPECT_TRUE(target.ok());
    const SceneDesc scene = floor_scene(depth_write);
    auto renderer = Renderer::create({platform::HeadlessContext::proc_loader()});
    EXPECT_TRUE(renderer.ok());
    Status loaded = (*renderer)->load(scene);
    EXPECT_TRUE(loaded.ok()) << loaded.error().message;

    RenderTarget rt = target->target();
    host_defaults();
    glBindFramebuffer(GL_FRAMEBUFFER, rt.framebuffer);
    glViewport(0, 0, out.width, out.height);
    glClearColor(0.0f, 0.0f, 1.0f, 1.0f);
    glClearDepthf(1.0f);
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    // The scene's camera for the viewport's aspect: the reference's view.
    const HostFrame frame = HostFrame::from_camera(scene.camera, rt, out.viewport);

    // The host's own draw, its own program and buffer.
    const ObjectDesc quad = host_quad_object();
    const Mesh mesh = build_object_mesh(quad.mesh);
    std::vector<float> triangles;
    for (std::uint32_t i : mesh.indices)
        for (int c = 0; c < 3; ++c) triangles.push_back(mesh.vertices[i].position[c]);
    const GLuint program = glCreateProgram();
    const GLuint vs = compile(GL_VERTEX_SHADER, kHostVertex), fs = compile(GL_FRAGMENT_SHADER, kHostFragment);
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glBindAttribLocation(program, 0, "a_position");
    glLinkProgram(program);
    GLuint buffer = 0;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(triangles.size() * sizeof(float)), triangles.data(),
                 GL_STATIC_DRAW);
    glUseProgram(program);
    const glm::mat4 mvp = frame.projection * frame.view * quad.transform.matrix();
    glUniformMatrix4fv(glGetUniformLocation(program, "u_mvp"), 1, GL_FALSE, &mvp[0][0]);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    glViewport(out.viewport.x, out.viewport.y, out.viewport.width, out.viewport.height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(triangles.size() / 3));
    glDisableVertexAttribArray(0);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR)) << "the test's own draw";

    // The library, between the host's draws.
    Status drawn = (*renderer)->draw(frame);
    EXPECT_TRUE(drawn.ok()) << drawn.error().message;
    auto image = target->read_pixels();
    EXPECT_TRUE(image.ok());
    out.image = std::move(*image);
    glDeleteBuffers(1, &buffer);
    glDeleteProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    return out;
}

bool green(const std::uint8_t* p) { return p[0] == 0 && p[1] == 255 && p[2] == 0; }
bool blue(const std::uint8_t* p) { return p[0] == 0 && p[1] == 0 && p[2] == 255; }

struct ContourCheck {
    int quad_wins = 0, floor_wins = 0;  // in the reference, inside the viewport
    int wrong = 0;                      // pixels the GPU shows otherwise, off the contour's 1-pixel band
};

ContourCheck check_against_reference(const HostPicture& host, bool depth_write) {
    // The reference: the floor and the host's quad as one scene,
    // depth-composited (every relief at its exact traced hit).
    SceneDesc both = floor_scene(depth_write);
    MaterialDesc green_material;
    green_material.name = "host green";
    green_material.technique.technique = Technique::flat;
    green_material.height_scale = 0.0f;
    both.materials.push_back(green_material);
    both.objects.push_back(host_quad_object());
    reference::ReferenceOptions ro;
    ro.depth_composite = true;
    auto truth = reference::render_reference(both, host.viewport.width, host.viewport.height, ro);
    EXPECT_TRUE(truth.ok()) << truth.error().message;
    ContourCheck c;
    if (!truth) return c;
    const int w = host.viewport.width, h = host.viewport.height;
    auto shown = [&](int x, int y) { return truth->object_index[static_cast<size_t>(y) * w + x]; };
    for (int y = 1; y + 1 < h; ++y)
        for (int x = 1; x + 1 < w; ++x) {
            const int o = shown(x, y);
            if (o < 0) continue;
            bool contour = false;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) contour |= shown(x + dx, y + dy) != o;
            const bool quad = o == 1;
            (quad ? c.quad_wins : c.floor_wins) += 1;
            if (contour) continue;
            const std::uint8_t* p =
                &host.image.pixels[(static_cast<size_t>(y + host.viewport.y) * host.width + x + host.viewport.x) * 4];
            if (green(p) != quad) ++c.wrong;
        }
    return c;
}

TEST(HostFrame, SubViewportAndTheHostsDepthCompositeAsTheReferenceSays) {
    const HostPicture host = draw_as_host(true);
    // Outside the viewport: the host's blue, untouched.
    int touched = 0;
    for (int y = 0; y < host.height; ++y)
        for (int x = 0; x < host.width; ++x) {
            const Viewport& v = host.viewport;
            if (x >= v.x && x < v.x + v.width && y >= v.y && y < v.y + v.height) continue;
            touched += !blue(&host.image.pixels[(static_cast<size_t>(y) * host.width + x) * 4]);
        }
    EXPECT_EQ(touched, 0) << "pixels outside the viewport changed";
    const ContourCheck c = check_against_reference(host, true);
    // Both win over large areas, and the GPU agrees with the reference
    // everywhere off the contour but for POM's own hit error at the bricks'
    // steps (measured on llvmpipe: see the note of issue 19).
    EXPECT_GT(c.quad_wins, 500);
    EXPECT_GT(c.floor_wins, 500);
    EXPECT_LE(c.wrong, (c.quad_wins + c.floor_wins) / 400) << c.wrong << " pixels disagree with the reference";
    std::printf("host frame, depth written: %d of %d pixels off the contour disagree with the reference\n", c.wrong,
                c.quad_wins + c.floor_wins);
}

TEST(HostFrame, WithoutDepthWriteTheContourIsThePolygonsNotTheReliefs) {
    // The same check must fail where the relief does not write its depth:
    // the quad then cuts the floor along the polygon's plane, not the relief.
    const HostPicture host = draw_as_host(false);
    const ContourCheck c = check_against_reference(host, true);
    // Measured on llvmpipe: 48 of 8452 (0 with depth written).
    EXPECT_GT(c.wrong, (c.quad_wins + c.floor_wins) / 400) << "the test would not see a missing depth write";
}

TEST(HostFrame, NothingClearedByDefaultAndTransformsMoveWithoutReload) {
    auto target = OffscreenTarget::create(64, 64);
    ASSERT_TRUE(target.ok());
    PlaneScene p;
    p.field.kind = FieldKind::bricks;
    p.field.size = 64;
    p.technique = Technique::normal;
    const SceneDesc scene = p.build();
    auto renderer = Renderer::create({platform::HeadlessContext::proc_loader()});
    ASSERT_TRUE(renderer.ok());
    ASSERT_TRUE((*renderer)->load(scene).ok());
    const RenderTarget rt = target->target();
    host_defaults();
    glBindFramebuffer(GL_FRAMEBUFFER, rt.framebuffer);
    glViewport(0, 0, 64, 64);
    glClearColor(1.0f, 0.0f, 0.0f, 1.0f);
    glClearDepthf(1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    HostFrame frame(rt);
    const PlanView camera = PlanView::from_camera(scene.camera, 64, 64);
    frame.view = camera.view;
    frame.projection = camera.projection;
    // The plane moved far to the side: nothing of it in view, and the
    // host's red untouched (no clear).
    frame.models = {glm::translate(glm::mat4(1.0f), glm::vec3(50.0f, 0.0f, 0.0f))};
    const PipelineCounters before = pipeline_counters();
    ASSERT_TRUE((*renderer)->draw(frame).ok());
    auto moved = target->read_pixels();
    ASSERT_TRUE(moved.ok());
    for (size_t i = 0; i < moved->pixels.size(); i += 4)
        ASSERT_TRUE(moved->pixels[i] == 255 && moved->pixels[i + 1] == 0 && moved->pixels[i + 2] == 0)
            << "pixel " << i / 4 << " changed though nothing is in view and nothing is cleared";
    // Back in place: drawn over the red.
    frame.models = {glm::mat4(1.0f)};
    ASSERT_TRUE((*renderer)->draw(frame).ok());
    auto placed = target->read_pixels();
    ASSERT_TRUE(placed.ok());
    const std::uint8_t* centre = &placed->pixels[(32 * 64 + 32) * 4];
    EXPECT_FALSE(centre[0] == 255 && centre[1] == 0 && centre[2] == 0) << "the plane was not drawn back in place";
    // Moving drew without loading: no image or mesh built, one plan per object per frame.
    const PipelineCounters used = pipeline_counters() - before;
    EXPECT_EQ(used.image_builds, 0u);
    EXPECT_EQ(used.mesh_builds, 0u);
    EXPECT_EQ(used.validations, 0u);
    EXPECT_EQ(used.object_plans, 2u);
    // The same frame again is not planned again.
    ASSERT_TRUE((*renderer)->draw(frame).ok());
    EXPECT_EQ((pipeline_counters() - before).object_plans, 2u);
    // A wrong number of transforms is refused with a message.
    frame.models = {glm::mat4(1.0f), glm::mat4(1.0f)};
    Status wrong = (*renderer)->draw(frame);
    ASSERT_FALSE(wrong.ok());
    EXPECT_NE(wrong.error().message.find("2 model transforms for 1 objects"), std::string::npos) << wrong.error().message;
    // A viewport outside the target too.
    frame.models.clear();
    frame.viewport = Viewport{40, 40, 32, 32};
    Status outside = (*renderer)->draw(frame);
    ASSERT_FALSE(outside.ok());
    EXPECT_NE(outside.error().message.find("not inside the 64x64 target"), std::string::npos) << outside.error().message;
}

TEST(HostFrame, OnePreparationForLoadPlanAndDraw) {
    PlaneScene p;
    p.field.kind = FieldKind::bricks;
    p.field.size = 64;
    SceneDesc scene = p.build();
    scene.objects.push_back(scene.objects[0]);
    scene.objects.back().name = "second";
    scene.objects.back().transform.translate = {0.5f, 0.0f, 0.01f};
    auto target = OffscreenTarget::create(64, 64);
    ASSERT_TRUE(target.ok());
    auto renderer = Renderer::create({platform::HeadlessContext::proc_loader()});
    ASSERT_TRUE(renderer.ok());
    const PipelineCounters before = pipeline_counters();
    ASSERT_TRUE((*renderer)->load(scene).ok());
    ASSERT_TRUE((*renderer)->draw(target->target()).ok());
    ASSERT_TRUE((*renderer)->draw(target->target()).ok());
    const PipelineCounters used = pipeline_counters() - before;
    EXPECT_EQ(used.validations, 1u);
    EXPECT_EQ(used.image_builds, 1u) << "one material";
    EXPECT_EQ(used.mesh_builds, 2u) << "two objects";
    EXPECT_EQ(used.object_plans, 2u) << "two objects, one frame's camera";
    EXPECT_EQ(used.programs_built, (*renderer)->program_count()) << "every program built is drawn";
    EXPECT_EQ((*renderer)->program_count(), 1u) << "both objects draw the one variant";

    // The exact reference reads the same preparation's images.
    const std::shared_ptr<const PreparedScene>& prepared = (*renderer)->prepared();
    ASSERT_TRUE(prepared);
    EXPECT_EQ(prepared->materials.size(), 1u);
    EXPECT_EQ(prepared->objects[0]->mesh.vertices.size(), prepared->objects[1]->mesh.vertices.size());
    reference::ReferenceOptions ro;
    ro.images = (*renderer)->material_image_options();
    const PipelineCounters before_reference = pipeline_counters();
    auto shared = reference::render_reference(*prepared, 48, 48, ro);
    ASSERT_TRUE(shared.ok()) << shared.error().message;
    const PipelineCounters reference_used = pipeline_counters() - before_reference;
    EXPECT_EQ(reference_used.validations, 0u);
    EXPECT_EQ(reference_used.image_builds, 0u) << "the reference built images the preparation has";
    // The same image as the reference that prepares for itself.
    auto own = reference::render_reference(scene, 48, 48, ro);
    ASSERT_TRUE(own.ok()) << own.error().message;
    EXPECT_EQ(shared->color.pixels, own->color.pixels);
    EXPECT_EQ((pipeline_counters() - before_reference).image_builds, 1u);
}

TEST(HostFrame, ASwappedMaterialRebuildsOnlyItself) {
    PlaneScene p;
    p.field.kind = FieldKind::bricks;
    p.field.size = 64;
    SceneDesc scene = p.build();
    MaterialDesc second = scene.materials[0];
    second.name = "second";
    scene.materials.push_back(second);
    scene.objects.push_back(scene.objects[0]);
    scene.objects.back().name = "b";
    scene.objects.back().material = "second";
    auto renderer = Renderer::create({platform::HeadlessContext::proc_loader()});
    ASSERT_TRUE(renderer.ok());
    ASSERT_TRUE((*renderer)->load(scene).ok());
    const auto first_material = (*renderer)->prepared()->materials[0];
    MaterialDesc swapped = second;
    swapped.height.field.kind = FieldKind::hemispheres;
    const PipelineCounters before = pipeline_counters();
    Status s = (*renderer)->replace_material(swapped);
    ASSERT_TRUE(s.ok()) << s.error().message;
    EXPECT_EQ((pipeline_counters() - before).image_builds, 1u);
    EXPECT_EQ((*renderer)->prepared()->materials[0], first_material) << "the other material is shared, not rebuilt";
    auto target = OffscreenTarget::create(32, 32);
    ASSERT_TRUE(target.ok());
    EXPECT_TRUE((*renderer)->draw(target->target()).ok());
    MaterialDesc unknown = second;
    unknown.name = "nowhere";
    Status missing = (*renderer)->replace_material(unknown);
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("no material 'nowhere'"), std::string::npos) << missing.error().message;
}

TEST(HostFrame, AnotherContextCurrentIsRefusedNotACrash) {
    PlaneScene p;
    p.field.size = 32;
    const SceneDesc scene = p.build();
    auto renderer = Renderer::create({platform::HeadlessContext::proc_loader()});
    ASSERT_TRUE(renderer.ok());
    Status first = (*renderer)->load(scene);
    ASSERT_TRUE(first.ok()) << first.error().message;
    auto target = OffscreenTarget::create(32, 32);
    ASSERT_TRUE(target.ok());
    {
        platform::ContextOptions options;
        options.es_major = test_es_major();
        auto other = platform::HeadlessContext::create(options);  // current from here
        ASSERT_TRUE(other.ok()) << other.error().message;
        Status drawn = (*renderer)->draw(target->target());
        ASSERT_FALSE(drawn.ok()) << "drew with another context current";
        EXPECT_NE(drawn.error().message.find("another OpenGL ES context is current"), std::string::npos)
            << drawn.error().message;
        Status loaded = (*renderer)->load(scene);
        EXPECT_FALSE(loaded.ok());
    }
    ASSERT_TRUE(GpuEnvironment::context()->make_current().ok());
    Status drawn = (*renderer)->draw(target->target());
    EXPECT_TRUE(drawn.ok()) << drawn.error().message;
}

TEST(HostFrame, FramebufferProblemsAreNamed) {
    PlaneScene p;
    p.field.size = 32;
    auto renderer = Renderer::create({platform::HeadlessContext::proc_loader()});
    ASSERT_TRUE(renderer.ok());
    ASSERT_TRUE((*renderer)->load(p.build()).ok());
    // Framebuffer 0 of a surfaceless context.
    Status zero = (*renderer)->draw(RenderTarget{0, 32, 32});
    ASSERT_FALSE(zero.ok());
    if (test_es_major() >= 3)
        EXPECT_NE(zero.error().message.find("GL_FRAMEBUFFER_UNDEFINED"), std::string::npos) << zero.error().message;
    EXPECT_EQ(zero.error().message.find("unknown framebuffer status"), std::string::npos) << zero.error().message;
    // A target larger than the framebuffer's attachments.
    auto target = OffscreenTarget::create(32, 32);
    ASSERT_TRUE(target.ok());
    RenderTarget larger = target->target();
    larger.width = 64;
    Status big = (*renderer)->draw(larger);
    ASSERT_FALSE(big.ok()) << "a 64x32 target accepted on a 32x32 framebuffer";
    EXPECT_NE(big.error().message.find("does not fit"), std::string::npos) << big.error().message;
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

TEST(HostFrame, EffectsWithoutThePlannerAreRefusedAtLoad) {
    Result<SceneDesc> showcase = builtin_scene("showcase");  // every material declares effects
    ASSERT_TRUE(showcase.ok());
    auto renderer = Renderer::create({platform::HeadlessContext::proc_loader()});  // no effect_planner
    ASSERT_TRUE(renderer.ok());
    Status loaded = (*renderer)->load(*showcase);
    ASSERT_FALSE(loaded.ok()) << "a scene that declares effects loaded without a planner";
    EXPECT_NE(loaded.error().message.find("RendererOptions::effect_planner"), std::string::npos)
        << loaded.error().message;
    EXPECT_EQ((*renderer)->program_count(), 0u);
}

}  // namespace
}  // namespace px::test
