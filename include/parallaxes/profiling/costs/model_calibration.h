// The cost model (cost_model.h) fitted to a real vendor compiler's figures.
//
// A calibration set pairs, shader by shader, what this project's static
// analysis counts (shader_costs.h: glslang's SPIR-V of the shader's source)
// with what a real compiler reported for the same source (a Mali Offline
// Compiler report read by vendor_compilers.h). The set is made once, at
// asset-build time, from a folder of shader sources and a folder of reports
// (`parallax profile --make-calibration-set`); the program carries the one
// in profiling/costs/calibration/ and `parallax profile --calibrate` fits
// the model's per-class weights on half of it and reports on the other half:
// rank correlation (Spearman) and the error of the predicted bound-pipe
// cycles. docs/profiling.md shows the result.
//
// GL-free: only glslang and the report parsers.
#pragma once

#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/effects/variant.h"
#include "parallaxes/profiling/costs/cost_model.h"
#include "parallaxes/profiling/costs/shader_costs.h"
#include "parallaxes/profiling/costs/vendor_compilers.h"

namespace px::profiling {

// One shader of a set: our counts and the compiler's figures.
struct CalibrationShader {
    std::string name;  // the source's file name, "rrect_blur.frag"
    ShaderStage stage = ShaderStage::fragment;
    // Ours: the longest path of the analysis (loops the analysis cannot
    // bound counted once, as the compiler's total row counts them).
    OpCounts counts;
    int varying_components = 0;
    int relaxed_varying_components = 0;  // of those, mediump or lowp
    // Theirs: the primary variant's figures on one row, per pipe as named.
    std::string row;  // "longest", or "total" where the longest path is N/A
    std::vector<std::string> pipes;
    std::vector<double> cycles;
    double bound_cycles() const;     // the busiest pipe's cycles
    std::string bound_pipe() const;  // its name ("A"; ties joined "V, T")
};

struct CalibrationSet {
    std::string gpu;       // "Mali-G78 r1p1 (Valhall)"
    std::string compiler;  // "malioc 7.7.0"
    std::string source;    // where the shaders and reports came from
    std::string made_by;   // the command that wrote the set
    std::vector<CalibrationShader> shaders;
};

// `where` names the file in errors, with the JSON path of a bad field.
Result<CalibrationSet> parse_calibration_set(const std::string& json, const std::string& where);
std::string calibration_set_json(const CalibrationSet& set);
// The set the program carries (profiling/costs/calibration/mali_g78_impeller.json).
const CalibrationSet& default_calibration_set();
const char* default_calibration_set_path();

// A malioc report, text or JSON (`--format json`: its first non-blank
// character is '{').
Result<VendorCycles> parse_malioc_report(const std::string& report);

// One shader's entry from its source (GLSL ES, compiled by glslang) and a
// compiler report of that source (malioc text or JSON). Refused, with the
// reason: a source glslang rejects, a report that does not parse, a report
// of another stage, a report without figures on either row.
Result<CalibrationShader> calibration_entry(const std::string& name, const std::string& source, ShaderStage stage,
                                            const std::string& report);
// The same from a report already read (parse_malioc_report).
Result<CalibrationShader> calibration_entry(const std::string& name, const std::string& source, ShaderStage stage,
                                            const VendorCycles& figures);

// What a fit found. Arithmetic (A) is fitted as
//   fp32 ops * w + fp16 ops * w * (the base model's fp16 ratio)
//   + transcendentals * t + branches * b + fixed,
// texture (T) as samples * s, varying (V) as components * v; each pipe on
// its own figures, by non-negative least squares. A class too few shaders
// of the fitting half use (fewer than three) is not fitted: it keeps the
// base model's ratio to the fp32 weight, and `notes` says so.
struct CalibrationRow {
    std::string name;
    bool held_out = false;
    double real = 0.0;  // the compiler's bound-pipe cycles
    std::string real_pipe;
    double predicted = 0.0;  // the fitted model's busiest pipe (latency left out: the compiler reports none)
    std::string predicted_pipe;
    double uncalibrated = 0.0;  // the base model's busiest pipe, in its own units
    double error() const { return real > 0.0 ? (predicted - real) / real : 0.0; }
};

struct CalibrationSummary {
    int shaders = 0;
    double spearman = 0.0;
    double median_abs_error = 0.0;  // of predicted against real bound-pipe cycles, relative
    double worst_abs_error = 0.0;
    double spearman_uncalibrated = 0.0;  // the base model's ranking of the same shaders
};

struct CalibrationFit {
    double fp32_op = 0.0, transcendental = 0.0, branch = 0.0, fixed = 0.0;  // A cycles per unit
    double sample = 0.0;             // T cycles per sample
    double varying_component = 0.0;  // V cycles per component
    std::vector<CalibrationRow> rows;  // the set's order
    CalibrationSummary fitted, held_out;
    // Each shader predicted by weights fitted on all the others (the
    // uncalibrated Spearman is not filled in).
    CalibrationSummary leave_one_out;
    std::vector<std::string> notes;
};

// Shaders are taken in name order, alternately into the fitting half and the
// held-out half (the first fits). Only fragment shaders are used (the model
// has no load/store pipe, which bounds most vertex shaders); an error if
// either half has fewer than four. `leave_one_out`: also refit once per
// shader for CalibrationFit::leave_one_out (the reports' figure; the model
// the program uses does not need it).
Result<CalibrationFit> fit_cost_model(const CalibrationSet& set, const CostModel& base, bool leave_one_out = true);

// `base` with the fitted weights (rates are their inverses), its texture
// latency kept at the same number of sample times, and the calibration
// recorded (CostModel::calibration).
Result<CostModel> calibrated_model(const CostModel& base, const CalibrationFit& fit, const CalibrationSet& set,
                                   const std::string& set_path);

// Spearman's rank correlation (ties share their mean rank); 0 for fewer than
// two values or a constant list.
double spearman(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace px::profiling
