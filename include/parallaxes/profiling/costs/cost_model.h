// A documented cost model for a mobile-class GPU: the static counts of
// include/parallaxes/profiling/costs/shader_costs.h turned into estimated cycles per pipe. Its
// parameters live in one data file (profiling/costs/cost_model.json, carried
// inside the program; `parallax profile --model FILE` reads another), with
// the assumptions beside them, printed with every report.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/profiling/costs/shader_costs.h"

namespace px::profiling {

struct CostModel {
    std::string name;
    std::string about;
    double fp32_ops_per_cycle = 1.0;
    double fp16_ops_per_cycle = 2.0;
    double transcendental_cycles = 4.0;
    double branch_cycles = 1.0;
    double samples_per_cycle = 1.0;
    double texture_latency_cycles = 100.0;
    double latency_hidden_share = 0.75;
    // false: texture waits are the greater of the dependent-read chain and
    // the waits in program order (reads are issued as written); true: the
    // chain alone (a scheduler issues every read as early as it can).
    bool compiler_reorders_reads = false;
    double varying_components_per_cycle = 2.0;
    // Interpolated mediump/lowp components per cycle (16-bit interpolation).
    double varying_fp16_components_per_cycle = 4.0;
    // Arithmetic cycles every invocation costs whatever it computes (the
    // colour write's conversion and the like); 0 in an uncalibrated model.
    double fixed_cycles = 0.0;
    // The real compiler the weights were fitted to (model_calibration.h);
    // empty gpu: chosen by hand, never compared with a real compiler.
    struct Calibration {
        std::string gpu;       // "Mali-G78 r1p1 (Valhall)"
        std::string compiler;  // "malioc 7.7.0"
        std::string set;       // the calibration set's path
        std::string command;   // the command that fitted it
        int fitted = 0, held_out = 0;  // shaders in each half
        double spearman = 0.0, median_abs_error = 0.0;  // on the held-out half
        bool present() const { return !gpu.empty(); }
        // "calibrated against Mali-G78 r1p1 (Valhall), malioc 7.7.0 (...)" or
        // "not calibrated against a real compiler".
        std::string summary() const;
    };
    Calibration calibration;
    struct LoopTrips {
        std::string file;  // a loop whose header is in this shaders_es/ file
        int trips = 1;
        std::string why;
    };
    std::vector<LoopTrips> loop_trips;
    std::vector<std::string> assumptions;
    // For analyse_spirv: file -> trips.
    std::map<std::string, int> trip_overrides() const;
};

// `where` names the file in errors, with the JSON path of a bad field.
Result<CostModel> parse_cost_model(const std::string& json, const std::string& where);
// The hand-chosen model the program carries (profiling/costs/cost_model.json):
// the base a calibration fits (its structure, fp16 ratio, latency, loops).
const CostModel& base_cost_model();
// The model reports use: the base fitted to the calibration set the program
// carries (costs/model_calibration.h), its `calibration` naming the GPU.
const CostModel& default_cost_model();
// The file's shape again, every field (what `profile --calibrate --model-out` writes).
std::string cost_model_json(const CostModel& model);

// Estimated cycles of one path through a stage.
struct PipeCycles {
    double arithmetic = 0.0;  // A: arithmetic, transcendental and branch cycles
    double texture = 0.0;     // T
    double varying = 0.0;     // V (fragment stage)
    double latency = 0.0;     // exposed texture latency (longest path only)
    double total = 0.0;       // the busiest pipe plus the exposed latency
    std::string bound;        // "A", "T", "V", or "A, T" when tied
};
// `round_trips`: the path's dependent-read chain (StageCost::texture_round_trips
// on the longest path); the stage's in-order waits are added per the model.
PipeCycles estimate(const StageCost& stage, const OpCounts& path, double round_trips, const CostModel& model);

}  // namespace px::profiling
