// One glslang set-up for the whole program: the precision emulation
// (precision.cpp) and the static shader costs (profiling/costs/) parse
// OpenGL ES sources through it, so both see a source the same way.
#pragma once

#include <memory>
#include <string>

#include <glslang/Public/ShaderLang.h>

#include "parallaxes/effects/variant.h"

namespace px::emulation {

// glslang's process-wide tables, set up once (never finalised: the process
// keeps them until it exits). Every use of glslang calls this first.
void initialize_glslang();

// An OpenGL ES source parsed as its own #version line says (100 without
// one), with no client API, so GLSL ES 1.00 is taken as written (glslang's
// SPIR-V rules would want 3.10). `name` names the source in glslang's
// messages ("name:3: ..."; nullptr: "0:3: ..."). `log` gets glslang's
// messages; the result is nullptr when glslang rejects the source. The
// parsed tree lives as long as the returned shader.
std::unique_ptr<glslang::TShader> parse_es_source(const std::string& source, ShaderStage stage, const char* name,
                                                  std::string& log);

}  // namespace px::emulation
