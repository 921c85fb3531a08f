// A partial preprocessor: resolves the conditional directives of a shader
// source (#if, #ifdef, #ifndef, #elif, #else, #endif) whose conditions the
// source's own #define and #undef lines decide, and drops the branches that
// are not taken, so that the text a driver (or a ShaderTransform) receives
// carries no code of an effect the variant does not use. What only the
// driver knows (GL_ES, GL_FRAGMENT_PRECISION_HIGH, extension macros,
// __VERSION__) stays for the driver: such a directive structure is kept as
// written, with what we can decide inside it still resolved.
//
// Rules (shader_source.cpp runs it on the assembled text, #version first):
//  - Macros are tracked in order: a #define or #undef in code that is
//    certainly compiled makes its name known; one inside a branch only the
//    driver can decide makes it unknown from then on.
//  - A name never defined or undefined here is undefined if it starts with
//    PX_ (the shaders' namespace: the driver defines none of them), else
//    unknown.
//  - Conditions: defined X, defined(X), !, &&, ||, parentheses, integer
//    literals, == != < > <= >=, and names whose definition is an integer
//    literal (or a name that is). Three-valued: `unknown && false` is false,
//    `unknown || true` is true. Anything else (an undefined name used as a
//    value, which GLSL ES makes an error; +, function-like macros) is
//    unknown: kept for the driver, never decided wrongly.
//  - Other directives (#define, #error, #extension, #pragma, ...) and every
//    other line are copied where their branch is kept. Comments stay with
//    their lines; those inside dropped branches go with them.
#pragma once

#include <string>
#include <vector>

#include "parallaxes/core/result.h"

namespace px {

// Where a line of a text came from, for messages: "shaders_es/chunks/shadows.glsl", 16.
struct LineOrigin {
    std::string file;
    int line = 0;
};

// `origins[i]` names line i of `text` (0-based) in errors; lines past its end
// are named "<name>:<line>". `kept_origins`, when given, gets the origin of
// each line of the result (a replaced directive line keeps its own), so a
// compiler's line numbers in the result map back to shaders_es/ files. A malformed structure (an #endif or #else
// without #if, #else after #else, #elif after #else, an #if never closed)
// is an error naming the line.
Result<std::string> resolve_conditionals(const std::string& text, const std::string& name,
                                         const std::vector<LineOrigin>& origins = {},
                                         std::vector<LineOrigin>* kept_origins = nullptr);

}  // namespace px
