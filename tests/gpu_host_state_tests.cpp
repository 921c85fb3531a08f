// The host's GL state survives the renderer, on ES 2.0 and ES 3.0: the test
// sets every row of the state table (gl/state.h: what the renderer saves,
// restores and sets aside for its draws) to a value other than GL's
// default, then checks every row after each call of the library: create,
// load, replace_material, draw, debug captures, read-back and destroy.
#include "gpu_fixture.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "parallaxes/gl/caps.h"
#include "parallaxes/gl/state.h"
#include "parallaxes/render/surface_capture.h"

namespace px::test {
namespace {

GLuint host_program(bool es3) {
    const char* vs = es3 ? "#version 300 es\nin vec4 p;\nvoid main() { gl_Position = p; }\n"
                         : "#version 100\nattribute vec4 p;\nvoid main() { gl_Position = p; }\n";
    const char* fs = es3 ? "#version 300 es\nprecision mediump float;\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n"
                         : "#version 100\nprecision mediump float;\nvoid main() { gl_FragColor = vec4(1.0); }\n";
    const GLuint program = glCreateProgram();
    for (auto [stage, text] : {std::pair<GLenum, const char*>{GL_VERTEX_SHADER, vs}, {GL_FRAGMENT_SHADER, fs}}) {
        const GLuint shader = glCreateShader(stage);
        glShaderSource(shader, 1, &text, nullptr);
        glCompileShader(shader);
        glAttachShader(program, shader);
        glDeleteShader(shader);
    }
    glLinkProgram(program);
    return program;
}

// The objects the host's state binds.
struct HostObjects {
    GlStateProbe probe;
    bool es3 = false;
};

HostObjects make_host_objects(bool es3, GLuint draw_framebuffer, GLuint read_framebuffer) {
    HostObjects h;
    h.es3 = es3;
    GlStateProbe& p = h.probe;
    p.program = host_program(es3);
    glGenBuffers(5, p.buffers);
    for (GLuint b : p.buffers) {
        glBindBuffer(GL_ARRAY_BUFFER, b);
        glBufferData(GL_ARRAY_BUFFER, 1024, nullptr, GL_STATIC_DRAW);
    }
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glGenTextures(static_cast<GLsizei>(GlStateProbe::kTextures), p.textures);
    glGenRenderbuffers(1, &p.renderbuffer);
    p.draw_framebuffer = draw_framebuffer;
    p.read_framebuffer = es3 ? read_framebuffer : draw_framebuffer;
    if (es3) {
        glGenVertexArrays(1, &p.vertex_array);
        glGenSamplers(static_cast<GLsizei>(GlStateProbe::kSamplers), p.samplers);
    }
    return h;
}

void delete_host_objects(HostObjects& h) {
    GlStateProbe& p = h.probe;
    glUseProgram(0);
    glDeleteProgram(p.program);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDeleteBuffers(5, p.buffers);
    glDeleteTextures(static_cast<GLsizei>(GlStateProbe::kTextures), p.textures);
    glDeleteRenderbuffers(1, &p.renderbuffer);
    if (h.es3) {
        glBindVertexArray(0);
        glDeleteVertexArrays(1, &p.vertex_array);
        glDeleteSamplers(static_cast<GLsizei>(GlStateProbe::kSamplers), p.samplers);
    }
}

std::string row_name(const GlStateValue& v) {
    return std::string(v.name) + (v.index >= 0 ? " " + std::to_string(v.index) : std::string());
}

// Every row the probe sets differs from what the context had before (GL's
// defaults: every earlier test gives the state back), so that the checks
// afterwards would see a change to it. Rows are matched by name and unit:
// the host's active unit adds one.
void expect_all_changed(const std::vector<GlStateValue>& initial, const std::vector<GlStateValue>& host) {
    ASSERT_GE(host.size(), initial.size());
    for (const GlStateValue& h : host) {
        // Odd attribute slots stay disabled on purpose: both kinds covered.
        if (h.name == "attribute" && h.index % 2) continue;
        const auto before = std::find_if(initial.begin(), initial.end(), [&](const GlStateValue& i) {
            return i.name == h.name && i.index == h.index;
        });
        // A unit only the host's active one reaches: its texture was unbound.
        const GlStateValue::Values unbound{};
        const GlStateValue::Values& was = before == initial.end() ? unbound : before->values;
        EXPECT_NE(was, h.values) << row_name(h) << " is still at its default: the probe does not set it";
    }
}

void expect_state(const Caps& caps, const std::vector<GlStateValue>& expected, const char* after) {
    const std::vector<GlStateValue> now = read_gl_state(caps);
    ASSERT_EQ(now.size(), expected.size()) << after;
    for (size_t i = 0; i < now.size(); ++i)
        EXPECT_EQ(now[i].values, expected[i].values) << row_name(expected[i]) << " changed by " << after;
}

TEST(HostState, EveryRowOfTheStateTableSurvivesEveryCall) {
    const bool es3 = test_es_major() >= 3;
    auto host_target = OffscreenTarget::create(64, 64);  // stands in for the app's own framebuffer
    ASSERT_TRUE(host_target.ok()) << host_target.error().message;
    auto other = OffscreenTarget::create(32, 32);
    auto third = OffscreenTarget::create(16, 16);
    ASSERT_TRUE(other.ok() && third.ok());
    const Caps caps = query_caps();

    // The image this scene gives with GL's default state around it.
    PlaneScene p;
    p.field.kind = FieldKind::bricks;
    p.field.size = 128;
    p.options.shadow = ShadowMode::soft;
    p.options.depth_write = true;
    const SceneDesc scene = p.build();
    const Image expected = render(scene, 64).image;

    const std::vector<GlStateValue> initial = read_gl_state(caps);
    // GL's defaults come back however the test ends (an ASSERT included):
    // the tests after it expect them.
    SavedGlState defaults(caps);
    HostObjects host = make_host_objects(es3, other->target().framebuffer, third->target().framebuffer);
    set_gl_state_probe(caps, host.probe);
    const std::vector<GlStateValue> before = read_gl_state(caps);
    expect_all_changed(initial, before);
    // The host's active unit is past the units the library binds: the table
    // covers it (an upload binds there).
    ASSERT_GE(GlStateProbe::kActiveUnit, kLibraryTextureUnits);
    EXPECT_TRUE(std::any_of(before.begin(), before.end(), [](const GlStateValue& v) {
        return v.name == "texture 2d" && v.index == GlStateProbe::kActiveUnit;
    }));

    auto renderer = Renderer::create(reading_files());
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;
    expect_state(caps, before, "create");
    Status loaded = (*renderer)->load(scene);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    expect_state(caps, before, "load");
    MaterialDesc replaced = scene.materials[0];
    replaced.height_scale *= 0.5f;
    replaced.albedo.low = glm::vec3(0.25f, 0.5f, 0.75f);
    Status swapped = (*renderer)->replace_material(replaced);
    ASSERT_TRUE(swapped.ok()) << swapped.error().message;
    expect_state(caps, before, "replace_material");
    swapped = (*renderer)->replace_material(scene.materials[0]);
    ASSERT_TRUE(swapped.ok()) << swapped.error().message;
    Status drawn = (*renderer)->draw(host_target->target());
    ASSERT_TRUE(drawn.ok()) << drawn.error().message;
    expect_state(caps, before, "draw");
    Result<SurfaceImage> surfaces = capture_surfaces(**renderer, 32, 32);
    ASSERT_TRUE(surfaces.ok()) << surfaces.error().message;
    expect_state(caps, before, "capture_surfaces");
    Result<Image> image = host_target->read_pixels();
    ASSERT_TRUE(image.ok()) << image.error().message;
    expect_state(caps, before, "read_pixels");
    renderer->reset();
    expect_state(caps, before, "destroy");
    delete_host_objects(host);

    // The host's scissor, stencil, blend, colour mask, depth state, (ES 3.0)
    // sampler objects, unpack buffer and rasterizer discard did not reach the image.
    const ImageDiff d = compare(*image, expected);
    EXPECT_EQ(d.max, 0) << "mean " << d.mean;
}

// KHR_debug: the context holds one callback. A host's own (and its user
// parameter) is never replaced; where the host has none, the renderer's
// collects the driver's messages and goes with the renderer.
TEST(HostState, TheHostsDebugCallbackIsLeftAlone) {
    const GetProcAddress get_proc = platform::HeadlessContext::proc_loader();
    const Caps caps = query_caps();
    if (!caps.khr_debug()) GTEST_SKIP() << "the context has no GL_KHR_debug";
    auto set_callback = reinterpret_cast<PFNGLDEBUGMESSAGECALLBACKKHRPROC>(get_proc("glDebugMessageCallbackKHR"));
    auto get_pointer = reinterpret_cast<PFNGLGETPOINTERVKHRPROC>(get_proc("glGetPointervKHR"));
    ASSERT_TRUE(set_callback && get_pointer);
    auto callback_now = [&] {
        std::pair<void*, void*> c{nullptr, nullptr};
        get_pointer(GL_DEBUG_CALLBACK_FUNCTION_KHR, &c.first);
        get_pointer(GL_DEBUG_CALLBACK_USER_PARAM_KHR, &c.second);
        return c;
    };
    static int host_messages = 0;
    int user = 7;
    const GLDEBUGPROCKHR host = [](GLenum, GLenum, GLuint, GLenum, GLsizei, const GLchar*, const void* param) {
        host_messages += *static_cast<const int*>(param) == 7 ? 1 : 0;
    };
    set_callback(host, &user);
    const std::pair<void*, void*> hosts{reinterpret_cast<void*>(host), &user};
    {
        RendererOptions options;
        options.get_proc_address = get_proc;
        auto renderer = Renderer::create(options);
        ASSERT_TRUE(renderer.ok()) << renderer.error().message;
        EXPECT_EQ(callback_now(), hosts) << "after create";
        PlaneScene p;
        ASSERT_TRUE((*renderer)->load(p.build()).ok());
        auto target = OffscreenTarget::create(32, 32);
        ASSERT_TRUE(target.ok());
        ASSERT_TRUE((*renderer)->draw(target->target()).ok());
        EXPECT_EQ(callback_now(), hosts) << "after draw";
    }
    EXPECT_EQ(callback_now(), hosts) << "after destroy";
    set_callback(nullptr, nullptr);
    {
        // No host callback: the renderer's, until it is destroyed.
        RendererOptions options;
        options.get_proc_address = get_proc;
        auto renderer = Renderer::create(options);
        ASSERT_TRUE(renderer.ok()) << renderer.error().message;
        EXPECT_NE(callback_now().first, nullptr) << "the renderer collects the driver's messages";
    }
    EXPECT_EQ(callback_now().first, nullptr) << "after destroy";
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

// Share of covered pixels whose shown height is the relief's floor (the trace
// reached the mortar) rather than the polygon (normal mapping shows height 1).
double traced_share(const SurfaceImage& s) {
    long covered = 0, floor = 0;
    for (const SurfaceSample& x : s.samples) {
        if (!x.covered) continue;
        ++covered;
        if (x.height < 0.5) ++floor;
    }
    return covered ? static_cast<double>(floor) / static_cast<double>(covered) : 0.0;
}

// u_texture_size is the size of the texture the trace reads, not of the
// normal map: with a separate height map of another size, the LOD choice
// (mip level from the traced texels per pixel) follows the height map.
// Straight on, 128 texels span about 117 pixels: mip level about 0.1 for a
// 128-texel height map and 1.1 for a 256-texel one, either side of the
// threshold at 0.75 (band 0.25). Below it the trace shows the mortar's floor;
// past it normal mapping shows the polygon everywhere.
TEST(TextureSize, LodFollowsTheTracedHeightMapNotTheNormalMap) {
    for (const auto [height_size, normal_size] : {std::pair<int, int>{128, 256}, {256, 128}}) {
        PlaneScene p;
        p.field.kind = FieldKind::bricks;
        p.field.size = height_size;
        p.technique = Technique::pom;
        p.options.lod = true;
        p.options.lod_threshold = 0.75f;
        p.options.lod_band = 0.25f;
        SceneDesc scene = p.build();
        MaterialDesc& m = scene.materials[0];
        m.pack_height_in_normal_alpha = false;  // the height map is its own texture
        m.normal.kind = TextureSource::Kind::procedural;
        m.normal.field = p.field;
        m.normal.field.size = normal_size;
        auto renderer = Renderer::create();
        ASSERT_TRUE(renderer.ok());
        Status loaded = (*renderer)->load(scene);
        ASSERT_TRUE(loaded.ok()) << loaded.error().message;
        ASSERT_TRUE((*renderer)->set_view(scene.camera, 128, 128).ok());  // plans: the reports say what is drawn
        ASSERT_TRUE((*renderer)->reports()[0].variant.lod) << "the context runs the LOD variant";
        auto surfaces = capture_surfaces(**renderer, 128, 128);
        ASSERT_TRUE(surfaces.ok()) << surfaces.error().message;
        const double share = traced_share(*surfaces);
        if (height_size == 128)
            EXPECT_GT(share, 0.05) << "a 128-texel height map under a " << normal_size
                                   << "-texel normal map is below the LOD threshold: the trace must reach the mortar";
        else
            EXPECT_LT(share, 0.001) << "a 256-texel height map under a " << normal_size
                                    << "-texel normal map is past the LOD threshold: normal mapping";
    }
}

}  // namespace
}  // namespace px::test

namespace px::test {
namespace {

// Without fragment highp (many ES 2.0 GPUs), the debug outputs cannot pack
// 24 exact bits: the shader packs 11 and says so, and the capture decodes it
// as such instead of returning wrong hits. Emulated on this context: the
// no-highp capture agrees with the highp one to the 11-bit quantum (1/2047
// of a tile) plus what mediump arithmetic moves, on most pixels.
TEST(DebugOutput, PackingWithoutFragmentHighpIsDecodedAsSuch) {
    PlaneScene p;
    p.field.kind = FieldKind::sine;
    p.field.size = 128;
    p.view_angle_deg = 40.0f;
    p.technique = Technique::pom;
    p.options.shadow = ShadowMode::hard;
    const SceneDesc scene = p.build();
    auto capture = [&](bool emulate, VariantKey& key) {
        RendererOptions options;
        options.effect_planner = effect_planner;
        options.texture_files = texture_files();
        options.emulate_no_fragment_highp = emulate;
        auto renderer = Renderer::create(options);
        EXPECT_TRUE(renderer.ok());
        EXPECT_TRUE((*renderer)->load(scene).ok());
        EXPECT_TRUE((*renderer)->set_view(scene.camera, 96, 96).ok());
        key = (*renderer)->reports().at(0).variant;
        auto surfaces = capture_surfaces(**renderer, 96, 96);
        EXPECT_TRUE(surfaces.ok()) << surfaces.error().message;
        return std::move(*surfaces);
    };
    VariantKey highp_key, mediump_key;
    const SurfaceImage highp = capture(false, highp_key);
    const SurfaceImage mediump = capture(true, mediump_key);
    EXPECT_FALSE(highp_key.no_fragment_highp);
    if (test_es_major() >= 3) {
        // ES 3.0 guarantees fragment highp: the option changes nothing.
        EXPECT_FALSE(mediump_key.no_fragment_highp);
        EXPECT_EQ(highp.packing_bits, 0);
        EXPECT_EQ(mediump.packing_bits, 0);
        return;
    }
    EXPECT_TRUE(mediump_key.no_fragment_highp);
    EXPECT_EQ(highp.packing_bits, 24);
    EXPECT_EQ(mediump.packing_bits, 11);
    std::vector<double> uv_diff;
    for (size_t i = 0; i < highp.samples.size(); ++i) {
        const SurfaceSample& a = highp.samples[i];
        const SurfaceSample& b = mediump.samples[i];
        ASSERT_EQ(a.covered, b.covered) << "pixel " << i;
        if (!a.covered) continue;
        // Modulo the tile: both are fract(uv).
        const double du = std::fabs(a.uv.x - b.uv.x), dv = std::fabs(a.uv.y - b.uv.y);
        uv_diff.push_back(std::max(std::min(du, 1.0 - du), std::min(dv, 1.0 - dv)));
    }
    ASSERT_GT(uv_diff.size(), 1000u);
    std::sort(uv_diff.begin(), uv_diff.end());
    // A decode of the 11-bit packing as 24 bits would put every uv near 0.
    EXPECT_LT(uv_diff[uv_diff.size() / 2], 4.0 / 2047.0) << "median uv difference, tiles";
}

}  // namespace
}  // namespace px::test
