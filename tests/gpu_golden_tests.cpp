// Golden images of every built-in scene, with the tolerances stated (and
// explained) in tests/golden/tolerances.json. The goldens hold on every
// x86-64 CPU class llvmpipe supports: ctest runs them on the machine's own
// (AVX2 and F16C here), with 128-bit vectors (LP_NATIVE_VECTOR_WIDTH=128),
// on SSE4.1 and on SSE2 (GALLIUM_OVERRIDE_CPU_CAPS), all with llvmpipe's
// 8-bit texture-filtering shortcut off (GALLIVM_PERF=no_aos_sampling: that
// path rounds differently with and without SSSE3, see tolerances.json), see
// tests/CMakeLists.txt. On the configuration the goldens were made on
// ("_made_on" in tolerances.json) the render must match its golden almost
// exactly, so a golden that no longer matches the code (a stale one) fails
// there instead of hiding inside the other CPUs' tolerance. A missing golden
// is reported apart from a mismatch; a mismatch names the configuration it
// ran on and writes the rendered image and a diff image into golden_failures/
// beside the test's working directory. PX_UPDATE_GOLDEN=1 writes the current
// renders as goldens and skips (ctest reports the skip as such); write them
// on the made-on configuration, or update "_made_on".
#include "gpu_fixture.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "parallaxes/assets/image_compare.h"
#include "parallaxes/gl/caps.h"

namespace px::test {
namespace {

const std::string kGoldenDir = std::string(PX_SOURCE_DIR) + "/tests/golden";

// The scene's entry of tolerances.json, with its "es2"/"es3" sub-entry and
// then its entry for the CPU the tests were built for ("arm64", "armhf"; if
// any) over it; the file's reader and the measure are the library's
// (assets/image_compare.h), shared with `parallax compare`.
Tolerance tolerance_for(const std::string& scene, int es_major) {
    Result<Tolerance> t = load_tolerances(kGoldenDir + "/tolerances.json", scene, es_major, compiled_cpu());
    if (t) return *t;
    ADD_FAILURE() << t.error().message;
    return Tolerance{0, 0.0, 0.0};
}

// Whether the CPU has F16C.
bool cpu_has_f16c() {
    std::ifstream cpuinfo("/proc/cpuinfo");
    for (std::string line; std::getline(cpuinfo, line);)
        if (line.rfind("flags", 0) == 0) return line.find(" f16c") != std::string::npos;
    return false;
}

std::string env_or(const char* name, const char* fallback) {
    const char* v = std::getenv(name);
    return v ? v : fallback;
}

// The rasterizer configuration a render ran on, as the driver reports it.
struct RasterConfig {
    std::string renderer;
    std::string version;    // GL_VERSION: "OpenGL ES 3.2 Mesa 22.3.6"
    int mediump_bits = 0;   // fragment mediump float precision: 10 = fp16 (llvmpipe uses F16C)
    bool cpu_f16c = false;  // the CPU's flag, which GALLIUM_OVERRIDE_CPU_CAPS can hide from Mesa

    bool fp16() const { return mediump_bits > 0 && mediump_bits <= 10; }
    int vector_bits() const {
        std::smatch m;
        return std::regex_search(renderer, m, std::regex("([0-9]+) bits")) ? std::stoi(m[1]) : 0;
    }
    // A short tag for file names: w256_f16c, w128_nof16c.
    std::string tag() const {
        return "w" + std::to_string(vector_bits()) + (fp16() ? "_f16c" : "_nof16c");
    }
    std::string describe() const {
        std::ostringstream s;
        s << "renderer '" << renderer << "', '" << version << "', F16C in use: " << (fp16() ? "yes" : "no") << " (mediump float "
          << mediump_bits << " bits), CPU F16C flag: " << (cpu_f16c ? "yes" : "no")
          << ", LP_NATIVE_VECTOR_WIDTH=" << env_or("LP_NATIVE_VECTOR_WIDTH", "(unset)")
          << ", GALLIUM_OVERRIDE_CPU_CAPS=" << env_or("GALLIUM_OVERRIDE_CPU_CAPS", "(unset)")
          << ", GALLIVM_PERF=" << env_or("GALLIVM_PERF", "(unset)");
        return s.str();
    }
};

RasterConfig raster_config() {
    const Caps caps = query_caps();
    return RasterConfig{caps.renderer, caps.version, caps.fragment_mediump_float.precision, cpu_has_f16c()};
}

// llvmpipe with its 8-bit texture-filtering path on rounds differently with
// and without SSSE3; the goldens are defined with it off. Empty when the
// configuration is right; otherwise what is wrong.
std::string sampling_problem(const RasterConfig& config) {
    if (config.renderer.find("llvmpipe") == std::string::npos) return {};
    const std::string perf = env_or("GALLIVM_PERF", "");
    if (perf.find("no_aos_sampling") != std::string::npos) return {};
    return "the goldens are defined with GALLIVM_PERF=no_aos_sampling (llvmpipe's 8-bit filtering rounds "
           "differently on CPUs without SSSE3; tests/golden/tolerances.json), and it is '" + perf +
           "' here: run them through ctest, or set it";
}

// The configuration the goldens were made on, and the limits that hold
// there (tolerances.json "_made_on"): a render on it must match its golden
// almost exactly. Absent: no such check (a failure, since the file has it).
struct MadeOn {
    std::string renderer;
    std::string mesa;  // GL_VERSION ends "Mesa <this>"
    int mediump_bits = 0;
    Tolerance tolerance;
    bool matches(const RasterConfig& c) const {
        const std::string suffix = "Mesa " + mesa;
        return c.renderer == renderer && c.mediump_bits == mediump_bits && c.version.size() >= suffix.size() &&
               c.version.compare(c.version.size() - suffix.size(), suffix.size(), suffix) == 0;
    }
};

Result<MadeOn> made_on() {
    const std::string path = kGoldenDir + "/tolerances.json";
    std::ifstream in(path);
    try {
        const nlohmann::json j = nlohmann::json::parse(in);
        const nlohmann::json& m = j.at("_made_on");
        MadeOn made;
        made.renderer = m.at("renderer").get<std::string>();
        made.mesa = m.at("mesa").get<std::string>();
        made.mediump_bits = m.at("mediump_float_bits").get<int>();
        const nlohmann::json& t = m.at("tolerance");
        made.tolerance = Tolerance{t.at("pixel_threshold").get<int>(), t.at("max_differing_share").get<double>(),
                                   t.at("max_mean_difference").get<double>()};
        return made;
    } catch (const std::exception& e) {
        return make_error(path + ": _made_on: " + e.what());
    }
}

// The comparison of a render with its golden; a failure to compare (a size
// mismatch) fails the test.
ImageComparison compare_to_golden(const Image& image, const Image& golden, const Tolerance& tolerance) {
    Result<ImageComparison> c = compare_images(image, golden, tolerance, "render", "golden");
    if (c) return *c;
    ADD_FAILURE() << c.error().message;
    ImageComparison failed;
    failed.tolerance = tolerance;
    failed.share = failed.mean = 1e9;
    return failed;
}

std::string golden_path(const std::string& scene_name) {
    return kGoldenDir + "/" + scene_name + "_es" + std::to_string(test_es_major()) + ".png";
}

std::string summary(const ImageComparison& c, const Tolerance& t) {
    std::ostringstream s;
    s << "max channel difference " << c.max_difference << ", " << c.differing << " pixels ("
      << 100.0 * c.share << "%) over " << t.pixel_threshold << " levels (allowed "
      << 100.0 * t.max_differing_share << "%), mean difference " << c.mean << " levels (allowed "
      << t.max_mean_difference << ")";
    return s.str();
}

class Golden : public ::testing::TestWithParam<std::string> {};

TEST_P(Golden, BuiltinSceneMatchesItsGolden) {
    const std::string scene_name = GetParam();
    const RasterConfig config = raster_config();
    RecordProperty("configuration", config.describe());
    if (const std::string problem = sampling_problem(config); !problem.empty()) FAIL() << problem;
    // The configuration asked for is the one the driver runs.
    if (const char* width = std::getenv("LP_NATIVE_VECTOR_WIDTH"))
        EXPECT_EQ(std::to_string(config.vector_bits()), width) << config.describe();
    auto scene = builtin_scene(scene_name);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    const Image image = render(*scene, 128).image;
    ASSERT_EQ(image.width, 128);
    const std::string golden_file = golden_path(scene_name);
    if (const char* update = std::getenv("PX_UPDATE_GOLDEN"); update && std::string(update) == "1") {
        Status s = write_png(golden_file, image);
        ASSERT_TRUE(s.ok()) << s.error().message;
        GTEST_SKIP() << "wrote " << golden_file << " on " << config.describe();
    }
    if (!std::filesystem::exists(golden_file))
        FAIL() << "MISSING GOLDEN (not a mismatch): " << golden_file
               << "; render it with PX_UPDATE_GOLDEN=1 and review it before committing";
    auto golden = load_image(golden_file, 4);
    ASSERT_TRUE(golden.ok()) << golden.error().message;
    ASSERT_EQ(golden->width, image.width);
    ASSERT_EQ(golden->height, image.height);

    Result<MadeOn> made = made_on();
    ASSERT_TRUE(made.ok()) << made.error().message;
    const bool strict = made->matches(config);
    // On the configuration the goldens were made on, a stale golden fails.
    const Tolerance tol = strict ? made->tolerance : tolerance_for(scene_name, test_es_major());
    const ImageComparison c = compare_to_golden(image, *golden, tol);
    const std::string stem = scene_name + "_es" + std::to_string(test_es_major());
    // One line per comparison, pass or fail: what the tolerances were measured from.
    std::cout << "[ golden   ] " << stem << " (" << config.tag() << (strict ? ", made-on configuration" : "")
              << "): " << summary(c, tol) << std::endl;
    if (c.passed()) return;

    std::error_code ec;
    const std::filesystem::path dir = std::filesystem::absolute("golden_failures", ec);
    std::filesystem::create_directories(dir, ec);
    const std::string actual = (dir / (stem + "_" + config.tag() + "_actual.png")).string();
    const std::string diff = (dir / (stem + "_" + config.tag() + "_diff.png")).string();
    const Status wrote_actual = write_png(actual, image);
    const Status wrote_diff = write_png(diff, c.diff);
    ADD_FAILURE() << "GOLDEN MISMATCH: " << stem << " on " << config.describe()
                  << (strict ? "\n  this is the configuration the goldens were made on (tolerances.json _made_on): "
                               "the golden is stale, or the code changed what it draws; review the diff, then "
                               "PX_UPDATE_GOLDEN=1 if the change is meant"
                             : "")
                  << "\n  " << summary(c, tol)
                  << "\n  golden: " << golden_file << "\n  actual: "
                  << (wrote_actual ? actual : "not written: " + wrote_actual.error().message)
                  << "\n  diff (red: over the threshold): "
                  << (wrote_diff ? diff : "not written: " + wrote_diff.error().message);
}

// The tolerances still catch a real change: every relief 5% deeper fails
// each scene's comparison, on whichever configuration this runs. (Measured
// when the tolerances were set: 2% deeper fails default, bricks and pit but
// not shapes; swapping pom and steep fails all four; see tolerances.json.)
class GoldenTolerance : public ::testing::TestWithParam<std::string> {};

TEST_P(GoldenTolerance, RejectsAFivePercentDeeperRelief) {
    const std::string scene_name = GetParam();
    if (const std::string problem = sampling_problem(raster_config()); !problem.empty()) FAIL() << problem;
    if (!std::filesystem::exists(golden_path(scene_name)))
        FAIL() << "MISSING GOLDEN: " << golden_path(scene_name);
    auto scene = builtin_scene(scene_name);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    for (MaterialDesc& m : scene->materials) m.height_scale *= 1.05f;
    const Image image = render(*scene, 128).image;
    ASSERT_EQ(image.width, 128);
    auto golden = load_image(golden_path(scene_name), 4);
    ASSERT_TRUE(golden.ok()) << golden.error().message;
    ASSERT_EQ(golden->width, image.width);
    ASSERT_EQ(golden->height, image.height);
    const Tolerance tol = tolerance_for(scene_name, test_es_major());
    const ImageComparison c = compare_to_golden(image, *golden, tol);
    EXPECT_FALSE(c.passed()) << scene_name << " with every height_scale 5% larger still passes its golden ("
                             << summary(c, tol) << ") on " << raster_config().describe()
                             << ": the tolerances are too loose to catch a regression";
}

INSTANTIATE_TEST_SUITE_P(BuiltinScenes, GoldenTolerance, ::testing::ValuesIn(builtin_scene_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

INSTANTIATE_TEST_SUITE_P(BuiltinScenes, Golden, ::testing::ValuesIn(builtin_scene_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace px::test
