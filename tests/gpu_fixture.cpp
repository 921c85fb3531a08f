#include "gpu_fixture.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <unistd.h>

namespace px::test {

std::unique_ptr<platform::HeadlessContext> GpuEnvironment::context_;

void GpuEnvironment::SetUp() {
    // (HeadlessContext::create keeps Mesa's shader cache out of runs on
    // another llvmpipe configuration; see platform/headless_context.cpp.)
    platform::ContextOptions options;
    options.es_major = test_es_major();
    auto context = platform::HeadlessContext::create(options);
    ASSERT_TRUE(context.ok()) << context.error().message;
    context_ = std::move(*context);
}

std::string test_folder(const std::string& tag, const std::string& name) {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string dir = ::testing::TempDir() + "/px_" + tag + "_" + std::to_string(::getpid()) + "_" +
                            (info ? info->name() : "t") + "_" + name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

SceneDesc PlaneScene::build() const {
    SceneDesc s;
    s.name = "test plane";
    const float a = glm::radians(view_angle_deg);
    // Tilt toward -y so the view direction has a tangent-space component.
    s.camera.position = glm::vec3(0.0f, -distance * std::sin(a), distance * std::cos(a));
    s.camera.target = glm::vec3(0.0f);
    s.camera.up = view_angle_deg < 1.0f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f);
    s.camera.fov_y_deg = fov_deg;
    LightDesc light;
    const float e = glm::radians(light_elevation_deg);
    light.direction = -glm::vec3(std::cos(e), 0.0f, std::sin(e));  // travels from +x, downward
    light.angular_radius_deg = light_angular_radius_deg;
    s.lights.push_back(light);

    MaterialDesc m;
    m.name = "surface";
    m.height.kind = TextureSource::Kind::procedural;
    m.height.field = field;
    m.height_scale = height_scale;
    m.height_bias = height_bias;
    if (textured_albedo) {
        m.albedo.kind = TextureSource::Kind::procedural;
        m.albedo.field.kind = FieldKind::sine;
        m.albedo.field.size = 256;
        m.albedo.field.frequency = 8.0f;
    } else {
        m.albedo.kind = TextureSource::Kind::color;
        m.albedo.color = glm::vec3(0.8f);
    }
    m.uv.scale = glm::vec2(uv_scale);
    m.technique = options;
    m.technique.technique = technique;
    s.materials.push_back(m);

    ObjectDesc o;
    o.name = "plane";
    o.mesh.kind = MeshKind::plane;
    o.mesh.size = 2.0f;
    o.material = "surface";
    s.objects.push_back(o);
    return s;
}

Rendered render(const SceneDesc& scene, int size, bool emulate_no_fragment_highp) {
    Rendered out;
    RendererOptions options;
    options.emulate_no_fragment_highp = emulate_no_fragment_highp;
    options.get_proc_address = platform::HeadlessContext::proc_loader();
    options.effect_planner = effect_planner;
    options.texture_files = texture_files();
    auto renderer = Renderer::create(options);
    EXPECT_TRUE(renderer.ok()) << renderer.error().message;
    if (!renderer) return out;
    auto target = OffscreenTarget::create(size, size);
    EXPECT_TRUE(target.ok()) << target.error().message;
    if (!target) return out;
    Status loaded = (*renderer)->load(scene);
    EXPECT_TRUE(loaded.ok()) << loaded.error().message;
    if (!loaded) return out;
    Status drawn = (*renderer)->draw(target->target());
    EXPECT_TRUE(drawn.ok()) << drawn.error().message;
    auto image = target->read_pixels();
    EXPECT_TRUE(image.ok()) << image.error().message;
    if (image) out.image = std::move(*image);
    out.reports = (*renderer)->reports();
    // PX_TEST_DUMP_DIR=folder keeps every rendered image, for looking at a failure.
    if (const char* dir = std::getenv("PX_TEST_DUMP_DIR"); dir && image) {
        static int counter = 0;
        const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
        const std::string name = std::string(dir) + "/" + (info ? info->name() : "render") + "_es" +
                                 std::to_string(test_es_major()) + "_" + std::to_string(counter++) + ".png";
        Status written = write_png(name, out.image);
        if (!written) ADD_FAILURE() << written.error().message;
    }
    return out;
}

ImageDiff compare(const Image& a, const Image& b) {
    ImageDiff d;
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    if (a.pixels.size() != b.pixels.size() || a.pixels.empty()) {
        d.mean = 255.0;
        d.max = 255;
        return d;
    }
    double sum = 0.0;
    size_t count = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        if (i % 4 == 3) continue;  // alpha
        const int diff = std::abs(int(a.pixels[i]) - int(b.pixels[i]));
        sum += diff;
        d.max = std::max(d.max, diff);
        ++count;
    }
    d.mean = sum / static_cast<double>(count);
    return d;
}

double luminance(const Image& image, int x, int y, int half_size) {
    double sum = 0.0;
    int count = 0;
    for (int j = y - half_size; j <= y + half_size; ++j)
        for (int i = x - half_size; i <= x + half_size; ++i) {
            if (i < 0 || j < 0 || i >= image.width || j >= image.height) continue;
            const std::uint8_t* p = image.texel(i, j);
            sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            ++count;
        }
    return count ? sum / count : 0.0;
}

glm::vec2 project(const SceneDesc& scene, const glm::vec3& world, int size) {
    const CameraDesc& c = scene.camera;
    const glm::mat4 view = glm::lookAt(c.position, c.target, c.up);
    const glm::mat4 projection = glm::perspective(glm::radians(c.fov_y_deg), 1.0f, c.near_plane, c.far_plane);
    const glm::vec4 clip = projection * view * glm::vec4(world, 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return (ndc * 0.5f + 0.5f) * static_cast<float>(size);
}

}  // namespace px::test
