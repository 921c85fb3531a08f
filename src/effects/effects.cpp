#include "parallaxes/effects/effects.h"

#include <sstream>

namespace px {

const char* effect_switch_name(EffectSwitch s) {
    switch (s) {
        case EffectSwitch::automatic: return "auto";
        case EffectSwitch::on: return "on";
        case EffectSwitch::off: return "off";
    }
    return "auto";
}

Result<EffectSwitch> parse_effect_switch(const std::string& name) {
    if (name == "auto") return EffectSwitch::automatic;
    if (name == "on") return EffectSwitch::on;
    if (name == "off") return EffectSwitch::off;
    return make_error("expected \"auto\", \"on\" or \"off\"");
}

namespace {
std::string num(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}
}  // namespace

Status validate_effect_request(const EffectRequest& r, const std::string& path) {
    // The smallest target a table can stand behind: the exact technique's
    // rounding is about 1/64 texel (docs/accuracy.md); 1/1024 leaves room.
    if (!(r.max_error_texels >= 1.0 / 1024.0 && r.max_error_texels <= 1000.0))
        return make_error(path + ".parallax.max_error_texels: must be within [0.0009765625, 1000] texels, got " +
                          num(r.max_error_texels));
    if (!(r.shadow_max_error > 0.0 && r.shadow_max_error <= 1.0))
        return make_error(path + ".shadow.max_error: must be within (0, 1] (a mean visibility difference), got " +
                          num(r.shadow_max_error));
    if (!(r.lod_threshold >= 0.0f && r.lod_threshold <= 16.0f))
        return make_error(path + ".lod_fade.threshold: must be within [0, 16] mip levels, got " + num(r.lod_threshold));
    if (!(r.lod_band > 0.0f && r.lod_band <= 8.0f))
        return make_error(path + ".lod_fade.band: must be within (0, 8] mip levels, got " + num(r.lod_band));
    // Contradictions: effects of the relief without the relief.
    if (!r.parallax) {
        if (r.shadow != ShadowMode::none)
            return make_error(path + ".shadow: \"" + shadow_mode_name(r.shadow) +
                              "\" contradicts \"parallax\": \"off\" (the shadow ray is traced through the relief)");
        if (r.depth_correction == EffectSwitch::on)
            return make_error(path + ".depth_correction: \"on\" contradicts \"parallax\": \"off\" (there is no "
                              "relief hit whose depth could be written)");
        if (r.lod_fade == EffectSwitch::on)
            return make_error(path + ".lod_fade: \"on\" contradicts \"parallax\": \"off\" (there is no parallax to "
                              "fade out)");
    }
    return {};
}

}  // namespace px
