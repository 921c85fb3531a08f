// What a material asks for when it declares effects instead of naming a
// technique: the planner (src/planner/) turns the request into the cheapest
// shader variant that meets it on a given context, camera and scene.
#pragma once

#include <cstdint>
#include <string>

#include "parallaxes/core/result.h"
#include "parallaxes/effects/technique.h"

namespace px {

// auto: the planner decides from the scene; on and off force the effect.
enum class EffectSwitch : std::uint8_t { automatic, on, off };

struct EffectRequest {
    // Parallax: the relief traced at all. off: normal mapping.
    bool parallax = true;
    // The quality target: the 95th percentile over the surface's pixels of
    // the hit's distance from the exact reference's, in texels of the mip
    // level the pixel samples (base-level texels where the texture is
    // magnified, 2^L texels at level L): what a viewer can see, so that a
    // surface far away is not asked for sub-texel accuracy that no pixel
    // shows. docs/planner.md says how it is predicted and measured.
    float max_error_texels = 1.0f;
    // Self-shadowing along a ray toward each light.
    ShadowMode shadow = ShadowMode::none;
    // The shadow's target: the mean |visibility difference| from the exact
    // reference's over the surface's pixels (0..1).
    float shadow_max_error = 0.1f;
    // Depth of the relief's hit written as the fragment's depth
    // (gl_FragDepth), so that other geometry meeting the relief is hidden
    // and shown where the relief is. auto: only where another object meets
    // or overlaps this one's relief in screen space.
    EffectSwitch depth_correction = EffectSwitch::automatic;
    // Tatarchuk's mip-level fade to normal mapping. auto: where the surface
    // crosses the threshold and the target still holds with it.
    EffectSwitch lod_fade = EffectSwitch::automatic;
    float lod_threshold = 3.0f;
    float lod_band = 1.0f;
};

const char* effect_switch_name(EffectSwitch s);
Result<EffectSwitch> parse_effect_switch(const std::string& name);

// Range checks; `path` is the request's JSON path (materials[i].effects).
Status validate_effect_request(const EffectRequest& request, const std::string& path);

}  // namespace px
