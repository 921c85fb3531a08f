// The precision emulation on the GPU (include/parallaxes/emulation/precision.h): the
// rewritten shaders run on llvmpipe. ES 3.0 only (the emitted sources are
// GLSL ES 3.00; ES 2.0 variants run through RendererOptions::emulate_es2):
// the gpu_es2 entry leaves these tests out (tests/CMakeLists.txt).
#include "gpu_fixture.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "parallaxes/emulation/precision.h"
#include "parallaxes/gl/caps.h"
#include "parallaxes/gl/framebuffer.h"
#include "parallaxes/gl/handles.h"
#include "parallaxes/gl/state.h"
#include "parallaxes/render/surface_capture.h"

namespace px::test {
namespace {

using emulation::PrecisionProfile;

ShaderHandle compile_or_fail(GLenum stage, const std::string& source) {
    ShaderHandle shader(glCreateShader(stage));
    const char* text = source.c_str();
    glShaderSource(shader.get(), 1, &text, nullptr);
    glCompileShader(shader.get());
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.get(), GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        char log[4096] = {};
        glGetShaderInfoLog(shader.get(), sizeof log, nullptr, log);
        ADD_FAILURE() << "compile failed:\n" << log << "\n" << source;
    }
    return shader;
}

// Draws one pixel with `fragment` (after the emulation under `profile`) into
// an RGBA32F target, the uniforms u_a and u_b set to a and b; returns it.
glm::vec4 draw_pixel(const std::string& fragment, PrecisionProfile profile, const glm::vec4& a, const glm::vec4& b) {
    const std::string vertex =
        "#version 300 es\nvoid main() {\n"
        "    gl_Position = vec4(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID & 2) * 2 - 1), 0.0, 1.0);\n}\n";
    auto vs = emulation::emulate_precision(vertex, ShaderStage::vertex, profile);
    auto fs = emulation::emulate_precision(fragment, ShaderStage::fragment, profile);
    EXPECT_TRUE(vs.ok()) << vs.error().message;
    EXPECT_TRUE(fs.ok()) << fs.error().message;
    if (!vs || !fs) return glm::vec4(0.0f);
    const Caps caps = query_caps();
    auto target = make_color_depth_framebuffer(1, 1, ColorFormat::rgba32f, caps);
    EXPECT_TRUE(target.ok()) << target.error().message;
    if (!target) return glm::vec4(0.0f);
    ShaderHandle v = compile_or_fail(GL_VERTEX_SHADER, *vs);
    ShaderHandle f = compile_or_fail(GL_FRAGMENT_SHADER, *fs);
    ProgramHandle program(glCreateProgram());
    glAttachShader(program.get(), v.get());
    glAttachShader(program.get(), f.get());
    glLinkProgram(program.get());
    GLint linked = GL_FALSE;
    glGetProgramiv(program.get(), GL_LINK_STATUS, &linked);
    EXPECT_EQ(linked, GL_TRUE);
    // Whatever earlier tests left set goes back afterwards; the draw itself
    // runs with nothing but the program between the triangle and the pixel.
    SavedGlState saved(caps);
    glBindFramebuffer(GL_FRAMEBUFFER, target->framebuffer.get());
    glBindVertexArray(0);
    glViewport(0, 0, 1, 1);
    for (GLenum cap : {GL_DEPTH_TEST, GL_SCISSOR_TEST, GL_STENCIL_TEST, GL_BLEND, GL_CULL_FACE, GL_RASTERIZER_DISCARD,
                       GL_SAMPLE_COVERAGE, GL_SAMPLE_ALPHA_TO_COVERAGE})
        glDisable(cap);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    set_pack_defaults(caps);
    glUseProgram(program.get());
    glUniform4f(glGetUniformLocation(program.get(), "u_a"), a.x, a.y, a.z, a.w);
    glUniform4f(glGetUniformLocation(program.get(), "u_b"), b.x, b.y, b.z, b.w);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glm::vec4 out(0.0f);
    glReadPixels(0, 0, 1, 1, GL_RGBA, GL_FLOAT, &out[0]);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    return out;
}

bool same_bits(float x, float y) { return std::memcmp(&x, &y, 4) == 0; }

// A mediump sum that rounds in fp16 (1 + 0.000732 is 1.000977 there, and
// 1.000732 in fp32), a sum past 65504 (inf), a product in fp16's subnormal
// range, and a mediump product stored into a lowp variable: on the GPU each
// equals round_fp16 / round_lowp applied on the CPU after every operation.
TEST(Emulation, RewrittenShaderRoundsAsTheCpu) {
    if (test_es_major() < 3) GTEST_SKIP() << "the emitted shaders are GLSL ES 3.00; this run is ES 2.0";
    const std::string fragment =
        "#version 300 es\nprecision mediump float;\n"
        "uniform mediump vec4 u_a;\nuniform mediump vec4 u_b;\n"
        "layout(location = 0) out highp vec4 o;\n"
        "void main() {\n"
        "    mediump float x = u_a.x + u_b.x;\n"
        "    mediump float y = u_a.y + u_b.y;\n"
        "    mediump float z = u_a.z * u_b.z;\n"
        "    lowp float w = u_a.w * u_b.w;\n"
        "    o = vec4(x, y, z, w);\n"
        "}\n";
    const glm::vec4 a(1.0f, 60000.0f, 1.0e-3f, 0.3f);
    const glm::vec4 b(0.000732f, 10000.0f, 4.1e-3f, 3.7f);
    using emulation::round_fp16;
    using emulation::round_lowp;
    const float x = round_fp16(round_fp16(a.x) + round_fp16(b.x));
    const float y = round_fp16(round_fp16(a.y) + round_fp16(b.y));
    const float z = round_fp16(round_fp16(a.z) * round_fp16(b.z));
    const float w16 = round_fp16(round_fp16(a.w) * round_fp16(b.w));
    // The chosen inputs do what they are for.
    ASSERT_NE(x, a.x + b.x);
    ASSERT_TRUE(std::isinf(y));
    ASSERT_LT(z, std::ldexp(1.0f, -14));
    ASSERT_GT(z, 0.0f);
    ASSERT_NE(round_lowp(w16), w16);

    const glm::vec4 fp16 = draw_pixel(fragment, PrecisionProfile::fp16, a, b);
    EXPECT_TRUE(same_bits(fp16.x, x)) << fp16.x << " vs " << x;
    EXPECT_TRUE(same_bits(fp16.y, y)) << fp16.y << " vs " << y;
    EXPECT_TRUE(same_bits(fp16.z, z)) << fp16.z << " vs " << z;
    EXPECT_TRUE(same_bits(fp16.w, w16)) << fp16.w << " vs " << w16;  // lowp is fp16 in this profile

    const glm::vec4 lowp = draw_pixel(fragment, PrecisionProfile::lowp, a, b);
    EXPECT_TRUE(same_bits(lowp.x, x)) << lowp.x << " vs " << x;
    EXPECT_TRUE(same_bits(lowp.w, round_lowp(w16))) << lowp.w << " vs " << round_lowp(w16);
}

std::string field_name(const SurfaceSample& s) {
    return "uv (" + std::to_string(s.uv.x) + ", " + std::to_string(s.uv.y) + ") height " + std::to_string(s.height) +
           " visibility " + std::to_string(s.visibility) + (s.covered ? "" : " uncovered");
}

bool same_sample(const SurfaceSample& a, const SurfaceSample& b) {
    return a.covered == b.covered && a.uv == b.uv && a.height == b.height && a.visibility == b.visibility;
}

struct Capture {
    SurfaceImage surfaces;
    std::string description;  // the variants drawn
};

Capture capture(const SceneDesc& scene, bool es2, const ShaderTransform& transform) {
    RendererOptions options;
    options.effect_planner = effect_planner;
    options.texture_files = texture_files();
    options.get_proc_address = platform::HeadlessContext::proc_loader();
    options.emulate_es2 = es2;
    options.shader_transform = transform;
    Capture c;
    auto renderer = Renderer::create(options);
    EXPECT_TRUE(renderer.ok()) << renderer.error().message;
    if (!renderer) return c;
    Status loaded = (*renderer)->load(scene);
    EXPECT_TRUE(loaded.ok()) << loaded.error().message;
    if (!loaded) return c;
    auto surfaces = capture_surfaces(**renderer, 128, 128);
    for (const DrawReport& r : (*renderer)->reports()) c.description += r.variant.describe();
    EXPECT_TRUE(surfaces.ok()) << surfaces.error().message;
    if (surfaces) c.surfaces = std::move(*surfaces);
    return c;
}

ShaderTransform emulate(PrecisionProfile profile) {
    return [profile](const std::string& source, ShaderStage stage) {
        return emulation::emulate_precision(source, stage, profile);
    };
}

// Pixels where two captures differ in anything (coverage, uv, height, visibility).
int differing(const SurfaceImage& a, const SurfaceImage& b, std::string* first = nullptr) {
    if (a.samples.size() != b.samples.size() || a.samples.empty()) return -1;
    int count = 0;
    for (size_t i = 0; i < a.samples.size(); ++i) {
        if (same_sample(a.samples[i], b.samples[i])) continue;
        if (first && count == 0)
            *first = "pixel " + std::to_string(i) + ": " + field_name(a.samples[i]) + " vs " + field_name(b.samples[i]);
        ++count;
    }
    return count;
}

// The control: every technique of the catalogue, with and without shadows,
// its ES 3.0 variants and its ES 2.0 ones (through emulate_es2), rewritten
// under the fp32 profile, must give the GPU's own debug outputs bit for bit:
// the profile re-emits the same program with the same precisions, so any
// difference is a rewriter bug. The fp16 profile must change some pixels, so
// that a transform doing nothing cannot pass.
TEST(Emulation, Fp32ProfileReproducesEveryTechniquePerPixel) {
    if (test_es_major() < 3) GTEST_SKIP() << "the emitted shaders are GLSL ES 3.00; this run is ES 2.0";
    int compared = 0;
    int fp16_changed = 0;
    for (const TechniqueInfo& info : technique_table()) {
        std::vector<ShadowMode> shadows{ShadowMode::none};
        if (info.options & kOptShadow) shadows = {ShadowMode::none, ShadowMode::hard, ShadowMode::soft};
        for (bool es2 : {false, true}) {
            if (es2 && info.min_es_major > 2) continue;  // maxmip: ES 3.0 only
            for (ShadowMode shadow : shadows) {
                PlaneScene p;
                p.field.kind = FieldKind::hemispheres;
                p.field.size = 128;
                p.height_scale = 0.1f;
                p.technique = info.id;
                p.options.shadow = shadow;
                p.view_angle_deg = 60.0f;
                const SceneDesc scene = p.build();
                const std::string what = std::string(info.name) + (es2 ? " es2" : " es3") + " shadow " +
                                         shadow_mode_name(shadow);
                const Capture original = capture(scene, es2, {});
                const Capture fp32 = capture(scene, es2, emulate(PrecisionProfile::identity));
                ASSERT_FALSE(original.surfaces.samples.empty()) << what;
                int covered = 0;
                for (const SurfaceSample& s : original.surfaces.samples) covered += s.covered;
                EXPECT_GT(covered, 128 * 128 / 4) << what << ": the plane fills the view";
                std::string first;
                const int diff = differing(original.surfaces, fp32.surfaces, &first);
                EXPECT_EQ(diff, 0) << what << " (" << original.description << "): " << first;
                // ES 2.0 variants too come back as floats: the context is ES 3.0.
                EXPECT_EQ(original.surfaces.packing_bits, 0) << what;
                ++compared;
                if (shadow == ShadowMode::none) {
                    const Capture fp16 = capture(scene, es2, emulate(PrecisionProfile::fp16));
                    const int changed = differing(original.surfaces, fp16.surfaces);
                    std::printf("  %-28s %5d covered, fp32 differs at %d, fp16 at %d pixels\n", what.c_str(), covered,
                                diff, changed);
                    fp16_changed += changed > 0;
                } else {
                    std::printf("  %-28s %5d covered, fp32 differs at %d pixels\n", what.c_str(), covered, diff);
                }
            }
        }
    }
    EXPECT_GT(compared, 20);
    EXPECT_GT(fp16_changed, 0) << "the fp16 profile changed no pixel of any technique: a no-op transform?";
}

// A transform's error reaches the caller of load(), naming the variant.
TEST(Emulation, TransformErrorsNameTheVariant) {
    if (test_es_major() < 3) GTEST_SKIP() << "the emitted shaders are GLSL ES 3.00; this run is ES 2.0";
    RendererOptions options;
    options.effect_planner = effect_planner;
    options.texture_files = texture_files();
    options.shader_transform = [](const std::string&, ShaderStage) -> Result<std::string> {
        return make_error("refused for the test");
    };
    auto renderer = Renderer::create(options);
    ASSERT_TRUE(renderer.ok());
    PlaneScene p;
    p.field.kind = FieldKind::hemispheres;
    Status loaded = (*renderer)->load(p.build());
    ASSERT_FALSE(loaded.ok());
    EXPECT_NE(loaded.error().message.find("refused for the test"), std::string::npos) << loaded.error().message;
    EXPECT_NE(loaded.error().message.find("pom"), std::string::npos) << loaded.error().message;
}

}  // namespace
}  // namespace px::test
