// Shader text: the files of shaders_es/ (embedded at build time), #include
// resolution, and assembling a full source for one variant. Plain text work,
// no GL: gl/program compiles what this assembles, and the variant listing,
// the validation tests and the cost profiles read it without a context.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/effects/variant.h"
#include "parallaxes/shaders/conditional.h"

namespace px {

struct EmbeddedShader {
    const char* path;  // relative to shaders_es/, e.g. "chunks/lighting.glsl"
    const char* text;
};
const std::vector<EmbeddedShader>& embedded_shaders();

// Another set of shader files to assemble from (path relative to shaders_es/
// -> text): the shaders of another commit, for `parallax profile --against`.
// nullptr below: the embedded ones.
using ShaderFiles = std::map<std::string, std::string>;

// Expands `#include "path"` lines (each file at most once per source; a
// missing file is an error naming the includer and its line).
Result<std::string> expand_includes(const std::string& entry_path);

// The full source for one stage of one variant: `#version` first (nothing may
// precede it, comments included, on some ES drivers), then any #extension
// lines, then the injected defines and the ES 2.0/3.0 compatibility preamble,
// then the expanded body. `es_major` is 2 (GLSL ES 1.00) or 3 (GLSL ES 3.00).
// The conditionals the defines and the preamble decide are resolved
// (shaders/conditional.h): the text carries no code of an effect the variant
// does not use; only conditions on the driver's macros (GL_*) are left.
struct AssembledSource {
    std::string text;
    // For messages: the variant's defines in one line.
    std::string defines_summary;
    // Where each line of `text` came from (0-based index = line - 1): a
    // shaders_es/ file and line, or the entry's version/defines/preamble.
    std::vector<LineOrigin> origins;
};
Result<AssembledSource> assemble_shader(const std::string& entry_path, ShaderStage stage, int es_major,
                                        const std::vector<std::string>& extensions,
                                        const std::vector<ShaderDefine>& defines,
                                        const ShaderFiles* files = nullptr);

// The shader sources of a variant: its vertex and fragment entries
// (VariantKey::vertex_entry, fragment_entry).
struct VariantSources {
    AssembledSource vertex;
    AssembledSource fragment;
};
Result<VariantSources> assemble_variant(const VariantKey& key, const ShaderFiles* files = nullptr);

// The source lines a driver's compile log points at, in order of first
// mention, at most `limit`: "0:LINE" (Mesa, ANGLE, Mali, Adreno, PowerVR)
// and "0(LINE)" (NVIDIA: "0(4) : error C1503"). 0 is the source string's
// index: this project passes one string.
std::vector<long> shader_log_lines(const std::string& log, std::size_t limit = 8);

}  // namespace px
