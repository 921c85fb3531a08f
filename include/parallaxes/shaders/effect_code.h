// Which effects' code an assembled variant carries. Each effect a variant
// can leave out (shadows, depth write, LOD, the trace, ...) has marker code:
// identifiers or fragments that occur only in that effect's code in
// shaders_es/ and the preamble. A variant that does not use an effect must
// carry none of its markers (assemble_shader resolves the conditionals, so
// the driver never sees the code); the tests check every enumerated variant,
// and any key a planner produces can be checked the same way. GL-free.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "parallaxes/effects/variant.h"
#include "parallaxes/shaders/shader_source.h"

namespace px {

struct EffectMarker {
    const char* effect;  // "shadows", "depth write", ...
    // An identifier (matched as a whole word) or a code fragment (matched
    // with whitespace runs as one space, and whole words at its ends), in the
    // source with its comments removed.
    const char* code;
    // Whether a variant uses the effect, from its canonical key.
    bool (*used)(const VariantKey& canonical);
};

const std::vector<EffectMarker>& effect_markers();

// Indices into effect_markers() of the markers that occur in either stage.
std::vector<std::size_t> effect_markers_in(const VariantSources& sources);

// The code of effects the variant does not use that its sources carry: one
// line per marker found ("shadows: 'px_light_visibility' ..."); empty when
// the sources are clean.
std::vector<std::string> unused_effect_code(const VariantKey& key, const VariantSources& sources);

}  // namespace px
