// Texture files written by the field's own encoders (PVRTexToolCLI 4.17,
// astcenc 4.2.0, basisu 1.15: tests/fixtures/third_party/README.md), drawn
// against each tool's own decode of the same file. The marker image is
// asymmetric (red top-left, green top-right, blue bottom-left), so a texture
// drawn upside down fails: each case also draws the file with the opposite
// row order forced (first_row) and requires that to differ.
#include "gpu_fixture.h"

#include <string>

#include "parallaxes/render/offscreen_target.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/texture/containers.h"

namespace px::test {
namespace {

const std::string kDir = std::string(PX_SOURCE_DIR) + "/tests/fixtures/third_party/";

using FirstRow = TextureSource::FirstRow;

TextureSource file_source(const std::string& name, FirstRow row = FirstRow::file) {
    TextureSource s;
    s.kind = TextureSource::Kind::file;
    s.path = kDir + name;
    s.first_row = row;
    return s;
}

// The row order that is not the file's own.
FirstRow opposite(const std::string& name) {
    Result<TextureData> t = read_texture_file(kDir + name);
    EXPECT_TRUE(t.ok()) << t.error().message;
    return t && t->rows == RowOrder::top_first ? FirstRow::bottom : FirstRow::top;
}

// A flat plane seen straight on, filling most of the image, lit from above
// (+v): albedo (and normals) as the file gives them.
SceneDesc plane(Technique technique) {
    PlaneScene p;
    p.technique = technique;
    p.textured_albedo = false;
    p.distance = 2.8f;
    SceneDesc s = p.build();
    const float e = glm::radians(50.0f);
    s.lights[0].direction = -glm::vec3(0.0f, std::cos(e), std::sin(e));
    return s;
}

// linear: the image holds linear light (HostFrame::TargetColor::linear)
// instead of what an sRGB display is sent.
Image draw(const SceneDesc& scene, bool force_decode, bool linear = false) {
    RendererOptions options = reading_files();
    options.force_texture_decode = force_decode;
    auto renderer = Renderer::create(options);
    EXPECT_TRUE(renderer.ok()) << renderer.error().message;
    auto target = OffscreenTarget::create(128, 128);
    EXPECT_TRUE(target.ok());
    if (!renderer || !target) return {};
    Status loaded = (*renderer)->load(scene);
    EXPECT_TRUE(loaded.ok()) << loaded.error().message;
    if (!loaded) return {};
    HostFrame frame = (*renderer)->scene_frame(target->target());
    if (linear) frame.target_color = HostFrame::TargetColor::linear;
    EXPECT_TRUE((*renderer)->draw(frame).ok());
    Result<Image> image = target->read_pixels();
    EXPECT_TRUE(image.ok());
    return image ? std::move(*image) : Image{};
}

// Every container and format the tools wrote, with and without mips, top
// row first and bottom row first, one non-power-of-two. `bound`: mean
// difference (0..255) from the tool's own decode drawn as a PNG: the two
// decoders' disagreement plus bilinear rounding.
struct Case {
    const char* file;
    double bound;
};
const Case kAlbedoCases[] = {
    {"ptt_etc2_rgb.ktx", 1.0},        {"ptt_etc2_rgb_mips.ktx", 1.0}, {"ptt_etc2_rgb_flipped.ktx", 1.0},
    {"ptt_etc2_npot.ktx", 1.0},       {"ptt_etc1.pvr", 1.0},          {"ptt_etc1_flipped.pvr", 1.0},
    {"ptt_pvrtc4_mips.pvr", 1.0},     {"ptt_rgba8_flipped.pvr", 1.0}, {"astcenc_6x6.astc", 1.0},
    {"astcenc_4x4.ktx", 1.0},         {"astcenc_npot_5x5.astc", 1.0}, {"basisu_etc1_mips.ktx", 1.0},
    {"basisu_bc1_mips.ktx", 1.0},     {"basisu_pvrtc4_mips.ktx", 1.0}, {"ktxparse_etc2_rgb.ktx2", 1.0},
    {"ktxparse_etc2_rgb_ru.ktx2", 1.0},
    // sRGB colour as the encoders write it (make_srgb_fixtures.sh): KTX 1.1
    // sRGB ETC2 (with and without mips) and ASTC, PVR v3 colour space 1, KTX
    // 2.0 vkFormat 148 with an sRGB transfer function.
    {"ptt_etc2_rgb_srgb.ktx", 1.0},   {"ptt_etc2_rgb_srgb_mips.ktx", 1.0}, {"ptt_etc2_rgb_srgb.pvr", 1.0},
    {"astcenc_4x4_srgb.ktx", 1.0},    {"ktxparse_etc2_rgb_srgb.ktx2", 1.0},
};

TEST(ThirdParty, FilesDrawTheRightWayUpOnTheGpuAndThroughTheCpuDecoders) {
    for (const Case& c : kAlbedoCases) {
        SCOPED_TRACE(c.file);
        SceneDesc expected = plane(Technique::flat), given = expected, flipped = expected;
        expected.materials[0].albedo = file_source(std::string(c.file) + ".decoded.png");
        // The tool's decode drawn in the colour space the tool wrote: the
        // *_srgb files sRGB (make_srgb_fixtures.sh), the others linear
        // (PVRTexToolCLI's lRGB, astcenc's -cl, basisu), except that .astc
        // declares nothing and is read as sRGB. Known from how each was made,
        // not from the reader, which must agree.
        const std::string name = c.file;
        const bool made_srgb = name.find("_srgb") != std::string::npos ||
                               name.compare(name.size() - 5, 5, ".astc") == 0;
        Result<TextureData> declared = read_texture_file(kDir + c.file);
        ASSERT_TRUE(declared.ok());
        EXPECT_EQ(declared->srgb, name.find("_srgb") != std::string::npos) << declared->color_space_source;
        expected.materials[0].albedo.color_space =
            made_srgb ? TextureSource::ColorSpace::srgb : TextureSource::ColorSpace::linear;
        given.materials[0].albedo = file_source(c.file);
        flipped.materials[0].albedo = file_source(c.file, opposite(c.file));
        const Image want = draw(expected, false);
        for (bool force_decode : {false, true}) {
            SCOPED_TRACE(force_decode ? "decoded on the CPU" : "uploaded as the context takes it");
            const ImageDiff d = compare(draw(given, force_decode), want);
            EXPECT_LE(d.mean, c.bound) << "max " << d.max;
        }
        // The same file the other way up is far from the tool's picture.
        const ImageDiff wrong = compare(draw(flipped, false), want);
        EXPECT_GE(wrong.mean, 10.0) << "the marker is not asymmetric enough to catch a flip";
        // The CPU image (what the exact reference shades with) is the tool's
        // decode, row for row.
        Result<MaterialImages> images = build_material_images(given.materials[0], "");
        ASSERT_TRUE(images.ok()) << images.error().message;
        Result<Image> decoded = load_image(kDir + c.file + ".decoded.png", 4);
        ASSERT_TRUE(decoded.ok());
        EXPECT_LE(compare(images->albedo, *decoded).mean, c.bound);
    }
}

// A third-party height map under a PNG albedo: the relief lines up with the
// paint as it does when the height map is the PNG the tool decoded.
TEST(ThirdParty, HeightMapLinesUpWithAPngAlbedo) {
    // maxmip reads the height texels with texelFetch (GLSL ES 3.00 only).
    std::vector<Technique> techniques = {Technique::pom};
    if (test_es_major() >= 3) techniques.push_back(Technique::maxmip);
    for (Technique technique : techniques) {
        SCOPED_TRACE(technique_name(technique));
        SceneDesc png = plane(technique);
        png.materials[0].albedo = file_source("marker.png");
        png.materials[0].height_scale = 0.1f;
        png.camera.position = glm::vec3(0.0f, -1.6f, 2.3f);  // looking along +v, so parallax shifts in v
        SceneDesc ktx = png, flipped = png;
        png.materials[0].height = file_source("ptt_relief_etc2.ktx.decoded.png");
        ktx.materials[0].height = file_source("ptt_relief_etc2.ktx");
        flipped.materials[0].height = file_source("ptt_relief_etc2.ktx", opposite("ptt_relief_etc2.ktx"));
        const Image want = draw(png, false);
        const ImageDiff d = compare(draw(ktx, false), want);
        EXPECT_LE(d.mean, 1.0) << "max " << d.max;
        const ImageDiff wrong = compare(draw(flipped, false), want);
        EXPECT_GE(wrong.mean, 4.0 * std::max(d.mean, 0.5));
    }
}

// A normal map stored bottom row first (PVRTexToolCLI -flip y,flag) and one
// stored top row first light the raised square's bevels from the same side
// as the PNG they were made from: the rows are mirrored, the normals'
// green channel is not.
TEST(ThirdParty, FlippedNormalMapsLightTheirBevelsLikeThePng) {
    SceneDesc png = plane(Technique::normal);
    png.materials[0].albedo.kind = TextureSource::Kind::color;
    png.materials[0].albedo.color = glm::vec3(0.8f);
    png.materials[0].pack_height_in_normal_alpha = false;  // the PNG normal map alone, as the files are
    SceneDesc top = png, bottom = png, wrong = png;
    png.materials[0].normal = file_source("relief_normal.png");
    top.materials[0].normal = file_source("ptt_relief_normal.ktx");
    bottom.materials[0].normal = file_source("ptt_relief_normal_flipped.pvr");
    wrong.materials[0].normal = file_source("ptt_relief_normal_flipped.pvr", FirstRow::top);
    // Compared as light (linear output): the bevels are the bright part of
    // the image, where an sRGB display's encoding compresses differences.
    const Image want = draw(png, false, true);
    for (const SceneDesc* s : {&top, &bottom}) {
        const ImageDiff d = compare(draw(*s, false, true), want);
        EXPECT_LE(d.mean, 2.0) << s->materials[0].normal.path << " max " << d.max;
    }
    const ImageDiff wrong_way = compare(draw(wrong, false, true), want);
    std::printf("measured: normal map read the wrong way up: mean %.2f max %d\n", wrong_way.mean, wrong_way.max);
    EXPECT_GE(wrong_way.mean, 4.0);
}

// texinfo's row line, through the readers: what each tool's file says.
TEST(ThirdParty, EachContainerReportsItsRowOrderAndWhereItCameFrom) {
    const std::pair<const char*, const char*> cases[] = {
        {"ptt_etc2_rgb.ktx", "KTXOrientation \"S=r,T=d,R=i\""},
        {"ptt_etc2_rgb_flipped.ktx", "KTXOrientation \"S=r,T=u,R=i\""},
        {"ptt_etc1.pvr", "PVR v3 orientation metadata (y down)"},
        {"ptt_etc1_flipped.pvr", "PVR v3 orientation metadata (y up)"},
        {"astcenc_4x4.ktx", "no KTXorientation"},
        {"astcenc_6x6.astc", ".astc declares none"},
        {"basisu_etc1_mips.ktx", "no KTXorientation"},
        {"ktxparse_etc2_rgb.ktx2", "no KTXorientation: \"rd\", the KTX 2.0 default"},
        {"ktxparse_etc2_rgb_ru.ktx2", "KTXorientation \"ru\""},
    };
    for (auto [file, source] : cases) {
        Result<TextureData> t = read_texture_file(kDir + file);
        ASSERT_TRUE(t.ok()) << file << ": " << t.error().message;
        EXPECT_NE(t->rows_source.find(source), std::string::npos) << file << ": " << t->rows_source;
    }
}

}  // namespace
}  // namespace px::test
