// Unit tests for the vendor shader compilers' parsers and runner
// (include/parallaxes/profiling/costs/vendor_compilers.h). Neither malioc nor the PowerVR compilers
// are installed here: the parsers read reports written for the tests after
// the tools' documentation (tests/data/vendor/README.md), and the runner runs
// fake compilers, shell scripts this file writes and puts first on PATH.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <limits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "parallaxes/profiling/costs/vendor_compilers.h"

namespace px::profiling {
namespace {

namespace fs = std::filesystem;

const std::string kData = std::string(PX_SOURCE_DIR) + "/tests/data/vendor/";

std::string read_sample(const std::string& name) {
    std::ifstream in(kData + name, std::ios::binary);
    EXPECT_TRUE(in) << "cannot read " << kData + name;
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// Figures compared exactly, N/A (NaN) included.
void expect_figures(const std::vector<double>& actual, const std::vector<double>& expected, const char* row) {
    ASSERT_EQ(actual.size(), expected.size()) << row;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        if (std::isnan(expected[i])) EXPECT_TRUE(std::isnan(actual[i])) << row << "[" << i << "]";
        else EXPECT_EQ(actual[i], expected[i]) << row << "[" << i << "]";
    }
}

bool has_note(const VendorCycles& c, const std::string& note) {
    for (const std::string& n : c.notes)
        if (n == note) return true;
    return false;
}

void expect_error_mentions(const Result<VendorCycles>& r, const std::vector<std::string>& parts) {
    ASSERT_FALSE(r.ok()) << "expected an error";
    for (const std::string& part : parts)
        EXPECT_NE(r.error().message.find(part), std::string::npos) << "'" << part << "' not in: " << r.error().message;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// --- malioc text ----------------------------------------------------------------

TEST(MaliocText, ValhallFragment) {
    auto r = parse_malioc_text(read_sample("malioc_valhall.txt"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const VendorCycles& c = *r;
    EXPECT_EQ(c.tool, "malioc 8.2.0");
    EXPECT_EQ(c.target, "Mali-G78 r1p1 (Valhall)");
    EXPECT_EQ(c.work_registers, 32);
    EXPECT_EQ(c.uniform_registers, 16);
    EXPECT_EQ(c.fp16_percent, 25.0);
    EXPECT_FALSE(c.stack_spilling);
    EXPECT_EQ(c.pipes, (std::vector<std::string>{"A", "FMA", "CVT", "SFU", "LS", "V", "T"}));
    expect_figures(c.total, {1.50, 0.88, 0.31, 0.25, 0.00, 0.50, 1.25}, "total");
    expect_figures(c.shortest, {0.56, 0.38, 0.06, 0.13, 0.00, 0.50, 0.50}, "shortest");
    expect_figures(c.longest, {1.19, 0.75, 0.25, 0.25, 0.00, 0.50, 1.25}, "longest");
    EXPECT_EQ(c.bound, "T");  // the longest path's
    EXPECT_EQ(c.cycles, -1.0);
    EXPECT_EQ(c.notes, (std::vector<std::string>{"uniform computation"}));
}

TEST(MaliocText, BifrostWithUnboundedLongestPath) {
    auto r = parse_malioc_text(read_sample("malioc_bifrost.txt"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const VendorCycles& c = *r;
    EXPECT_EQ(c.tool, "malioc 7.4.0");
    EXPECT_EQ(c.target, "Mali-G72 r0p3 (Bifrost)");
    EXPECT_EQ(c.work_registers, 20);
    EXPECT_EQ(c.uniform_registers, 8);
    EXPECT_EQ(c.fp16_percent, 0.0);
    EXPECT_EQ(c.pipes, (std::vector<std::string>{"A", "LS", "V", "T"}));
    expect_figures(c.total, {0.92, 0.00, 1.00, 1.00}, "total");
    expect_figures(c.shortest, {0.58, 0.00, 1.00, 0.50}, "shortest");
    expect_figures(c.longest, {kNaN, kNaN, kNaN, kNaN}, "longest");
    EXPECT_EQ(c.bound, "V, T");  // the longest path is N/A: the total's bound
    EXPECT_EQ(c.notes, (std::vector<std::string>{"modifies coverage", "uses late ZS test"}));
}

TEST(MaliocText, Version8VertexVariantsAndSpill) {
    auto r = parse_malioc_text(read_sample("malioc_valhall_vertex_8x.txt"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const VendorCycles& c = *r;
    EXPECT_EQ(c.tool, "malioc 8.2.0");
    EXPECT_EQ(c.target, "Mali-G710 r0p0 (Valhall)");
    EXPECT_EQ(c.work_registers, 46);  // the Position variant's: "46 (71% used at 100% occupancy)"
    EXPECT_EQ(c.uniform_registers, 24);
    EXPECT_TRUE(c.stack_spilling);
    EXPECT_EQ(c.pipes, (std::vector<std::string>{"A", "FMA", "CVT", "SFU", "LS", "T"}));
    expect_figures(c.longest, {0.38, 0.38, 0.00, 0.00, 3.00, 0.00}, "longest");
    EXPECT_EQ(c.bound, "LS");
    EXPECT_TRUE(has_note(c, "figures of the Position variant; the report also has Varying variant"));
    EXPECT_TRUE(has_note(c, "stack spill 8 bytes"));
    EXPECT_TRUE(has_note(c, "uniform computation"));
}

TEST(MaliocText, OlderCapitalisedRowsWithoutArchitecture) {
    // The Midgard-era layout of Arm's guide: "Total Instruction Cycles:", no Architecture line.
    const std::string report =
        "Mali Offline Compiler v6.4.0 (Build 7b4d94)\n\nConfiguration\n=============\n\n"
        "Hardware: Mali-T880 r2p0\nDriver: Midgard r23p0-00rel0\nShader type: OpenGL ES Fragment\n\n"
        "Main shader\n===========\n\nWork registers: 2 (100% occupancy)\nUniform registers: 2\n"
        "Stack spilling: false\n\n"
        "                             A   LS    T  Bound\n"
        "Total Instruction Cycles:  6.0  1.0  0.0      A\n"
        "Shortest Path Cycles:      1.7  1.0  0.0      A\n"
        "Longest Path Cycles:       1.7  1.0  0.0      A\n\n"
        "A = Arithmetic, LS = Load/Store, T = Texture\n";
    auto r = parse_malioc_text(report);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->target, "Mali-T880 r2p0");
    EXPECT_EQ(r->work_registers, 2);
    EXPECT_EQ(r->fp16_percent, -1.0);  // not reported on Midgard
    EXPECT_EQ(r->pipes, (std::vector<std::string>{"A", "LS", "T"}));
    expect_figures(r->total, {6.0, 1.0, 0.0}, "total");
    EXPECT_EQ(r->bound, "A");
}

TEST(MaliocText, MalformedReportsNameWhatIsMissing) {
    expect_error_mentions(parse_malioc_text(read_sample("malioc_truncated.txt")), {"malioc report", "Longest path cycles"});
    expect_error_mentions(parse_malioc_text(read_sample("malioc_bad_number.txt")), {"Shortest path cycles", "-0.56"});
    expect_error_mentions(parse_malioc_text(""), {"banner"});
    expect_error_mentions(parse_malioc_text("random words\nno report here\n"), {"banner"});

    const std::string good = read_sample("malioc_valhall.txt");
    auto without = [&](const std::string& line) {
        std::string s = good;
        const std::size_t at = s.find(line);
        EXPECT_NE(at, std::string::npos) << line;
        return s.erase(at, line.size());
    };
    auto replaced = [&](const std::string& from, const std::string& to) {
        std::string s = good;
        const std::size_t at = s.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        return s.replace(at, from.size(), to);
    };
    expect_error_mentions(parse_malioc_text(without("Hardware: Mali-G78 r1p1\n")), {"Hardware"});
    expect_error_mentions(parse_malioc_text(without("Work registers: 32\n")), {"Work registers"});
    expect_error_mentions(parse_malioc_text(without("Uniform registers: 16\n")), {"Uniform registers"});
    expect_error_mentions(parse_malioc_text(replaced("Main shader\n===========", "Main\n")), {"Main shader"});
    expect_error_mentions(parse_malioc_text(replaced("T    Bound", "T")), {"pipe header"});
    expect_error_mentions(parse_malioc_text(replaced("1.25        A", "1.25")), {"Total instruction cycles", "expected 7"});
    expect_error_mentions(parse_malioc_text(replaced("1.50", "1.5e999")), {"Total instruction cycles", "1.5e999"});
    expect_error_mentions(parse_malioc_text(replaced("1.50", "nan")), {"Total instruction cycles", "nan"});
    expect_error_mentions(parse_malioc_text(replaced("1.50", "x1")), {"not a number"});
    expect_error_mentions(parse_malioc_text(replaced("Work registers: 32", "Work registers: -3")), {"Work registers", "-3"});
    expect_error_mentions(parse_malioc_text(replaced("Work registers: 32", "Work registers: 99999999999")),
                          {"Work registers"});
    expect_error_mentions(parse_malioc_text(replaced("16-bit arithmetic: 25%", "16-bit arithmetic: 250%")), {"over 100%"});
}

// --- Real malioc reports (tests/data/vendor/real/SOURCES.md) --------------------

const VendorVariant* variant_named(const VendorCycles& c, const std::string& name) {
    for (const VendorVariant& v : c.variants)
        if (v.name == name) return &v;
    return nullptr;
}

// 7.4 on a Valhall G710: a vertex shader's Position and Varying variants
// under "----" rules inside "Main shader", each reported on its own; the
// primary figures are the Position variant's, not the Varying one's.
TEST(MaliocRealReports, Valhall74VertexVariantsUnderDashRules) {
    auto r = parse_malioc_text(read_sample("real/malioc_7.4_g710_vertex_idvs.txt"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const VendorCycles& c = *r;
    EXPECT_EQ(c.tool, "malioc 7.4.0");
    EXPECT_EQ(c.target, "Mali-G710 r0p0 (Valhall)");
    EXPECT_EQ(c.shader_type, "OpenGL ES Vertex");
    ASSERT_EQ(c.variants.size(), 2u);
    EXPECT_EQ(c.name, "Position");
    EXPECT_EQ(c.work_registers, 19);
    EXPECT_EQ(c.uniform_registers, 44);
    EXPECT_EQ(c.fp16_percent, 0.0);
    EXPECT_EQ(c.pipes, (std::vector<std::string>{"FMA", "CVT", "SFU", "LS", "T"}));
    expect_figures(c.longest, {0.25, 0.00, 0.00, 2.00, 0.00}, "position longest");
    EXPECT_EQ(c.bound, "LS");
    const VendorVariant* varying = variant_named(c, "Varying");
    ASSERT_NE(varying, nullptr);
    EXPECT_EQ(varying->work_registers, 7);
    EXPECT_EQ(varying->uniform_registers, 12);
    expect_figures(varying->total, {0.02, 0.00, 0.00, 3.00, 0.00}, "varying total");
    expect_figures(varying->shortest, {0.02, 0.00, 0.00, 3.00, 0.00}, "varying shortest");
    expect_figures(varying->longest, {0.02, 0.00, 0.00, 3.00, 0.00}, "varying longest");
    EXPECT_TRUE(has_note(c, "figures of the Position variant; the report also has Varying variant"));
    EXPECT_FALSE(has_note(c, "uniform computation"));  // "Has uniform computation: false"
}

// 8.8 on an Arm 5th Generation G1: the A column beside FMA, CVT and SFU,
// "Stack use: false" and an indented " - Idle SIMD lanes" line.
TEST(MaliocRealReports, FifthGeneration88Fragment) {
    auto r = parse_malioc_text(read_sample("real/malioc_8.8_g1_fragment_5thgen.txt"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const VendorCycles& c = *r;
    EXPECT_EQ(c.tool, "malioc 8.8.0");
    EXPECT_EQ(c.target, "Mali-G1 r0p1 (Arm 5th Generation)");
    EXPECT_EQ(c.shader_type, "Vulkan Fragment");
    ASSERT_EQ(c.variants.size(), 1u);
    EXPECT_EQ(c.name, "Main");
    EXPECT_EQ(c.work_registers, 13);
    EXPECT_EQ(c.uniform_registers, 16);
    EXPECT_EQ(c.fp16_percent, 25.0);
    EXPECT_FALSE(c.stack_spilling);
    EXPECT_EQ(c.pipes, (std::vector<std::string>{"A", "FMA", "CVT", "SFU", "LS", "V", "T"}));
    expect_figures(c.total, {0.27, 0.19, 0.05, 0.25, 0.00, 0.06, 0.25}, "total");
    expect_figures(c.shortest, {0.19, 0.08, 0.05, 0.19, 0.00, 0.06, 0.25}, "shortest");
    expect_figures(c.longest, {0.27, 0.19, 0.05, 0.25, 0.00, 0.06, 0.25}, "longest");
    EXPECT_EQ(c.bound, "A");
    EXPECT_EQ(c.shortest_bound, "T");
    EXPECT_EQ(c.notes, (std::vector<std::string>{"uniform computation"}));
}

// Loops the compiler cannot bound: the longest path is N/A and the total
// instruction cycles are kept as the only bound; a spill region.
TEST(MaliocRealReports, LongestPathNotAvailableKeepsTheTotal) {
    auto r = parse_malioc_text(read_sample("real/malioc_8.8_g1_compute_longest_na.txt"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const VendorCycles& c = *r;
    EXPECT_EQ(c.shader_type, "Vulkan Compute");
    EXPECT_EQ(c.work_registers, 64);
    EXPECT_EQ(c.uniform_registers, 72);
    EXPECT_TRUE(c.stack_spilling);
    EXPECT_TRUE(has_note(c, "stack spill 84 bytes"));
    expect_figures(c.total, {3.67, 2.42, 1.09, 1.25, 52.00, 0.00}, "total");
    expect_figures(c.shortest, {0.02, 0.00, 0.02, 0.00, 0.00, 0.00}, "shortest");
    expect_figures(c.longest, {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN}, "longest");
    EXPECT_EQ(c.shortest_bound, "A, CVT");
    EXPECT_EQ(c.longest_bound, "");
    EXPECT_EQ(c.bound, "LS");  // the total's
}

TEST(MaliocRealReports, Bifrost81FragmentWithNotes) {
    auto r = parse_malioc_text(read_sample("real/malioc_8.1_g76_fragment_bifrost.txt"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const VendorCycles& c = *r;
    EXPECT_EQ(c.tool, "malioc 8.1.0");
    EXPECT_EQ(c.target, "Mali-G76 r0p0 (Bifrost)");
    EXPECT_EQ(c.work_registers, 31);
    EXPECT_EQ(c.uniform_registers, 66);
    EXPECT_EQ(c.fp16_percent, 38.0);
    EXPECT_EQ(c.pipes, (std::vector<std::string>{"A", "LS", "V", "T"}));
    expect_figures(c.total, {5.30, 0.00, 1.88, 3.00}, "total");
    expect_figures(c.longest, {5.30, 0.00, 1.88, 3.00}, "longest");
    EXPECT_EQ(c.bound, "A");
    EXPECT_EQ(c.notes, (std::vector<std::string>{"uniform computation"}));
}

// Arm's guide quotes a Midgard report from its Configuration section on:
// read, its version unknown and said so.
TEST(MaliocRealReports, MidgardQuotedWithoutBanner) {
    auto r = parse_malioc_text(read_sample("real/malioc_midgard_t880_quoted_without_banner.txt"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const VendorCycles& c = *r;
    EXPECT_EQ(c.tool, "malioc");
    EXPECT_TRUE(has_note(c, "no banner: the compiler's version is not in the report"));
    EXPECT_EQ(c.target, "Mali-T880 r2p0");
    EXPECT_EQ(c.pipes, (std::vector<std::string>{"A", "LS", "T"}));
    expect_figures(c.total, {6.0, 1.0, 0.0}, "total");
    expect_figures(c.shortest, {1.7, 1.0, 0.0}, "shortest");
    expect_figures(c.longest, {1.7, 1.0, 0.0}, "longest");
    EXPECT_EQ(c.fp16_percent, -1.0);
}

// A real 7.2 JSON report: schema version 0, figures in the variant's own
// pipeline order (not the hardware list's), 16-bit share 0.
TEST(MaliocRealReports, Json72ValhallFragment) {
    auto r = parse_malioc_json(read_sample("real/malioc_7.2_g78_fragment.json"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const VendorCycles& c = *r;
    EXPECT_EQ(c.tool, "malioc 7.2.0");
    EXPECT_EQ(c.target, "Mali-G78 r1p1 (Valhall)");
    EXPECT_EQ(c.shader_type, "OpenGL ES Fragment");
    ASSERT_EQ(c.variants.size(), 1u);
    EXPECT_EQ(c.name, "Main");
    EXPECT_EQ(c.work_registers, 32);
    EXPECT_EQ(c.uniform_registers, 18);
    EXPECT_EQ(c.fp16_percent, 0.0);
    EXPECT_FALSE(c.stack_spilling);
    EXPECT_EQ(c.pipes, (std::vector<std::string>{"FMA", "CVT", "SFU", "LS", "V", "T"}));
    expect_figures(c.total, {1.40625, 0.078125, 0.8125, 0.0, 0.75, 0.25}, "total");
    expect_figures(c.shortest, {1.40625, 0.046875, 0.8125, 0.0, 0.75, 0.25}, "shortest");
    expect_figures(c.longest, {1.40625, 0.078125, 0.8125, 0.0, 0.75, 0.25}, "longest");
    EXPECT_EQ(c.bound, "FMA");
    EXPECT_EQ(c.notes, (std::vector<std::string>{"uniform computation"}));
}

// What the parser does not know is refused with the line quoted, never
// read wrong: an N/A where a figure stood, a new row, a column dropped.
TEST(MaliocRealReports, ChangedLayoutsAreRefusedWithTheLineQuoted) {
    const std::string vertex = read_sample("real/malioc_7.4_g710_vertex_idvs.txt");
    auto replaced = [](std::string s, const std::string& from, const std::string& to) {
        const std::size_t at = s.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        return at == std::string::npos ? s : s.replace(at, from.size(), to);
    };
    // N/A is a value the tool prints: read, never refused.
    auto na = parse_malioc_text(replaced(vertex, "16-bit arithmetic: 0%", "16-bit arithmetic: N/A"));
    ASSERT_TRUE(na.ok()) << na.error().message;
    EXPECT_EQ(na->fp16_percent, -1.0);
    EXPECT_EQ(na->work_registers, 19);
    // A row under a name the parser does not know.
    expect_error_mentions(
        parse_malioc_text(replaced(vertex, "Shortest path cycles:    ", "Average path cycles:     ")),
        {"Average path cycles:", "0.25", "Position variant"});
    // A figure dropped from a row: the line quoted.
    expect_error_mentions(parse_malioc_text(replaced(vertex, "0.02    0.00    0.00    3.00    0.00       LS",
                                                     "0.02    0.00    3.00    0.00       LS")),
                          {"Total instruction cycles", "expected 5", "0.02    0.00    3.00", "Varying variant"});
    // Figures on a line of no known shape.
    expect_error_mentions(parse_malioc_text(replaced(vertex, "Work registers: 7\n", "Work registers: 7\n7 12 0.5\n")),
                          {"does not know", "'7 12 0.5'"});
}

// --- malioc JSON ------------------------------------------------------------------

TEST(MaliocJson, ValhallFragment) {
    auto r = parse_malioc_json(read_sample("malioc_valhall.json"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const VendorCycles& c = *r;
    EXPECT_EQ(c.tool, "malioc 8.2.0");
    EXPECT_EQ(c.target, "Mali-G78 r1p1 (Valhall)");
    EXPECT_EQ(c.work_registers, 32);
    EXPECT_EQ(c.uniform_registers, 16);
    EXPECT_EQ(c.fp16_percent, 25.0);
    EXPECT_FALSE(c.stack_spilling);
    EXPECT_EQ(c.pipes, (std::vector<std::string>{"A", "FMA", "CVT", "SFU", "LS", "V", "T"}));
    expect_figures(c.total, {1.5, 0.875, 0.3125, 0.25, 0.0, 0.5, 1.25}, "total");
    expect_figures(c.shortest, {0.5625, 0.375, 0.0625, 0.125, 0.0, 0.5, 0.5}, "shortest");
    expect_figures(c.longest, {1.1875, 0.75, 0.25, 0.25, 0.0, 0.5, 1.25}, "longest");
    EXPECT_EQ(c.bound, "T");
    EXPECT_EQ(c.notes, (std::vector<std::string>{"uniform computation"}));
}

TEST(MaliocJson, AgreesWithTheTextReportOfTheSameCompile) {
    // The text report prints the JSON's figures to two decimals.
    auto text = parse_malioc_text(read_sample("malioc_valhall.txt"));
    auto json = parse_malioc_json(read_sample("malioc_valhall.json"));
    ASSERT_TRUE(text.ok() && json.ok());
    EXPECT_EQ(text->tool, json->tool);
    EXPECT_EQ(text->target, json->target);
    EXPECT_EQ(text->work_registers, json->work_registers);
    EXPECT_EQ(text->uniform_registers, json->uniform_registers);
    EXPECT_EQ(text->fp16_percent, json->fp16_percent);
    EXPECT_EQ(text->pipes, json->pipes);
    EXPECT_EQ(text->bound, json->bound);
    EXPECT_EQ(text->notes, json->notes);
    for (std::size_t i = 0; i < text->pipes.size(); ++i) {
        EXPECT_NEAR(text->total[i], json->total[i], 0.0051) << i;
        EXPECT_NEAR(text->shortest[i], json->shortest[i], 0.0051) << i;
        EXPECT_NEAR(text->longest[i], json->longest[i], 0.0051) << i;
    }
}

TEST(MaliocJson, NullPathsVariantsAndSpill) {
    nlohmann::json j = nlohmann::json::parse(read_sample("malioc_valhall.json"));
    auto& variant = j["shaders"][0]["variants"][0];
    variant["performance"]["longest_path_cycles"] = nullptr;
    variant["performance"]["shortest_path_cycles"]["cycle_count"][0] = nullptr;
    for (auto& p : variant["properties"])
        if (p["name"] == "stack_spill_bytes") p["value"] = 24;
    variant["name"] = "Position";
    nlohmann::json varying = variant;
    varying["name"] = "Varying";
    j["shaders"][0]["variants"].push_back(varying);
    auto r = parse_malioc_json(j.dump());
    ASSERT_TRUE(r.ok()) << r.error().message;
    expect_figures(r->longest, std::vector<double>(7, kNaN), "longest");
    EXPECT_TRUE(std::isnan(r->shortest[0]));
    EXPECT_EQ(r->bound, "A");  // the total's: the longest path is null
    EXPECT_TRUE(r->stack_spilling);
    EXPECT_TRUE(has_note(*r, "stack spill 24 bytes"));
    EXPECT_TRUE(has_note(*r, "figures of the Position variant; the report also has Varying variant"));
}

TEST(MaliocJson, MalformedReportsNameWhatIsMissing) {
    expect_error_mentions(parse_malioc_json(read_sample("malioc_truncated.json")), {"malioc JSON report", "not valid JSON"});
    expect_error_mentions(parse_malioc_json(read_sample("malioc_no_registers.json")), {"work_registers_used"});
    expect_error_mentions(parse_malioc_json(read_sample("malioc_error.json")), {"'error' report", "undeclared identifier"});
    expect_error_mentions(parse_malioc_json("[]"), {"not a JSON object"});
    expect_error_mentions(parse_malioc_json("{}"), {"shaders"});

    const nlohmann::json good = nlohmann::json::parse(read_sample("malioc_valhall.json"));
    auto mutated = [&](auto change) {
        nlohmann::json j = good;
        change(j["shaders"][0]["variants"][0]);
        return parse_malioc_json(j.dump());
    };
    expect_error_mentions(mutated([](nlohmann::json& v) { v["performance"].erase("total_cycles"); }), {"total_cycles"});
    expect_error_mentions(mutated([](nlohmann::json& v) { v["performance"]["total_cycles"]["cycle_count"].erase(0); }),
                          {"total_cycles.cycle_count has 6 values for 7 pipelines"});
    expect_error_mentions(mutated([](nlohmann::json& v) { v["performance"]["longest_path_cycles"]["cycle_count"][2] = -1; }),
                          {"longest_path_cycles.cycle_count[2]", "-1"});
    expect_error_mentions(mutated([](nlohmann::json& v) { v["performance"]["total_cycles"]["cycle_count"][1] = "0.5"; }),
                          {"cycle_count[1] is not a number"});
    expect_error_mentions(mutated([](nlohmann::json& v) { v["performance"].erase("pipelines"); }), {"pipelines"});
    expect_error_mentions(mutated([](nlohmann::json& v) { v.erase("performance"); }), {"no performance"});
    expect_error_mentions(mutated([](nlohmann::json& v) {
                              for (auto& p : v["properties"])
                                  if (p["name"] == "uniform_registers_used") p["value"] = 2.5;
                          }),
                          {"uniform_registers_used", "2.5"});
    expect_error_mentions(mutated([](nlohmann::json& v) {
                              for (auto& p : v["properties"])
                                  if (p["name"] == "fp16_arithmetic") p["value"] = 101;
                          }),
                          {"fp16_arithmetic"});
    nlohmann::json no_core = good;
    no_core["shaders"][0]["hardware"].erase("core");
    expect_error_mentions(parse_malioc_json(no_core.dump()), {"hardware.core"});
    nlohmann::json no_variants = good;
    no_variants["shaders"][0]["variants"] = nlohmann::json::array();
    expect_error_mentions(parse_malioc_json(no_variants.dump()), {"variants"});
}

// --- PowerVR ----------------------------------------------------------------------

TEST(PowerVr, Profile) {
    auto r = parse_powervr_output(read_sample("powervr_rogue.prof"));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const VendorCycles& c = *r;
    EXPECT_EQ(c.cycles, 13.0);  // the worst-case estimate
    EXPECT_EQ(c.work_registers, 6);
    EXPECT_EQ(c.uniform_registers, -1);
    EXPECT_EQ(c.fp16_percent, -1.0);
    EXPECT_TRUE(c.pipes.empty());
    EXPECT_TRUE(c.total.empty() && c.shortest.empty() && c.longest.empty());
    EXPECT_EQ(c.bound, "");
    EXPECT_EQ(c.notes, (std::vector<std::string>{"cycles: worst-case performance estimate", "best-case estimate 9 cycles",
                                                 "per-line estimate total 14 cycles", "global USC instructions 2"}));
}

TEST(PowerVr, FallbackFigures) {
    auto emulated = parse_powervr_output("Emulated cycles = 21.5\ntemp registers: 4\n");
    ASSERT_TRUE(emulated.ok()) << emulated.error().message;
    EXPECT_EQ(emulated->cycles, 21.5);
    EXPECT_EQ(emulated->work_registers, 4);
    auto per_line = parse_powervr_output("0: fmad r0, r1, r2, r3\nPer-line Cycle Estimate Total: 7\n");
    ASSERT_TRUE(per_line.ok()) << per_line.error().message;
    EXPECT_EQ(per_line->cycles, 7.0);
    EXPECT_EQ(per_line->notes, (std::vector<std::string>{"cycles: per-line cycle estimate total"}));
}

TEST(PowerVr, MalformedProfiles) {
    expect_error_mentions(parse_powervr_output(read_sample("powervr_no_cycles.prof")), {"PowerVR profile", "no cycle figure"});
    expect_error_mentions(parse_powervr_output(""), {"no cycle figure"});
    expect_error_mentions(parse_powervr_output("Performance estimate (Worst): -4\n"), {"Performance estimate (Worst)", "-4"});
    expect_error_mentions(parse_powervr_output("Performance estimate (Worst): inf\n"), {"inf"});
    expect_error_mentions(parse_powervr_output("Performance estimate (Worst):\n"), {"missing number"});
    expect_error_mentions(parse_powervr_output("Performance estimate (Worst): 12\nTemporary registers: many\n"),
                          {"Temporary registers", "many"});
}

// --- Finding and running the tools --------------------------------------------------

// A temporary folder of fake compilers put first on PATH; PATH is restored after.
class FakeTools : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        folder_ = fs::temp_directory_path() / ("px_vendor_tools_" + std::string(info->name()) + "_" + std::to_string(getpid()));
        fs::remove_all(folder_);
        fs::create_directories(folder_);
        const char* path = std::getenv("PATH");
        old_path_ = path ? path : "";
        had_path_ = path != nullptr;
    }
    void TearDown() override {
        if (had_path_) setenv("PATH", old_path_.c_str(), 1);
        else unsetenv("PATH");
        std::error_code ec;
        fs::remove_all(folder_, ec);
    }
    // Writes an executable (or not) script named `name` into the folder.
    std::string script(const std::string& name, const std::string& body, bool executable = true) {
        const fs::path file = folder_ / name;
        std::ofstream(file) << "#!/bin/sh\n" << body;
        chmod(file.c_str(), executable ? 0755 : 0644);
        return file.string();
    }
    void put_first_on_path() { setenv("PATH", (folder_.string() + ":" + old_path_).c_str(), 1); }
    void make_path_only_the_folder() { setenv("PATH", folder_.c_str(), 1); }

    VendorTool find(const std::string& name) {
        for (const VendorTool& t : find_vendor_tools())
            if (t.name == name) return t;
        ADD_FAILURE() << name << " not found on PATH";
        return {};
    }

    fs::path folder_;
    std::string old_path_;
    bool had_path_ = false;
};

const std::string kFragment = "#version 300 es\nprecision mediump float;\nout vec4 colour;\nvoid main() { colour = vec4(1.0); }\n";

TEST_F(FakeTools, FindsExecutablesOnPathOnly) {
    make_path_only_the_folder();
    EXPECT_TRUE(find_vendor_tools().empty());
    const std::string malioc = script("malioc", "exit 0\n");
    script("GLSLESCompiler_Series6", "exit 0\n", false);  // not executable: not a tool
    const std::string rogue = script("GLSLESCompiler_Rogue", "exit 0\n");
    fs::create_directories(folder_ / "GLSLESCompiler_Series6XT");  // a folder, not a tool
    const std::vector<VendorTool> found = find_vendor_tools();
    ASSERT_EQ(found.size(), 2u);
    EXPECT_EQ(found[0].name, "malioc");
    EXPECT_EQ(found[0].path, malioc);
    EXPECT_EQ(found[1].name, "GLSLESCompiler_Rogue");
    EXPECT_EQ(found[1].path, rogue);

    setenv("PATH", "", 1);
    EXPECT_TRUE(find_vendor_tools().empty());
    unsetenv("PATH");
    EXPECT_TRUE(find_vendor_tools().empty());
}

TEST_F(FakeTools, AbsentLineNamesTheCandidates) {
    const std::string line = vendor_tools_absent_line();
    EXPECT_EQ(line.rfind("no vendor compiler on PATH (looked for malioc, GLSLESCompiler_Rogue", 0), 0u) << line;
    EXPECT_EQ(line.back(), ')');
}

TEST_F(FakeTools, RunsMaliocAndParsesItsJson) {
    // The fake checks what it is given: the stage flag, JSON, a .frag file holding the source.
    script("malioc",
           "last=\"\"; for a in \"$@\"; do last=\"$a\"; done\n"
           "case \"$*\" in *--fragment*--format\\ json*) ;; *) echo \"unexpected arguments: $*\"; exit 2;; esac\n"
           "case \"$last\" in *.frag) ;; *) echo \"not a .frag file: $last\"; exit 2;; esac\n"
           "grep -q 'void main' \"$last\" || { echo 'source missing'; exit 2; }\n"
           "cat '" + kData + "malioc_valhall.json'\n");
    put_first_on_path();
    auto r = run_vendor_tool(find("malioc"), kFragment, ShaderStage::fragment, 3);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->tool, "malioc 8.2.0");
    EXPECT_EQ(r->work_registers, 32);
    EXPECT_EQ(r->bound, "T");
    expect_figures(r->longest, {1.1875, 0.75, 0.25, 0.25, 0.0, 0.5, 1.25}, "longest");
}

TEST_F(FakeTools, MaliocPrintingTextIsReadToo) {
    script("malioc",
           "case \"$*\" in *--vertex*.vert) ;; *) echo \"unexpected arguments: $*\"; exit 2;; esac\n"
           "cat '" + kData + "malioc_valhall_vertex_8x.txt'\n");
    put_first_on_path();
    auto r = run_vendor_tool(find("malioc"), "#version 100\nvoid main() { gl_Position = vec4(0.0); }\n",
                             ShaderStage::vertex, 2);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->tool, "malioc 8.2.0");
    EXPECT_EQ(r->work_registers, 46);
}

TEST_F(FakeTools, FailingToolIsAnErrorWithItsOutput) {
    script("malioc", "echo 'ERROR: 0:3: syntax error near colour'\necho 'second line' >&2\nexit 1\n");
    put_first_on_path();
    auto r = run_vendor_tool(find("malioc"), kFragment, ShaderStage::fragment, 3);
    expect_error_mentions(r, {"malioc", "exited with status 1", "syntax error near colour", "second line"});
}

TEST_F(FakeTools, FailingToolWithAJsonErrorReport) {
    script("malioc", "cat '" + kData + "malioc_error.json'\nexit 1\n");
    put_first_on_path();
    auto r = run_vendor_tool(find("malioc"), kFragment, ShaderStage::fragment, 3);
    expect_error_mentions(r, {"exited with status 1", "undeclared identifier"});
}

TEST_F(FakeTools, UnparsableOutputNamesWhatIsMissing) {
    script("malioc", "cat '" + kData + "malioc_truncated.json'\n");
    put_first_on_path();
    auto r = run_vendor_tool(find("malioc"), kFragment, ShaderStage::fragment, 3);
    expect_error_mentions(r, {"malioc", "exited with status 0", "not valid JSON"});
}

TEST_F(FakeTools, HangingToolIsKilledAtTheLimit) {
    // The script's child (sleep) must die too: it holds the output pipe open.
    script("malioc", "echo 'starting'\nsleep 30\necho 'never printed'\n");
    put_first_on_path();
    const auto start = std::chrono::steady_clock::now();
    auto r = run_vendor_tool(find("malioc"), kFragment, ShaderStage::fragment, 3, std::chrono::seconds(2));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    expect_error_mentions(r, {"malioc", "killed after the 2000 ms limit", "starting"});
    EXPECT_GE(seconds, 1.9);
    EXPECT_LT(seconds, 10.0);
}

TEST_F(FakeTools, RunawayOutputIsCapped) {
    script("malioc", "head -c 6000000 /dev/zero | tr '\\000' 'a'\n");
    put_first_on_path();
    auto r = run_vendor_tool(find("malioc"), kFragment, ShaderStage::fragment, 3, std::chrono::seconds(20));
    expect_error_mentions(r, {"malioc", "4 MiB"});
}

TEST_F(FakeTools, RunsThePowerVrCompilerAndReadsItsProfileFile) {
    // `<in> <out> -f -profile`: the profile goes to <out>.prof.
    script("GLSLESCompiler_Rogue",
           "case \"$1\" in *.frag) ;; *) echo \"not a .frag file: $1\"; exit 2;; esac\n"
           "[ \"$3\" = -f ] && [ \"$4\" = -profile ] || { echo \"unexpected arguments: $*\"; exit 2; }\n"
           "cp '" + kData + "powervr_rogue.prof' \"$2.prof\"\necho 'Compilation successful'\n");
    put_first_on_path();
    auto r = run_vendor_tool(find("GLSLESCompiler_Rogue"), kFragment, ShaderStage::fragment, 3);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->tool, "GLSLESCompiler_Rogue");
    EXPECT_EQ(r->target, "Rogue");
    EXPECT_EQ(r->cycles, 13.0);
    EXPECT_EQ(r->work_registers, 6);
}

TEST_F(FakeTools, BadArgumentsAreErrors) {
    const std::string malioc = script("malioc", "exit 0\n");
    expect_error_mentions(run_vendor_tool(VendorTool{"malioc", malioc}, kFragment, ShaderStage::fragment, 4), {"not 2 or 3"});
    expect_error_mentions(run_vendor_tool(VendorTool{"glslangValidator", malioc}, kFragment, ShaderStage::fragment, 3),
                          {"not a vendor compiler"});
    expect_error_mentions(run_vendor_tool(VendorTool{"malioc", "malioc"}, kFragment, ShaderStage::fragment, 3),
                          {"absolute path"});
    expect_error_mentions(
        run_vendor_tool(VendorTool{"malioc", (folder_ / "missing").string()}, kFragment, ShaderStage::fragment, 3),
        {"malioc"});
}


// --- Hostile tools: files that are not files, text that is not text, time --------

TEST(CleanToolText, KeepsTextAndRemovesWhatDrivesATerminal) {
    EXPECT_EQ(clean_tool_text("Work registers: 32\n\tnext"), "Work registers: 32\n\tnext");
    EXPECT_EQ(clean_tool_text("caf\xc3\xa9 \xe2\x86\x92 \xf0\x9f\x99\x82"), "caf\xc3\xa9 \xe2\x86\x92 \xf0\x9f\x99\x82");
    EXPECT_EQ(clean_tool_text("\x1b[31mred\x1b[0m"), "red");
    EXPECT_EQ(clean_tool_text("a\x1b]0;window title\x07" "b"), "ab");
    EXPECT_EQ(clean_tool_text("a\x1b]8;;http://x\x1b\\link\x1b]8;;\x1b\\"), "alink");
    EXPECT_EQ(clean_tool_text("\x1b" "cclear\x1b[2J\x1b[H"), "clear");
    EXPECT_EQ(clean_tool_text("a\rb\x08" "c\x07" "d\x7f"), "abcd");
    EXPECT_EQ(clean_tool_text("x\xc2\x9b" "31my"), "xy");      // C1 CSI, encoded
    EXPECT_EQ(clean_tool_text("x\xc2\x9d" "0;t\x07y"), "xy");  // C1 OSC, encoded
    // An unterminated control string stops at the line's end, not the text's.
    EXPECT_EQ(clean_tool_text("a\x1b]0;never ends\nnext line"), "a\nnext line");
    // Bytes that are not UTF-8 become U+FFFD, one each.
    const std::string r = "\xef\xbf\xbd";
    EXPECT_EQ(clean_tool_text("bad\xff\xfe"), "bad" + r + r);
    EXPECT_EQ(clean_tool_text("\xc0\xaf"), r + r);              // overlong '/'
    EXPECT_EQ(clean_tool_text("\xed\xa0\x80"), r + r + r);      // a surrogate
    EXPECT_EQ(clean_tool_text("\xf4\x90\x80\x80"), r + r + r + r);  // past U+10FFFF
    EXPECT_EQ(clean_tool_text("trunc\xe2\x86"), "trunc" + r + r);
}

TEST(CleanToolText, AnyBytesMakeValidJsonAndNoEscape) {
    // Every pair of bytes, and each behind an escape: the result is always
    // valid UTF-8 (nlohmann::json's dump throws otherwise) and holds no ESC.
    for (int a = 0; a < 256; ++a) {
        for (int b = 0; b < 256; ++b) {
            const std::string raw{static_cast<char>(a), static_cast<char>(b), '\x1b', static_cast<char>(b)};
            const std::string clean = clean_tool_text(raw);
            ASSERT_EQ(clean.find('\x1b'), std::string::npos) << a << " " << b;
            ASSERT_NO_THROW((void)nlohmann::json(clean).dump()) << a << " " << b;
        }
    }
}

TEST_F(FakeTools, OutputThatIsNotTextIsCleanedBeforeAnyoneSeesIt) {
    script("malioc", "printf 'ERROR: \\033[2J\\033]0;pwned\\007bad \\377\\376 bytes\\n'\nexit 1\n");
    put_first_on_path();
    auto r = run_vendor_tool(find("malioc"), kFragment, ShaderStage::fragment, 3);
    expect_error_mentions(r, {"exited with status 1", "ERROR: bad \xef\xbf\xbd\xef\xbf\xbd bytes"});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message.find('\x1b'), std::string::npos);
    EXPECT_EQ(r.error().message.find("pwned"), std::string::npos);
    EXPECT_NO_THROW((void)nlohmann::json(r.error().message).dump());
}

TEST_F(FakeTools, AProfileFileThatIsNotARegularFileIsNotOpened) {
    // A FIFO at <out>.prof: opening it for reading would wait for a writer for ever.
    script("GLSLESCompiler_Rogue", "mkfifo \"$2.prof\"\necho 'Compilation successful'\n");
    put_first_on_path();
    expect_error_mentions(run_vendor_tool(find("GLSLESCompiler_Rogue"), kFragment, ShaderStage::fragment, 3),
                          {"GLSLESCompiler_Rogue", "profile.prof is a FIFO, not a regular file"});
    script("GLSLESCompiler_Rogue", "ln -s '" + kData + "powervr_rogue.prof' \"$2.prof\"\necho 'Compilation successful'\n");
    expect_error_mentions(run_vendor_tool(find("GLSLESCompiler_Rogue"), kFragment, ShaderStage::fragment, 3),
                          {"profile.prof is a symbolic link: not followed"});
    script("GLSLESCompiler_Rogue", "mkdir \"$2.prof\"\necho 'Compilation successful'\n");
    expect_error_mentions(run_vendor_tool(find("GLSLESCompiler_Rogue"), kFragment, ShaderStage::fragment, 3),
                          {"profile.prof is a folder"});
}

TEST_F(FakeTools, ARunHasOneBudgetAndAToolThatRanOutIsNotStartedAgain) {
    // Two compilers that hang (each counts its starts) and one that works.
    const std::string starts = (folder_ / "starts").string();
    script("malioc", "echo malioc >>'" + starts + "'\nsleep 30\n");
    script("GLSLESCompiler_Rogue", "echo rogue >>'" + starts + "'\nsleep 30\n");
    script("GLSLESCompiler_Series6", "echo series6 >>'" + starts + "'\ncp '" + kData +
                                         "powervr_rogue.prof' \"$2.prof\"\n");
    put_first_on_path();
    VendorRun run({find("malioc"), find("GLSLESCompiler_Rogue"), find("GLSLESCompiler_Series6")},
                  std::chrono::milliseconds(1000));
    // One run gets at most half the budget.
    expect_error_mentions(run.run(run.tools()[0], kFragment, ShaderStage::fragment, 3), {"killed after the 500 ms limit"});
    Result<VendorCycles> again = run.run(run.tools()[0], kFragment, ShaderStage::fragment, 3);
    ASSERT_FALSE(again.ok());
    EXPECT_EQ(again.error().message.rfind("skipped: malioc ran out of time", 0), 0u) << again.error().message;
    // The second hang takes the rest: the budget is spent for every tool.
    expect_error_mentions(run.run(run.tools()[1], kFragment, ShaderStage::fragment, 3), {"killed after"});
    Result<VendorCycles> spent = run.run(run.tools()[2], kFragment, ShaderStage::fragment, 3);
    ASSERT_FALSE(spent.ok());
    EXPECT_EQ(spent.error().message.rfind("skipped: the vendor compilers' time", 0), 0u) << spent.error().message;
    std::ifstream in(starts);
    std::stringstream started;
    started << in.rdbuf();
    EXPECT_EQ(started.str(), "malioc\nrogue\n");
    ASSERT_EQ(run.notes().size(), 3u);
    EXPECT_NE(run.notes()[0].find("malioc did not finish within 0.5 s and was not run again"), std::string::npos)
        << run.notes()[0];
    EXPECT_NE(run.notes()[2].find("was spent"), std::string::npos) << run.notes()[2];
}

TEST_F(FakeTools, ARunWithinItsBudgetRunsEveryTool) {
    script("GLSLESCompiler_Rogue", "cp '" + kData + "powervr_rogue.prof' \"$2.prof\"\n");
    put_first_on_path();
    VendorRun run({find("GLSLESCompiler_Rogue")}, std::chrono::seconds(60));
    for (int i = 0; i < 3; ++i) {
        auto r = run.run(run.tools()[0], kFragment, ShaderStage::fragment, 3);
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_EQ(r->cycles, 13.0);
    }
    EXPECT_TRUE(run.notes().empty());
}

}  // namespace
}  // namespace px::profiling
