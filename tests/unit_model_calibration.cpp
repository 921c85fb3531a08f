// The cost model fitted to a real compiler's figures (profiling/costs/
// model_calibration.h): the carried set, the fit and what it claims, the
// making of a set's entry, and refusals of bad sets.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "parallaxes/profiling/costs/cost_model.h"
#include "parallaxes/profiling/costs/model_calibration.h"

namespace px::profiling {
namespace {

TEST(ModelCalibration, TheCarriedSetIsMalocsFiguresForFragmentShaders) {
    const CalibrationSet& set = default_calibration_set();
    EXPECT_NE(set.gpu.find("Mali-G78"), std::string::npos) << set.gpu;
    EXPECT_EQ(set.compiler, "malioc 7.7.0");
    ASSERT_GE(set.shaders.size(), 30u);
    for (const CalibrationShader& s : set.shaders) {
        EXPECT_EQ(s.stage, ShaderStage::fragment) << s.name;
        EXPECT_GT(s.bound_cycles(), 0.0) << s.name;
        EXPECT_EQ(s.pipes, (std::vector<std::string>{"A", "LS", "V", "T"})) << s.name;
    }
}

// The issue's goal, on shaders the weights never saw: the fit must rank and
// size the held-out half, and beat the hand-chosen rates at ranking them.
TEST(ModelCalibration, TheFitMeetsTheGoalOnTheShadersHeldOutOfIt) {
    Result<CalibrationFit> fit = fit_cost_model(default_calibration_set(), base_cost_model());
    ASSERT_TRUE(fit) << fit.error().message;
    EXPECT_EQ(fit->held_out.shaders + fit->fitted.shaders, static_cast<int>(default_calibration_set().shaders.size()));
    EXPECT_GE(fit->held_out.spearman, 0.9);
    EXPECT_LE(fit->held_out.median_abs_error, 0.30);
    EXPECT_GT(fit->held_out.spearman, fit->held_out.spearman_uncalibrated);
    EXPECT_GE(fit->leave_one_out.spearman, 0.9);
    EXPECT_LE(fit->leave_one_out.median_abs_error, 0.30);
    EXPECT_EQ(fit->leave_one_out.shaders, static_cast<int>(default_calibration_set().shaders.size()));
}

TEST(ModelCalibration, TheModelReportsUseIsTheFitAndNamesItsGpu) {
    Result<CalibrationFit> fit = fit_cost_model(default_calibration_set(), base_cost_model());
    ASSERT_TRUE(fit);
    const CostModel& m = default_cost_model();
    ASSERT_TRUE(m.calibration.present());
    EXPECT_EQ(m.calibration.gpu, default_calibration_set().gpu);
    EXPECT_NEAR(1.0 / m.fp32_ops_per_cycle, fit->fp32_op, 1e-12);
    EXPECT_NEAR(1.0 / m.samples_per_cycle, fit->sample, 1e-12);
    EXPECT_NEAR(1.0 / m.varying_components_per_cycle, fit->varying_component, 1e-12);
    EXPECT_NEAR(m.fixed_cycles, fit->fixed, 1e-12);
    EXPECT_DOUBLE_EQ(m.calibration.spearman, fit->held_out.spearman);
    EXPECT_NE(m.calibration.summary().find("Mali-G78"), std::string::npos) << m.calibration.summary();
    EXPECT_FALSE(base_cost_model().calibration.present());
    EXPECT_NE(base_cost_model().calibration.summary().find("not calibrated"), std::string::npos);
    // The fp16 rate keeps the base model's ratio to fp32 (the set has too few
    // mediump shaders to fit it), and latency the same number of sample times.
    EXPECT_NEAR(m.fp16_ops_per_cycle / m.fp32_ops_per_cycle,
                base_cost_model().fp16_ops_per_cycle / base_cost_model().fp32_ops_per_cycle, 1e-12);
    EXPECT_NEAR(m.texture_latency_cycles * m.samples_per_cycle,
                base_cost_model().texture_latency_cycles * base_cost_model().samples_per_cycle, 1e-9);
}

// Figures made by known weights: the fit finds them, and predicts the
// held-out half exactly.
TEST(ModelCalibration, AFitRecoversTheWeightsThatMadeTheFigures) {
    CalibrationSet set;
    set.gpu = "test GPU";
    set.compiler = "test";
    unsigned state = 12345;
    auto next = [&](unsigned range) {  // a small LCG: counts without a pattern
        state = state * 1103515245u + 12345u;
        return static_cast<double>((state >> 16) % range);
    };
    for (int i = 0; i < 12; ++i) {
        CalibrationShader s;
        s.name = "s" + std::to_string(10 + i) + ".frag";
        s.counts.arithmetic = 10.0 + next(200);
        s.counts.transcendental = next(8);
        s.counts.branches = next(20);
        s.counts.samples = 1 + next(4);
        s.varying_components = 2 + static_cast<int>(next(9));
        s.row = "longest";
        s.pipes = {"A", "LS", "V", "T"};
        const double a = 0.01 * s.counts.arithmetic + 0.05 * s.counts.transcendental + 0.003 * s.counts.branches + 0.07;
        s.cycles = {a, 0.0, 0.125 * s.varying_components, 0.25 * s.counts.samples};
        set.shaders.push_back(s);
    }
    Result<CalibrationFit> fit = fit_cost_model(set, base_cost_model());
    ASSERT_TRUE(fit) << fit.error().message;
    EXPECT_NEAR(fit->fp32_op, 0.01, 1e-7);
    EXPECT_NEAR(fit->transcendental, 0.05, 1e-6);
    EXPECT_NEAR(fit->branch, 0.003, 1e-6);
    EXPECT_NEAR(fit->fixed, 0.07, 1e-6);
    EXPECT_NEAR(fit->sample, 0.25, 1e-9);
    EXPECT_NEAR(fit->varying_component, 0.125, 1e-9);
    EXPECT_LT(fit->held_out.worst_abs_error, 1e-5);
    EXPECT_EQ(fit->held_out.shaders, 6);
    // The halves alternate in name order; the first fits.
    EXPECT_FALSE(fit->rows[0].held_out);
    EXPECT_TRUE(fit->rows[1].held_out);
    Result<CostModel> model = calibrated_model(base_cost_model(), *fit, set, "t.json");
    ASSERT_TRUE(model) << model.error().message;
    EXPECT_NEAR(model->fp32_ops_per_cycle, 100.0, 1e-3);
    EXPECT_EQ(model->calibration.set, "t.json");
    // What is written is read back the same.
    Result<CostModel> again = parse_cost_model(cost_model_json(*model), "written.json");
    ASSERT_TRUE(again) << again.error().message;
    EXPECT_DOUBLE_EQ(again->fp32_ops_per_cycle, model->fp32_ops_per_cycle);
    EXPECT_DOUBLE_EQ(again->fixed_cycles, model->fixed_cycles);
    EXPECT_EQ(again->calibration.gpu, "test GPU");
    EXPECT_EQ(again->assumptions, model->assumptions);
    // Too few shaders to hold any out.
    set.shaders.resize(7);
    EXPECT_FALSE(fit_cost_model(set, base_cost_model()));
}

// Midgard's reports have no varying pipe (A, LS, T): no varying rate can be
// fitted, and the fit says so rather than make a model that charges nothing.
TEST(ModelCalibration, ACompilerWithoutAVaryingPipeCannotCalibrateTheModel) {
    CalibrationSet set;
    set.gpu = "Mali-T880 r2p0 (Midgard)";
    for (int i = 0; i < 10; ++i) {
        CalibrationShader s;
        s.name = "m" + std::to_string(i) + ".frag";
        s.counts.arithmetic = 10.0 + 7.0 * i;
        s.counts.samples = 1 + i % 3;
        s.varying_components = 2 + i % 4;
        s.row = "longest";
        s.pipes = {"A", "LS", "T"};
        s.cycles = {0.07 * s.counts.arithmetic, 0.5 * s.varying_components, s.counts.samples};
        set.shaders.push_back(s);
    }
    Result<CalibrationFit> fit = fit_cost_model(set, base_cost_model());
    ASSERT_FALSE(fit);
    EXPECT_NE(fit.error().message.find("varying 0"), std::string::npos) << fit.error().message;
}

TEST(ModelCalibration, SpearmanRanksWithTies) {
    EXPECT_DOUBLE_EQ(spearman({1, 2, 3, 4}, {10, 20, 30, 40}), 1.0);
    EXPECT_DOUBLE_EQ(spearman({1, 2, 3, 4}, {4, 3, 2, 1}), -1.0);
    EXPECT_DOUBLE_EQ(spearman({1, 1, 1}, {1, 2, 3}), 0.0);
    EXPECT_NEAR(spearman({1, 2, 2, 3}, {1, 2, 3, 4}), 0.9486832980505138, 1e-12);
    EXPECT_DOUBLE_EQ(spearman({1}, {1}), 0.0);
}

constexpr const char* kShader =
    "#version 100\n"
    "precision mediump float;\n"
    "uniform highp sampler2D tex;\n"
    "varying highp vec2 uv;\n"
    "void main() { gl_FragColor = texture2D(tex, uv) * 0.5 + vec4(uv, 0.0, 1.0); }\n";

std::string report(const std::string& type, const std::string& longest) {
    return "Mali Offline Compiler v7.7.0 (Build d01859)\n"
           "Copyright (c) 2007-2022 Arm Limited. All rights reserved.\n\n"
           "Configuration\n=============\n\n"
           "Hardware: Mali-G78 r1p1\nArchitecture: Valhall\nDriver: r39p0-00rel0\nShader type: OpenGL ES " +
           type +
           "\n\nMain shader\n===========\n\n"
           "Work registers: 8 (25% used at 100% occupancy)\nUniform registers: 2 (3% used)\nStack spilling: false\n"
           "16-bit arithmetic: 0%\n\n"
           "                                A      LS       V       T    Bound\n"
           "Total instruction cycles:    0.11    0.00    0.25    0.25     V, T\n"
           "Shortest path cycles:        0.11    0.00    0.25    0.25     V, T\n"
           "Longest path cycles:  " + longest + "\n\n"
           "A = Arithmetic, LS = Load/Store, V = Varying, T = Texture\n";
}

TEST(ModelCalibration, AnEntryIsOurCountsBesideTheReportsFigures) {
    Result<CalibrationShader> e =
        calibration_entry("t.frag", kShader, ShaderStage::fragment, report("Fragment", "      0.11    0.00    0.25    0.25     V, T"));
    ASSERT_TRUE(e) << e.error().message;
    EXPECT_EQ(e->row, "longest");
    EXPECT_EQ(e->varying_components, 2);
    EXPECT_EQ(e->counts.samples, 1.0);
    EXPECT_GT(e->counts.arithmetic, 0.0);
    EXPECT_EQ(e->cycles, (std::vector<double>{0.11, 0.0, 0.25, 0.25}));
    EXPECT_EQ(e->bound_pipe(), "V, T");
    // Where the compiler cannot bound the longest path, its total is compared.
    Result<CalibrationShader> na = calibration_entry(
        "t.frag", kShader, ShaderStage::fragment, report("Fragment", "       N/A     N/A     N/A     N/A      N/A"));
    ASSERT_TRUE(na) << na.error().message;
    EXPECT_EQ(na->row, "total");
    // A report of another stage, a report that is not one, a source glslang refuses.
    Result<CalibrationShader> vertex =
        calibration_entry("t.frag", kShader, ShaderStage::fragment, report("Vertex", "      0.11    0.00    0.25    0.25     V, T"));
    ASSERT_FALSE(vertex);
    EXPECT_NE(vertex.error().message.find("Vertex report for a fragment shader"), std::string::npos) << vertex.error().message;
    Result<CalibrationShader> garbage = calibration_entry("t.frag", kShader, ShaderStage::fragment, "hello\n");
    ASSERT_FALSE(garbage);
    EXPECT_NE(garbage.error().message.find("t.frag (report)"), std::string::npos) << garbage.error().message;
    EXPECT_FALSE(calibration_entry("t.frag", "void main() { x }", ShaderStage::fragment,
                                   report("Fragment", "      0.11    0.00    0.25    0.25     V, T")));
}

std::string set_text(const std::string& shader) {
    return R"({"gpu": "g", "compiler": "c", "source": "s", "made_by": "m", "shaders": [)" + shader + "]}";
}

TEST(ModelCalibration, ABadSetIsRefusedNamingTheFieldAndTheFile) {
    const std::string good = R"({"name": "a.frag", "stage": "fragment", "ours": {"arithmetic": 1, "fp16": 0, )"
                             R"("transcendental": 0, "samples": 1, "branches": 0, "varying_components": 2}, )"
                             R"("theirs": {"row": "longest", "pipes": ["A", "T"], "cycles": [0.1, 0.25]}})";
    ASSERT_TRUE(parse_calibration_set(set_text(good), "set.json"));
    auto refused = [](const std::string& text, const std::string& expected) {
        Result<CalibrationSet> r = parse_calibration_set(text, "set.json");
        ASSERT_FALSE(r) << expected;
        EXPECT_NE(r.error().message.find("set.json: "), std::string::npos) << r.error().message;
        EXPECT_NE(r.error().message.find(expected), std::string::npos) << r.error().message;
    };
    auto with = [&](const std::string& from, const std::string& to) {
        std::string s = good;
        s.replace(s.find(from), from.size(), to);
        return set_text(s);
    };
    refused("{", "not JSON");
    refused("[]", "must be a JSON object");
    refused(R"({"gpu": "g", "compiler": "c", "source": "s", "made_by": "m"})", "$.shaders");
    refused(R"({"compiler": "c", "source": "s", "made_by": "m", "shaders": []})", "$.gpu");
    refused(with("[0.1, 0.25]", "[0.1]"), "$.shaders[0].theirs.cycles");
    refused(with("[0.1, 0.25]", "[0, 0]"), "$.shaders[0].theirs.cycles: every pipe is 0");
    refused(with("[0.1, 0.25]", "[0.1, \"x\"]"), "$.shaders[0].theirs.cycles[1]");
    refused(with("\"arithmetic\": 1", "\"arithmetic\": -1"), "$.shaders[0].ours.arithmetic");
    refused(with("\"fp16\": 0", "\"fp16\": 5"), "$.shaders[0].ours.fp16");
    refused(with("\"varying_components\": 2", "\"varying_components\": 2.5"), "$.shaders[0].ours.varying_components");
    refused(with("\"fragment\"", "\"compute\""), "$.shaders[0].stage");
    refused(with("\"longest\"", "\"middle\""), "$.shaders[0].theirs.row");
    refused(set_text(good + "," + good), "$.shaders[1].name: \"a.frag\" appears twice");
    // A model's calibration block is checked like the rest of the model.
    Result<CostModel> bad = parse_cost_model(
        R"({"arithmetic": {"fp32_ops_per_cycle": 1, "fp16_ops_per_cycle": 2, "transcendental_cycles": 4, "branch_cycles": 1},)"
        R"( "texture": {"samples_per_cycle": 1, "latency_cycles": 100, "latency_hidden_share": 0.5},)"
        R"( "varying": {"components_per_cycle": 2}, "calibration": {"gpu": 3}})",
        "m.json");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("m.json: $.calibration.gpu"), std::string::npos) << bad.error().message;
}

}  // namespace
}  // namespace px::profiling
