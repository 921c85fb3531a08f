// Shared set-up for the surfaceless GPU tests: one headless context per test
// process, its ES version from PX_TEST_ES (2 or 3; ctest runs both), and
// small scenes built in code so each test controls exactly what it measures.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "parallaxes/platform/headless_context.h"
#include "parallaxes/render/offscreen_target.h"
#include "parallaxes/render/renderer.h"

namespace px::test {

// A renderer's options for scenes that read files: the headless loader and
// every texture file reader.
inline RendererOptions reading_files() {
    RendererOptions o;
    o.get_proc_address = platform::HeadlessContext::proc_loader();
    o.texture_files = texture_files();
    return o;
}

inline int test_es_major() {
    const char* es = std::getenv("PX_TEST_ES");
    return es && std::string(es) == "2" ? 2 : 3;
}

// The context lives for the whole test program.
class GpuEnvironment : public ::testing::Environment {
public:
    void SetUp() override;
    void TearDown() override { context_.reset(); }
    static platform::HeadlessContext* context() { return context_.get(); }

private:
    static std::unique_ptr<platform::HeadlessContext> context_;
};

// A plane of size 2 in the xy plane at the origin, facing +z, with one
// material; the camera looks at its centre from `view_angle_deg` off the
// normal (0 = straight on), `distance` away.
struct PlaneScene {
    FieldSpec field;
    float height_scale = 0.08f;
    std::optional<float> height_bias;
    Technique technique = Technique::pom;
    TechniqueOptions options;
    float view_angle_deg = 0.0f;
    float distance = 3.0f;
    float fov_deg = 40.0f;
    float light_elevation_deg = 60.0f;  // light from the +x side
    float light_angular_radius_deg = 2.0f;
    bool textured_albedo = true;        // a checker-like albedo so uv shifts show
    float uv_scale = 1.0f;

    SceneDesc build() const;
};

struct Rendered {
    Image image;
    std::vector<DrawReport> reports;
};

// Renders a scene at size x size pixels; fails the test on any error.
// `emulate_no_fragment_highp`: as a GPU without fragment highp (ES 2.0 only).
Rendered render(const SceneDesc& scene, int size = 128, bool emulate_no_fragment_highp = false);

// A fresh folder of its own per test under gtest's temporary folder:
// TempDir/px_<tag>_<pid>_<test name>_<name>, emptied first.
std::string test_folder(const std::string& tag, const std::string& name);

// Mean absolute difference per channel (0..255) and the largest one.
struct ImageDiff {
    double mean = 0.0;
    int max = 0;
};
ImageDiff compare(const Image& a, const Image& b);

// Mean luminance (0..255) of a square of pixels centred at (x, y).
double luminance(const Image& image, int x, int y, int half_size = 1);

// Where a world point lands in the image, in pixels (row 0 = bottom).
glm::vec2 project(const SceneDesc& scene, const glm::vec3& world, int size);

}  // namespace px::test
