// Mobile precisions emulated on a GPU that computes in fp32: the real shader
// source is parsed (glslang), and emitted again as GLSL ES 3.00 with every
// value rounded as a mobile GPU would round it. The emulated shader is the
// same program the GPU runs, not a second transcription of the techniques.
//
// Not part of the installed library (it links glslang): tools/, profiling/
// and tests/ use it, through RendererOptions::shader_transform.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/effects/variant.h"

namespace px::emulation {

enum class PrecisionProfile {
    // No rounding: the source emitted again with its own precision
    // qualifiers. The control: on any driver it must compute what the
    // original computes (tests/gpu_emulation_tests.cpp checks it per pixel).
    identity,
    // No rounding, every value declared highp: strict fp32 arithmetic, the
    // baseline the mobile profiles are measured against (on Mesa with F16C
    // the declarations in force lower mediump to fp16 in part).
    fp32,
    // Strict IEEE binary16 for every mediump and lowp value: round to
    // nearest even after each operation, subnormals, overflow to infinity.
    fp16,
    // mediump as fp16; lowp at the GLSL ES 1.00 section 4.5.2 minimums:
    // range [-2, 2], absolute precision 2^-8.
    lowp,
    // The fragment stage has no highp (many ES 2.0 GPUs): every fragment
    // float is fp16; the vertex stage as in fp16.
    nohighp,
    // The PowerVR whitepaper's choice (section 3.2.2): every fragment-stage
    // value at the lowp minimums, whatever it is declared as; the vertex
    // stage as fp16. Not a profile any shader here declares: the experiment
    // that shows where all-lowp holds and where it breaks.
    lowp_all,
};

const char* profile_name(PrecisionProfile profile);
// "identity", "fp32", "fp16", "lowp", "nohighp" or "lowp_all".
Result<PrecisionProfile> parse_profile(std::string_view name);

// Functions emitted without rounding: the debug outputs' encoders
// (shaders_es/chunks/debug_output.glsl). They pack results for read-back;
// rounding them would corrupt the measurement, not emulate the technique.
const std::vector<std::string>& default_exempt_functions();

// `source`: a complete GLSL ES 1.00 or 3.00 source (as shaders/shader_source
// assembles it). Returns a GLSL ES 3.00 source that computes the same thing
// with every float value rounded as `profile` says (the rules are in
// precision.cpp's header comment). Integers are not emulated: they are
// computed as the driver computes highp int. Errors: a source glslang rejects
// (its info log), or a construct the emitter does not support (named).
Result<std::string> emulate_precision(const std::string& source, ShaderStage stage, PrecisionProfile profile,
                                      const std::vector<std::string>& exempt_functions = default_exempt_functions());

// Parses `source` as glslang does for emulate_precision (ES profile, the
// source's own #version, default limits); the info log on failure.
Status check_parses(const std::string& source, ShaderStage stage);

// The emitted shaders' rounding, on the CPU (for tests): binary16 round to
// nearest even (subnormals, +-inf past 65504, NaN kept), and the lowp
// minimum (the nearest-even multiple of 2^-8, clamped to [-2, 2]; NaN kept).
float round_fp16(float x);
float round_lowp(float x);

}  // namespace px::emulation
