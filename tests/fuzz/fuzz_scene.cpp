// libFuzzer target: scene text through the parser and the scene checks,
// as a host app's parse_scene call receives it. Any crash, sanitizer
// report, leak or input slower than the -timeout is a finding; each one
// becomes a test in tests/unit_hostile.cpp.
#include <cstddef>
#include <cstdint>
#include <string>

#include "scene/material_images.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    px::Result<px::SceneDesc> scene = px::parse_scene(text, "fuzz.json");
    if (scene) {
        // What a loaded scene must satisfy: parse_scene ran both checks.
        if (!px::validate_scene(*scene)) __builtin_trap();
        if (!px::check_scene_resources(*scene, false)) __builtin_trap();
    } else if (scene.error().message.size() > 4096) {
        __builtin_trap();  // messages bound what they echo
    }
    return 0;
}
