// The renderer options behind each precision of `parallax stability`:
// "native" draws the shaders as they ship; the emulated profiles (fp32,
// fp16, lowp, nohighp) rewrite them with rounding after every operation
// (src/emulation) and run them on an ES 3.0 context.
#pragma once

#include <string>

#include "parallaxes/platform/headless_context.h"
#include "parallaxes/profiling/measurement/stability.h"

namespace px::tools {

bool is_emulated_precision(const std::string& name);
profiling::RendererFactory make_renderer_factory(GetProcAddress get_proc_address);

}  // namespace px::tools
