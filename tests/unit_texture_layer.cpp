// The texture layer above the codecs and containers: format arithmetic,
// what a context samples, the asset step's chains and layouts, texture files
// in materials (layout, 11-bit heights, refusals) and the resampling of
// non-power-of-two maps. GL-free.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "parallaxes/core/files.h"
#include "parallaxes/effects/variant.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/scene/scene_textures.h"
#include "parallaxes/texture/containers.h"
#include "parallaxes/texture/convert.h"
#include "parallaxes/texture/decode.h"
#include "parallaxes/texture/format.h"

namespace px {
namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::string temp_dir(const std::string& name) {
    const std::string d = ::testing::TempDir() + "/px_texture_layer_" + std::to_string(::getpid()) + "_" + name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

TEST(TextureFormats, BlockArithmetic) {
    // 37 x 20 texels: ceil(37/4) x ceil(20/4) = 10 x 5 blocks.
    EXPECT_EQ(*image_bytes(TextureFormat::etc2_rgb8, 37, 20), 10u * 5u * 8u);
    EXPECT_EQ(*image_bytes(TextureFormat::eac_rg11, 37, 20), 10u * 5u * 16u);
    // ASTC 12x10: ceil(37/12) x ceil(20/10) = 4 x 2 blocks of 16 bytes.
    EXPECT_EQ(*image_bytes(TextureFormat::astc_12x10, 37, 20), 4u * 2u * 16u);
    // PVRTC1: at least 2 x 2 blocks (8 x 8 texels at 4 bpp, 16 x 8 at 2 bpp).
    EXPECT_EQ(*image_bytes(TextureFormat::pvrtc1_rgb_4bpp, 1, 1), 32u);
    EXPECT_EQ(*image_bytes(TextureFormat::pvrtc1_rgba_2bpp, 4, 4), 32u);
    EXPECT_EQ(*image_bytes(TextureFormat::pvrtc1_rgb_2bpp, 64, 32), 8u * 8u * 8u);
    EXPECT_EQ(*image_bytes(TextureFormat::rgb8, 3, 2), 18u);
    // Never wraps: zero, or more than 2^31 per side, is no size.
    EXPECT_FALSE(image_bytes(TextureFormat::rgba8, 0, 4));
    EXPECT_FALSE(image_bytes(TextureFormat::rgba8, std::uint64_t{1} << 40, 4));
    EXPECT_EQ(full_mip_count(37, 20), 6);  // 37x20 18x10 9x5 4x2 2x1 1x1
    EXPECT_EQ(full_mip_count(1, 1), 1);
    EXPECT_EQ(mip_extent(37, 3), 4u);
    EXPECT_EQ(mip_extent(37, 40), 1u);
}

TEST(TextureFormats, NamesAndCodes) {
    for (const FormatInfo& f : all_formats()) {
        Result<TextureFormat> parsed = parse_format(f.name);
        ASSERT_TRUE(parsed.ok()) << f.name;
        EXPECT_EQ(*parsed, f.format);
        EXPECT_EQ(&format_info(f.format), &f);
        if (f.compressed()) {
            Result<TextureFormat> gl = format_from_gl(f.gl_internal_format, 0, 0);
            ASSERT_TRUE(gl.ok()) << f.name;
            EXPECT_EQ(*gl, f.format);
        }
        if (f.vk_format) EXPECT_EQ(*format_from_vk(f.vk_format), f.format) << f.name;
    }
    EXPECT_TRUE(contains(parse_format("etc3").error().message, "known: r8, rg8"));
    EXPECT_TRUE(contains(format_from_gl(0x9279, 0, 0).error().message, "sRGB"));
    EXPECT_TRUE(contains(format_from_vk(0).error().message, "Basis Universal"));
    EXPECT_TRUE(contains(format_from_vk(145).error().message, "BC6H or BC7"));
    EXPECT_TRUE(contains(format_from_pvr(15, 0).error().message, "BC7"));
    // The table's "no PVR code" marker is no code.
    EXPECT_FALSE(format_from_pvr(0xFFFFFFFFu, 0).ok());
    // Uncompressed PVR: channel letters and bit counts.
    const std::uint64_t rgba8 = 'r' | ('g' << 8) | ('b' << 16) | (std::uint64_t('a') << 24) |
                                (std::uint64_t(0x08080808) << 32);
    EXPECT_EQ(*format_from_pvr(rgba8, 0), TextureFormat::rgba8);
    EXPECT_FALSE(format_from_pvr(rgba8, 12).ok());  // float channels
}

TEST(TextureFormats, WhatAContextSamples) {
    Caps es2 = Caps::full(2);
    EXPECT_FALSE(context_samples(es2, TextureFormat::etc2_rgb8));
    EXPECT_FALSE(context_samples(es2, TextureFormat::etc1_rgb8));
    es2.extensions.insert("GL_OES_compressed_ETC1_RGB8_texture");
    EXPECT_TRUE(context_samples(es2, TextureFormat::etc1_rgb8));
    EXPECT_TRUE(context_samples(es2, TextureFormat::rgba8));
    Caps es3 = Caps::full(3);
    EXPECT_TRUE(context_samples(es3, TextureFormat::eac_r11));
    EXPECT_FALSE(context_samples(es3, TextureFormat::astc_4x4));
    EXPECT_FALSE(context_samples(es3, TextureFormat::pvrtc1_rgb_4bpp));
    // ETC1 goes up as ETC2 RGB on ES 3.0 without the ETC1 extension.
    EXPECT_TRUE(context_samples(es3, TextureFormat::etc1_rgb8));
    EXPECT_EQ(upload_internal_format(es3, TextureFormat::etc1_rgb8), glenum::kRgb8Etc2);
    // An extension whose format the context does not list is not sampled.
    es3.extensions.insert("GL_KHR_texture_compression_astc_ldr");
    es3.compressed_formats = {glenum::kRgb8Etc2, glenum::kR11Eac, glenum::kAstc4x4};
    EXPECT_TRUE(context_samples(es3, TextureFormat::astc_4x4));
    EXPECT_FALSE(context_samples(es3, TextureFormat::astc_6x6));
    EXPECT_FALSE(context_samples(es3, TextureFormat::eac_rg11));
    EXPECT_TRUE(contains(format_requirement(TextureFormat::pvrtc1_rgb_4bpp), "GL_IMG_texture_compression_pvrtc"));
}

TEST(TextureAssetStep, ChainsOfAnySize) {
    HeightField field;
    field.width = 37;
    field.height = 20;
    field.texels.assign(37 * 20, 0.25f);
    for (TextureFormat f : {TextureFormat::r8, TextureFormat::eac_r11, TextureFormat::bc4, TextureFormat::astc_6x6}) {
        Result<TextureData> t = encode_height_texture(field, f);
        ASSERT_TRUE(t.ok()) << format_name(f) << ": " << t.error().message;
        ASSERT_EQ(t->levels.size(), 6u) << format_name(f);
        EXPECT_EQ(t->levels[2].width, 9u);
        EXPECT_EQ(t->levels[2].height, 5u);
        // A constant field stays constant down the chain.
        for (size_t level = 0; level < t->levels.size(); ++level) {
            Result<Image> rgba = decode_rgba8(*t, level);
            ASSERT_TRUE(rgba.ok());
            for (size_t i = 0; i < rgba->pixels.size(); i += 4)
                ASSERT_NEAR(rgba->pixels[i], 64, 1) << format_name(f) << " level " << level;
        }
    }
    // PVRTC1 needs powers of two.
    EXPECT_TRUE(contains(encode_height_texture(field, TextureFormat::pvrtc1_rgb_4bpp).error().message, "power-of-two"));
}

TEST(TextureAssetStep, NormalLayouts) {
    Image normal;
    normal.width = normal.height = 8;
    normal.channels = 4;
    normal.pixels.assign(8 * 8 * 4, 0);
    for (size_t i = 0; i < normal.pixels.size(); i += 4) {
        normal.pixels[i] = 160;  // x = 0.255
        normal.pixels[i + 1] = 128;
        normal.pixels[i + 2] = 247;
        normal.pixels[i + 3] = 255;
    }
    // Two channels: x, y only.
    Result<TextureData> rg = encode_normal_texture(normal, TextureFormat::rg8);
    ASSERT_TRUE(rg.ok());
    EXPECT_EQ(rg->levels.size(), 4u);
    EXPECT_EQ(rg->bytes[0], 160);
    EXPECT_EQ(rg->bytes[1], 128);
    // A normal map cannot live in one channel.
    EXPECT_TRUE(contains(encode_normal_texture(normal, TextureFormat::eac_r11).error().message, "two or more channels"));
    // Mip levels of unit normals stay unit normals.
    Result<TextureData> rgb = encode_normal_texture(normal, TextureFormat::rgb8);
    ASSERT_TRUE(rgb.ok());
    const std::uint8_t* last = rgb->image(rgb->levels.size() - 1);
    const double x = last[0] / 127.5 - 1, y = last[1] / 127.5 - 1, z = last[2] / 127.5 - 1;
    EXPECT_NEAR(std::sqrt(x * x + y * y + z * z), 1.0, 0.01);
}

TEST(TextureAssetStep, Variants) {
    EXPECT_EQ(asset_formats("etc2")->height, TextureFormat::eac_r11);
    EXPECT_EQ(asset_formats("etc2")->normal, TextureFormat::eac_rg11);
    EXPECT_EQ(asset_formats("bc")->normal, TextureFormat::bc5);
    EXPECT_EQ(asset_formats("astc")->albedo, TextureFormat::astc_4x4);
    EXPECT_EQ(asset_formats("astc_10x8")->height, TextureFormat::astc_10x8);
    EXPECT_FALSE(asset_formats("astc_3x3").ok());
    EXPECT_TRUE(contains(asset_formats("dxt").error().message, "known: raw, etc1"));
}

// A scene's material through the asset step, read back from its files.
SceneDesc one_material_scene(const FieldSpec& field, Technique technique) {
    SceneDesc s;
    MaterialDesc m;
    m.name = "m";
    m.height.kind = TextureSource::Kind::procedural;
    m.height.field = field;
    m.technique.technique = technique;
    s.materials.push_back(m);
    return s;
}

TEST(TextureFilesInMaterials, LayoutAndElevenBitHeights) {
    FieldSpec sine;
    sine.kind = FieldKind::sine;
    sine.size = 64;
    SceneDesc scene = one_material_scene(sine, Technique::pom);
    ConvertOptions o;
    o.formats = *asset_formats("etc2");
    Result<std::vector<ConvertedFile>> files = convert_scene_textures(scene, o, temp_dir("etc2"), nullptr);
    ASSERT_TRUE(files.ok()) << files.error().message;
    ASSERT_EQ(files->size(), 2u);  // height and normal; the default albedo stays a colour
    const MaterialDesc& m = scene.materials[0];
    EXPECT_EQ(m.height.kind, TextureSource::Kind::file);
    EXPECT_TRUE(is_texture_file(m.height.path));
    Result<MaterialImages> images = build_material_images(m, "");
    ASSERT_TRUE(images.ok()) << images.error().message;
    EXPECT_FALSE(images->layout.packed_height);  // texture files are never packed
    EXPECT_TRUE(images->layout.normal_rg);
    EXPECT_TRUE(images->layout.height_11bit);
    ASSERT_TRUE(images->height_texture);
    EXPECT_EQ(images->height_texture->format, TextureFormat::eac_r11);
    EXPECT_EQ(images->height_texture->levels.size(), 7u);
    // The traced field is the decoded 11-bit texels: multiples of 1/2047,
    // and not all on the 8-bit grid.
    int off_8bit = 0;
    for (float t : images->traced.texels) {
        const float v = t * 2047.0f;
        ASSERT_NEAR(v, std::round(v), 1e-3f);
        off_8bit += std::fabs(t * 255.0f - std::round(t * 255.0f)) > 0.01f;
    }
    EXPECT_GT(off_8bit, 0);
    // The variant keys carry the layout.
    VariantKey k;
    k.technique = Technique::maxmip;
    const VariantKey laid = k.with_layout(images->layout);
    EXPECT_NE(laid.id(), k.id());
    bool rg = false, eleven = false;
    for (const ShaderDefine& d : laid.defines()) {
        rg |= d.name == "PX_NORMAL_RG";
        eleven |= d.name == "PX_HEIGHT_11BIT";
    }
    EXPECT_TRUE(rg);
    EXPECT_TRUE(eleven);
    // Only the exact walk snaps heights: pom's key ignores the 11 bits.
    VariantKey pom;
    pom.technique = Technique::pom;
    EXPECT_FALSE(pom.with_layout(images->layout).canonical().height_11bit);
}

TEST(TextureFilesInMaterials, Refusals) {
    const std::string dir = temp_dir("refusals");
    MaterialDesc m;
    m.name = "m";
    m.height.kind = TextureSource::Kind::file;
    m.height.path = dir + "/missing.ktx";
    EXPECT_TRUE(contains(build_material_images(m, "").error().message, "missing.ktx"));
    // Not a container at all.
    ASSERT_TRUE(write_file_atomically(dir + "/text.ktx", std::string("hello, world")).ok());
    m.height.path = dir + "/text.ktx";
    EXPECT_TRUE(contains(build_material_images(m, "").error().message, "not a texture container"));
    // A depth map in a texture file: the GPU would sample it upside down.
    HeightField f;
    f.width = f.height = 4;
    f.texels.assign(16, 0.5f);
    Result<TextureData> t = encode_height_texture(f, TextureFormat::r8);
    ASSERT_TRUE(t.ok());
    auto bytes = write_ktx1(*t);
    ASSERT_TRUE(bytes.ok());
    ASSERT_TRUE(write_file_atomically(dir + "/h.ktx", bytes->data(), bytes->size()).ok());
    m.height.path = dir + "/h.ktx";
    m.height.convention = HeightConvention::depth;
    EXPECT_TRUE(contains(build_material_images(m, "").error().message, "must hold height"));
    // A cube map is not a material's texture.
    Result<TextureData> cube = allocate_texture(TextureFormat::r8, 4, 4, 1, 1, 6, 1 << 20);
    ASSERT_TRUE(cube.ok());
    auto cube_bytes = write_ktx1(*cube);
    ASSERT_TRUE(cube_bytes.ok());
    ASSERT_TRUE(write_file_atomically(dir + "/cube.ktx", cube_bytes->data(), cube_bytes->size()).ok());
    m.height.path = dir + "/cube.ktx";
    m.height.convention = HeightConvention::height;
    EXPECT_TRUE(contains(build_material_images(m, "").error().message, "6 faces"));
}

TEST(TextureFilesInMaterials, NonPowerOfTwoResampling) {
    FieldSpec f;
    f.kind = FieldKind::hemispheres;
    f.size = 96;
    // pom takes the 96 x 96 field as it is.
    Result<MaterialImages> pom = build_material_images(one_material_scene(f, Technique::pom).materials[0], "");
    ASSERT_TRUE(pom.ok());
    EXPECT_EQ(pom->traced.width, 96);
    EXPECT_TRUE(pom->notes.empty());
    // maxmip's pyramid needs powers of two: resampled, and said.
    Result<MaterialImages> maxmip = build_material_images(one_material_scene(f, Technique::maxmip).materials[0], "");
    ASSERT_TRUE(maxmip.ok());
    EXPECT_EQ(maxmip->traced.width, 128);
    EXPECT_EQ(maxmip->normal.width, 128);  // the packed normal map carries the height
    ASSERT_EQ(maxmip->notes.size(), 1u);
    EXPECT_TRUE(contains(maxmip->notes[0], "height 96x96 resampled to 128x128"));
    // The resampled field samples the original surface at the new centres.
    const double u = (5 + 0.5) / 128.0, v = (77 + 0.5) / 128.0;
    EXPECT_NEAR(maxmip->field.at(5, 77), pom->field.sample_bilinear(u, v), 1e-5);
    // No npot on the context: every texture.
    MaterialImageOptions no_npot;
    no_npot.power_of_two_textures = true;
    SceneDesc s = one_material_scene(f, Technique::pom);
    s.materials[0].albedo.kind = TextureSource::Kind::procedural;
    s.materials[0].albedo.field.kind = FieldKind::sine;
    s.materials[0].albedo.field.size = 40;
    Result<MaterialImages> all = build_material_images(s.materials[0], "", no_npot);
    ASSERT_TRUE(all.ok());
    EXPECT_EQ(all->albedo.width, 64);
    EXPECT_EQ(all->traced.width, 128);
    EXPECT_EQ(all->notes.size(), 2u);
}

}  // namespace
}  // namespace px

namespace px {
namespace {

const std::string kThirdParty = std::string(PX_SOURCE_DIR) + "/tests/fixtures/third_party/";

// basisu 1.15 stores PVRTC1 levels under 8x8 as the one block they cover;
// read, they are repeated to the 2x2 blocks GL takes, and decode as basisu's
// own decoder shows them.
TEST(ThirdPartyFiles, BasisuPvrtcSmallLevelsDecodeAsBasisuDoes) {
    Result<TextureData> t = read_texture_file(kThirdParty + "basisu_pvrtc4_mips.ktx");
    ASSERT_TRUE(t.ok()) << t.error().message;
    ASSERT_EQ(t->levels.size(), 7u);
    EXPECT_EQ(t->notes.size(), 3u);
    for (std::size_t level : {4u, 5u, 6u}) {
        SCOPED_TRACE(level);
        EXPECT_EQ(t->levels[level].image_bytes, 32u);
        Result<Image> ours = decode_rgba8(*t, level);
        ASSERT_TRUE(ours.ok()) << ours.error().message;
        Result<Image> theirs = load_image(kThirdParty + "basisu_pvrtc4_mips.ktx.level" + std::to_string(level) +
                                              ".decoded.png", 4);
        ASSERT_TRUE(theirs.ok()) << theirs.error().message;
        ASSERT_EQ(ours->width, theirs->width);
        ASSERT_EQ(ours->height, theirs->height);
        // decode_rgba8 keeps the stored order (top row first here);
        // load_image puts the bottom row first.
        double sum = 0;
        for (int y = 0; y < ours->height; ++y)
            for (int x = 0; x < ours->width; ++x)
                for (int c = 0; c < 3; ++c)
                    sum += std::abs(ours->texel(x, y)[c] - theirs->texel(x, theirs->height - 1 - y)[c]);
        EXPECT_LE(sum / (3.0 * ours->width * ours->height), 1.0);
    }
}

// A short PVRTC level that is neither size is refused, saying both sizes.
TEST(ThirdPartyFiles, PvrtcLevelsOfAnyOtherSizeAreRefusedWithTheRule) {
    Result<std::vector<std::uint8_t>> file = read_file_bounded(kThirdParty + "basisu_pvrtc4_mips.ktx", 1 << 20, "test");
    ASSERT_TRUE(file.ok());
    std::vector<std::uint8_t> bytes = *file;
    // The 1x1 level is the last: 4 bytes of imageSize, 8 of data. Say 16.
    const std::size_t at = bytes.size() - 12;
    ASSERT_EQ(bytes[at], 8);
    bytes[at] = 16;
    bytes.insert(bytes.end(), 8, 0);
    Result<TextureData> t = read_texture(bytes.data(), bytes.size());
    ASSERT_FALSE(t.ok());
    EXPECT_NE(t.error().message.find("imageSize 16"), std::string::npos) << t.error().message;
    EXPECT_NE(t.error().message.find("at least 2x2 blocks"), std::string::npos) << t.error().message;
}

TEST(ThirdPartyFiles, UnsupportedFormatsAreNamed) {
    Result<TextureData> bc7 = read_texture_file(kThirdParty + "basisu_bc7.ktx");
    ASSERT_FALSE(bc7.ok());
    EXPECT_NE(bc7.error().message.find("BC7 (GL_COMPRESSED_RGBA_BPTC_UNORM)"), std::string::npos)
        << bc7.error().message;
    const std::uint8_t basis[] = {'s', 'B', 0x13, 0, 0x4D, 0, 0, 0};
    Result<TextureData> b = read_texture(basis, sizeof basis);
    ASSERT_FALSE(b.ok());
    EXPECT_NE(b.error().message.find("basisu -unpack"), std::string::npos) << b.error().message;
}

// This library's convert output, decoded by PVRTexToolCLI and astcenc at
// asset-build time (tests/fixtures/third_party/README.md): the tools show
// the marker the right way up, and today's encoder and writers still make
// exactly those files.
TEST(ThirdPartyFiles, OurFilesReadTheRightWayUpInTheToolsDecoders) {
    MaterialDesc m;
    m.name = "relief";
    m.albedo.kind = TextureSource::Kind::file;
    m.albedo.path = kThirdParty + "marker.png";
    Result<MaterialImages> images = build_material_images(m, "");
    ASSERT_TRUE(images.ok()) << images.error().message;
    Result<Image> marker = load_image(kThirdParty + "marker.png", 4);
    ASSERT_TRUE(marker.ok());
    const std::pair<const char*, TextureFormat> cases[] = {{"ours_etc2_albedo.ktx", TextureFormat::etc2_rgb8},
                                                           {"ours_etc2_albedo.pvr", TextureFormat::etc2_rgb8},
                                                           {"ours_astc_albedo.ktx", TextureFormat::astc_4x4},
                                                           {"ours_astc_albedo.pvr", TextureFormat::astc_4x4}};
    for (auto [file, format] : cases) {
        SCOPED_TRACE(file);
        Result<TextureData> t = encode_color_texture(images->albedo, format, true);
        ASSERT_TRUE(t.ok()) << t.error().message;
        const bool pvr = std::string(file).find(".pvr") != std::string::npos;
        Result<std::vector<std::uint8_t>> bytes = pvr ? write_pvr3(*t) : write_ktx1(*t);
        ASSERT_TRUE(bytes.ok());
        Result<std::vector<std::uint8_t>> committed = read_file_bounded(kThirdParty + file, 1 << 20, "fixture");
        ASSERT_TRUE(committed.ok());
        EXPECT_TRUE(*bytes == *committed) << "convert no longer writes the file the tools decoded";
        Result<Image> decoded = load_image(kThirdParty + file + ".decoded.png", 4);
        ASSERT_TRUE(decoded.ok()) << decoded.error().message;
        ASSERT_EQ(decoded->width, marker->width);
        ASSERT_EQ(decoded->height, marker->height);
        double same = 0, mirrored = 0;
        for (int y = 0; y < marker->height; ++y)
            for (int x = 0; x < marker->width; ++x)
                for (int c = 0; c < 3; ++c) {
                    same += std::abs(decoded->texel(x, y)[c] - marker->texel(x, y)[c]);
                    mirrored += std::abs(decoded->texel(x, y)[c] - marker->texel(x, marker->height - 1 - y)[c]);
                }
        const double n = 3.0 * marker->width * marker->height;
        EXPECT_LE(same / n, 3.0);       // the format's own error
        EXPECT_GE(mirrored / n, 20.0);  // upside down would be far off
    }
}

}  // namespace
}  // namespace px
