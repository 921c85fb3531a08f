// A headless context and an offscreen target of one size: what the
// benchmark commands draw into. The target is released before the context.
#pragma once

#include <memory>
#include <optional>

#include "parallaxes/core/result.h"
#include "parallaxes/planner/planner.h"
#include "parallaxes/platform/headless_context.h"
#include "parallaxes/render/offscreen_target.h"
#include "parallaxes/render/renderer.h"

namespace px::tools {

struct DrawSurface {
    std::unique_ptr<platform::HeadlessContext> context;  // declared first: released last
    std::optional<OffscreenTarget> target;                // always engaged (made after the context)
};

// The renderer as the `parallax` program makes it: the effect planner, every
// texture-file reader, and GL from the headless context (or `get_proc_address`).
inline RendererOptions program_renderer_options(GetProcAddress get_proc_address = platform::HeadlessContext::proc_loader()) {
    RendererOptions o;
    o.effect_planner = effect_planner;
    o.texture_files = texture_files();
    o.get_proc_address = get_proc_address;
    return o;
}

// OpenGL ES 3.0 by default: float debug captures, and every technique
// (ES 2.0 captures through RGBA8 passes).
inline Result<DrawSurface> make_draw_surface(int width, int height, int es_major = 3) {
    platform::ContextOptions options;
    options.es_major = es_major;
    Result<std::unique_ptr<platform::HeadlessContext>> context = platform::HeadlessContext::create(options);
    if (!context) return context.error();
    DrawSurface surface;
    surface.context = std::move(*context);
    Result<OffscreenTarget> target = OffscreenTarget::create(width, height);
    if (!target) return target.error();
    surface.target.emplace(std::move(*target));
    return surface;
}

}  // namespace px::tools
