// Unit tests for src/assets: images (stb round trips, orientation) and height
// fields (bilinear sampling, procedural kinds, normal maps).
#include <gtest/gtest.h>

#include <stb/stb_image.h>  // declarations only: the implementation lives in image.cpp

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>  // getpid: a per-process temp directory

#include "parallaxes/assets/color.h"
#include "parallaxes/assets/heightfield.h"
#include "parallaxes/assets/image.h"

namespace px {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

// A fresh temporary directory per test, removed afterwards.
class TempDir {
public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = fs::temp_directory_path() /
                ("px_unit_assets_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
                 std::to_string(::getpid()));
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

HeightField make_field(int w, int h, std::vector<float> texels) {
    HeightField f;
    f.width = w;
    f.height = h;
    f.texels = std::move(texels);
    return f;
}

HeightField generate(const FieldSpec& spec) {
    Result<HeightField> r = make_height_field(spec);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(r).value() : HeightField{};
}

std::string generate_error(const FieldSpec& spec) {
    Result<HeightField> r = make_height_field(spec);
    EXPECT_FALSE(r.ok()) << "expected an error for field '" << field_kind_name(spec.kind) << "'";
    return r.ok() ? std::string() : r.error().message;
}

void expect_in_unit_range(const HeightField& f) {
    ASSERT_EQ(f.texels.size(), static_cast<size_t>(f.width) * f.height);
    for (float t : f.texels) {
        ASSERT_GE(t, 0.0f);
        ASSERT_LE(t, 1.0f);
    }
}

int count_nonzero(const HeightField& f) {
    int n = 0;
    for (float t : f.texels) n += t != 0.0f;
    return n;
}

// --- HeightField::at / sample_bilinear ------------------------------------------------

// 3 x 2 field with distinct values: row 0 = {1, 2, 3}, row 1 = {4, 5, 6} (scaled).
HeightField three_by_two() { return make_field(3, 2, {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f}); }

TEST(HeightField, AtWrapsInBothDirections) {
    const HeightField f = three_by_two();
    EXPECT_FLOAT_EQ(f.at(0, 0), 0.1f);
    EXPECT_FLOAT_EQ(f.at(2, 1), 0.6f);
    EXPECT_FLOAT_EQ(f.at(-1, 0), 0.3f);
    EXPECT_FLOAT_EQ(f.at(3, 0), 0.1f);
    EXPECT_FLOAT_EQ(f.at(0, -1), 0.4f);
    EXPECT_FLOAT_EQ(f.at(4, 2), 0.2f);
    EXPECT_FLOAT_EQ(f.at(-4, -3), 0.6f);
}

TEST(HeightField, BilinearAtTexelCentresEqualsTexel) {
    const HeightField f = three_by_two();
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x)
            EXPECT_NEAR(f.sample_bilinear((x + 0.5) / 3.0, (y + 0.5) / 2.0), f.at(x, y), 1e-12)
                << x << "," << y;
}

TEST(HeightField, BilinearMidwayIsMean) {
    const HeightField f = three_by_two();
    // Between (0,0) and (1,0): u = 1/3 is the shared edge, v at row centre.
    EXPECT_NEAR(f.sample_bilinear(1.0 / 3.0, 0.25), (0.1 + 0.2) / 2, 1e-7);
    // Between rows at a column centre.
    EXPECT_NEAR(f.sample_bilinear(0.5, 0.5), (0.2 + 0.5) / 2, 1e-7);
    // Corner shared by four texels.
    EXPECT_NEAR(f.sample_bilinear(2.0 / 3.0, 0.5), (0.2 + 0.3 + 0.5 + 0.6) / 4, 1e-7);
    // A quarter of the way: weights 3/4, 1/4 (u = (0.5 + 0.25) / 3).
    EXPECT_NEAR(f.sample_bilinear(0.75 / 3.0, 0.25), 0.75 * 0.1 + 0.25 * 0.2, 1e-7);
}

TEST(HeightField, BilinearWrapsAtEdges) {
    const HeightField f = three_by_two();
    // u = 0 lies midway between the last and first columns.
    EXPECT_NEAR(f.sample_bilinear(0.0, 0.25), (0.3 + 0.1) / 2, 1e-7);
    EXPECT_NEAR(f.sample_bilinear(1.0, 0.25), (0.3 + 0.1) / 2, 1e-7);
    // v = 0 lies midway between the last and first rows.
    EXPECT_NEAR(f.sample_bilinear(0.5 / 3.0, 0.0), (0.4 + 0.1) / 2, 1e-7);
    // The (0, 0) corner mixes the four corner texels.
    EXPECT_NEAR(f.sample_bilinear(0.0, 0.0), (0.1 + 0.3 + 0.4 + 0.6) / 4, 1e-7);
    // Periodic: whole tiles away, including negative ones.
    for (double u : {0.1, 0.37, 0.9})
        for (double v : {0.05, 0.6}) {
            const double s = f.sample_bilinear(u, v);
            EXPECT_NEAR(f.sample_bilinear(u + 3.0, v - 2.0), s, 1e-9);
            EXPECT_NEAR(f.sample_bilinear(u - 5.0, v + 7.0), s, 1e-9);
        }
}

// --- Images ---------------------------------------------------------------------------

TEST(HeightFieldFromImage, TakesRedChannelAndHonoursConvention) {
    Image img;
    img.width = 2;
    img.height = 1;
    img.channels = 4;
    img.pixels = {0, 200, 200, 200, 255, 0, 0, 0};
    const HeightField h = height_field_from_image(img, HeightConvention::height);
    EXPECT_FLOAT_EQ(h.at(0, 0), 0.0f);
    EXPECT_FLOAT_EQ(h.at(1, 0), 1.0f);
    const HeightField d = height_field_from_image(img, HeightConvention::depth);
    EXPECT_FLOAT_EQ(d.at(0, 0), 1.0f);
    EXPECT_FLOAT_EQ(d.at(1, 0), 0.0f);

    Image grey;
    grey.width = 1;
    grey.height = 2;
    grey.channels = 1;
    grey.pixels = {51, 204};
    const HeightField g = height_field_from_image(grey, HeightConvention::depth);
    EXPECT_NEAR(g.at(0, 0), 1.0 - 51 / 255.0, 1e-6);
    EXPECT_NEAR(g.at(0, 1), 1.0 - 204 / 255.0, 1e-6);
}

TEST(Image, SolidImage) {
    const Image img = make_solid_image(3, 2, 10, 20, 30);
    ASSERT_EQ(img.width, 3);
    ASSERT_EQ(img.height, 2);
    ASSERT_EQ(img.channels, 4);
    ASSERT_EQ(img.pixels.size(), 24u);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) {
            const std::uint8_t* p = img.texel(x, y);
            EXPECT_EQ(p[0], 10);
            EXPECT_EQ(p[1], 20);
            EXPECT_EQ(p[2], 30);
            EXPECT_EQ(p[3], 255);
        }
    EXPECT_EQ(make_solid_image(1, 1, 1, 2, 3, 4).pixels, (std::vector<std::uint8_t>{1, 2, 3, 4}));
}

Image gradient_image(int w, int h, int channels) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = channels;
    img.pixels.resize(static_cast<size_t>(w) * h * channels);
    for (size_t i = 0; i < img.pixels.size(); ++i)
        img.pixels[i] = static_cast<std::uint8_t>((i * 37 + 11) % 256);
    return img;
}

TEST(Image, PngRoundTripPreservesPixelsAndOrientation) {
    TempDir dir;
    const Image img = gradient_image(5, 3, 4);
    const std::string path = dir.file("round.png");
    const Status s = write_png(path, img);
    ASSERT_TRUE(s.ok()) << s.error().message;
    EXPECT_FALSE(fs::exists(path + ".tmp"));

    Result<Image> back = load_image(path, 4);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->width, 5);
    EXPECT_EQ(back->height, 3);
    EXPECT_EQ(back->channels, 4);
    EXPECT_EQ(back->pixels, img.pixels);  // row 0 stays row 0

    // In the file itself rows are top-down: the file's first row is the
    // image's last row (v = 1). Read with plain stb, no flipping.
    int w = 0, h = 0, n = 0;
    std::ifstream in(path, std::ios::binary);
    const std::string file_bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    stbi_uc* raw = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(file_bytes.data()),
                                         static_cast<int>(file_bytes.size()), &w, &h, &n, 4);
    ASSERT_NE(raw, nullptr);
    ASSERT_EQ(w, 5);
    ASSERT_EQ(h, 3);
    for (int x = 0; x < 5 * 4; ++x) {
        EXPECT_EQ(raw[x], img.texel(0, 2)[x]) << "file top row = image row 2";
        EXPECT_EQ(raw[2 * 5 * 4 + x], img.texel(0, 0)[x]) << "file bottom row = image row 0";
    }
    stbi_image_free(raw);
}

TEST(Image, PngRoundTripGreyAndChannelConversion) {
    TempDir dir;
    const Image grey = gradient_image(4, 4, 1);
    const std::string path = dir.file("grey.png");
    ASSERT_TRUE(write_png(path, grey).ok());

    Result<Image> one = load_image(path, 1);
    ASSERT_TRUE(one.ok()) << one.error().message;
    EXPECT_EQ(one->pixels, grey.pixels);

    Result<Image> four = load_image(path, 4);
    ASSERT_TRUE(four.ok()) << four.error().message;
    ASSERT_EQ(four->channels, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const std::uint8_t g = grey.texel(x, y)[0];
            const std::uint8_t* p = four->texel(x, y);
            EXPECT_EQ(p[0], g);
            EXPECT_EQ(p[1], g);
            EXPECT_EQ(p[2], g);
            EXPECT_EQ(p[3], 255);
        }
}

TEST(Image, WritePngOverwritesExistingFile) {
    TempDir dir;
    const std::string path = dir.file("over.png");
    ASSERT_TRUE(write_png(path, make_solid_image(2, 2, 1, 2, 3)).ok());
    ASSERT_TRUE(write_png(path, make_solid_image(3, 1, 9, 8, 7)).ok());
    Result<Image> back = load_image(path);
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(back->width, 3);
    EXPECT_EQ(back->texel(2, 0)[0], 9);
}

TEST(Image, LoadMissingFileNamesPath) {
    TempDir dir;
    const std::string path = dir.file("does_not_exist.png");
    Result<Image> r = load_image(path);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(path), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("No such file"), std::string::npos) << r.error().message;
}

TEST(Image, LoadGarbageFileNamesPathAndReason) {
    TempDir dir;
    const std::string path = dir.file("garbage.png");
    {
        std::ofstream out(path, std::ios::binary);
        out << "this is not an image, just some text that no decoder accepts";
    }
    Result<Image> r = load_image(path);
    ASSERT_FALSE(r.ok());
    const std::string& msg = r.error().message;
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    // stb's reason follows the context; for unrecognised data it is "unknown image type".
    EXPECT_NE(msg.find("not a PNG or JPEG file"), std::string::npos) << msg;
}

TEST(Image, LoadRejectsBadChannelCount) {
    TempDir dir;
    const std::string path = dir.file("ok.png");
    ASSERT_TRUE(write_png(path, make_solid_image(1, 1, 0, 0, 0)).ok());
    EXPECT_FALSE(load_image(path, 0).ok());
    EXPECT_FALSE(load_image(path, 5).ok());
}

TEST(Image, WritePngFailureNamesPathAndLeavesNoFile) {
    TempDir dir;
    const std::string path = dir.file("missing_dir/out.png");
    const Status s = write_png(path, make_solid_image(2, 2, 0, 0, 0));
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find(path), std::string::npos) << s.error().message;
    EXPECT_FALSE(fs::exists(path));
    EXPECT_FALSE(fs::exists(path + ".tmp"));

    Image bad = make_solid_image(2, 2, 0, 0, 0);
    bad.pixels.pop_back();
    const std::string bad_path = dir.file("bad.png");
    EXPECT_FALSE(write_png(bad_path, bad).ok());
    EXPECT_FALSE(fs::exists(bad_path));
    EXPECT_FALSE(write_png(bad_path, Image{}).ok());
}

// --- Field kind names ---------------------------------------------------------------

TEST(FieldKind, NamesRoundTrip) {
    const std::vector<std::string> names = field_kind_names();
    EXPECT_EQ(names.size(), 9u);
    for (const std::string& name : names) {
        Result<FieldKind> k = parse_field_kind(name);
        ASSERT_TRUE(k.ok()) << name;
        EXPECT_EQ(field_kind_name(*k), name);
    }
    EXPECT_STREQ(field_kind_name(FieldKind::hemispheres), "hemispheres");
    EXPECT_EQ(*parse_field_kind("pit"), FieldKind::pit);
}

TEST(FieldKind, ParseErrorNamesBadNameAndKnownNames) {
    Result<FieldKind> r = parse_field_kind("brick");
    ASSERT_FALSE(r.ok());
    const std::string& msg = r.error().message;
    EXPECT_NE(msg.find("'brick'"), std::string::npos) << msg;
    for (const std::string& name : field_kind_names())
        EXPECT_NE(msg.find(name), std::string::npos) << "known name " << name << " missing: " << msg;
    EXPECT_FALSE(parse_field_kind("").ok());
    EXPECT_FALSE(parse_field_kind("Flat").ok());
}

// --- Procedural fields ------------------------------------------------------------------

TEST(Procedural, EveryKindIsInRangeAndDeterministic) {
    for (const std::string& name : field_kind_names()) {
        FieldSpec spec;
        spec.kind = *parse_field_kind(name);
        spec.size = 64;
        const HeightField a = generate(spec);
        ASSERT_EQ(a.width, 64) << name;
        ASSERT_EQ(a.height, 64) << name;
        expect_in_unit_range(a);
        const HeightField b = generate(spec);
        EXPECT_EQ(a.texels, b.texels) << name;
    }
}

TEST(Procedural, ValidatesSize) {
    FieldSpec spec;
    spec.size = 0;
    std::string msg = generate_error(spec);
    EXPECT_NE(msg.find("field 'flat'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("size"), std::string::npos) << msg;
    spec.size = 8193;
    generate_error(spec);
    spec.size = 1;
    EXPECT_EQ(generate(spec).texels.size(), 1u);
}

TEST(Procedural, Flat) {
    FieldSpec spec;
    spec.kind = FieldKind::flat;
    spec.size = 8;
    spec.level = 0.25f;
    const HeightField f = generate(spec);
    for (float t : f.texels) EXPECT_FLOAT_EQ(t, 0.25f);
    spec.level = 1.5f;
    EXPECT_NE(generate_error(spec).find("level"), std::string::npos);
    spec.level = -0.1f;
    generate_error(spec);
    spec.level = std::nanf("");
    generate_error(spec);
}

TEST(Procedural, Spike) {
    FieldSpec spec;
    spec.kind = FieldKind::spike;
    spec.size = 32;
    const HeightField f = generate(spec);
    EXPECT_EQ(count_nonzero(f), 1);
    EXPECT_FLOAT_EQ(f.at(16, 16), 1.0f);
    spec.size = 1;
    EXPECT_FLOAT_EQ(generate(spec).at(0, 0), 1.0f);
}

TEST(Procedural, Pit) {
    FieldSpec spec;
    spec.kind = FieldKind::pit;
    spec.size = 64;
    spec.radius = 0.25f;
    const HeightField f = generate(spec);
    EXPECT_FLOAT_EQ(f.at(32, 32), 0.0f);
    EXPECT_FLOAT_EQ(f.at(31, 31), 0.0f);
    EXPECT_FLOAT_EQ(f.at(0, 0), 1.0f);
    EXPECT_FLOAT_EQ(f.at(63, 63), 1.0f);
    // |u - 0.5| < 0.25 covers texel centres 16.5/64 .. 47.5/64: texels 16..47.
    EXPECT_EQ(count_nonzero(f), 64 * 64 - 32 * 32);
    EXPECT_FLOAT_EQ(f.at(15, 32), 1.0f);
    EXPECT_FLOAT_EQ(f.at(16, 32), 0.0f);
    EXPECT_FLOAT_EQ(f.at(47, 32), 0.0f);
    EXPECT_FLOAT_EQ(f.at(48, 32), 1.0f);
    spec.radius = 0.0f;
    EXPECT_NE(generate_error(spec).find("radius"), std::string::npos);
    spec.radius = 0.5f;
    generate_error(spec);
}

// Runs of raised texels along row y: lengths in order, starting from a ground texel.
std::vector<int> raised_runs(const HeightField& f, int y) {
    int start = 0;
    while (start < f.width && f.at(start, y) != 0.0f) ++start;
    std::vector<int> runs;
    int run = 0;
    for (int i = 1; i <= f.width; ++i) {
        if (f.at(start + i, y) != 0.0f) {
            ++run;
        } else if (run > 0) {
            runs.push_back(run);
            run = 0;
        }
    }
    return runs;
}

TEST(Procedural, LinesOneTexelWide) {
    FieldSpec spec;
    spec.kind = FieldKind::lines;
    spec.size = 64;
    spec.count = 5;
    spec.line_width = 1;
    const HeightField f = generate(spec);
    EXPECT_EQ(raised_runs(f, 0), std::vector<int>(5, 1));
    EXPECT_EQ(count_nonzero(f), 5 * 64);
    for (float t : f.texels) EXPECT_TRUE(t == 0.0f || t == 1.0f);
    // Constant in v.
    for (int y = 1; y < 64; ++y)
        for (int x = 0; x < 64; ++x) ASSERT_EQ(f.at(x, y), f.at(x, 0)) << x << "," << y;
}

TEST(Procedural, LinesWideAndEvenlySpaced) {
    FieldSpec spec;
    spec.kind = FieldKind::lines;
    spec.size = 64;
    spec.count = 4;
    spec.line_width = 3;
    const HeightField f = generate(spec);
    EXPECT_EQ(raised_runs(f, 7), std::vector<int>(4, 3));
    // Period 16: each line's start is 16 texels after the previous one.
    std::vector<int> starts;
    for (int x = 0; x < 64; ++x)
        if (f.at(x, 0) != 0.0f && f.at(x - 1, 0) == 0.0f) starts.push_back(x);
    ASSERT_EQ(starts.size(), 4u);
    for (size_t i = 1; i < starts.size(); ++i) EXPECT_EQ(starts[i] - starts[i - 1], 16);

    // Lines that cannot stay apart are rejected.
    spec.count = 20;
    EXPECT_NE(generate_error(spec).find("field 'lines'"), std::string::npos);
    spec.count = 4;
    spec.line_width = 0;
    EXPECT_NE(generate_error(spec).find("line_width"), std::string::npos);
}

TEST(Procedural, BricksMortarBrickAndRunningBond) {
    FieldSpec spec;
    spec.kind = FieldKind::bricks;
    spec.size = 256;
    spec.count = 4;  // rows of height 64 texels; bricks 128 texels wide
    spec.mortar = 0.06f;
    const HeightField f = generate(spec);
    // The tile corner lies on a joint.
    EXPECT_FLOAT_EQ(f.at(0, 0), 0.0f);
    // Horizontal joint between rows 0 and 1 (v = 0.25).
    EXPECT_FLOAT_EQ(f.at(40, 64), 0.0f);
    // Row 0 brick centre (u = 0.25, v = 0.125).
    EXPECT_FLOAT_EQ(f.at(63, 31), 1.0f);
    // Row 1 is shifted by half a brick: u = 0.25 is a vertical joint there,
    // and u = 0.5 (a joint in row 0) is a brick centre.
    EXPECT_FLOAT_EQ(f.at(63, 95), 0.0f);
    EXPECT_FLOAT_EQ(f.at(127, 31), 0.0f);
    EXPECT_FLOAT_EQ(f.at(127, 95), 1.0f);
    // The bevel gives intermediate heights, rising away from the joint.
    bool has_bevel = false;
    for (float t : f.texels) has_bevel |= (t > 0.0f && t < 1.0f);
    EXPECT_TRUE(has_bevel);
    // Walking from the joint at x = 0 into the brick along row 0's centre,
    // heights never decrease until the brick top.
    for (int x = 1; x < 60; ++x) EXPECT_GE(f.at(x, 31), f.at(x - 1, 31)) << x;
    // Mortar 0.06 of 256 texels: ~15 texels per joint, half each side of u = 0.
    EXPECT_FLOAT_EQ(f.at(5, 31), 0.0f);
    EXPECT_FLOAT_EQ(f.at(250, 31), 0.0f);
    EXPECT_FLOAT_EQ(f.at(20, 31), 1.0f);
    expect_in_unit_range(f);
}

TEST(Procedural, BricksValidation) {
    FieldSpec spec;
    spec.kind = FieldKind::bricks;
    spec.size = 64;
    spec.count = 0;
    const std::string msg = generate_error(spec);
    EXPECT_NE(msg.find("field 'bricks'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("count"), std::string::npos) << msg;
    EXPECT_NE(msg.find("got 0"), std::string::npos) << msg;
    spec.count = 3;  // odd: the bond would break at the tile edge
    EXPECT_NE(generate_error(spec).find("even"), std::string::npos);
    spec.count = 4;
    spec.mortar = 0.0f;
    EXPECT_NE(generate_error(spec).find("mortar"), std::string::npos);
    spec.mortar = 0.2f;
    generate_error(spec);
}

TEST(Procedural, TextRaisesGlyphOnFlatGround) {
    FieldSpec spec;
    spec.kind = FieldKind::text;
    spec.size = 256;
    spec.text = "I";
    const HeightField f = generate(spec);
    for (float t : f.texels) EXPECT_TRUE(t == 0.0f || t == 1.0f);
    // The stem of the I passes through the tile centre; the corners are ground.
    EXPECT_FLOAT_EQ(f.at(128, 128), 1.0f);
    EXPECT_FLOAT_EQ(f.at(0, 0), 0.0f);
    EXPECT_FLOAT_EQ(f.at(255, 255), 0.0f);
    EXPECT_FLOAT_EQ(f.at(20, 128), 0.0f);
    // One glyph, 7 rows high, limited to 80% of the tile height: font pixels
    // are 0.8/7 of the tile; "I" has 11 of them.
    const double pixel = 0.8 / 7 * 256;
    const double expected = 11 * pixel * pixel;
    EXPECT_NEAR(count_nonzero(f), expected, 0.05 * expected);
}

TEST(Procedural, TextIsUprightAndFillsWidth) {
    FieldSpec spec;
    spec.kind = FieldKind::text;
    spec.size = 256;
    spec.text = "L";
    const HeightField f = generate(spec);
    // "L": its foot (the full-width font row) is at the bottom, i.e. low v.
    int lowest = -1, highest = -1;
    for (int y = 0; y < 256 && lowest < 0; ++y)
        for (int x = 0; x < 256; ++x)
            if (f.at(x, y) != 0.0f) lowest = y;
    for (int y = 255; y >= 0 && highest < 0; --y)
        for (int x = 0; x < 256; ++x)
            if (f.at(x, y) != 0.0f) highest = y;
    ASSERT_GE(lowest, 0);
    const auto row_count = [&](int y) {
        int n = 0;
        for (int x = 0; x < 256; ++x) n += f.at(x, y) != 0.0f;
        return n;
    };
    EXPECT_GT(row_count(lowest), 3 * row_count(highest)) << "glyph is upside down";

    // A long string fills ~80% of the tile width.
    spec.text = "HELLO 42";
    const HeightField g = generate(spec);
    int min_x = 256, max_x = -1;
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            if (g.at(x, y) != 0.0f) {
                min_x = std::min(min_x, x);
                max_x = std::max(max_x, x);
            }
    const double width = (max_x - min_x + 1) / 256.0;
    EXPECT_NEAR(width, 0.8, 0.02);
    EXPECT_NEAR((min_x + max_x + 1) / 2.0, 128.0, 2.0) << "centred";
}

TEST(Procedural, TextRejectsUnknownCharacters) {
    FieldSpec spec;
    spec.kind = FieldKind::text;
    spec.size = 64;
    spec.text = "AB?";
    std::string msg = generate_error(spec);
    EXPECT_NE(msg.find("field 'text'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'?'"), std::string::npos) << msg;
    spec.text = "ok";
    msg = generate_error(spec);
    EXPECT_NE(msg.find("'o'"), std::string::npos) << msg;
    spec.text = "";
    generate_error(spec);
    // Every supported character renders.
    spec.text = "ABCDEFGHIJKLMNOPQRSTUVWXYZ 0123456789";
    spec.size = 512;
    EXPECT_GT(count_nonzero(generate(spec)), 0);
}

TEST(Procedural, HemispheresAndCones) {
    FieldSpec spec;
    spec.size = 128;
    spec.count = 4;  // cells of 32 texels; bump radius 0.45 * 32 = 14.4 texels
    for (FieldKind kind : {FieldKind::hemispheres, FieldKind::cones}) {
        spec.kind = kind;
        const HeightField f = generate(spec);
        expect_in_unit_range(f);
        // Cell corners are outside the bumps.
        EXPECT_FLOAT_EQ(f.at(0, 0), 0.0f);
        EXPECT_FLOAT_EQ(f.at(31, 32), 0.0f);
        // Cell centres (between texels 15 and 16) are near the top.
        EXPECT_GT(f.at(16, 16), kind == FieldKind::cones ? 0.95f : 0.998f);
        // Every cell looks the same.
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) ASSERT_EQ(f.at(x, y), f.at(x + 64, y + 96));
    }
    // Texel (16 + 7, 16) is 7.5 texels = 7.5/32 cell from the centre
    // horizontally and 0.5/32 vertically.
    const double r = std::sqrt(7.5 * 7.5 + 0.5 * 0.5) / 32 / 0.45;
    spec.kind = FieldKind::hemispheres;
    EXPECT_NEAR(generate(spec).at(23, 16), std::sqrt(1 - r * r), 1e-6);
    spec.kind = FieldKind::cones;
    EXPECT_NEAR(generate(spec).at(23, 16), 1 - r, 1e-6);
    spec.count = 0;
    EXPECT_NE(generate_error(spec).find("count"), std::string::npos);
}

TEST(Procedural, Sine) {
    FieldSpec spec;
    spec.kind = FieldKind::sine;
    spec.size = 6;
    spec.frequency = 1.0f;
    const HeightField f = generate(spec);
    // Texel centres 1.5/6 = 0.25 and 4.5/6 = 0.75 are the sine's extremes.
    EXPECT_NEAR(f.at(1, 1), 1.0, 1e-6);
    EXPECT_NEAR(f.at(4, 4), 1.0, 1e-6);
    EXPECT_NEAR(f.at(1, 4), 0.0, 1e-6);
    EXPECT_NEAR(f.at(4, 1), 0.0, 1e-6);

    spec.size = 64;
    spec.frequency = 3.0f;
    const HeightField g = generate(spec);
    for (int y = 0; y < 64; y += 7)
        for (int x = 0; x < 64; x += 5) {
            const double u = (x + 0.5) / 64, v = (y + 0.5) / 64;
            const double expected = 0.5 + 0.5 * std::sin(2 * kPi * 3 * u) * std::sin(2 * kPi * 3 * v);
            EXPECT_NEAR(g.at(x, y), expected, 1e-6);
        }
    spec.frequency = 2.5f;  // not whole periods: would not tile
    EXPECT_NE(generate_error(spec).find("frequency"), std::string::npos);
    spec.frequency = 0.0f;
    generate_error(spec);
}

// --- Normal maps ------------------------------------------------------------------

TEST(NormalMap, FlatFieldPointsStraightUp) {
    FieldSpec spec;
    spec.size = 8;
    spec.level = 0.5f;
    const HeightField f = generate(spec);
    const Image packed = derive_normal_map(f, 0.1f, true);
    ASSERT_EQ(packed.channels, 4);
    ASSERT_EQ(packed.width, 8);
    ASSERT_EQ(packed.height, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const std::uint8_t* p = packed.texel(x, y);
            EXPECT_EQ(p[0], 128);
            EXPECT_EQ(p[1], 128);
            EXPECT_EQ(p[2], 255);
            EXPECT_EQ(p[3], 128);  // round(0.5 * 255) = round(127.5)
        }
    const Image unpacked = derive_normal_map(f, 0.1f, false);
    EXPECT_EQ(unpacked.texel(3, 3)[3], 255);
}

// h = x / w along u (a ramp; it wraps at the edge, so test interior texels).
HeightField ramp_u(int w) {
    HeightField f = make_field(w, 4, std::vector<float>(static_cast<size_t>(w) * 4));
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < w; ++x) f.ref(x, y) = static_cast<float>(x) / static_cast<float>(w);
    return f;
}

TEST(NormalMap, RampGivesExpectedSlope) {
    // h rises by 1 over the tile, scale 0.5: dH/du = 0.5, n = (-0.5, 0, 1)/sqrt(1.25)
    // = (-0.4472, 0, 0.8944): R = round(0.2764 * 255) = 70, B = round(0.9472 * 255) = 242.
    for (int w : {16, 32}) {  // the slope is per tile, independent of resolution
        const Image n = derive_normal_map(ramp_u(w), 0.5f, false);
        const std::uint8_t* p = n.texel(w / 2, 1);
        EXPECT_EQ(p[0], 70) << w;
        EXPECT_EQ(p[1], 128) << w;
        EXPECT_EQ(p[2], 242) << w;
        EXPECT_EQ(p[3], 255) << w;
    }
    // The same ramp along v tilts green instead of red.
    HeightField v = make_field(4, 16, std::vector<float>(64));
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 4; ++x) v.ref(x, y) = static_cast<float>(y) / 16.0f;
    const Image nv = derive_normal_map(v, 0.5f, false);
    EXPECT_EQ(nv.texel(1, 8)[0], 128);
    EXPECT_EQ(nv.texel(1, 8)[1], 70);
    EXPECT_EQ(nv.texel(1, 8)[2], 242);
}

TEST(NormalMap, WrapsAtEdgesAndPacksHeight) {
    // At x = 0 the central difference uses x = w - 1 (the top of the ramp), so
    // the ramp's wrap-around cliff shows as a steep slope the other way.
    const Image n = derive_normal_map(ramp_u(16), 0.5f, true);
    EXPECT_GT(n.texel(0, 0)[0], 128);
    EXPECT_GT(n.texel(15, 0)[0], 128);
    for (int x = 0; x < 16; ++x)
        EXPECT_EQ(n.texel(x, 2)[3], std::lround(x / 16.0 * 255)) << x;
}

TEST(HeightImage, AllColourChannelsHoldHeight) {
    const HeightField f = make_field(2, 1, {0.0f, 0.6f});
    const Image img = height_image(f);
    ASSERT_EQ(img.channels, 4);
    EXPECT_EQ(img.pixels, (std::vector<std::uint8_t>{0, 0, 0, 255, 153, 153, 153, 255}));
    // Back to a field: the height survives (to 8 bits).
    const HeightField back = height_field_from_image(img, HeightConvention::height);
    EXPECT_NEAR(back.at(1, 0), 0.6, 0.5 / 255);
}

// The colour ramp: height 0 is `low`, 1 is `high`, linear between; the
// defaults are height_image; grain varies texels of one height around the
// ramp's colour (mean near it, never the same everywhere), deterministically.
TEST(HeightRamp, MapsHeightToColourWithGrain) {
    const HeightField f = make_field(2, 1, {0.0f, 0.5f});
    HeightRamp ramp;
    EXPECT_EQ(ramp_image(f, ramp).pixels, height_image(f).pixels);
    ramp.low[0] = 0.2f;
    ramp.high[0] = 0.6f;
    ramp.low[1] = ramp.high[1] = 1.0f;
    ramp.low[2] = 0.0f;
    ramp.high[2] = 0.0f;
    EXPECT_EQ(ramp_image(f, ramp).pixels, (std::vector<std::uint8_t>{51, 255, 0, 255, 102, 255, 0, 255}));

    FieldSpec flat;
    flat.kind = FieldKind::flat;
    flat.size = 64;
    flat.level = 1.0f;
    const HeightField level = *make_height_field(flat);
    HeightRamp grainy;
    grainy.high[0] = grainy.high[1] = grainy.high[2] = 0.5f;
    grainy.grain = 0.3f;
    const Image a = ramp_image(level, grainy);
    EXPECT_EQ(a.pixels, ramp_image(level, grainy).pixels);
    double sum = 0.0;
    int lo = 255, hi = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const int r = a.texel(x, y)[0];
            sum += r;
            lo = std::min(lo, r);
            hi = std::max(hi, r);
            EXPECT_GE(r, 127 - 39);  // 0.5 * (1 - 0.3) in bytes, rounded
            EXPECT_LE(r, 128 + 39);
        }
    EXPECT_NEAR(sum / (64.0 * 64.0), 127.5, 8.0);
    EXPECT_GT(hi - lo, 20);
}

}  // namespace
}  // namespace px

// The sRGB curve (IEC 61966-2-1) at its published points, and both ways.
TEST(SrgbCurve, MatchesTheStandardsPointsAndInvertsItself) {
    EXPECT_NEAR(px::srgb_to_linear(0.5), 0.214041, 1e-6);
    EXPECT_NEAR(px::srgb_to_linear(0.04045), 0.04045 / 12.92, 1e-9);  // the toe's end
    EXPECT_NEAR(px::linear_to_srgb(0.0031308), 0.0031308 * 12.92, 1e-7);
    EXPECT_NEAR(px::linear_to_srgb(0.18), 0.461356, 1e-5);  // photographic mid-grey
    for (int v = 0; v <= 255; ++v) EXPECT_EQ(px::linear_to_srgb8(px::srgb_to_linear(v / 255.0)), v) << v;
    EXPECT_EQ(px::linear_to_srgb8(-1.0), 0);
    EXPECT_EQ(px::linear_to_srgb8(2.0), 255);
}

// A mip level of sRGB colour averages light, not code values: black and
// white make 188 (half the light), not 128; alpha and data average as stored.
TEST(SrgbCurve, MipLevelsAverageLinearLight) {
    px::Image img;
    img.width = 2;
    img.height = 1;
    img.channels = 4;
    img.pixels = {0, 0, 0, 0, 255, 255, 255, 255};
    const px::Image srgb = px::next_mip_level(img, true);
    ASSERT_EQ(srgb.width, 1);
    ASSERT_EQ(srgb.height, 1);
    EXPECT_EQ(srgb.pixels[0], 188);
    EXPECT_EQ(srgb.pixels[3], 128);  // alpha: as stored
    const px::Image data = px::next_mip_level(img, false);
    EXPECT_EQ(data.pixels[0], 128);
    // Odd sides fold their last texel in: 3x3 -> 1x1 averages all nine.
    px::Image odd;
    odd.width = odd.height = 3;
    odd.channels = 1;
    odd.pixels = {0, 0, 9, 0, 0, 9, 9, 9, 9};
    const px::Image folded = px::next_mip_level(odd, false);
    ASSERT_EQ(folded.pixels.size(), 1u);
    EXPECT_EQ(folded.pixels[0], 5);
}
