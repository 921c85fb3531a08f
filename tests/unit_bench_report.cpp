// Unit tests for the benchmark report writers (include/parallaxes/profiling/reports/bench_results.h):
// CSV, JSON, the Pareto SVG and the markdown report, on a synthetic run whose
// answers are known, plus the atomic write and its errors.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>  // getpid: a per-process temp directory

#include "parallaxes/effects/technique.h"
#include "parallaxes/profiling/reports/bench_results.h"

namespace px::profiling {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
const std::string kPit = "pit \"deep\", v2";  // needs CSV quoting and XML escaping

// A fresh temporary directory per test, removed afterwards.
class TempDir {
public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = fs::temp_directory_path() / ("px_unit_bench_report_" + std::string(info->test_suite_name()) + "_" +
                                             info->name() + "_" + std::to_string(::getpid()));
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
    if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "text does not contain '" << part << "':\n" << text;
}

size_t count(const std::string& text, const std::string& part) {
    size_t n = 0;
    for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++n;
    return n;
}

BenchRow row(const std::string& scene, double angle, const std::string& technique, int samples, double error,
             double ratio) {
    BenchRow r;
    r.scene = scene;
    r.angle_deg = angle;
    r.technique = technique;
    r.samples = samples;
    r.pixels = 200000;
    r.uv_error_mean = error;
    r.uv_error_p95 = 2 * error;
    r.uv_error_max = 4 * error;
    r.wrong_surface_share = error > 1 ? 0.4 : 0.02;
    r.depth_error_mean = 0.01;
    r.depth_error_max = 0.2;
    r.shadow_disagreement = 0.05;
    r.color_psnr_db = 35;
    r.frame_ms_median = 10 * ratio;
    r.frame_ms_min = 9.5 * ratio;
    r.frame_ms_max = 11 * ratio;
    r.ns_per_pixel = r.frame_ms_median * 1e6 / static_cast<double>(r.pixels);
    r.ratio_to_normal = ratio;
    return r;
}

// Known answers (mean error <= target, lowest ratio):
//   bricks 75°: 1 -> pom 8 (1.5), 0.5 -> pom 16 (2.0), 0.25 -> relief 16 (2.4);
//               normal and offset_limited reach nothing (3.1, 2.3 texels).
//   bricks 0°:  1 and 0.5 -> flat (0.9), 0.25 -> normal (1.0).
//   pit 75°:    1 -> pom 16 (2.1), 0.5 -> relief 16 (2.5), 0.25 -> maxmip (2.9);
//               steep reaches nothing (1.2 texels).
BenchRun synthetic_run() {
    BenchRun run;
    run.date = "2026-11-25T10:00:00Z";
    run.command = "parallax bench --scenes bricks,pit --angles 0,75 -o out/bench";
    run.gl_renderer = "llvmpipe (LLVM 15.0.6, 256 bits)";
    run.gl_version = "OpenGL ES 3.0 Mesa 22.3.6";
    run.threads = 2;
    run.width = 512;
    run.height = 384;
    run.frames = 9;
    run.rows = {
        row("bricks", 75, "normal", 0, 3.1, 1.0),
        row("bricks", 75, "offset_limited", 0, 2.3, 1.1),
        row("bricks", 75, "pom", 8, 0.9, 1.5),
        row("bricks", 75, "pom", 32, 0.2, 3.0),  // out of sample order on purpose
        row("bricks", 75, "pom", 16, 0.4, 2.0),
        row("bricks", 75, "relief", 8, 0.6, 1.7),
        row("bricks", 75, "relief", 16, 0.22, 2.4),
        row("bricks", 75, "maxmip", 0, 0.004, 2.6),
        row("bricks", 75, "displaced_mesh", 0, 0.0, 12.0),
        row("bricks", 0, "flat", 0, 0.3, 0.9),
        row("bricks", 0, "normal", 0, 0.05, 1.0),
        row("bricks", 0, "pom", 8, 0.02, 1.4),
        row(kPit, 75, "steep", 8, 1.2, 1.3),
        row(kPit, 75, "pom", 8, 1.5, 1.6),
        row(kPit, 75, "pom", 16, 0.8, 2.1),
        row(kPit, 75, "relief", 16, 0.45, 2.5),
        row(kPit, 75, "maxmip", 0, 0.01, 2.9),
    };
    run.rows[12].color_psnr_db = kInf;    // pit steep: written as null / inf / ∞
    run.rows[12].depth_error_max = kNaN;  // written as null / empty / n/a
    return run;
}

// ------------------------------------------------------------------- CSV

// RFC 4180 records (quoted fields may hold commas, quotes and newlines).
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
    std::vector<std::vector<std::string>> records;
    std::vector<std::string> record;
    std::string field;
    bool quoted = false, field_started = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (quoted) {
            if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
                field += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else {
                field += c;
            }
        } else if (c == '"') {
            EXPECT_TRUE(field.empty()) << "quote inside an unquoted field at " << i;
            quoted = true;
        } else if (c == ',') {
            record.push_back(field);
            field.clear();
        } else if (c == '\n') {
            record.push_back(field);
            records.push_back(record);
            record.clear();
            field.clear();
        } else {
            field += c;
        }
        field_started = true;
    }
    EXPECT_FALSE(quoted) << "unterminated quoted field";
    if (field_started && (!field.empty() || !record.empty())) {
        record.push_back(field);
        records.push_back(record);
    }
    return records;
}

TEST(BenchReportCsv, OneRecordPerRowWithQuotingAndRunColumns) {
    TempDir dir;
    const BenchRun run = synthetic_run();
    const std::string path = dir.file("bench.csv");
    const Status s = write_csv(run, path);
    ASSERT_TRUE(s.ok()) << s.error().message;
    const std::string text = read_text(path);
    EXPECT_TRUE(contains(text, "\"pit \"\"deep\"\", v2\""));
    EXPECT_TRUE(contains(text, "\"llvmpipe (LLVM 15.0.6, 256 bits)\""));

    const auto records = parse_csv(text);
    ASSERT_EQ(records.size(), run.rows.size() + 1);
    const std::vector<std::string>& header = records[0];
    auto column = [&](const std::string& name) {
        const auto it = std::find(header.begin(), header.end(), name);
        EXPECT_NE(it, header.end()) << "no column " << name;
        return static_cast<size_t>(it - header.begin());
    };
    for (size_t i = 1; i < records.size(); ++i) {
        ASSERT_EQ(records[i].size(), header.size()) << "record " << i;
        const BenchRow& r = run.rows[i - 1];
        EXPECT_EQ(records[i][column("scene")], r.scene);
        EXPECT_EQ(records[i][column("technique")], r.technique);
        EXPECT_EQ(records[i][column("gl_renderer")], run.gl_renderer);
        EXPECT_EQ(records[i][column("threads")], "2");
        EXPECT_EQ(std::stoi(records[i][column("samples")]), r.samples);
        EXPECT_DOUBLE_EQ(std::stod(records[i][column("ratio_to_normal")]), r.ratio_to_normal);
        EXPECT_NEAR(std::stod(records[i][column("uv_error_mean")]), r.uv_error_mean, 1e-6 * r.uv_error_mean);
    }
    // pit steep: NaN empty, inf spelled out.
    EXPECT_EQ(records[13][column("depth_error_max")], "");
    EXPECT_EQ(records[13][column("color_psnr_db")], "inf");
    // %.6g: enough digits, no noise.
    EXPECT_EQ(records[1][column("ns_per_pixel")], "50");
}

// ------------------------------------------------------------------ JSON

TEST(BenchReportJson, ParsesBackWithEveryField) {
    TempDir dir;
    const BenchRun run = synthetic_run();
    const std::string path = dir.file("bench.json");
    const Status s = write_json(run, path);
    ASSERT_TRUE(s.ok()) << s.error().message;
    const std::string text = read_text(path);
    EXPECT_TRUE(contains(text, "\n  \"command\"")) << "not pretty-printed";

    const nlohmann::json doc = nlohmann::json::parse(text);  // throws (fails the test) if malformed
    EXPECT_EQ(doc.at("date"), run.date);
    EXPECT_EQ(doc.at("command"), run.command);
    EXPECT_EQ(doc.at("gl_renderer"), run.gl_renderer);
    EXPECT_EQ(doc.at("gl_version"), run.gl_version);
    EXPECT_EQ(doc.at("threads"), 2);
    EXPECT_EQ(doc.at("width"), 512);
    EXPECT_EQ(doc.at("height"), 384);
    EXPECT_EQ(doc.at("frames"), 9);
    const nlohmann::json& rows = doc.at("rows");
    ASSERT_EQ(rows.size(), run.rows.size());
    for (size_t i = 0; i < rows.size(); ++i) {
        const BenchRow& r = run.rows[i];
        const nlohmann::json& j = rows[i];
        EXPECT_EQ(j.size(), r.iteration_histogram.empty() ? 28u : 29u) << "fields in row " << i;
        EXPECT_TRUE(j.at("gpu_cycles").is_null());  // no --gpu: NaN
        EXPECT_TRUE(j.at("gpu_cycles_per_pixel").is_null());
        EXPECT_EQ(j.at("input_floor_p95").get<double>(), r.input_floor_p95);
        EXPECT_TRUE(j.at("own_ray_error_p95").is_null());  // not measured: NaN
        EXPECT_EQ(j.at("scene"), r.scene);
        EXPECT_EQ(j.at("technique"), r.technique);
        EXPECT_EQ(j.at("samples"), r.samples);
        EXPECT_EQ(j.at("pixels"), r.pixels);
        EXPECT_EQ(j.at("angle_deg").get<double>(), r.angle_deg);
        EXPECT_EQ(j.at("uv_error_mean").get<double>(), r.uv_error_mean);
        EXPECT_EQ(j.at("uv_error_p95").get<double>(), r.uv_error_p95);
        EXPECT_EQ(j.at("frame_ms_median").get<double>(), r.frame_ms_median);
        EXPECT_EQ(j.at("ns_per_pixel").get<double>(), r.ns_per_pixel);
        EXPECT_EQ(j.at("ratio_to_normal").get<double>(), r.ratio_to_normal);
    }
    EXPECT_TRUE(rows[12].at("color_psnr_db").is_null());
    EXPECT_TRUE(rows[12].at("depth_error_max").is_null());
    EXPECT_EQ(rows[11].at("color_psnr_db").get<double>(), 35.0);
}

// -------------------------------------------------------------- markdown

// The text from `heading` to the next heading.
std::string section(const std::string& md, const std::string& heading) {
    const size_t start = md.find(heading + "\n");
    EXPECT_NE(start, std::string::npos) << "no section " << heading << " in\n" << md;
    if (start == std::string::npos) return "";
    const size_t end = md.find("\n#", start + heading.size());
    return md.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

TEST(BenchReportMarkdown, CheapestSettingPerTargetAndNeverReaches) {
    TempDir dir;
    const BenchRun run = synthetic_run();
    const std::string path = dir.file("report.md");
    const Status s = write_report_md(run, path);
    ASSERT_TRUE(s.ok()) << s.error().message;
    const std::string md = read_text(path);

    for (const char* part : {"2026-11-25T10:00:00Z", "`parallax bench --scenes bricks,pit --angles 0,75 -o out/bench`",
                             "llvmpipe (LLVM 15.0.6, 256 bits)", "OpenGL ES 3.0 Mesa 22.3.6", "**llvmpipe threads:** 2",
                             "512×384", "**Frames:** 9", "mobile GPU"})
        EXPECT_TRUE(contains(md, part));

    const std::string bricks75 = section(md, "### bricks at 75°");
    EXPECT_TRUE(contains(bricks75, "| ≤ 1 texel | pom, 8 samples | 0.9 | 1.50× | 15 |"));
    EXPECT_TRUE(contains(bricks75, "| ≤ 0.5 texel | pom, 16 samples | 0.4 | 2.00× | 20 |"));
    EXPECT_TRUE(contains(bricks75, "| ≤ 0.25 texel | relief, 16 samples | 0.22 | 2.40× | 24 |"));
    EXPECT_TRUE(contains(bricks75, "offset_limited never reaches 1 texel at 75° on bricks (best: 2.3 texels)"));
    EXPECT_TRUE(contains(bricks75, "normal never reaches 1 texel at 75° on bricks (best: 3.1 texels)"));
    // One line per technique: the loosest target it misses implies the tighter ones.
    EXPECT_EQ(count(bricks75, "never reaches"), 2u) << bricks75;
    EXPECT_EQ(count(bricks75, "pom never"), 0u);

    const std::string bricks0 = section(md, "### bricks at 0°");
    EXPECT_TRUE(contains(bricks0, "| ≤ 1 texel | flat | 0.3 | 0.90× |"));
    EXPECT_TRUE(contains(bricks0, "| ≤ 0.5 texel | flat | 0.3 | 0.90× |"));
    EXPECT_TRUE(contains(bricks0, "| ≤ 0.25 texel | normal | 0.05 | 1.00× |"));
    EXPECT_TRUE(contains(bricks0, "flat never reaches 0.25 texel at 0° on bricks (best: 0.3 texels)"));
    EXPECT_EQ(count(bricks0, "never reaches"), 1u) << bricks0;
    EXPECT_LT(md.find("### bricks at 0°"), md.find("### bricks at 75°")) << "angles ascending";

    const std::string pit75 = section(md, "### pit \"deep\", v2 at 75°");
    EXPECT_TRUE(contains(pit75, "| ≤ 1 texel | pom, 16 samples | 0.8 | 2.10× |"));
    EXPECT_TRUE(contains(pit75, "| ≤ 0.5 texel | relief, 16 samples | 0.45 | 2.50× |"));
    EXPECT_TRUE(contains(pit75, "| ≤ 0.25 texel | maxmip | 0.01 | 2.90× |"));
    EXPECT_TRUE(contains(pit75, "steep never reaches 1 texel at 75° on pit \"deep\", v2 (best: 1.2 texels)"));

    // Full table: every row once, with its median [min–max].
    const std::string all = section(md, "## All settings");
    EXPECT_EQ(count(all, "\n| bricks |"), 12u);
    EXPECT_EQ(count(all, "\n| pit \"deep\", v2 |"), 5u);
    EXPECT_TRUE(contains(
        all, "| bricks | 75° | pom | 16 | 0.4 | 0.8 | 1.6 | 2.0 % | 0.01 / 0.2 | 0.05 | 35.0 | 20 [19–22] | 2.00× |"));
    EXPECT_TRUE(
        contains(all, "| pit \"deep\", v2 | 75° | steep | 8 | 1.2 | 2.4 | 4.8 | 40.0 % | 0.01 / n/a | 0.05 | ∞ |"));
    EXPECT_LT(all.find("| bricks | 75° | pom | 16 |"), all.find("| bricks | 75° | pom | 32 |"));
}

TEST(BenchReportMarkdown, TieOnRatioGoesToTheFasterMedian) {
    TempDir dir;
    BenchRun run = synthetic_run();
    run.rows = {row("s", 60, "pom", 8, 0.4, 2.0), row("s", 60, "relief", 8, 0.3, 2.0)};
    run.rows[0].frame_ms_median = 30;
    run.rows[1].frame_ms_median = 25;
    const std::string path = dir.file("report.md");
    ASSERT_TRUE(write_report_md(run, path).ok());
    const std::string md = read_text(path);
    EXPECT_TRUE(contains(md, "| ≤ 0.5 texel | relief, 8 samples |"));
    EXPECT_TRUE(contains(md, "| ≤ 0.25 texel | not reached (best: relief, 8 samples, 0.3 texels) |"));
}

TEST(BenchReportMarkdown, ErrorExactlyAtTheTargetReachesIt) {
    TempDir dir;
    BenchRun run = synthetic_run();
    run.rows = {row("s", 30, "pom", 8, 0.5, 2.0), row("s", 30, "relief", 8, 0.25, 2.2)};
    const std::string path = dir.file("report.md");
    ASSERT_TRUE(write_report_md(run, path).ok());
    const std::string md = read_text(path);
    EXPECT_TRUE(contains(md, "| ≤ 0.5 texel | pom, 8 samples |"));
    EXPECT_TRUE(contains(md, "| ≤ 0.25 texel | relief, 8 samples |"));
    EXPECT_TRUE(contains(md, "pom never reaches 0.25 texel at 30° on s (best: 0.5 texels)"));
    EXPECT_EQ(count(md, "never reaches"), 1u);
}

// ------------------------------------------------------------------- SVG

// Tags balance and nest, attributes are quoted, '&' only starts an entity.
::testing::AssertionResult well_formed(const std::string& svg) {
    std::vector<std::string> open;
    size_t i = 0;
    while (i < svg.size()) {
        if (svg[i] == '&') {
            const size_t semi = svg.find(';', i);
            const std::string entity = svg.substr(i, semi == std::string::npos ? 8 : semi - i + 1);
            if (entity != "&amp;" && entity != "&lt;" && entity != "&gt;" && entity != "&quot;" && entity != "&apos;")
                return ::testing::AssertionFailure() << "bad entity '" << entity << "' at " << i;
            ++i;
            continue;
        }
        if (svg[i] != '<') {
            ++i;
            continue;
        }
        size_t end = i + 1;
        bool in_quotes = false;
        while (end < svg.size() && (in_quotes || svg[end] != '>')) {
            if (svg[end] == '"') in_quotes = !in_quotes;
            if (svg[end] == '<' && !in_quotes) return ::testing::AssertionFailure() << "'<' inside a tag at " << end;
            ++end;
        }
        if (end >= svg.size()) return ::testing::AssertionFailure() << "unterminated tag at " << i;
        const std::string tag = svg.substr(i + 1, end - i - 1);
        const bool closing = !tag.empty() && tag[0] == '/';
        const bool self_closing = !tag.empty() && tag.back() == '/';
        const std::string name =
            tag.substr(closing ? 1 : 0, tag.find_first_of(" /\n", closing ? 1 : 0) - (closing ? 1 : 0));
        if (closing) {
            if (open.empty() || open.back() != name)
                return ::testing::AssertionFailure()
                       << "</" << name << "> closes <" << (open.empty() ? "" : open.back()) << "> at " << i;
            open.pop_back();
            if (open.empty() && svg.find('<', end) != std::string::npos)
                return ::testing::AssertionFailure() << "content after the root element";
        } else if (!self_closing) {
            open.push_back(name);
        }
        i = end + 1;
    }
    if (!open.empty()) return ::testing::AssertionFailure() << "<" << open.back() << "> never closed";
    return ::testing::AssertionSuccess();
}

// The <title>s of the points on the frontier.
std::vector<std::string> frontier_points(const std::string& svg) {
    std::vector<std::string> out;
    const std::string start = "<g class=\"point on-frontier\"><title>";
    for (size_t at = svg.find(start); at != std::string::npos; at = svg.find(start, at + 1)) {
        const size_t begin = at + start.size();
        out.push_back(svg.substr(begin, svg.find("</title>", begin) - begin));
    }
    return out;
}

TEST(BenchReportSvg, PanelsLegendFrontier) {
    TempDir dir;
    const BenchRun run = synthetic_run();
    const std::string path = dir.file("pareto.svg");
    const Status s = write_pareto_svg(run, path);
    ASSERT_TRUE(s.ok()) << s.error().message;
    const std::string svg = read_text(path);

    EXPECT_EQ(svg.rfind("<svg", 0), 0u);
    EXPECT_TRUE(contains(svg, "xmlns=\"http://www.w3.org/2000/svg\""));
    EXPECT_TRUE(well_formed(svg));
    EXPECT_EQ(count(svg, "<script"), 0u);
    EXPECT_EQ(count(svg, "@font-face"), 0u);
    EXPECT_EQ(count(svg, "href"), 0u);

    // Title with renderer, date and size.
    EXPECT_TRUE(contains(svg, "llvmpipe (LLVM 15.0.6, 256 bits), 2026-11-25T10:00:00Z, 512×384"));
    // Angles 0 and 75 only: two panels.
    EXPECT_EQ(count(svg, "class=\"panel-title\""), 2u);
    EXPECT_TRUE(contains(svg, "class=\"panel-title\">0-30°</text>"));
    EXPECT_TRUE(contains(svg, "class=\"panel-title\">75-89°</text>"));
    EXPECT_EQ(count(svg, "45-60°"), 0u);

    // A legend entry per technique, none twice.
    // The techniques in the rows, in the technique table's order, then the baseline.
    std::vector<std::string> techniques;
    for (const TechniqueInfo& info : technique_table())
        if (std::any_of(run.rows.begin(), run.rows.end(), [&](const BenchRow& r) { return r.technique == info.name; }))
            techniques.push_back(info.name);
    techniques.push_back(kDisplacedMesh);
    std::vector<std::string> entries;
    const std::string entry = "<g class=\"legend-entry\">";
    for (size_t at = svg.find(entry); at != std::string::npos; at = svg.find(entry, at + 1))
        entries.push_back(svg.substr(at, svg.find("</g>", at) - at));
    ASSERT_EQ(entries.size(), techniques.size());
    for (size_t i = 0; i < techniques.size(); ++i) EXPECT_TRUE(contains(entries[i], ">" + techniques[i] + "</text>"));
    // Two scenes: a line style each in the legend.
    EXPECT_TRUE(contains(svg, ">pit &quot;deep&quot;, v2</text>"));

    // One frontier per panel, as a step line.
    EXPECT_EQ(count(svg, "<path class=\"frontier\" d=\"M"), 2u);
    EXPECT_TRUE(contains(svg, " H"));
    // 75°: normal, offset_limited, steep 8, pom 8, relief 8, pom 16, relief 16,
    // maxmip on bricks (pit's maxmip ties its clamped error at a higher cost);
    // 0°: flat, normal, pom 8.
    const std::vector<std::string> frontier = frontier_points(svg);
    EXPECT_EQ(frontier.size(), 11u);
    auto on_frontier = [&](const std::string& prefix) {
        return std::any_of(frontier.begin(), frontier.end(),
                           [&](const std::string& f) { return f.rfind(prefix, 0) == 0; });
    };
    for (const char* p : {"normal — bricks at 75°", "offset_limited — bricks at 75°", "steep, 8 samples — pit",
                          "pom, 8 samples — bricks at 75°", "relief, 8 samples — bricks", "pom, 16 samples — bricks",
                          "relief, 16 samples — bricks", "maxmip — bricks at 75°", "flat — bricks at 0°",
                          "normal — bricks at 0°", "pom, 8 samples — bricks at 0°"})
        EXPECT_TRUE(on_frontier(p)) << p;
    for (const char* p : {"displaced_mesh", "pom, 32 samples", "maxmip — pit", "pom, 16 samples — pit"})
        EXPECT_FALSE(on_frontier(p)) << p;

    // Guides, log axes, the clamp footnote, sample labels.
    EXPECT_EQ(count(svg, "class=\"guide\""), 8u);
    EXPECT_TRUE(contains(svg, ">1 texel</text>"));
    EXPECT_TRUE(contains(svg, ">0.01</text>"));
    EXPECT_TRUE(contains(svg, ">1×</text>"));
    EXPECT_TRUE(contains(svg, "below 0.01 texel is drawn at 0.01 (2 points)"));
    EXPECT_GE(count(svg, "class=\"point-label\""), 4u);
    // Series: bricks pom at 75° joins 8, 16 and 32 in that order.
    EXPECT_GE(count(svg, "<polyline"), 3u);
}

TEST(BenchReportSvg, AnglesGoToTheirClass) {
    TempDir dir;
    BenchRun run = synthetic_run();
    run.rows = {row("a", 15, "pom", 8, 0.5, 2.0),
                row("a", 35, "pom", 8, 0.5, 2.0),
                row("a", 40, "pom", 8, 0.5, 2.0),
                row("a", 60, "pom", 8, 0.5, 2.0),
                row("a", 80, "pom", 8, 0.5, 2.0),
                row("a", 89, "pom", 16, 0.3, 3.0),
                row("a", 80, "a_technique_outside_the_catalogue", 0, 0.3, 4.0)};
    const std::string path = dir.file("pareto.svg");
    ASSERT_TRUE(write_pareto_svg(run, path).ok());
    const std::string svg = read_text(path);
    EXPECT_TRUE(well_formed(svg));
    EXPECT_EQ(count(svg, "class=\"panel-title\""), 3u);
    EXPECT_TRUE(contains(svg, ">view 15°, 35°</text>"));
    EXPECT_TRUE(contains(svg, ">view 40°, 60°</text>"));
    EXPECT_TRUE(contains(svg, ">view 80°, 89°</text>"));
    // Names outside the catalogue get a colour and an entry too (cut to fit).
    EXPECT_EQ(count(svg, "<g class=\"legend-entry\">"), 2u);
    EXPECT_TRUE(contains(svg, ">a_technique_outsid"));
    EXPECT_EQ(count(svg, "scene (line style)"), 0u) << "one scene needs no line-style legend";
}

TEST(BenchReportSvg, UnplottableRowsAreCountedNotDrawn) {
    TempDir dir;
    BenchRun run = synthetic_run();
    run.rows = {row("a", 75, "pom", 8, 0.5, 2.0), row("a", 75, "pom", 16, kNaN, 2.5),
                row("a", 75, "relief", 8, 0.4, 0.0)};
    const std::string path = dir.file("pareto.svg");
    ASSERT_TRUE(write_pareto_svg(run, path).ok());
    const std::string svg = read_text(path);
    EXPECT_TRUE(well_formed(svg));
    EXPECT_EQ(count(svg, "<g class=\"point"), 1u);
    EXPECT_TRUE(contains(svg, "2 rows without"));
}

// ---------------------------------------------------------- edge cases

TEST(BenchReport, EmptyRunWritesEveryFile) {
    TempDir dir;
    BenchRun run;
    ASSERT_TRUE(write_csv(run, dir.file("e.csv")).ok());
    ASSERT_TRUE(write_json(run, dir.file("e.json")).ok());
    ASSERT_TRUE(write_pareto_svg(run, dir.file("e.svg")).ok());
    ASSERT_TRUE(write_report_md(run, dir.file("e.md")).ok());
    EXPECT_EQ(parse_csv(read_text(dir.file("e.csv"))).size(), 1u);
    EXPECT_TRUE(nlohmann::json::parse(read_text(dir.file("e.json"))).at("rows").empty());
    const std::string svg = read_text(dir.file("e.svg"));
    EXPECT_TRUE(well_formed(svg));
    EXPECT_EQ(count(svg, "class=\"panel-title\""), 0u);
    EXPECT_TRUE(contains(read_text(dir.file("e.md")), "No rows."));
}

using Writer = Status (*)(const BenchRun&, const std::string&);
const std::vector<std::pair<const char*, Writer>> kWriters = {
    {"csv", write_csv}, {"json", write_json}, {"svg", write_pareto_svg}, {"md", write_report_md}};

TEST(BenchReport, UnwritablePathNamesItAndTheReason) {
    const BenchRun run = synthetic_run();
    for (const auto& [ext, writer] : kWriters) {
        const std::string path = std::string("/nonexistent/dir/x.") + ext;
        const Status s = writer(run, path);
        ASSERT_FALSE(s.ok()) << path;
        EXPECT_TRUE(contains(s.error().message, path));
        EXPECT_TRUE(contains(s.error().message, std::strerror(ENOENT)));
    }
}

TEST(BenchReport, FailedRenameLeavesNothingBehind) {
    TempDir dir;
    const BenchRun run = synthetic_run();
    for (const auto& [ext, writer] : kWriters) {
        // A non-empty directory where the file should go: rename cannot replace it.
        const std::string path = dir.file(std::string("taken.") + ext);
        fs::create_directories(fs::path(path) / "child");
        const Status s = writer(run, path);
        ASSERT_FALSE(s.ok()) << path;
        EXPECT_TRUE(contains(s.error().message, path));
        EXPECT_FALSE(fs::exists(path + ".tmp")) << "temporary file left behind";
        EXPECT_TRUE(fs::is_directory(path));
    }
}

TEST(BenchReport, ReplacesAnExistingFileAndRemovesTheTemporary) {
    TempDir dir;
    const BenchRun run = synthetic_run();
    for (const auto& [ext, writer] : kWriters) {
        const std::string path = dir.file(std::string("out.") + ext);
        std::ofstream(path) << "old contents that are longer than nothing";
        ASSERT_TRUE(writer(run, path).ok()) << path;
        EXPECT_EQ(read_text(path).find("old contents"), std::string::npos);
        EXPECT_FALSE(fs::exists(path + ".tmp"));
    }
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 4);
}

}  // namespace
}  // namespace px::profiling

// The reports' small chart (include/parallaxes/profiling/reports/svg_plot.h): the same bytes for the
// same input, points that cannot be drawn left out (not drawn at NaN), text
// escaped, and the scatter's line of equality and factor band.
#include "parallaxes/profiling/reports/svg_plot.h"

namespace {

std::size_t count_of(const std::string& text, const std::string& part) {
    std::size_t n = 0;
    for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
    return n;
}

}  // namespace

TEST(SvgPlot, PointsAxesAndEscaping) {
    using px::profiling::PlotOptions;
    using px::profiling::PlotSeries;
    PlotSeries s{"model <cycles> & time", "#1f77b4", {1, 2, 3, 4}, {1.0, 0.8, std::nan(""), 0.5}, {"a", "b", "c", "d"}, true};
    PlotOptions o;
    o.title = "ladder";
    o.x_categories = {"1", "2", "3", "4"};
    const std::string svg = px::profiling::svg_plot({s}, o);
    EXPECT_EQ(svg, px::profiling::svg_plot({s}, o));
    EXPECT_EQ(svg.rfind("<svg ", 0), 0u);
    EXPECT_NE(svg.find("</svg>\n"), std::string::npos);
    EXPECT_EQ(count_of(svg, "r=\"4\""), 3u + 1u);  // three drawable points and the legend's mark
    EXPECT_EQ(svg.find("nan"), std::string::npos);
    EXPECT_NE(svg.find("model &lt;cycles&gt; &amp; time"), std::string::npos);
    EXPECT_EQ(count_of(svg, "<path "), 1u);

    // A log-log scatter: a point at 0 cannot be drawn; y = x and the factor-2 band are.
    PlotSeries points{"variants", "#2ca02c", {0.0, 1.5, 3.0}, {1.0, 2.0, 9.0}, {}, false};
    PlotOptions scatter;
    scatter.log_x = scatter.log_y = true;
    scatter.equality = true;
    scatter.band = 2.0;
    const std::string plot = px::profiling::svg_plot({points}, scatter);
    EXPECT_EQ(count_of(plot, "r=\"4\""), 2u + 1u);
    EXPECT_EQ(count_of(plot, "stroke-dasharray=\"5 4\""), 2u);
    EXPECT_NE(plot.find("dashed: a factor of 2"), std::string::npos);
}

namespace px::profiling {
namespace {

// The exact walk's work, where a row counted it: one line per counted row,
// percentiles and the histogram as shares of its pixels; no section at all
// where nothing was counted.
TEST(BenchReportMarkdown, WorkSectionListsCountedRowsOnly) {
    TempDir dir;
    BenchRun run = synthetic_run();
    const std::string plain = dir.file("plain.md");
    ASSERT_TRUE(write_report_md(run, plain).ok());
    EXPECT_FALSE(contains(read_text(plain), "## Work per pixel"));
    BenchRow& counted = run.rows[0];
    counted.iterations_median = 3;
    counted.iterations_p90 = 9;
    counted.iterations_p99 = 40;
    counted.iterations_max = 130;
    counted.fetches_median = 12;
    counted.iteration_histogram = {1, 2, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    const std::string path = dir.file("report.md");
    ASSERT_TRUE(write_report_md(run, path).ok());
    const std::string work = section(read_text(path), "## Work per pixel of the exact walk");
    EXPECT_TRUE(contains(work, " | 3 / 9 / 40 / 130 | 12 | 25% 50% 25% |")) << work;
    EXPECT_EQ(count(work, "\n| " + counted.scene + " |"), 1u) << work;
    const std::string json = dir.file("bench.json");
    ASSERT_TRUE(write_json(run, json).ok());
    const nlohmann::json doc = nlohmann::json::parse(read_text(json));
    EXPECT_EQ(doc.at("rows")[0].at("iteration_histogram").size(), 13u);
    EXPECT_EQ(doc.at("rows")[0].at("iterations_p99").get<double>(), 40.0);
}

// bench --gpu: a section only when the run has GPU figures; per pixel is the
// compiler's cycles where it kept no loop, times the counted iterations
// where it kept one, "–" where a kept loop's iterations are not counted;
// the ratio is to normal mapping's at the same scene and angle.
TEST(BenchReportMarkdown, GpuSectionPutsTheCompilersCostBesideTheError) {
    TempDir dir;
    BenchRun run = synthetic_run();
    const std::string plain = dir.file("plain.md");
    ASSERT_TRUE(write_report_md(run, plain).ok());
    EXPECT_FALSE(contains(read_text(plain), "## On a real GPU compiler"));
    run.gpu = "Mali-G57 (Valhall): Panfrost of Mali-G57 (Panfrost) | OpenGL ES 3.1 Mesa 22.3.6";
    BenchRow& normal = run.rows[0];   // bricks 75 normal
    BenchRow& pom32 = run.rows[3];    // bricks 75 pom 32
    BenchRow& maxmip = run.rows[7];   // bricks 75 maxmip
    BenchRow& relief = run.rows[6];   // bricks 75 relief 16: a kept loop, not counted
    normal.gpu_cycles = normal.gpu_cycles_per_pixel = 2.5;
    normal.gpu_loops = 0;
    pom32.gpu_cycles = pom32.gpu_cycles_per_pixel = 10;
    pom32.gpu_loops = 0;
    maxmip.gpu_cycles = 40;
    maxmip.gpu_loops = 1;
    maxmip.gpu_cycles_per_pixel = 40 * 6;
    relief.gpu_cycles = 3.5;
    relief.gpu_loops = 1;
    const std::string path = dir.file("report.md");
    ASSERT_TRUE(write_report_md(run, path).ok());
    const std::string gpu = section(read_text(path), "## On a real GPU compiler");
    EXPECT_TRUE(contains(gpu, "Mali-G57 (Valhall)")) << gpu;
    EXPECT_TRUE(contains(gpu, "| bricks | 75° | pom | 32 | 0.4 | 10 | 0 | 10 | 4 | 3.00× |")) << gpu;
    EXPECT_TRUE(contains(gpu, "| bricks | 75° | maxmip | 0 | 0.008 | 40 | 1 | 240 | 96 | 2.60× |")) << gpu;
    EXPECT_TRUE(contains(gpu, "| bricks | 75° | relief | 16 | 0.44 | 3.5 | 1 | – | – | 2.40× |")) << gpu;
    EXPECT_EQ(count(gpu, "\n| "), 6u) << gpu;  // header, rule and the four rows with figures
    const std::string json = dir.file("bench.json");
    ASSERT_TRUE(write_json(run, json).ok());
    const nlohmann::json doc = nlohmann::json::parse(read_text(json));
    EXPECT_EQ(doc.at("gpu").get<std::string>(), run.gpu);
    EXPECT_EQ(doc.at("rows")[7].at("gpu_cycles_per_pixel").get<double>(), 240.0);
    EXPECT_TRUE(doc.at("rows")[6].at("gpu_cycles_per_pixel").is_null());
    EXPECT_TRUE(doc.at("rows")[1].at("gpu_cycles").is_null());
}

// pareto_gpu.svg: the same plot with the compiler's cost on the x axis: a
// point per row with GPU cycles per pixel, at its ratio to normal mapping's;
// a row whose kept loop was not counted is left out and said to be.
TEST(BenchReportSvg, GpuParetoPlotsCyclesOverNormalMappings) {
    TempDir dir;
    BenchRun run = synthetic_run();
    EXPECT_FALSE(write_pareto_gpu_svg(run, dir.file("none.svg")).ok()) << "a run without GPU figures has nothing to plot";
    run.gpu = "Mali-G57 (Valhall): Panfrost";
    run.rows[0].gpu_cycles = run.rows[0].gpu_cycles_per_pixel = 2.5;  // bricks 75 normal
    run.rows[0].gpu_loops = 0;
    run.rows[3].gpu_cycles = run.rows[3].gpu_cycles_per_pixel = 10;   // bricks 75 pom 32
    run.rows[3].gpu_loops = 0;
    run.rows[6].gpu_cycles = 3.5;                                     // relief 16: kept loop, not counted
    run.rows[6].gpu_loops = 1;
    const std::string path = dir.file("pareto_gpu.svg");
    ASSERT_TRUE(write_pareto_gpu_svg(run, path).ok());
    const std::string svg = read_text(path);
    EXPECT_TRUE(contains(svg, "GPU cycles per pixel ÷ normal mapping")) << svg.substr(0, 2000);
    EXPECT_TRUE(contains(svg, "4.00× normal (GPU cycles)")) << "pom 32: 10 / 2.5";
    EXPECT_TRUE(contains(svg, "1.00× normal (GPU cycles)"));
    EXPECT_TRUE(contains(svg, "Mali-G57 (Valhall)"));
    EXPECT_TRUE(contains(svg, "without a finite angle, GPU cycles per pixel or error not plotted"));
    EXPECT_FALSE(contains(svg, "frame time ÷ normal mapping"));
}

// A run on a real GPU (the bench on NVIDIA's EGL, 2026-12-04) does not call
// its times llvmpipe's, nor list llvmpipe threads, nor explain its costs by
// llvmpipe's loop unrolling.
TEST(BenchReportMarkdown, HeaderNamesTheRendererTheTimesCameFrom) {
    TempDir dir;
    BenchRun run = synthetic_run();
    run.gl_renderer = "NVIDIA H200/PCIe/SSE2";
    run.gl_version = "OpenGL ES 3.2 NVIDIA 580.159.04";
    const std::string path = dir.file("report.md");
    ASSERT_TRUE(write_report_md(run, path).ok());
    const std::string md = read_text(path);
    EXPECT_TRUE(contains(md, "Frame times come from the renderer above")) << md.substr(0, 800);
    for (const char* part : {"llvmpipe threads", "Frame times come from llvmpipe", "llvmpipe unrolls"})
        EXPECT_FALSE(contains(md, part)) << part;
}



}  // namespace
}  // namespace px::profiling
