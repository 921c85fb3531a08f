// Golden images of the built-in scenes, with the tolerances stated in
// tests/golden/tolerances.json. A missing golden is reported apart from a
// mismatch; a mismatch writes the rendered image and a diff image next to
// the test binary. PX_UPDATE_GOLDEN=1 writes the current renders as goldens.
#include "gpu_fixture.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

namespace px::test {
namespace {

const std::string kGoldenDir = std::string(PX_SOURCE_DIR) + "/tests/golden";

struct Tolerance {
    int pixel_threshold = 0;
    double max_differing_share = 0.0;
    double max_mean_difference = 0.0;
};

Tolerance tolerance_for(const std::string& scene) {
    std::ifstream file(kGoldenDir + "/tolerances.json");
    EXPECT_TRUE(file.good()) << "cannot read " << kGoldenDir << "/tolerances.json";
    const nlohmann::json j = nlohmann::json::parse(file, nullptr, false);
    EXPECT_FALSE(j.is_discarded()) << "tolerances.json is malformed";
    EXPECT_TRUE(j.contains(scene)) << "tolerances.json has no entry for '" << scene << "'";
    Tolerance t;
    if (j.is_discarded() || !j.contains(scene)) return t;
    t.pixel_threshold = j[scene].value("pixel_threshold", 0);
    t.max_differing_share = j[scene].value("max_differing_share", 0.0);
    t.max_mean_difference = j[scene].value("max_mean_difference", 0.0);
    return t;
}

// Whether this CPU has F16C (llvmpipe lowers mediump to fp16 only with it).
bool cpu_has_f16c() {
    std::ifstream cpuinfo("/proc/cpuinfo");
    for (std::string line; std::getline(cpuinfo, line);)
        if (line.rfind("flags", 0) == 0) return line.find(" f16c") != std::string::npos;
    return false;
}

// The goldens hold for the rasterizer configuration that made them; on
// another one the comparison says nothing about the renderer.
std::string configuration_mismatch() {
    std::ifstream file(kGoldenDir + "/tolerances.json");
    const nlohmann::json j = nlohmann::json::parse(file, nullptr, false);
    if (j.is_discarded() || !j.contains("_generated_on")) return "";
    const std::string renderer = query_caps().renderer;
    const std::string golden_renderer = j["_generated_on"].value("renderer", "");
    const bool golden_f16c = j["_generated_on"].value("f16c", true);
    if (renderer != golden_renderer)
        return "goldens were made on '" + golden_renderer + "', this renderer is '" + renderer + "'";
    if (cpu_has_f16c() != golden_f16c)
        return std::string("goldens were made on a CPU ") + (golden_f16c ? "with" : "without") +
               " F16C (mediump as fp16), this one " + (golden_f16c ? "lacks it" : "has it");
    return "";
}

class Golden : public ::testing::TestWithParam<std::string> {};

TEST_P(Golden, BuiltinSceneMatchesItsGolden) {
    const std::string scene_name = GetParam();
    auto scene = builtin_scene(scene_name);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    const Image image = render(*scene, 128).image;
    ASSERT_EQ(image.width, 128);
    const std::string golden_path =
        kGoldenDir + "/" + scene_name + "_es" + std::to_string(test_es_major()) + ".png";
    if (const char* update = std::getenv("PX_UPDATE_GOLDEN"); update && std::string(update) == "1") {
        Status s = write_png(golden_path, image);
        ASSERT_TRUE(s.ok()) << s.error().message;
        GTEST_SKIP() << "wrote " << golden_path;
    }
    if (const std::string mismatch = configuration_mismatch(); !mismatch.empty())
        GTEST_SKIP() << mismatch << "; re-render with PX_UPDATE_GOLDEN=1 on this configuration";
    if (!std::filesystem::exists(golden_path))
        FAIL() << "MISSING GOLDEN (not a mismatch): " << golden_path
               << "; render it with PX_UPDATE_GOLDEN=1 and review it before committing";
    auto golden = load_image(golden_path, 4);
    ASSERT_TRUE(golden.ok()) << golden.error().message;
    ASSERT_EQ(golden->width, image.width);
    ASSERT_EQ(golden->height, image.height);

    const Tolerance tol = tolerance_for(scene_name);
    Image diff = image;
    long differing = 0;
    double sum = 0.0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            int worst = 0;
            for (int c = 0; c < 3; ++c) {
                const int d = std::abs(int(image.texel(x, y)[c]) - int(golden->texel(x, y)[c]));
                worst = std::max(worst, d);
                sum += d;
            }
            if (worst > tol.pixel_threshold) ++differing;
            std::uint8_t* p = diff.texel(x, y);  // red where it differs, grey elsewhere
            const std::uint8_t grey = static_cast<std::uint8_t>(image.texel(x, y)[1] / 4);
            p[0] = worst > tol.pixel_threshold ? 255 : grey;
            p[1] = p[2] = grey;
            p[3] = 255;
        }
    const double share = double(differing) / (image.width * image.height);
    const double mean = sum / (3.0 * image.width * image.height);
    const bool ok = share <= tol.max_differing_share && mean <= tol.max_mean_difference;
    if (!ok) {
        const std::string stem = scene_name + "_es" + std::to_string(test_es_major());
        (void)write_png(stem + "_actual.png", image);
        (void)write_png(stem + "_diff.png", diff);
    }
    EXPECT_LE(share, tol.max_differing_share)
        << scene_name << ": " << differing << " pixels differ by more than " << tol.pixel_threshold
        << " levels; see " << scene_name << "_es" << test_es_major() << "_diff.png beside the test binary";
    EXPECT_LE(mean, tol.max_mean_difference) << scene_name << ": mean difference " << mean << " levels";
}

INSTANTIATE_TEST_SUITE_P(BuiltinScenes, Golden, ::testing::Values("default", "pit", "shapes"));

}  // namespace
}  // namespace px::test
