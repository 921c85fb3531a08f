// The host's GL state survives the renderer, on ES 2.0 and ES 3.0: the test
// sets every piece of state the library touches (and the state that would
// change what it draws) to a value other than GL's default, loads a scene,
// draws it, reads its debug outputs and reads a target back, then checks
// every piece again with plain glGet calls of its own.
#include "gpu_fixture.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "parallaxes/gl/state.h"
#include "parallaxes/render/surface_capture.h"

namespace px::test {
namespace {

using StateList = std::vector<std::pair<std::string, double>>;

// Everything the test sets, read with the raw API (not gl/state.h's code).
StateList read_state(bool es3) {
    StateList s;
    auto integer = [&s](const std::string& name, GLenum pname, int count = 1) {
        GLint v[4] = {0, 0, 0, 0};
        glGetIntegerv(pname, v);
        for (int i = 0; i < count; ++i) s.emplace_back(name + (count > 1 ? "[" + std::to_string(i) + "]" : ""), v[i]);
    };
    auto real = [&s](const std::string& name, GLenum pname, int count = 1) {
        GLfloat v[4] = {0, 0, 0, 0};
        glGetFloatv(pname, v);
        for (int i = 0; i < count; ++i) s.emplace_back(name + (count > 1 ? "[" + std::to_string(i) + "]" : ""), v[i]);
    };
    auto enabled = [&s](const std::string& name, GLenum cap) { s.emplace_back(name, glIsEnabled(cap) ? 1.0 : 0.0); };
    if (es3) {
        integer("draw framebuffer", GL_DRAW_FRAMEBUFFER_BINDING);
        integer("read framebuffer", GL_READ_FRAMEBUFFER_BINDING);
        integer("vertex array", GL_VERTEX_ARRAY_BINDING);
        integer("pixel pack buffer", GL_PIXEL_PACK_BUFFER_BINDING);
        integer("pixel unpack buffer", GL_PIXEL_UNPACK_BUFFER_BINDING);
        integer("unpack row length", GL_UNPACK_ROW_LENGTH);
        integer("unpack skip rows", GL_UNPACK_SKIP_ROWS);
        integer("unpack skip pixels", GL_UNPACK_SKIP_PIXELS);
        integer("unpack image height", GL_UNPACK_IMAGE_HEIGHT);
        integer("pack row length", GL_PACK_ROW_LENGTH);
        integer("pack skip rows", GL_PACK_SKIP_ROWS);
        enabled("primitive restart", GL_PRIMITIVE_RESTART_FIXED_INDEX);
    } else {
        integer("framebuffer", GL_FRAMEBUFFER_BINDING);
    }
    integer("renderbuffer", GL_RENDERBUFFER_BINDING);
    integer("program", GL_CURRENT_PROGRAM);
    integer("array buffer", GL_ARRAY_BUFFER_BINDING);
    integer("element array buffer", GL_ELEMENT_ARRAY_BUFFER_BINDING);
    integer("active texture", GL_ACTIVE_TEXTURE);
    GLint active = 0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    for (int unit = 0; unit < 4; ++unit) {
        glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
        integer("texture unit " + std::to_string(unit), GL_TEXTURE_BINDING_2D);
        if (es3) integer("sampler unit " + std::to_string(unit), GL_SAMPLER_BINDING);
    }
    glActiveTexture(static_cast<GLenum>(active));
    integer("pack alignment", GL_PACK_ALIGNMENT);
    integer("unpack alignment", GL_UNPACK_ALIGNMENT);
    integer("viewport", GL_VIEWPORT, 4);
    enabled("scissor test", GL_SCISSOR_TEST);
    integer("scissor box", GL_SCISSOR_BOX, 4);
    enabled("cull face", GL_CULL_FACE);
    integer("cull face mode", GL_CULL_FACE_MODE);
    integer("front face", GL_FRONT_FACE);
    enabled("polygon offset fill", GL_POLYGON_OFFSET_FILL);
    enabled("depth test", GL_DEPTH_TEST);
    integer("depth func", GL_DEPTH_FUNC);
    integer("depth write mask", GL_DEPTH_WRITEMASK);
    real("depth range", GL_DEPTH_RANGE, 2);
    real("depth clear value", GL_DEPTH_CLEAR_VALUE);
    enabled("blend", GL_BLEND);
    integer("blend src rgb", GL_BLEND_SRC_RGB);
    integer("blend dst rgb", GL_BLEND_DST_RGB);
    integer("blend src alpha", GL_BLEND_SRC_ALPHA);
    integer("blend dst alpha", GL_BLEND_DST_ALPHA);
    integer("blend equation rgb", GL_BLEND_EQUATION_RGB);
    integer("blend equation alpha", GL_BLEND_EQUATION_ALPHA);
    real("blend color", GL_BLEND_COLOR, 4);
    integer("color write mask", GL_COLOR_WRITEMASK, 4);
    real("color clear value", GL_COLOR_CLEAR_VALUE, 4);
    enabled("stencil test", GL_STENCIL_TEST);
    integer("stencil func", GL_STENCIL_FUNC);
    integer("stencil ref", GL_STENCIL_REF);
    integer("stencil value mask", GL_STENCIL_VALUE_MASK);
    integer("stencil fail", GL_STENCIL_FAIL);
    integer("stencil pass depth fail", GL_STENCIL_PASS_DEPTH_FAIL);
    integer("stencil pass depth pass", GL_STENCIL_PASS_DEPTH_PASS);
    integer("stencil write mask", GL_STENCIL_WRITEMASK);
    integer("stencil back func", GL_STENCIL_BACK_FUNC);
    integer("stencil back write mask", GL_STENCIL_BACK_WRITEMASK);
    enabled("dither", GL_DITHER);
    enabled("sample coverage", GL_SAMPLE_COVERAGE);
    enabled("sample alpha to coverage", GL_SAMPLE_ALPHA_TO_COVERAGE);
    // The vertex attributes of the bound VAO (ES 3.0: the host's own) or of
    // the context (ES 2.0).
    // Every slot the library may point (kLibraryAttributeSlots, the ES 2.0
    // minimum of 8): until 2026-12-05 the guard saved 4, while the library
    // enabled 6, then 8, on every ES 2.0 draw.
    for (GLuint a = 0; a < static_cast<GLuint>(kLibraryAttributeSlots); ++a) {
        const std::string name = "attribute " + std::to_string(a);
        GLint v = 0;
        glGetVertexAttribiv(a, GL_VERTEX_ATTRIB_ARRAY_ENABLED, &v);
        s.emplace_back(name + " enabled", v);
        glGetVertexAttribiv(a, GL_VERTEX_ATTRIB_ARRAY_SIZE, &v);
        s.emplace_back(name + " size", v);
        glGetVertexAttribiv(a, GL_VERTEX_ATTRIB_ARRAY_STRIDE, &v);
        s.emplace_back(name + " stride", v);
        glGetVertexAttribiv(a, GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING, &v);
        s.emplace_back(name + " buffer", v);
        void* pointer = nullptr;
        glGetVertexAttribPointerv(a, GL_VERTEX_ATTRIB_ARRAY_POINTER, &pointer);
        s.emplace_back(name + " pointer", static_cast<double>(reinterpret_cast<std::uintptr_t>(pointer)));
    }
    return s;
}

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

// Sets every entry of read_state to a value other than GL's default.
struct HostObjects {
    GLuint program = 0, vertex_array = 0, buffers[4] = {0, 0, 0, 0}, textures[4] = {0, 0, 0, 0},
           samplers[4] = {0, 0, 0, 0}, renderbuffer = 0;
};

HostObjects set_host_state(bool es3, GLuint draw_framebuffer, GLuint read_framebuffer) {
    HostObjects h;
    h.program = host_program(es3);
    glGenBuffers(4, h.buffers);
    for (GLuint b : h.buffers) {
        glBindBuffer(GL_ARRAY_BUFFER, b);
        glBufferData(GL_ARRAY_BUFFER, 1024, nullptr, GL_STATIC_DRAW);
    }
    glGenTextures(4, h.textures);
    glGenRenderbuffers(1, &h.renderbuffer);
    glBindRenderbuffer(GL_RENDERBUFFER, h.renderbuffer);
    if (es3) {
        glGenVertexArrays(1, &h.vertex_array);
        glBindVertexArray(h.vertex_array);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, draw_framebuffer);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, read_framebuffer);
        // A pixel buffer bound for unpacking: an upload that did not unbind
        // it would read the host's buffer instead of the image.
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, h.buffers[2]);
        glBindBuffer(GL_PIXEL_PACK_BUFFER, h.buffers[3]);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 7);
        glPixelStorei(GL_UNPACK_SKIP_ROWS, 1);
        glPixelStorei(GL_UNPACK_SKIP_PIXELS, 2);
        glPixelStorei(GL_UNPACK_IMAGE_HEIGHT, 3);
        glPixelStorei(GL_PACK_ROW_LENGTH, 5);
        glPixelStorei(GL_PACK_SKIP_ROWS, 1);
        glEnable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
        glGenSamplers(4, h.samplers);
    } else {
        glBindFramebuffer(GL_FRAMEBUFFER, draw_framebuffer);
    }
    glUseProgram(h.program);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, h.buffers[1]);  // into the host's VAO on ES 3.0
    glBindBuffer(GL_ARRAY_BUFFER, h.buffers[0]);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 12, reinterpret_cast<void*>(4));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 3, GL_FLOAT, GL_FALSE, 20, reinterpret_cast<void*>(8));
    glEnableVertexAttribArray(4);
    glVertexAttribPointer(4, 3, GL_FLOAT, GL_FALSE, 24, reinterpret_cast<void*>(12));
    glEnableVertexAttribArray(6);
    glVertexAttribPointer(6, 1, GL_FLOAT, GL_FALSE, 28, reinterpret_cast<void*>(16));
    glBindBuffer(GL_ARRAY_BUFFER, h.buffers[1]);
    for (int unit = 0; unit < 4; ++unit) {
        glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
        glBindTexture(GL_TEXTURE_2D, h.textures[unit]);
        // A sampler object overrides the texture's own filtering and wrapping.
        if (es3) glBindSampler(static_cast<GLuint>(unit), h.samplers[unit]);
    }
    glActiveTexture(GL_TEXTURE5);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 8);
    glViewport(3, 5, 7, 9);  // not HostIntegration's (1, 2, 3, 4), which an earlier test leaves
    // Scissor, stencil and the colour mask would each stop the draw: it must
    // set them aside and give them back.
    glEnable(GL_SCISSOR_TEST);
    glScissor(5, 6, 7, 8);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT);
    glFrontFace(GL_CW);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
    glDepthRangef(0.25f, 0.75f);
    glClearDepthf(0.5f);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_DST_COLOR, GL_ONE_MINUS_DST_ALPHA);
    glBlendEquationSeparate(GL_FUNC_SUBTRACT, GL_FUNC_REVERSE_SUBTRACT);
    glBlendColor(0.125f, 0.25f, 0.5f, 0.75f);
    glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
    glClearColor(0.125f, 0.25f, 0.375f, 0.5f);
    glEnable(GL_STENCIL_TEST);
    glStencilFuncSeparate(GL_FRONT, GL_NEVER, 3, 0x0F);
    glStencilFuncSeparate(GL_BACK, GL_LESS, 1, 0x07);
    glStencilOpSeparate(GL_FRONT, GL_INCR, GL_DECR, GL_INVERT);
    glStencilMaskSeparate(GL_FRONT, 0x55);
    glStencilMaskSeparate(GL_BACK, 0x33);
    glDisable(GL_DITHER);
    glEnable(GL_SAMPLE_COVERAGE);
    glEnable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    return h;
}

void delete_host_objects(HostObjects& h, bool es3) {
    glUseProgram(0);
    glDeleteProgram(h.program);
    glDeleteBuffers(4, h.buffers);
    glDeleteTextures(4, h.textures);
    glDeleteRenderbuffers(1, &h.renderbuffer);
    if (es3) {
        glBindVertexArray(0);
        glDeleteVertexArrays(1, &h.vertex_array);
        glDeleteSamplers(4, h.samplers);
    }
}

// Every entry the test sets differs from what the context had before (GL's
// defaults: every earlier test gives the state back), so that the check
// afterwards would see a change to it.
void expect_all_changed(const StateList& initial, const StateList& host) {
    ASSERT_EQ(initial.size(), host.size());
    // Entries that keep their default on purpose: attribute slots 1, 3, 5
    // and 7 (left disabled, so both kinds are covered), two colour channels.
    for (size_t i = 0; i < host.size(); ++i) {
        const std::string& name = host[i].first;
        if (name.rfind("attribute 1 ", 0) == 0 || name.rfind("attribute 3 ", 0) == 0 ||
            name.rfind("attribute 5 ", 0) == 0 || name.rfind("attribute 7 ", 0) == 0)
            continue;
        if (name == "color write mask[0]" || name == "color write mask[2]") continue;  // left on
        if (name == "scissor box[2]" || name == "scissor box[3]") continue;  // default is the first surface's size
        // The reference value reads back clamped to the bound framebuffer's
        // stencil bits, and the targets here have none.
        if (name == "stencil ref") continue;
        EXPECT_NE(initial[i].second, host[i].second) << name << " is still at its default: the test does not set it";
    }
}

TEST(HostState, EveryPieceSurvivesLoadDrawCaptureAndReadBack) {
    const bool es3 = test_es_major() >= 3;
    auto host_target = OffscreenTarget::create(64, 64);  // stands in for the app's own framebuffer
    ASSERT_TRUE(host_target.ok()) << host_target.error().message;
    auto other = OffscreenTarget::create(32, 32);
    auto third = OffscreenTarget::create(16, 16);
    ASSERT_TRUE(other.ok() && third.ok());

    // The image this scene gives with GL's default state around it.
    PlaneScene p;
    p.field.kind = FieldKind::bricks;
    p.field.size = 128;
    p.options.shadow = ShadowMode::soft;
    p.options.depth_write = true;
    const SceneDesc scene = p.build();
    const Image expected = render(scene, 64).image;

    const StateList initial = read_state(es3);
    HostObjects host = set_host_state(es3, other->target().framebuffer, third->target().framebuffer);
    const StateList before = read_state(es3);
    expect_all_changed(initial, before);

    auto renderer = Renderer::create();
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;
    Status loaded = (*renderer)->load(scene);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(read_state(es3), before) << "after load";
    Status drawn = (*renderer)->draw(host_target->target());
    ASSERT_TRUE(drawn.ok()) << drawn.error().message;
    const StateList after_draw = read_state(es3);
    Result<SurfaceImage> surfaces = capture_surfaces(**renderer, 32, 32);
    ASSERT_TRUE(surfaces.ok()) << surfaces.error().message;
    const StateList after_capture = read_state(es3);
    Result<Image> image = host_target->read_pixels();
    ASSERT_TRUE(image.ok()) << image.error().message;
    const StateList after_read = read_state(es3);
    delete_host_objects(host, es3);

    for (size_t i = 0; i < before.size(); ++i) {
        EXPECT_EQ(after_draw[i].second, before[i].second) << before[i].first << " changed by draw";
        EXPECT_EQ(after_capture[i].second, before[i].second) << before[i].first << " changed by capture_surfaces";
        EXPECT_EQ(after_read[i].second, before[i].second) << before[i].first << " changed by read_pixels";
    }
    // The host's scissor, stencil, blend, colour mask, depth state and (ES
    // 3.0) sampler objects and unpack buffer did not reach the image.
    const ImageDiff d = compare(*image, expected);
    EXPECT_EQ(d.max, 0) << "mean " << d.mean;
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
