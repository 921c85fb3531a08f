// The planner: turns what a material asks for into the shader variant that a
// context with these capabilities draws, and says why wherever the two differ.
#pragma once

#include <string>
#include <vector>

#include "core/caps.h"
#include "core/result.h"
#include "effects/variant.h"
#include "scene/scene.h"

namespace px {

// The planner's answer for one material: the variant, and why it differs
// from what the material asked for (one note per change).
struct VariantPlan {
    VariantKey key;
    std::vector<std::string> notes;
};

// Picks the variant for a material on a context with these capabilities:
// options the technique does not have are dropped, options the context cannot
// run are dropped with the reason (e.g. depth write on ES 2.0 without
// GL_EXT_frag_depth), a relief with zero depth falls back to normal mapping.
// Errors: the technique needs a newer ES version than the context has.
// `traced_width` and `traced_height`: the size of the height field the
// technique traces, when known (0: unknown); maxmip's pyramid halves every
// level exactly, so a field that is not a power of two in both gets the
// table's fallback, with the reason.
Result<VariantPlan> plan_variant(const MaterialDesc& material, const Caps& caps, int traced_width = 0,
                                 int traced_height = 0);

}  // namespace px
