// Reads what the current OpenGL ES context can do into core/caps.h's plain
// data (the only part of Caps that needs GL).
#pragma once

#include "parallaxes/core/caps.h"

namespace px {

// Reads the current context's capabilities (a context must be current).
Caps query_caps();

}  // namespace px
