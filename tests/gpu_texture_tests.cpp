// Compressed textures on the GPU: Mesa's decoders against ours, scenes drawn
// from every asset variant against the uncompressed one, the CPU fallback
// (PVRTC, which llvmpipe does not sample; everything on ES 2.0 but ETC1),
// maxmip exact on an 11-bit EAC height map, and non-power-of-two maps.
#include "gpu_fixture.h"

#include <GLES3/gl3.h>

#include <filesystem>
#include <string>
#include <vector>

#include "parallaxes/gl/caps.h"
#include "parallaxes/gl/texture.h"
#include "parallaxes/profiling/measurement/bench.h"
#include "parallaxes/reference/reference_image.h"
#include "parallaxes/render/surface_capture.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/scene/scene_textures.h"
#include "parallaxes/texture/codecs.h"
#include "parallaxes/texture/convert.h"
#include "parallaxes/texture/decode.h"

namespace px::test {
namespace {

// An RGBA8 test image with smooth regions, edges and alpha steps.
Image test_image(int w, int h) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = 4;
    img.pixels.resize(static_cast<size_t>(w) * h * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::uint8_t* t = img.texel(x, y);
            t[0] = static_cast<std::uint8_t>(x * 255 / std::max(1, w - 1));
            t[1] = static_cast<std::uint8_t>(y * 255 / std::max(1, h - 1));
            t[2] = static_cast<std::uint8_t>(((x / 8 + y / 8) % 2) ? 220 : 30);
            t[3] = static_cast<std::uint8_t>(x < w / 2 ? 255 : 96);
        }
    return img;
}

// Every texel of level 0 of `texture` as the GPU samples it (texelFetch,
// written to RGBA8): Mesa's decoder of the format.
Image gpu_texels(GLuint texture, int w, int h) {
    static const char* vs =
        "#version 300 es\nvoid main() { vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);"
        " gl_Position = vec4(p, 0.0, 1.0); }\n";
    static const char* fs =
        "#version 300 es\nprecision highp float; uniform highp sampler2D t; out vec4 c;\n"
        "void main() { c = texelFetch(t, ivec2(gl_FragCoord.xy), 0); }\n";
    auto compile = [](GLenum type, const char* src) {
        GLuint s = glCreateShader(type);
        glShaderSource(s, 1, &src, nullptr);
        glCompileShader(s);
        GLint ok = 0;
        glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
        EXPECT_TRUE(ok);
        return s;
    };
    GLuint program = glCreateProgram();
    GLuint v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, fs);
    glAttachShader(program, v);
    glAttachShader(program, f);
    glLinkProgram(program);
    auto target = OffscreenTarget::create(w, h);
    EXPECT_TRUE(target.ok());
    Image out;
    if (!target) return out;
    glBindFramebuffer(GL_FRAMEBUFFER, target->target().framebuffer);
    glViewport(0, 0, w, h);
    // Whatever earlier tests left set (host-state tests leave plenty).
    for (GLenum cap : {GL_DEPTH_TEST, GL_BLEND, GL_SCISSOR_TEST, GL_STENCIL_TEST, GL_CULL_FACE, GL_RASTERIZER_DISCARD,
                       GL_SAMPLE_ALPHA_TO_COVERAGE, GL_SAMPLE_COVERAGE, GL_POLYGON_OFFSET_FILL})
        glDisable(cap);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glBindSampler(0, 0);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glUseProgram(program);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, texture);
    glUniform1i(glGetUniformLocation(program, "t"), 0);
    GLuint vao = 0;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glDeleteVertexArrays(1, &vao);
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteProgram(program);
    glDeleteShader(v);
    glDeleteShader(f);
    auto pixels = target->read_pixels();
    EXPECT_TRUE(pixels.ok());
    if (pixels) out = std::move(*pixels);
    return out;
}

// Mesa is the decoder of record for the formats it samples: our CPU
// decode of the same bytes (what a context without the format gets) must
// give the texels Mesa gives. Exact for ETC/EAC (every texel fixed by the
// specification; R11/RG11 shown at 8 bits both ways); within one level for
// BC1..BC5, whose 1/3 and 2/3 palette entries decoders may round either
// way (the S3TC and RGTC specifications allow it), and for ASTC, whose LDR
// texels are 16-bit values that astcenc's 8-bit decode and Mesa's float
// path round to 8 bits differently.
TEST(Textures, CpuDecodersMatchMesaOnEverySampledFormat) {
    if (test_es_major() < 3) GTEST_SKIP() << "texelFetch needs OpenGL ES 3.0; this run is ES 2.0";
    const Caps caps = query_caps();
    const int w = 37, h = 21;  // partial blocks at both edges
    const Image source = test_image(w, h);
    int checked = 0;
    for (const FormatInfo& f : all_formats()) {
        if (!f.compressed() || f.family == FormatFamily::pvrtc) continue;
        if (!context_samples(caps, f.format)) continue;
      // An encoded image, and for the block formats every bit of which is
      // meaningful (ETC2, EAC, BC) random blocks too: they reach every mode
      // (ETC2's T, H and planar; BC1's three-colour blocks) whatever our
      // encoders choose. ASTC's random blocks are mostly reserved encodings;
      // ETC1's differential blocks whose sums leave 0..31 are undefined in
      // ETC1 (ETC2 gave them its T, H and planar modes), and decoders differ.
      for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1 && (f.family == FormatFamily::astc || f.family == FormatFamily::etc1)) break;
        Result<std::vector<std::uint8_t>> bytes = encode_image(f.format, w, h, source.pixels.data());
        if (pass == 1 || !bytes) {
            // No encoder for this format (bc1_rgba, bc2): random blocks only.
            bytes = std::vector<std::uint8_t>(*image_bytes(f.format, w, h));
            std::uint32_t state = 12345u + static_cast<std::uint32_t>(f.format);
            for (std::uint8_t& b : *bytes) {
                state = state * 1664525u + 1013904223u;
                b = static_cast<std::uint8_t>(state >> 24);
            }
        }
        TextureData data;
        data.format = f.format;
        data.width = w;
        data.height = h;
        data.levels.push_back(TextureLevel{static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(h), bytes->size(), 0});
        data.bytes = *bytes;
        Result<Image> cpu = decode_rgba8(data);
        ASSERT_TRUE(cpu.ok()) << f.name << ": " << cpu.error().message;
        TextureUpload report;
        Result<Texture> gpu_texture = upload_texture_data(data, caps, f.name, false, false, &report,
                                                        [](const TextureData& d, size_t l) { return decode_rgba8(d, l); });
        ASSERT_TRUE(gpu_texture.ok()) << f.name << ": " << gpu_texture.error().message;
        EXPECT_TRUE(report.direct) << f.name;
        const Image gpu = gpu_texels(gpu_texture->handle.get(), w, h);
        ASSERT_EQ(gpu.width, w);
        // Every channel: GL fills those the format lacks (0, 0, 1) as we do.
        int worst = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 4; ++c) {
                    const int d = std::abs(int(cpu->texel(x, y)[c]) - int(gpu.texel(x, y)[c]));
                    worst = std::max(worst, d);
                }
        // On random blocks Mesa's 8-bit integer arithmetic for the BC3 alpha
        // and BC4/BC5 palettes lands up to 2 levels from the rounded exact
        // fractions (measured); encoded images stay within 1.
        const bool bc = f.family == FormatFamily::s3tc || f.family == FormatFamily::rgtc;
        const int allowed = bc ? (pass == 1 ? 2 : 1) : f.family == FormatFamily::astc ? 1 : 0;
        EXPECT_LE(worst, allowed) << f.name << (pass ? " (random blocks)" : "") << ": our CPU decode differs from Mesa's by "
                                  << worst << " levels";
        ++checked;
      }
    }
    // llvmpipe samples ETC1, ETC2/EAC (5), ASTC (14), S3TC (4), RGTC (2):
    // 26 formats, 11 of them twice.
    EXPECT_GE(checked, 37) << "formats this context samples directly";
}

// A scene whose one material reads every slot from files of `variant`.
struct Converted {
    SceneDesc scene;
    std::vector<ConvertedFile> files;
};

Converted convert(const SceneDesc& scene, const std::string& variant, const std::string& folder) {
    Converted c{scene, {}};
    ConvertOptions o;
    auto formats = asset_formats(variant);
    EXPECT_TRUE(formats.ok());
    o.formats = *formats;
    auto files = convert_scene_textures(c.scene, o, folder, nullptr);
    EXPECT_TRUE(files.ok()) << variant << ": " << files.error().message;
    if (files) c.files = *files;
    return c;
}

SceneDesc textured_plane() {
    PlaneScene p;
    p.field.kind = FieldKind::bricks;
    p.field.size = 128;
    p.technique = Technique::pom;
    p.view_angle_deg = 40.0f;
    return p.build();
}

// The same scene drawn from each compressed variant of its assets and from
// the uncompressed one (the same asset step: r8 height, rgb8 normals, rgb8
// albedo, the same mip chains), with the per-texture path each took. The
// bound is on the mean difference per channel (0..255) over the image; the
// maxima are brick edges, where a height difference moves a step's
// silhouette by a pixel. Measured on ES 3.0 (llvmpipe, 128 px): etc1 2.72,
// etc2 2.07, astc 0.39, bc 2.25, pvrtc 4.76 (PVRTC's low-pass colours blur
// the mortar joints of the height and normal maps).
TEST(Textures, CompressedVariantsDrawTheUncompressedImage) {
    const SceneDesc scene = textured_plane();
    const std::string root = test_folder("textures", "variants");
    const Converted raw = convert(scene, "raw", root + "/raw");
    const Rendered reference = render(raw.scene, 128);
    ASSERT_EQ(reference.image.width, 128);
    const std::pair<const char*, double> variants[] = {{"etc1", 3.4}, {"etc2", 2.6}, {"astc", 0.6}, {"bc", 2.8}, {"pvrtc", 6.0}};
    for (auto [variant, bound] : variants) {
        const Converted c = convert(scene, variant, root + "/" + variant);
        ASSERT_EQ(c.files.size(), 3u) << variant;  // height, normal, albedo
        auto renderer = Renderer::create(reading_files());
        ASSERT_TRUE(renderer.ok());
        auto target = OffscreenTarget::create(128, 128);
        ASSERT_TRUE(target.ok());
        Status loaded = (*renderer)->load(c.scene);
        ASSERT_TRUE(loaded.ok()) << variant << ": " << loaded.error().message;
        ASSERT_TRUE((*renderer)->draw(target->target()).ok());
        auto image = target->read_pixels();
        ASSERT_TRUE(image.ok());
        const ImageDiff d = compare(*image, reference.image);
        std::printf("measured: %-6s mean %.2f max %d (bound %.1f)\n", variant, d.mean, d.max, bound);
        EXPECT_LT(d.mean, bound) << variant << " (max " << d.max << ")";
        // Every file's upload is reported, with the path its context allows.
        const Caps& caps = (*renderer)->caps();
        int files = 0;
        for (const TextureUpload& u : (*renderer)->texture_uploads()) {
            if (u.container == "image") continue;
            ++files;
            // An sRGB albedo goes up direct where the context samples the
            // format's sRGB form (S3TC's is not listed by llvmpipe: decoded).
            const bool srgb = u.color_space.rfind("sRGB, decoded by the texture unit", 0) == 0;
            EXPECT_EQ(u.direct, srgb ? context_samples_srgb(caps, u.format) : context_samples(caps, u.format))
                << variant << " " << u.what << ": " << u.color_space;
            EXPECT_NE(u.path.find(u.direct ? "direct" : "CPU decode"), std::string::npos) << u.path;
            // Every level as the file gives it (ES 2.0's base-level copy for the trace: one).
            const bool trace_copy = u.what.find("base level for the trace") != std::string::npos;
            EXPECT_EQ(u.levels, trace_copy ? 1 : full_mip_count(u.width, u.height)) << u.what;
        }
        EXPECT_GE(files, 3) << variant;  // ES 2.0 uploads the traced height once more (base level)
    }
}

// PVRTC on Mesa (no GL_IMG_texture_compression_pvrtc): the file goes up
// through the CPU decoder, the report says so, and the image is the one a
// direct upload of the decoded texels would give.
TEST(Textures, PvrtcRendersThroughTheCpuFallbackAndSaysSo) {
    const SceneDesc scene = textured_plane();
    const std::string root = test_folder("textures", "pvrtc");
    const Converted c = convert(scene, "pvrtc", root);
    auto renderer = Renderer::create(reading_files());
    ASSERT_TRUE(renderer.ok());
    if ((*renderer)->caps().has("GL_IMG_texture_compression_pvrtc")) GTEST_SKIP() << "this context samples PVRTC";
    ASSERT_TRUE((*renderer)->load(c.scene).ok());
    int fallbacks = 0;
    for (const TextureUpload& u : (*renderer)->texture_uploads()) {
        if (u.container == "image") continue;
        EXPECT_EQ(u.format, TextureFormat::pvrtc1_rgb_4bpp);
        EXPECT_FALSE(u.direct);
        EXPECT_NE(u.path.find("CPU decode to RGBA8"), std::string::npos) << u.path;
        EXPECT_NE(u.path.find("GL_IMG_texture_compression_pvrtc"), std::string::npos) << u.path;
        ++fallbacks;
    }
    EXPECT_GE(fallbacks, 3);
    auto target = OffscreenTarget::create(128, 128);
    ASSERT_TRUE(target.ok());
    ASSERT_TRUE((*renderer)->draw(target->target()).ok());
    auto image = target->read_pixels();
    ASSERT_TRUE(image.ok());
    // Forcing the decode of a format the context does sample gives the same
    // image as its direct upload: the fallback uploads the same texels.
    // ETC1, whose texels our decoder gives exactly as Mesa does (above).
    const Converted etc1 = convert(scene, "etc1", root + "/etc1");
    const Rendered direct = render(etc1.scene, 128);
    RendererOptions forced;
    forced.effect_planner = effect_planner;
    forced.texture_files = texture_files();
    forced.get_proc_address = platform::HeadlessContext::proc_loader();
    forced.force_texture_decode = true;
    auto decoding = Renderer::create(forced);
    ASSERT_TRUE(decoding.ok());
    ASSERT_TRUE((*decoding)->load(etc1.scene).ok());
    for (const TextureUpload& u : (*decoding)->texture_uploads())
        if (u.container != "image") EXPECT_NE(u.path.find("decoding forced"), std::string::npos) << u.path;
    ASSERT_TRUE((*decoding)->draw(target->target()).ok());
    auto decoded = target->read_pixels();
    ASSERT_TRUE(decoded.ok());
    const ImageDiff d = compare(*decoded, direct.image);
    EXPECT_EQ(d.max, 0) << "mean " << d.mean;
}

// maxmip stays exact on a compressed height map: its max pyramid is built
// from the decoded 11-bit texels the GPU samples (not from the 8-bit
// original), and the reference traces the same texels.
TEST(Textures, MaxmipIsExactOnAnElevenBitEacHeightMap) {
    if (test_es_major() < 3) GTEST_SKIP() << "11-bit heights need OpenGL ES 3.0 (ES 2.0 decodes EAC R11 to 8 bits)";
    for (const std::string& scene_name : {std::string("sine"), std::string("bricks")}) {
        for (double angle : {0.0, 70.0}) {
            auto scene = profiling::bench_scene(scene_name, angle);
            ASSERT_TRUE(scene.ok());
            const Converted c = convert(*scene, "etc2", test_folder("textures", scene_name + std::to_string(int(angle))));
            SceneDesc s = c.scene;
            s.materials[0].technique.technique = Technique::maxmip;
            auto images = build_material_images(s.materials[0], s.base_dir);
            ASSERT_TRUE(images.ok()) << images.error().message;
            ASSERT_TRUE(images->layout.height_11bit);
            // The 11-bit texels are not all on the 8-bit grid: the test would
            // not tell 11 from 8 bits otherwise.
            int off_grid = 0;
            for (float t : images->traced.texels) off_grid += std::fabs(t * 255.0f - std::round(t * 255.0f)) > 0.01f;
            EXPECT_GT(off_grid, 0);
            auto truth = reference::render_reference(s, 96, 96);
            ASSERT_TRUE(truth.ok()) << truth.error().message;
            auto renderer = Renderer::create(reading_files());
            ASSERT_TRUE(renderer.ok());
            ASSERT_TRUE((*renderer)->load(s).ok());
            ASSERT_TRUE((*renderer)->set_view(s.camera, 96, 96).ok());
            EXPECT_TRUE((*renderer)->reports()[0].variant.height_11bit) << (*renderer)->reports()[0].variant.describe();
            auto surfaces = capture_surfaces(**renderer, 96, 96);
            ASSERT_TRUE(surfaces.ok()) << surfaces.error().message;
            auto e = reference::compare_surfaces(*surfaces, truth->surface, truth->texture_width, truth->texture_height);
            ASSERT_TRUE(e.ok());
            EXPECT_LE(e->uv_error_mean, 0.1) << scene_name << " at " << angle;
            EXPECT_GT(e->pixels, 500);
        }
    }
}

// maxmip on non-square height maps, both ways round, is exact on both
// contexts: on GLSL ES 1.00 a field wider than tall has pyramid levels past
// log2(height) one row each in its atlas (assets/max_mipmap.h), which the
// shader's closed form must place where build_max_atlas put them.
TEST(Textures, MaxmipIsExactOnNonSquareHeightMaps) {
    const std::string root = test_folder("textures", "nonsquare");
    for (const auto& [w, h] : {std::pair<int, int>{128, 16}, std::pair<int, int>{16, 128}}) {
        HeightField field;
        field.width = w;
        field.height = h;
        field.texels.resize(static_cast<size_t>(w) * h);
        // A smooth swell, and thin ridges only in the fourth eighth of the
        // long side (cells touching them: the second quarter): an upper level
        // read at the wrong place (the level below it, whose node 0 is the
        // first quarter) misses them.
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const int along = w > h ? x : y, across = w > h ? y : x;
                const bool ridge = along * 8 / std::max(w, h) == 3 && (along + across) % 5 == 0;
                field.ref(x, y) = ridge ? 1.0f : 0.3f + 0.2f * std::sin(x * 0.19f + y * 0.41f);
            }
        Result<TextureData> t = encode_height_texture(field, TextureFormat::r8);
        ASSERT_TRUE(t.ok()) << t.error().message;
        t->container = ContainerKind::ktx1;
        auto bytes = write_ktx1(*t);
        ASSERT_TRUE(bytes.ok());
        const std::string path = root + "/h" + std::to_string(w) + "x" + std::to_string(h) + ".ktx";
        {
            FILE* f = std::fopen(path.c_str(), "wb");
            ASSERT_TRUE(f);
            std::fwrite(bytes->data(), 1, bytes->size(), f);
            std::fclose(f);
        }
        for (double angle : {60.0, 85.0}) {
            auto scene = profiling::bench_scene("sine", angle);
            ASSERT_TRUE(scene.ok());
            MaterialDesc& m = scene->materials[0];
            m.height = TextureSource{};
            m.height.kind = TextureSource::Kind::file;
            m.height.path = path;
            m.pack_height_in_normal_alpha = false;
            m.technique.technique = Technique::maxmip;
            const std::string where = std::to_string(w) + "x" + std::to_string(h) + " at " + std::to_string(angle);
            auto truth = reference::render_reference(*scene, 96, 96);
            ASSERT_TRUE(truth.ok()) << truth.error().message;
            ASSERT_EQ(truth->texture_width, w) << where;
            auto renderer = Renderer::create(reading_files());
            ASSERT_TRUE(renderer.ok());
            Status loaded = (*renderer)->load(*scene);
            ASSERT_TRUE(loaded.ok()) << loaded.error().message;
            ASSERT_TRUE((*renderer)->set_view(scene->camera, 96, 96).ok());
            EXPECT_EQ((*renderer)->reports()[0].variant.technique, Technique::maxmip) << where;
            auto surfaces = capture_surfaces(**renderer, 96, 96);
            ASSERT_TRUE(surfaces.ok()) << surfaces.error().message;
            auto e = reference::compare_surfaces(*surfaces, truth->surface, truth->texture_width, truth->texture_height);
            ASSERT_TRUE(e.ok());
            EXPECT_LE(e->uv_error_mean, 0.1) << where;
            EXPECT_GT(e->pixels, 500) << where;
        }
    }
}

// Non-power-of-two and non-square height maps draw with every technique:
// maxmip's is resampled to the next power of two (said in the notes), the
// others take it as it is.
TEST(Textures, NonPowerOfTwoHeightMapsWorkWithEveryTechnique) {
    const std::string root = test_folder("textures", "npot");
    HeightField field;
    field.width = 90;
    field.height = 50;
    field.texels.resize(90 * 50);
    for (int y = 0; y < 50; ++y)
        for (int x = 0; x < 90; ++x)
            field.ref(x, y) = 0.5f + 0.5f * std::sin(x * 0.21f) * std::cos(y * 0.33f);
    Result<TextureData> t = encode_height_texture(field, TextureFormat::r8);
    ASSERT_TRUE(t.ok()) << t.error().message;
    t->container = ContainerKind::ktx1;
    auto bytes = write_ktx1(*t);
    ASSERT_TRUE(bytes.ok());
    const std::string path = root + "/h.ktx";
    {
        FILE* f = std::fopen(path.c_str(), "wb");
        ASSERT_TRUE(f);
        std::fwrite(bytes->data(), 1, bytes->size(), f);
        std::fclose(f);
    }
    for (const TechniqueInfo& info : technique_table()) {
        if (info.min_es_major > test_es_major()) continue;
        SceneDesc scene = textured_plane();
        scene.materials[0].height.kind = TextureSource::Kind::file;
        scene.materials[0].height.path = path;
        scene.materials[0].technique.technique = info.id;
        auto renderer = Renderer::create(reading_files());
        ASSERT_TRUE(renderer.ok());
        Status loaded = (*renderer)->load(scene);
        ASSERT_TRUE(loaded.ok()) << info.name << ": " << loaded.error().message;
        ASSERT_TRUE((*renderer)->set_view(scene.camera, 64, 64).ok());
        EXPECT_EQ((*renderer)->reports()[0].variant.technique, info.id) << info.name;
        bool resampled = false;
        for (const std::string& n : (*renderer)->texture_notes()) resampled |= n.find("resampled to 128x64") != std::string::npos;
        EXPECT_EQ(resampled, info.id == Technique::maxmip) << info.name;
        auto target = OffscreenTarget::create(64, 64);
        ASSERT_TRUE(target.ok());
        EXPECT_TRUE((*renderer)->draw(target->target()).ok()) << info.name;
    }
}

// On an OpenGL ES 2.0 context without GL_OES_texture_npot a repeating
// non-power-of-two texture is incomplete: the load resamples every such
// texture (files decoded first) and says so, and the image is close to
// the one a context with npot draws.
TEST(Textures, EsTwoWithoutNpotResamplesAndSaysSo) {
    if (test_es_major() != 2) GTEST_SKIP() << "an ES 2.0 case";
    PlaneScene p;
    p.field.kind = FieldKind::sine;
    p.field.size = 96;
    p.technique = Technique::pom;
    p.view_angle_deg = 30.0f;
    SceneDesc scene = p.build();
    scene.materials[0].albedo.field.size = 80;
    const Rendered with_npot = render(scene, 96);
    RendererOptions o;
    o.effect_planner = effect_planner;
    o.texture_files = texture_files();
    o.get_proc_address = platform::HeadlessContext::proc_loader();
    o.emulate_no_texture_npot = true;
    auto renderer = Renderer::create(o);
    ASSERT_TRUE(renderer.ok());
    Status loaded = (*renderer)->load(scene);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    std::string notes;
    for (const std::string& n : (*renderer)->texture_notes()) notes += n + "\n";
    EXPECT_NE(notes.find("height 96x96 resampled to 128x128"), std::string::npos) << notes;
    EXPECT_NE(notes.find("albedo 80x80 resampled to 128x128"), std::string::npos) << notes;
    EXPECT_NE(notes.find("GL_OES_texture_npot"), std::string::npos) << notes;
    auto target = OffscreenTarget::create(96, 96);
    ASSERT_TRUE(target.ok());
    ASSERT_TRUE((*renderer)->draw(target->target()).ok());
    auto image = target->read_pixels();
    ASSERT_TRUE(image.ok());
    EXPECT_LT(compare(*image, with_npot.image).mean, 3.0);
}

// GLSL ES 1.00 shades the hit with texture2D, whose mip level comes from the
// hit uv's derivatives: they jump where the relief occludes itself, and
// the pixels along every rim read a blurred mip. With derivatives, the
// shader biases that level to the unshifted uv's (PX_SHADE_LOD_BIAS), as
// GLSL ES 3.00's textureGrad reads: against the exact reference's colour,
// the rims' pixels come back. The same draw with the bias off (the variant
// of a context without GL_OES_standard_derivatives) shows the defect.
TEST(Textures, EsTwoShadesTheHitAtTheUnshiftedUvsMipLevel) {
    if (test_es_major() != 2) GTEST_SKIP() << "an ES 2.0 case";
    for (Technique technique : {Technique::maxmip, Technique::pom}) {
        PlaneScene p;
        p.field.kind = FieldKind::hemispheres;
        // Magnified (a 64-texel tile over about 200 pixels): the unshifted
        // uv's level is the base level, which the reference shades with.
        p.field.size = 64;
        p.height_scale = 0.1f;
        p.technique = technique;
        p.options.max_samples = 64;
        p.view_angle_deg = 55.0f;
        p.textured_albedo = false;
        const SceneDesc scene = p.build();
        constexpr int kSize = 256;
        auto truth = reference::render_reference(scene, kSize, kSize);
        ASSERT_TRUE(truth.ok()) << truth.error().message;
        std::vector<Image> images;
        for (bool bias : {true, false}) {
            RendererOptions o;
            o.effect_planner = effect_planner;
            o.get_proc_address = platform::HeadlessContext::proc_loader();
            if (!bias)
                o.variant_transform = [](const VariantKey& k) {
                    VariantKey without = k;
                    without.no_derivatives = true;
                    return without;
                };
            auto renderer = Renderer::create(o);
            ASSERT_TRUE(renderer.ok());
            Status loaded = (*renderer)->load(scene);
            ASSERT_TRUE(loaded.ok()) << loaded.error().message;
            auto target = OffscreenTarget::create(kSize, kSize);
            ASSERT_TRUE(target.ok());
            ASSERT_TRUE((*renderer)->draw(target->target()).ok());
            ASSERT_EQ((*renderer)->reports().front().variant.shade_lod_bias(), bias);
            auto image = target->read_pixels();
            ASSERT_TRUE(image.ok());
            images.push_back(std::move(*image));
        }
        // Pixels more than 16 levels off the exact reference's colour.
        auto off = [&](const Image& a) {
            int n = 0;
            for (size_t i = 0; i + 3 < a.pixels.size(); i += 4)
                for (int c = 0; c < 3; ++c)
                    if (std::abs(int(a.pixels[i + c]) - int(truth->color.pixels[i + c])) > 16) {
                        ++n;
                        break;
                    }
            return n;
        };
        const int with_bias = off(images[0]), without = off(images[1]);
        std::printf("%s: %d pixels off the reference with the bias, %d without\n", technique_name(technique), with_bias,
                    without);
        // Measured: 78 and 104 pixels with the bias, 760 and 765 without.
        EXPECT_LT(with_bias, kSize * kSize / 200) << technique_name(technique);
        EXPECT_GT(without, 4 * with_bias) << technique_name(technique);
    }
}

}  // namespace
}  // namespace px::test
