// Unit tests for src/assets/image_compare: the golden-image measure the GPU
// golden tests and `parallax compare` share, and tolerance files.
#include <gtest/gtest.h>

#include <string>

#include "parallaxes/assets/image_compare.h"
#include "parallaxes/scene/scene.h"

namespace px {
namespace {

Image grey(int w, int h, std::uint8_t level) { return make_solid_image(w, h, level, level, level); }

Image rgb(int w, int h, std::uint8_t level) {
    Image image;
    image.width = w;
    image.height = h;
    image.channels = 3;
    image.pixels.assign(static_cast<size_t>(w * h * 3), level);
    return image;
}

bool is_red(const Image& diff, int x, int y) {
    const std::uint8_t* p = diff.texel(x, y);
    return p[0] == 255 && p[1] == 0 && p[2] == 0 && p[3] == 255;
}

TEST(ImageCompare, IdenticalImagesPass) {
    const Image a = grey(4, 4, 100);
    Result<ImageComparison> c = compare_images(a, a, Tolerance{0, 0.0, 0.0});
    ASSERT_TRUE(c.ok()) << c.error().message;
    EXPECT_TRUE(c->passed());
    EXPECT_EQ(c->pixels, 16);
    EXPECT_EQ(c->differing, 0);
    EXPECT_EQ(c->max_difference, 0);
    EXPECT_DOUBLE_EQ(c->mean, 0.0);
    // The diff: the actual image's green / 4 as grey, opaque, no red.
    ASSERT_EQ(c->diff.width, 4);
    ASSERT_EQ(c->diff.channels, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const std::uint8_t* p = c->diff.texel(x, y);
            EXPECT_EQ(p[0], 25);
            EXPECT_EQ(p[1], 25);
            EXPECT_EQ(p[2], 25);
            EXPECT_EQ(p[3], 255);
        }
}

TEST(ImageCompare, CountsAPixelOverTheThresholdOnly) {
    const Image golden = grey(4, 4, 100);
    Image actual = golden;
    actual.texel(1, 2)[2] = 109;  // 9 over in blue: over a threshold of 8
    actual.texel(3, 0)[0] = 92;   // 8 under in red: at the threshold, not over
    Result<ImageComparison> c = compare_images(actual, golden, Tolerance{8, 0.0, 100.0});
    ASSERT_TRUE(c.ok()) << c.error().message;
    EXPECT_EQ(c->differing, 1);
    EXPECT_DOUBLE_EQ(c->share, 1.0 / 16.0);
    EXPECT_EQ(c->max_difference, 9);
    EXPECT_TRUE(is_red(c->diff, 1, 2));
    EXPECT_FALSE(is_red(c->diff, 3, 0));
    EXPECT_FALSE(c->share_within());  // no differing pixel allowed
    EXPECT_TRUE(c->mean_within());
    EXPECT_FALSE(c->passed());
    c->tolerance.max_differing_share = 1.0 / 16.0;  // exactly the share: passes
    EXPECT_TRUE(c->passed());
}

TEST(ImageCompare, MeanIsOverEveryColourChannelOfEveryPixel) {
    const Image golden = grey(2, 2, 50);
    Image actual = golden;
    actual.texel(0, 0)[0] = 56;  // +6
    actual.texel(1, 1)[1] = 47;  // -3
    actual.texel(1, 0)[3] = 0;   // alpha: ignored
    Result<ImageComparison> c = compare_images(actual, golden, Tolerance{255, 0.0, 0.75});
    ASSERT_TRUE(c.ok()) << c.error().message;
    EXPECT_DOUBLE_EQ(c->mean, 9.0 / 12.0);
    EXPECT_EQ(c->max_difference, 6);
    EXPECT_EQ(c->differing, 0);
    EXPECT_TRUE(c->passed());  // exactly the mean allowed
    c->tolerance.max_mean_difference = 0.74;
    EXPECT_FALSE(c->mean_within());
    EXPECT_TRUE(c->share_within());
    EXPECT_FALSE(c->passed());
}

TEST(ImageCompare, RgbAgainstRgba) {
    Result<ImageComparison> c = compare_images(rgb(3, 2, 10), grey(3, 2, 10), Tolerance{});
    ASSERT_TRUE(c.ok()) << c.error().message;
    EXPECT_TRUE(c->passed());
}

TEST(ImageCompare, SizeMismatchIsAnErrorNamingBoth) {
    Result<ImageComparison> c = compare_images(grey(4, 4, 0), grey(4, 2, 0), Tolerance{}, "a.png", "b.png");
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().message, "size mismatch: a.png is 4x4, b.png is 4x2");
}

TEST(ImageCompare, UnusableImagesAreErrors) {
    Image one_channel = grey(2, 2, 0);
    one_channel.channels = 1;
    one_channel.pixels.resize(4);
    Result<ImageComparison> c = compare_images(one_channel, grey(2, 2, 0), Tolerance{}, "a.png", "b.png");
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find("a.png: 1 channel(s)"), std::string::npos) << c.error().message;
    Image short_buffer = grey(2, 2, 0);
    short_buffer.pixels.resize(3);
    c = compare_images(grey(2, 2, 0), short_buffer, Tolerance{}, "a.png", "b.png");
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find("b.png: pixel buffer holds 3 bytes"), std::string::npos) << c.error().message;
    c = compare_images(Image{}, Image{}, Tolerance{}, "a.png", "b.png");
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find("a.png: empty image"), std::string::npos) << c.error().message;
}

// --- Tolerance files -------------------------------------------------------

const std::string kFile = R"({
  "_comment": ["notes are ignored"],
  "bricks": {"pixel_threshold": 8, "max_differing_share": 0.001, "max_mean_difference": 0.22,
             "es3": {"max_mean_difference": 0.3}},
  "pit": {"pixel_threshold": 4, "max_differing_share": 0.002, "max_mean_difference": 0.33}
})";

TEST(Tolerances, ReadsAnEntryAndItsEsOverride) {
    Result<Tolerance> t = parse_tolerances(kFile, "t.json", "bricks", 2);
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_EQ(t->pixel_threshold, 8);
    EXPECT_DOUBLE_EQ(t->max_differing_share, 0.001);
    EXPECT_DOUBLE_EQ(t->max_mean_difference, 0.22);
    t = parse_tolerances(kFile, "t.json", "bricks", 3);
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_EQ(t->pixel_threshold, 8);
    EXPECT_DOUBLE_EQ(t->max_mean_difference, 0.3);
    t = parse_tolerances(kFile, "t.json", "bricks", 0);
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_DOUBLE_EQ(t->max_mean_difference, 0.22);
    t = parse_tolerances(kFile, "t.json", "pit", 3);
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_EQ(t->pixel_threshold, 4);
}

// A CPU's override applies over the entry and its ES version's, and holds
// its own ES versions' overrides; other CPUs' are checked but not applied.
TEST(Tolerances, ACpusOverrideAppliesOnThatCpuAlone) {
    const std::string file = R"({"s": {"pixel_threshold": 8, "max_differing_share": 0.001, "max_mean_difference": 0.2,
        "es2": {"max_mean_difference": 0.25},
        "arm64": {"max_differing_share": 0.004, "_why": "measured", "es2": {"pixel_threshold": 10}},
        "armhf": {"max_mean_difference": 1.0}}})";
    Result<Tolerance> t = parse_tolerances(file, "t.json", "s", 2, "x86_64");
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_EQ(t->pixel_threshold, 8);
    EXPECT_DOUBLE_EQ(t->max_differing_share, 0.001);
    EXPECT_DOUBLE_EQ(t->max_mean_difference, 0.25);
    t = parse_tolerances(file, "t.json", "s", 2, "arm64");
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_EQ(t->pixel_threshold, 10);
    EXPECT_DOUBLE_EQ(t->max_differing_share, 0.004);
    EXPECT_DOUBLE_EQ(t->max_mean_difference, 0.25);
    t = parse_tolerances(file, "t.json", "s", 3, "arm64");
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_EQ(t->pixel_threshold, 8);
    EXPECT_DOUBLE_EQ(t->max_differing_share, 0.004);
    EXPECT_DOUBLE_EQ(t->max_mean_difference, 0.2);
    t = parse_tolerances(file, "t.json", "s", 3, "armhf");
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_DOUBLE_EQ(t->max_mean_difference, 1.0);
    EXPECT_DOUBLE_EQ(t->max_differing_share, 0.001);
}

TEST(Tolerances, TheCompiledCpuIsOneAFileCanName) {
    const std::string cpu = compiled_cpu();
    EXPECT_TRUE(cpu == "x86_64" || cpu == "i386" || cpu == "arm64" || cpu == "armhf") << cpu;
#if defined(__aarch64__)
    EXPECT_EQ(cpu, "arm64");
#elif defined(__x86_64__)
    EXPECT_EQ(cpu, "x86_64");
#endif
}

// The message a file gives for `scene`, or "" when it parses.
std::string error_of(const std::string& text, const std::string& scene = "s", int es = 3, const std::string& cpu = {}) {
    Result<Tolerance> t = parse_tolerances(text, "t.json", scene, es, cpu);
    return t ? "" : t.error().message;
}

TEST(Tolerances, ErrorsNameTheFileAndJsonPath) {
    const std::string fields = R"("pixel_threshold": 8, "max_differing_share": 0.001)";
    EXPECT_EQ(error_of(R"({"s": {)" + fields + R"(, "max_mean_difference": "0.1"}})"),
              "t.json: s.max_mean_difference: expected a number in 0..255 (levels), got string \"0.1\"");
    EXPECT_EQ(error_of(R"({"s": {)" + fields + R"(, "max_mean_difference": -0.1}})"),
              "t.json: s.max_mean_difference: expected a number in 0..255 (levels), got number -0.1");
    EXPECT_EQ(error_of(R"({"s": {"pixel_threshold": 8.5, "max_differing_share": 0, "max_mean_difference": 0}})"),
              "t.json: s.pixel_threshold: expected an integer in 0..255 (levels), got number 8.5");
    EXPECT_EQ(error_of(R"({"s": {"pixel_threshold": -1, "max_differing_share": 0, "max_mean_difference": 0}})"),
              "t.json: s.pixel_threshold: expected an integer in 0..255 (levels), got number -1");
    EXPECT_EQ(error_of(R"({"s": {"pixel_threshold": 8, "max_differing_share": 5, "max_mean_difference": 0}})"),
              "t.json: s.max_differing_share: expected a number in 0..1 (a share of the pixels), got number 5");
    EXPECT_EQ(error_of(R"({"s": {)" + fields + R"(}})"), "t.json: s: missing \"max_mean_difference\"");
    // An override is checked whichever ES version is asked for.
    EXPECT_EQ(error_of(R"({"s": {)" + fields + R"(, "max_mean_difference": 0, "es2": {"pixel_threshold": true}}})"),
              "t.json: s.es2.pixel_threshold: expected an integer in 0..255 (levels), got boolean true");
    EXPECT_EQ(error_of(R"({"s": {)" + fields + R"(, "max_mean_difference": 0, "es3": [1]}})"),
              "t.json: s.es3: expected an object, got array of 1");
    EXPECT_EQ(error_of(R"({"s": {)" + fields + R"(, "max_mean_difference": 0, "es3": {"max_mean": 1}}})"),
              "t.json: s.es3: unknown field 'max_mean' (an override holds pixel_threshold, max_differing_share, "
              "max_mean_difference)");
    EXPECT_EQ(error_of(R"({"s": 3})"), "t.json: s: expected an object, got number 3");
    EXPECT_EQ(error_of("[]"), "t.json: expected an object of scene entries at the top level, got array of 0");
}

// A CPU's override is checked on every CPU, applied or not, and holds no
// misspelt field.
TEST(Tolerances, ACpusOverrideIsCheckedOnEveryCpu) {
    const std::string entry = R"({"s": {"pixel_threshold": 8, "max_differing_share": 0.001, "max_mean_difference": 0.2, )";
    EXPECT_EQ(error_of(entry + R"("arm64": {"es3": {"pixel_threshold": 300}}}})", "s", 2, "x86_64"),
              "t.json: s.arm64.es3.pixel_threshold: expected an integer in 0..255 (levels), got number 300");
    EXPECT_EQ(error_of(entry + R"("armhf": {"max_share": 0.1}}})", "s", 2, "armhf"),
              "t.json: s.armhf: unknown field 'max_share' (an override holds pixel_threshold, max_differing_share, "
              "max_mean_difference; a CPU's also es2 and es3)");
}

TEST(Tolerances, UnknownSceneListsTheFilesScenes) {
    EXPECT_EQ(error_of(kFile, "brick"), "t.json: no entry for scene 'brick' (the file has: bricks, pit)");
}

TEST(Tolerances, NotesAreNeverAnEntry) {
    const std::string file =
        R"({"_made_on": {"pixel_threshold": 1, "max_differing_share": 0, "max_mean_difference": 0}, )"
        R"("pit": {"pixel_threshold": 8, "max_differing_share": 0.001, "max_mean_difference": 0.3}})";
    EXPECT_EQ(error_of(file, "_made_on"), "t.json: no entry for scene '_made_on' (the file has: pit)");
}

TEST(Tolerances, MalformedJsonGivesLineAndColumn) {
    const std::string message = error_of("{\n  \"s\": {,}\n}\n");
    EXPECT_EQ(message.rfind("t.json:2:9: malformed JSON", 0), 0u) << message;
}

TEST(Tolerances, MissingFileIsNamed) {
    Result<Tolerance> t = load_tolerances("/nonexistent/tolerances.json", "s", 3);
    ASSERT_FALSE(t.ok());
    EXPECT_NE(t.error().message.find("/nonexistent/tolerances.json"), std::string::npos) << t.error().message;
}

// The project's own file has a valid entry for every built-in scene.
TEST(Tolerances, ProjectFileCoversEveryBuiltinScene) {
    for (const std::string& scene : builtin_scene_names())
        for (int es : {2, 3}) {
            for (const char* cpu : {"x86_64", "arm64", "armhf"}) {
                Result<Tolerance> t =
                    load_tolerances(std::string(PX_SOURCE_DIR) + "/tests/golden/tolerances.json", scene, es, cpu);
                EXPECT_TRUE(t.ok()) << t.error().message;
            }
        }
}

}  // namespace
}  // namespace px
