#include "profile_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "parallaxes/core/files.h"
#include "parallaxes/core/text.h"
#include "parallaxes/profiling/costs/model_calibration.h"
#include "parallaxes/profiling/costs/shader_profile.h"
#include "parallaxes/profiling/reports/svg_plot.h"
#include "parallaxes/profiling/costs/vendor_compilers.h"

namespace px::tools {

namespace {

constexpr std::size_t kMaxSetBytes = 16u << 20;
constexpr std::size_t kMaxShaderBytes = 4u << 20;
constexpr std::size_t kMaxSetShaders = 10000;

std::string significant_text4(double v) { return significant_text(v, 4); }

std::string signed_percent(double share) {
    const double rounded = std::round(100.0 * share);
    return (rounded > 0 ? "+" : "") + fixed_text(rounded == 0.0 ? 0.0 : rounded, 0) + " %";
}

Result<profiling::CostModel> load_model(const std::string& file) {
    if (file.empty()) return profiling::base_cost_model();
    Result<std::vector<std::uint8_t>> bytes = read_file_bounded(file, 1u << 20, "cost model");
    if (!bytes) return bytes.error();
    return profiling::parse_cost_model(std::string(bytes->begin(), bytes->end()), file);
}

Result<profiling::CalibrationSet> load_set(const std::string& file) {
    if (file.empty()) return profiling::default_calibration_set();
    Result<std::vector<std::uint8_t>> bytes = read_file_bounded(file, kMaxSetBytes, "calibration set");
    if (!bytes) return bytes.error();
    return profiling::parse_calibration_set(std::string(bytes->begin(), bytes->end()), file);
}

std::string weights_text(const profiling::CalibrationFit& fit) {
    return "A " + significant_text4(fit.fp32_op) + " per fp32 scalar operation, " + significant_text4(fit.transcendental) +
           " per transcendental, " + significant_text4(fit.branch) + " per branch, " + significant_text4(fit.fixed) +
           " per invocation; T " + significant_text4(fit.sample) + " per texture sample; V " + significant_text4(fit.varying_component) +
           " per varying component";
}

std::string summary_line(const char* half, const profiling::CalibrationSummary& s) {
    return std::string(half) + " (" + std::to_string(s.shaders) + " shaders): Spearman " + fixed_text(s.spearman, 3) +
           " (the hand-chosen rates: " + fixed_text(s.spearman_uncalibrated, 3) + "), median |error| " +
           fixed_text(100.0 * s.median_abs_error, 1) + " %, worst " + fixed_text(100.0 * s.worst_abs_error, 0) + " %";
}

bool goal_met(const profiling::CalibrationSummary& held) { return held.spearman >= 0.9 && held.median_abs_error <= 0.30; }

std::string fit_table(const profiling::CalibrationFit& fit, profiling::ReportFormat format) {
    std::vector<std::vector<std::string>> rows;
    for (const profiling::CalibrationRow& r : fit.rows)
        rows.push_back({r.name, r.held_out ? "held out" : "fit", fixed_text(r.real, 2) + " " + r.real_pipe,
                        fixed_text(r.predicted, 2) + " " + r.predicted_pipe, signed_percent(r.error())});
    return profiling::render_table({"shader", "half", "compiler: bound cycles", "model: bound cycles", "error"}, rows, format);
}

std::string fit_json(const profiling::CalibrationSet& set, const profiling::CalibrationFit& fit, const std::string& command) {
    nlohmann::json rows = nlohmann::json::array();
    for (const profiling::CalibrationRow& r : fit.rows)
        rows.push_back({{"shader", r.name},           {"held_out", r.held_out},           {"real", r.real},
                        {"real_pipe", r.real_pipe},   {"predicted", r.predicted},         {"predicted_pipe", r.predicted_pipe},
                        {"error", r.error()},         {"uncalibrated", r.uncalibrated}});
    auto summary = [](const profiling::CalibrationSummary& s) {
        return nlohmann::json{{"shaders", s.shaders},
                              {"spearman", s.spearman},
                              {"median_abs_error", s.median_abs_error},
                              {"worst_abs_error", s.worst_abs_error},
                              {"spearman_uncalibrated", s.spearman_uncalibrated}};
    };
    return nlohmann::json{{"command", command},
                          {"gpu", set.gpu},
                          {"compiler", set.compiler},
                          {"source", set.source},
                          {"weights",
                           {{"fp32_op", fit.fp32_op},
                            {"transcendental", fit.transcendental},
                            {"branch", fit.branch},
                            {"fixed", fit.fixed},
                            {"sample", fit.sample},
                            {"varying_component", fit.varying_component}}},
                          {"fitted", summary(fit.fitted)},
                          {"held_out", summary(fit.held_out)},
                          {"leave_one_out", [&] {
                               nlohmann::json j = summary(fit.leave_one_out);
                               j.erase("spearman_uncalibrated");
                               return j;
                           }()},
                          {"goal_met", goal_met(fit.held_out)},
                          {"notes", fit.notes},
                          {"shaders", rows}}
               .dump(2) +
           "\n";
}

// The report: what was fitted to what, the weights, every shader, the two
// halves' figures and the goal.
std::string fit_report(const profiling::CalibrationSet& set, const profiling::CalibrationFit& fit,
                       profiling::ReportFormat format) {
    const bool md = format == profiling::ReportFormat::markdown;
    const std::string bullet = md ? "- " : "";
    std::string s = bullet + "Compiler: " + set.compiler + " on " + set.gpu + "\n" + bullet + "Shaders: " + set.source + "\n" +
                    bullet + "Fitted weights (cycles per thread): " + weights_text(fit) + "\n";
    for (const std::string& note : fit.notes) s += bullet + "Note: " + note + "\n";
    s += "\n" + fit_table(fit, format) + "\n";
    s += bullet + summary_line("Held out", fit.held_out) + "\n";
    s += bullet + summary_line("Fitted", fit.fitted) + "\n";
    s += bullet + "Leave-one-out (each of the " + std::to_string(fit.leave_one_out.shaders) +
         " predicted by weights fitted on the others): Spearman " + fixed_text(fit.leave_one_out.spearman, 3) +
         ", median |error| " + fixed_text(100.0 * fit.leave_one_out.median_abs_error, 1) + " %, worst " +
         fixed_text(100.0 * fit.leave_one_out.worst_abs_error, 0) + " %\n";
    s += bullet + "Goal on the held-out half (Spearman >= 0.9, median |error| <= 30 %): " +
         (goal_met(fit.held_out) ? "met" : "NOT met") + "\n";
    return s;
}

std::string fit_svg(const profiling::CalibrationSet& set, const profiling::CalibrationFit& fit) {
    profiling::PlotSeries fitted{"fitting half", "#1f77b4", {}, {}, {}, false};
    profiling::PlotSeries held{"held-out half", "#d62728", {}, {}, {}, false};
    for (const profiling::CalibrationRow& r : fit.rows) {
        profiling::PlotSeries& s = r.held_out ? held : fitted;
        s.x.push_back(r.real);
        s.y.push_back(r.predicted);
        // Only the misses are named: most points sit on top of each other.
        s.labels.push_back(std::abs(r.error()) >= 0.15 ? r.name.substr(0, r.name.rfind('.')) : std::string());
    }
    profiling::PlotOptions o;
    o.title = "The cost model against " + set.compiler + ", " + set.gpu;
    o.subtitle = "bound-pipe cycles per thread, one point per shader (misses of 15 % or more named); fitted on the blue half";
    o.x_label = "compiler: bound-pipe cycles";
    o.y_label = "model: bound-pipe cycles";
    o.log_x = o.log_y = true;
    o.equality = true;
    o.band = 1.3;
    o.width = 900;
    o.height = 560;
    return profiling::svg_plot({fitted, held}, o);
}

// The files of `dir` (sorted) whose names end in .frag or .vert.
Result<std::vector<std::filesystem::path>> shader_files(const std::string& dir) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) return make_error("--shaders: '" + dir + "' is not a folder");
    std::vector<std::filesystem::path> files;
    for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string ext = it->path().extension().string();
        if ((ext == ".frag" || ext == ".vert") && it->is_regular_file(ec)) files.push_back(it->path());
        if (files.size() > kMaxSetShaders) return make_error("--shaders: more than 10000 shaders in '" + dir + "'");
    }
    if (ec) return make_error("--shaders: cannot list '" + dir + "': " + ec.message());
    std::sort(files.begin(), files.end());
    return files;
}

// The report for fragment shader `name` in `dir`: NAME.txt or NAME.json,
// directly or in a frag/ sub-folder (the layout malioc report collections use).
std::string find_report(const std::string& dir, const std::string& name) {
    for (const char* sub : {"", "frag/"})
        for (const char* ext : {".txt", ".json"}) {
            const std::string path = dir + "/" + sub + name + ext;
            std::error_code ec;
            if (std::filesystem::is_regular_file(path, ec)) return path;
        }
    return {};
}

std::string read_text(const std::string& path, std::size_t limit, const char* what, std::string& error) {
    Result<std::vector<std::uint8_t>> bytes = read_file_bounded(path, limit, what);
    if (!bytes) {
        error = bytes.error().message;
        return {};
    }
    return std::string(bytes->begin(), bytes->end());
}

// Every calibration set beside the carried one (profiling/costs/calibration/,
// from the repository the doc is written in), fitted the same way: one row
// per GPU, the fit's held-out figures or why it cannot be made.
std::string other_classes_table(const std::string& doc_path) {
    const std::filesystem::path root = std::filesystem::path(doc_path).parent_path().parent_path();
    const std::filesystem::path folder = root / std::filesystem::path(profiling::default_calibration_set_path()).parent_path();
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
        if (it->path().extension() == ".json") files.push_back(it->path());
    std::sort(files.begin(), files.end());
    std::vector<std::vector<std::string>> rows;
    for (const std::filesystem::path& file : files) {
        Result<profiling::CalibrationSet> set = load_set(file.string());
        if (!set) continue;
        Result<profiling::CalibrationFit> fit = profiling::fit_cost_model(*set, profiling::base_cost_model());
        const std::string name = "`" + file.filename().string() + "`";
        if (!fit) {
            rows.push_back({set->gpu, name, "-", "-", "-", "-", "cannot be fitted: " + fit.error().message});
            continue;
        }
        rows.push_back({set->gpu, name, fixed_text(fit->held_out.spearman, 3), fixed_text(100.0 * fit->held_out.median_abs_error, 1) + " %",
                        fixed_text(fit->held_out.spearman_uncalibrated, 3), fixed_text(fit->leave_one_out.spearman, 3),
                        goal_met(fit->held_out) ? "met" : "not met"});
    }
    if (rows.empty()) return "";
    return profiling::render_table({"GPU", "set", "held-out Spearman", "held-out median error", "hand-chosen rates' Spearman",
                                    "leave-one-out Spearman", "goal"},
                                   rows, profiling::ReportFormat::markdown);
}

}  // namespace

Result<profiling::CostModel> model_fitted_to(const std::string& set_file, const std::string& base_file) {
    Result<profiling::CostModel> base = load_model(base_file);
    if (!base) return base.error();
    Result<profiling::CalibrationSet> set = load_set(set_file);
    if (!set) return set.error();
    Result<profiling::CalibrationFit> fit = profiling::fit_cost_model(*set, *base, false);
    if (!fit) return make_error(set_file + ": " + fit.error().message);
    return profiling::calibrated_model(*base, *fit, *set, set_file);
}

int run_calibrate(const CalibrationArgs& a) {
    Result<profiling::ReportFormat> format = profiling::parse_report_format(a.format);
    if (!format) return fail("--format: " + format.error().message);
    if (!a.model_out.empty())
        if (const std::string unwritable = check_output_file(a.model_out); !unwritable.empty())
            return fail("--model-out: " + unwritable);
    Result<profiling::CostModel> base = load_model(a.model_file);
    if (!base) return fail(base.error().message);
    Result<profiling::CalibrationSet> set = load_set(a.set_file);
    if (!set) return fail(set.error().message);
    Result<profiling::CalibrationFit> fit = profiling::fit_cost_model(*set, *base);
    if (!fit) return fail((a.set_file.empty() ? std::string(profiling::default_calibration_set_path()) : a.set_file) + ": " +
                          fit.error().message);
    if (*format == profiling::ReportFormat::json) std::fputs(fit_json(*set, *fit, a.command).c_str(), stdout);
    else std::fputs(fit_report(*set, *fit, *format).c_str(), stdout);
    if (!a.model_out.empty()) {
        const std::string path = a.set_file.empty() ? std::string(profiling::default_calibration_set_path()) : a.set_file;
        Result<profiling::CostModel> model = profiling::calibrated_model(*base, *fit, *set, path);
        if (!model) return fail(model.error().message);
        Status w = write_file_atomically(a.model_out, profiling::cost_model_json(*model));
        if (!w) return fail(w.error().message);
        std::fprintf(stderr, "wrote %s\n", a.model_out.c_str());
    }
    return 0;
}

int run_make_calibration_set(const CalibrationArgs& a) {
    if (a.shaders.empty() || a.reports.empty())
        return fail("--make-calibration-set needs --shaders DIR (the sources) and --reports DIR (the compiler's reports of them)");
    if (const std::string unwritable = check_output_file(a.make_set); !unwritable.empty())
        return fail("--make-calibration-set: " + unwritable);
    Result<std::vector<std::filesystem::path>> files = shader_files(a.shaders);
    if (!files) return fail(files.error().message);
    profiling::CalibrationSet set;
    set.source = a.source.empty() ? a.shaders : a.source;
    set.made_by = a.command;
    int skipped = 0, vertex_shaders = 0;
    for (const std::filesystem::path& file : *files) {
        const std::string name = file.filename().string();
        // The model has no load/store pipe, which bounds most vertex shaders:
        // the set is of fragment shaders.
        if (file.extension() == ".vert") {
            ++vertex_shaders;
            continue;
        }
        const std::string report_path = find_report(a.reports, name);
        if (report_path.empty()) {
            std::fprintf(stderr, "parallax: %s: no report %s{.txt,.json} in %s; left out\n", name.c_str(), name.c_str(),
                         a.reports.c_str());
            ++skipped;
            continue;
        }
        std::string error;
        const std::string source = read_text(file.string(), kMaxShaderBytes, "shader source", error);
        const std::string report = error.empty() ? read_text(report_path, kMaxShaderBytes, "compiler report", error) : "";
        if (!error.empty()) return fail(error);
        const std::string where = " (source " + file.string() + ", report " + report_path + ")";
        Result<profiling::VendorCycles> figures = profiling::parse_malioc_report(report);
        if (!figures) return fail(name + " (report): " + figures.error().message + where);
        Result<profiling::CalibrationShader> entry = profiling::calibration_entry(name, source, ShaderStage::fragment, *figures);
        if (!entry) return fail(entry.error().message + where);
        const std::string gpu = figures->target.empty() ? "an unnamed GPU (the report names none)" : figures->target;
        const std::string tool = figures->tool.empty() ? "malioc (version unknown)" : figures->tool;
        if (set.gpu.empty()) set.gpu = gpu, set.compiler = tool;
        else if (set.gpu != gpu || set.compiler != tool)
            return fail(report_path + ": " + tool + " on " + gpu + ", where the set's other reports are " + set.compiler +
                        " on " + set.gpu + ": one set is one compiler on one GPU");
        set.shaders.push_back(std::move(*entry));
    }
    if (set.shaders.empty()) return fail("no shader in " + a.shaders + " has a report in " + a.reports);
    Status w = write_file_atomically(a.make_set, profiling::calibration_set_json(set));
    if (!w) return fail(w.error().message);
    std::fprintf(stderr, "wrote %s: %zu fragment shaders (%d without a report and %d vertex shaders left out), %s on %s\n",
                 a.make_set.c_str(), set.shaders.size(), skipped, vertex_shaders, set.compiler.c_str(), set.gpu.c_str());
    return 0;
}

Status doc_calibration(std::ostringstream& doc, const std::string& doc_path) {
    const profiling::CalibrationSet& set = profiling::default_calibration_set();
    Result<profiling::CalibrationFit> fit = profiling::fit_cost_model(set, profiling::base_cost_model());
    if (!fit) return make_error(std::string(profiling::default_calibration_set_path()) + ": " + fit.error().message);
    const std::string picture = "profiling_calibration.svg";
    Status w = write_file_atomically((std::filesystem::path(doc_path).parent_path() / picture).string(), fit_svg(set, *fit));
    if (!w) return w;
    doc << "## The cost model against a real compiler\n\n"
        << "The model's weights are fitted to what Arm's Mali Offline Compiler reports for real shaders: "
        << set.shaders.size() << " fragment shaders of Flutter's Impeller renderer and " << set.compiler
        << "'s report of each on " << set.gpu << ". The set (`" << profiling::default_calibration_set_path()
        << "`, its README says where every part came from) holds this project's counts of each shader "
        << "(glslang's SPIR-V, as `parallax profile` counts its own) beside the compiler's figures; the shader "
        << "sources are not in this repository. It was made by `" << set.made_by << "` beside a checkout of the "
        << "reports' repository.\n\n"
        << "`parallax profile --calibrate` takes the shaders in name order, fits on every other one and judges the "
        << "fit on the rest. Each pipe is fitted on its own figures by non-negative least squares: arithmetic from "
        << "fp32 operations (mediump ones at the base model's ratio), transcendentals, branches and a cost per "
        << "invocation; texture from samples; varyings from interpolated components. The compared figure is the "
        << "bound pipe's cycles on the longest path (the total where the compiler cannot bound the longest). "
        << "Texture latency is not in the compiler's figures and is left out of the comparison. Every report of "
        << "`parallax profile` uses the fitted model and says so; the hand-chosen rates of "
        << "profiling/costs/cost_model.json are the base it fits (their ranking of the same shaders is given for "
        << "comparison).\n\n"
        << fit_report(set, *fit, profiling::ReportFormat::markdown) << "\n"
        << "![the model against the compiler, one point per shader](" << picture << ")\n\n"
        << "### Other GPU classes\n\n"
        << "The same shaders' reports on other Mali GPUs make sets of their own (`profiling/costs/calibration/`, "
        << "made the same way); `parallax profile --calibration-set FILE` profiles with the model fitted to one "
        << "(and names its GPU), `--calibrate --calibration-set FILE` shows that fit, `--model-out MODEL` keeps it. "
        << "Each fitted the same way:\n\n"
        << other_classes_table(doc_path) << "\n"
        << "The model's three pipes are Valhall's and Bifrost's: on the newer Valhall (Mali-G710) the fit does as "
        << "well as on the Mali-G78; on Bifrost (Mali-G76) it sizes the shaders within 20 % but ranks the held-out "
        << "half below the goal, worse than the hand-chosen rates; Midgard (Mali-T880) interpolates varyings "
        << "through its load/store pipe, which the model does not have, so no varying rate can be fitted.\n\n"
        << "What the figures do not show: half the set are Impeller's advanced blend shaders, which differ in "
        << "their blend function only, so the held-out half resembles the fitting half more than an unrelated "
        << "shader would (the leave-one-out line is the same test with every shader held out once). The set's "
        << "shaders are short and read one or two textures; this project's marches are loops of dependent reads, "
        << "whose cost the model's loop trip counts and texture latency (not calibrated) decide. mediump varyings "
        << "are charged at the 16-bit rate, a ratio the set cannot fit (every varying in it is highp). Only fragment "
        << "shaders are used: the model has no load/store pipe, which bounds most vertex shaders on this GPU. "
        << "The two largest misses, under-predictions of about 40 %, are the two shaders whose loops run a "
        << "uniform number of times (gaussian_blur, morphology_filter), where the compiler's total row is "
        << "compared with the analysis counting the loop once; why they differ was not investigated.\n\n";
    return {};
}

}  // namespace px::tools
