// Materials as asset packs ship them (issue 49): height read from any
// channel of any file (the normal map's own alpha, a mask's green), and
// normal maps in either green convention. Each case is drawn against its
// twin in the layout the renderer already knew, on the context's ES version
// (ctest runs both), with every technique that reads what changed.
#include "gpu_fixture.h"

#include <filesystem>
#include <string>
#include <vector>

#include "parallaxes/assets/heightfield.h"
#include "parallaxes/assets/image.h"
#include "parallaxes/texture/containers.h"
#include "parallaxes/texture/convert.h"

namespace px::test {
namespace {

std::string test_folder(const std::string& name) {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string dir = ::testing::TempDir() + "/px_packs_" + std::to_string(::getpid()) + "_" +
                            (info ? info->name() : "t") + "_" + name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

HeightField bricks_field() {
    FieldSpec spec;
    spec.kind = FieldKind::bricks;
    spec.size = 128;
    auto field = make_height_field(spec);
    EXPECT_TRUE(field.ok());
    return field ? *field : HeightField{};
}

// One channel of an image set to another image's grey.
Image with_channel(Image rgba, const Image& grey, int channel) {
    for (int y = 0; y < rgba.height; ++y)
        for (int x = 0; x < rgba.width; ++x) rgba.texel(x, y)[channel] = grey.texel(x, y)[0];
    return rgba;
}

void write(const std::string& path, const Image& image) {
    Status s = write_png(path, image);
    ASSERT_TRUE(s.ok()) << s.error().message;
}

void write_ktx(const std::string& path, const Image& rgba) {
    auto t = encode_color_texture(rgba, TextureFormat::rgba8);
    ASSERT_TRUE(t.ok()) << t.error().message;
    auto bytes = write_ktx1(*t);
    ASSERT_TRUE(bytes.ok()) << bytes.error().message;
    std::FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::fwrite(bytes->data(), 1, bytes->size(), f);
    std::fclose(f);
}

TextureSource file(const std::string& path) {
    TextureSource s;
    s.kind = TextureSource::Kind::file;
    s.path = path;
    return s;
}

// The plane at a raking view, lit from +y so that the bevels' green (v)
// component decides which side of a brick is lit.
SceneDesc plane(Technique technique, const std::string& dir) {
    PlaneScene p;
    p.technique = technique;
    p.view_angle_deg = 35.0f;
    SceneDesc s = p.build();
    s.base_dir = dir;
    s.lights[0].direction = glm::normalize(glm::vec3(0.3f, -0.8f, -0.5f));  // travels from +y, downward
    return s;
}

const Technique kTechniques[] = {Technique::normal,         Technique::parallax, Technique::offset_limited,
                                 Technique::steep,          Technique::pom,      Technique::relief,
                                 Technique::maxmip};

// The normal map's alpha as height, and a mask's green: the same image as
// the same height in a grey file of its own, for every technique. From
// images the renderer packs alpha itself (exactly equal); from one KTX file
// holding both, it reads that file in place: one texture for normal and
// height, none uploaded for the height.
TEST(AssetPacks, HeightFromAnyChannelDrawsAsASeparateHeightMap) {
    const std::string dir = test_folder("channels");
    const HeightField field = bricks_field();
    const Image height = height_image(field);
    const Image normal_rgb = derive_normal_map(field, 0.08f, false);
    write(dir + "/height.png", height);
    write(dir + "/normal.png", normal_rgb);
    write(dir + "/normal_height.png", with_channel(normal_rgb, height, 3));  // RGB normal, A height
    Image mask = normal_rgb;  // a packed mask: noise in r and b, the height in g
    for (std::size_t i = 0; i < mask.pixels.size(); ++i) mask.pixels[i] = static_cast<std::uint8_t>((i * 37) % 251);
    write(dir + "/mask.png", with_channel(mask, height, 1));
    write_ktx(dir + "/normal_height.ktx", with_channel(normal_rgb, height, 3));
    write_ktx(dir + "/mask.ktx", with_channel(mask, height, 1));

    for (Technique t : kTechniques) {
        SceneDesc separate = plane(t, dir);
        separate.materials[0].height = file("height.png");
        separate.materials[0].normal = file("normal.png");
        const Rendered expected = render(separate, 128);

        SceneDesc in_alpha = separate;
        in_alpha.materials[0].height = file("normal_height.png");
        in_alpha.materials[0].height.channel = TextureSource::Channel::a;
        in_alpha.materials[0].normal = file("normal_height.png");
        const ImageDiff a = compare(render(in_alpha, 128).image, expected.image);
        EXPECT_EQ(a.max, 0) << technique_name(t) << ": height from the normal map's alpha";

        SceneDesc in_green = separate;
        in_green.materials[0].height = file("mask.png");
        in_green.materials[0].height.channel = TextureSource::Channel::g;
        const ImageDiff g = compare(render(in_green, 128).image, expected.image);
        EXPECT_EQ(g.max, 0) << technique_name(t) << ": height from a mask's green";

        // A texture file's green: decoded to 8 bits on the CPU, the same texels.
        SceneDesc ktx_green = separate;
        ktx_green.materials[0].height = file("mask.ktx");
        ktx_green.materials[0].height.channel = TextureSource::Channel::g;
        const ImageDiff kg = compare(render(ktx_green, 128).image, expected.image);
        EXPECT_EQ(kg.max, 0) << technique_name(t) << ": height from a KTX file's green";

        // One KTX file for both, read in place. Its mips are the encoder's
        // box filter, not the GPU's: the shading's minified reads may differ
        // by a level or two; the trace reads the base level, the same texels.
        SceneDesc one_file = separate;
        one_file.materials[0].height = file("normal_height.ktx");
        one_file.materials[0].height.channel = TextureSource::Channel::a;
        one_file.materials[0].normal = file("normal_height.ktx");
        SceneDesc two_files = one_file;
        two_files.materials[0].height = file("height.png");
        two_files.materials[0].normal = file("normal_height.ktx");
        auto renderer = Renderer::create(reading_files());
        ASSERT_TRUE(renderer.ok());
        Status loaded = (*renderer)->load(one_file);
        ASSERT_TRUE(loaded.ok()) << loaded.error().message;
        int height_uploads = 0, normal_uploads = 0;
        for (const TextureUpload& u : (*renderer)->texture_uploads()) {
            if (u.what.find("height (") != std::string::npos && u.what.find("base level") == std::string::npos)
                ++height_uploads;
            if (u.what.find("normal map") != std::string::npos) {
                ++normal_uploads;
                EXPECT_NE(u.what.find("with the height in its own alpha"), std::string::npos) << u.what;
            }
        }
        EXPECT_EQ(normal_uploads, 1) << technique_name(t);
        EXPECT_EQ(height_uploads, 0) << technique_name(t) << ": the height is the normal file's alpha";
        // The two differ in the variant only (packed against separate
        // height), and the traced texels are the same: measured max 3,
        // mean under 0.001 (llvmpipe, 128 px); a height read at the wrong
        // rows (the file's top-first order ignored) gave max 221, mean 10.
        const ImageDiff k = compare(render(one_file, 128).image, render(two_files, 128).image);
        std::printf("measured: %s one KTX for normal and height against two files: mean %.4f max %d\n",
                    technique_name(t), k.mean, k.max);
        EXPECT_LE(k.max, 4) << technique_name(t) << ": height in the KTX normal file's alpha (mean " << k.mean << ")";
        EXPECT_LT(k.mean, 0.01) << technique_name(t);
    }
}

// Height asked of an alpha that holds none, or of a channel the file does
// not have: refused, naming the file and the channel.
TEST(AssetPacks, AChannelWithoutHeightIsRefused) {
    const std::string dir = test_folder("refused");
    const HeightField field = bricks_field();
    write(dir + "/normal.png", derive_normal_map(field, 0.08f, false));  // RGB: no alpha
    SceneDesc s = plane(Technique::pom, dir);
    s.materials[0].height = file("normal.png");
    s.materials[0].height.channel = TextureSource::Channel::a;
    auto renderer = Renderer::create(reading_files());
    ASSERT_TRUE(renderer.ok());
    Status loaded = (*renderer)->load(s);
    ASSERT_FALSE(loaded.ok());
    EXPECT_NE(loaded.error().message.find("normal.png' holds no height in its alpha"), std::string::npos)
        << loaded.error().message;
    EXPECT_NE(loaded.error().message.find("material 'surface'"), std::string::npos) << loaded.error().message;
}

// A DirectX-style normal map (green down) with "green": "down" draws as
// its OpenGL-style twin, from an image (turned on the CPU) and from a
// texture file (uploaded as it is, the shaders negate green); read the
// wrong way, the bevels facing the light and those facing away swap.
TEST(AssetPacks, GreenDownNormalMapsDrawLikeTheirOpenGlTwins) {
    const std::string dir = test_folder("green");
    const HeightField field = bricks_field();
    const Image gl = derive_normal_map(field, 0.08f, false);
    Image dx = gl;
    for (std::size_t i = 1; i < dx.pixels.size(); i += 4) dx.pixels[i] = static_cast<std::uint8_t>(255 - dx.pixels[i]);
    write(dir + "/gl.png", gl);
    write(dir + "/dx.png", dx);
    write_ktx(dir + "/gl.ktx", gl);
    write_ktx(dir + "/dx.ktx", dx);
    write(dir + "/height.png", height_image(field));
    for (Technique t : {Technique::normal, Technique::pom, Technique::maxmip}) {
        for (const char* ext : {".png", ".ktx"}) {
            SceneDesc twin = plane(t, dir);
            twin.materials[0].height = file("height.png");
            twin.materials[0].normal = file(std::string("gl") + ext);
            const Image expected = render(twin, 128).image;

            SceneDesc down = twin;
            down.materials[0].normal = file(std::string("dx") + ext);
            down.materials[0].normal.green = TextureSource::Green::down;
            const ImageDiff same = compare(render(down, 128).image, expected);
            std::printf("measured: %s%s green down against its twin: mean %.4f max %d\n", technique_name(t), ext,
                        same.mean, same.max);
            // From images, exactly (the CPU turns 255 - g back). From a file
            // uploaded as it is, within what rounding allows: the file's mip
            // levels are box filters of each file (a level of 255 - g is not
            // 255 minus the level of g where the mean ends in .5), and
            // llvmpipe's 8-bit bilinear filter rounds 255 - g and g apart by
            // a step. Measured (llvmpipe, 128 px, ES 2.0 and 3.0): max 3 to 4,
            // mean 0.05 to 0.07; with mip-less files max 2.
            if (std::string(ext) == ".png") {
                EXPECT_EQ(same.max, 0) << technique_name(t) << ext << ": green down read as down";
            } else {
                EXPECT_LE(same.max, 4) << technique_name(t) << ext << ": green down read as down";
                EXPECT_LT(same.mean, 0.1) << technique_name(t) << ext;
            }

            SceneDesc wrong = down;
            wrong.materials[0].normal.green = TextureSource::Green::up;
            const ImageDiff flipped = compare(render(wrong, 128).image, expected);
            // Measured (llvmpipe, 128 px): mean 4 to 6 per channel, max over 60.
            EXPECT_GT(flipped.mean, 2.0) << technique_name(t) << ext << ": the wrong convention must show";
            EXPECT_GT(flipped.max, 40) << technique_name(t) << ext;
        }
    }
}

}  // namespace
}  // namespace px::test
