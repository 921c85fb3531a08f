// libFuzzer target: scene text through the parser and the scene checks,
// as a host app's parse_scene call receives it. Any crash, sanitizer
// report, leak or input slower than the -timeout is a finding; each one
// becomes a test in tests/unit_hostile.cpp.
#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <memory>
#include <string>

#include "parallaxes/planner/planner.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/scene/scene.h"

namespace {

// The effect planner on the parsed scene, on an ES 3.0 and a bare ES 2.0
// context: whatever the camera, transforms and requests, a plan or an
// error, never a crash. Small procedural fields are measured; anything
// else gets a stand-in relief of its declared size (no decoding here).
void plan(const px::SceneDesc& scene) {
    std::vector<px::MaterialRelief> reliefs;
    for (const px::MaterialDesc& m : scene.materials) {
        px::MaterialRelief r;
        const px::FieldSpec& f = m.height.field;
        if (m.height.kind == px::TextureSource::Kind::procedural && f.size <= 128) {
            px::Result<px::MaterialImages> images = px::build_material_images(m, "");
            if (images) r = px::material_relief(px::quantized_8bit(images->field), m);
        }
        if (r.traced_width == 0) {
            r.traced_width = r.traced_height = std::max(1, std::min(f.size, 4096));
            r.features.width = r.features.height = r.traced_width;
            r.features.range = 1.0;
            r.features.steepness = 1.0;
            r.features.thinnest_texels = 1.0;
            r.features.depth_texels = static_cast<double>(m.height_scale) * r.traced_width;
        }
        reliefs.push_back(r);
    }
    for (int es : {3, 2}) {
        px::Caps caps;
        caps.es_major = es;
        px::Result<std::unique_ptr<px::ScenePlanner>> planner = px::ScenePlanner::create(scene, caps, reliefs);
        if (!planner) continue;
        px::Result<std::vector<px::ObjectPlan>> plans = (*planner)->plan(scene.camera, 64, 48);
        if (plans && plans->size() != scene.objects.size()) __builtin_trap();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    px::Result<px::SceneDesc> scene = px::parse_scene(text, "fuzz.json");
    if (scene) {
        // What a loaded scene must satisfy: parse_scene ran both checks.
        if (!px::validate_scene(*scene)) __builtin_trap();
        if (!px::check_scene_resources(*scene, false)) __builtin_trap();
        plan(*scene);
    } else if (scene.error().message.size() > 4096) {
        __builtin_trap();  // messages bound what they echo
    }
    return 0;
}
