#include "parallaxes/profiling/costs/shader_profile.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <sstream>

#include <nlohmann/json.hpp>

namespace px::profiling {

Result<VariantProfile> profile_variant(const VariantKey& key, const CostModel& model, const ShaderFiles* files) {
    Result<VariantSources> sources = assemble_variant(key, files);
    if (!sources) return sources.error();
    VariantProfile p;
    p.key = key.canonical();
    p.name = p.key.describe();
    const TripOverrides trips = model.trip_overrides();
    Result<StageCost> vertex = stage_cost(sources->vertex, ShaderStage::vertex, trips);
    if (!vertex) return with_context(p.name + " vertex stage", vertex.error());
    Result<StageCost> fragment = stage_cost(sources->fragment, ShaderStage::fragment, trips);
    if (!fragment) return with_context(p.name + " fragment stage", fragment.error());
    p.vertex = std::move(*vertex);
    p.fragment = std::move(*fragment);
    // The shortest path waits for at most one read after another where it reads at all.
    const double shortest_trips = std::min(p.fragment.shortest.samples, p.fragment.texture_round_trips);
    p.fragment_shortest = estimate(p.fragment, p.fragment.shortest, shortest_trips, model);
    p.fragment_longest = estimate(p.fragment, p.fragment.longest, p.fragment.texture_round_trips, model);
    p.vertex_longest = estimate(p.vertex, p.vertex.longest, p.vertex.texture_round_trips, model);
    return p;
}

Result<ReportFormat> parse_report_format(const std::string& name) {
    if (name == "table") return ReportFormat::table;
    if (name == "md" || name == "markdown") return ReportFormat::markdown;
    if (name == "json") return ReportFormat::json;
    return make_error("unknown format '" + name + "' (table, md or json)");
}

namespace {

std::string fixed(double v, int digits = 1) {
    if (!std::isfinite(v)) return "n/a";
    char b[64];
    std::snprintf(b, sizeof b, "%.*f", digits, v);
    return b;
}

std::string percent(double share) { return fixed(100.0 * share, 0) + "%"; }

// Model cycles: two decimals, as malioc prints its own (a calibrated model's
// cycles per thread are fractions).
std::string cycles(double v) { return fixed(v, 2); }

// A model parameter: four significant digits (rates range from 0.01 to 100s).
std::string parameter(double v) {
    if (!std::isfinite(v)) return "n/a";
    char b[64];
    std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}

double fp16_share(const OpCounts& c) { return c.arithmetic > 0 ? c.fp16 / c.arithmetic : 0.0; }

std::string short_file(const std::string& where) {
    const std::size_t slash = where.rfind('/');
    return slash == std::string::npos ? where : where.substr(slash + 1);
}

std::string loops_text(const StageCost& s) {
    std::string out;
    for (const LoopCost& l : s.loops) {
        if (!out.empty()) out += ", ";
        out += short_file(l.where) + " x" + (l.trip_count >= 0 ? std::to_string(l.trip_count) : "?");
        if (l.counted_trips != l.trip_count) out += " (counted " + std::to_string(l.counted_trips) + ")";
    }
    return out.empty() ? "-" : out;
}

std::string vendor_text(const VariantProfile& p) {
    std::string out;
    for (const VendorFigures& v : p.vendor_fragment) {
        if (!out.empty()) out += "; ";
        out += v.tool + ":";
        if (v.cycles >= 0) out += " " + fixed(v.cycles, 2) + " cycles";
        // The longest path; where the tool cannot bound it (N/A: loops it
        // cannot count), the total instruction cycles, its only bound.
        const bool unbounded = !v.longest.empty() && std::all_of(v.longest.begin(), v.longest.end(),
                                                                [](double x) { return std::isnan(x); });
        const std::vector<double>& row = unbounded && !v.total.empty() ? v.total : v.longest;
        if (unbounded) out += row.empty() ? " longest N/A" : " longest N/A, total";
        for (std::size_t i = 0; i < v.pipes.size() && i < row.size(); ++i)
            out += " " + v.pipes[i] + "=" + (std::isnan(row[i]) ? std::string("N/A") : fixed(row[i], 2));
        if (!v.bound.empty()) out += " (" + v.bound + ")";
        if (v.work_registers >= 0) out += " regs=" + std::to_string(v.work_registers);
    }
    return out.empty() ? "-" : out;
}

// The metrics compared between variants, in report order.
struct Metric {
    const char* name;
    std::function<std::optional<double>(const VariantProfile&)> value;
    int digits;
};

const std::vector<Metric>& metrics() {
    using P = VariantProfile;
    static const std::vector<Metric> m = {
        {"fragment: estimated cycles, longest path", [](const P& p) { return std::optional<double>(p.fragment_longest.total); }, 2},
        {"fragment: estimated cycles, shortest path", [](const P& p) { return std::optional<double>(p.fragment_shortest.total); }, 2},
        {"fragment: A cycles (longest)", [](const P& p) { return std::optional<double>(p.fragment_longest.arithmetic); }, 2},
        {"fragment: T cycles (longest)", [](const P& p) { return std::optional<double>(p.fragment_longest.texture); }, 2},
        {"fragment: V cycles", [](const P& p) { return std::optional<double>(p.fragment_longest.varying); }, 2},
        {"fragment: exposed latency cycles", [](const P& p) { return std::optional<double>(p.fragment_longest.latency); }, 2},
        {"fragment: arithmetic ops (longest)", [](const P& p) { return std::optional<double>(p.fragment.longest.arithmetic); }, 0},
        {"fragment: 16-bit share of arithmetic", [](const P& p) { return std::optional<double>(100.0 * fp16_share(p.fragment.longest)); }, 0},
        {"fragment: transcendental ops (longest)", [](const P& p) { return std::optional<double>(p.fragment.longest.transcendental); }, 0},
        {"fragment: texture samples (longest)", [](const P& p) { return std::optional<double>(p.fragment.longest.samples); }, 0},
        {"fragment: texture reads in the code", [](const P& p) { return std::optional<double>(double(p.fragment.samples.size())); }, 0},
        {"fragment: dependent reads", [](const P& p) { return std::optional<double>(p.fragment.dependent_samples); }, 0},
        {"fragment: texture round trips", [](const P& p) { return std::optional<double>(p.fragment.texture_round_trips); }, 0},
        {"fragment: waits in program order", [](const P& p) { return std::optional<double>(p.fragment.in_order_waits); }, 0},
        {"fragment: RelaxedPrecision results %", [](const P& p) { return std::optional<double>(100.0 * p.fragment.relaxed_share()); }, 0},
        {"fragment: varying components", [](const P& p) { return std::optional<double>(p.fragment.varying_components); }, 0},
        {"vertex: arithmetic ops", [](const P& p) { return std::optional<double>(p.vertex.longest.arithmetic); }, 0},
        {"vertex: transcendental ops", [](const P& p) { return std::optional<double>(p.vertex.longest.transcendental); }, 0},
        {"vertex: estimated cycles", [](const P& p) { return std::optional<double>(p.vertex_longest.total); }, 2},
        {"NIR fragment: ALU instructions", [](const P& p) { return p.nir_fragment ? std::optional<double>(p.nir_fragment->alu) : std::nullopt; }, 0},
        {"NIR fragment: texture instructions", [](const P& p) { return p.nir_fragment ? std::optional<double>(p.nir_fragment->texture) : std::nullopt; }, 0},
        {"NIR fragment: 16-bit ALU %", [](const P& p) { return p.nir_fragment ? std::optional<double>(100.0 * p.nir_fragment->alu_16bit_share()) : std::nullopt; }, 0},
        {"NIR fragment: loops left", [](const P& p) { return p.nir_fragment ? std::optional<double>(p.nir_fragment->loops) : std::nullopt; }, 0},
        {"NIR vertex: ALU instructions", [](const P& p) { return p.nir_vertex ? std::optional<double>(p.nir_vertex->alu) : std::nullopt; }, 0},
        {"llvmpipe ns per pixel", [](const P& p) { return p.measured ? std::optional<double>(p.measured->ns_per_pixel) : std::nullopt; }, 2},
        {"llvmpipe time / normal mapping", [](const P& p) { return p.measured ? std::optional<double>(p.measured->ratio_to_normal) : std::nullopt; }, 2},
        {"hit uv error, mean (texels)", [](const P& p) { return p.measured ? std::optional<double>(p.measured->uv_error_mean) : std::nullopt; }, 3},
        {"colour PSNR (dB)", [](const P& p) { return p.measured ? std::optional<double>(p.measured->color_psnr_db) : std::nullopt; }, 1},
    };
    return m;
}

nlohmann::json counts_json(const OpCounts& c) {
    return {{"arithmetic", c.arithmetic}, {"fp16", c.fp16}, {"transcendental", c.transcendental},
            {"samples", c.samples}, {"branches", c.branches}};
}

nlohmann::json cycles_json(const PipeCycles& c) {
    return {{"A", c.arithmetic}, {"T", c.texture}, {"V", c.varying}, {"latency", c.latency}, {"total", c.total}, {"bound", c.bound}};
}

nlohmann::json stage_json(const StageCost& s) {
    nlohmann::json loops = nlohmann::json::array(), samples = nlohmann::json::array();
    for (const LoopCost& l : s.loops)
        loops.push_back({{"where", l.where}, {"trip_count", l.trip_count}, {"counted_trips", l.counted_trips},
                         {"depth", l.depth}, {"has_samples", l.has_samples}});
    for (const SampleCost& r : s.samples)
        samples.push_back({{"where", r.where}, {"dependent", r.dependent}, {"waits_on", r.waits_on}, {"repeats", r.repeats}});
    return {{"spirv_words", s.spirv_words},
            {"instructions", {{"arithmetic", s.arithmetic_instructions}, {"transcendental", s.transcendental_instructions},
                              {"texture", s.texture_instructions}, {"control_flow", s.control_instructions}}},
            {"relaxed_precision_share", s.relaxed_share()},
            {"varying_components", s.varying_components},
            {"relaxed_varying_components", s.relaxed_varying_components},
            {"total", counts_json(s.total)},
            {"shortest", counts_json(s.shortest)},
            {"longest", counts_json(s.longest)},
            {"unknown_trips", s.unknown_trips},
            {"dependent_samples", s.dependent_samples},
            {"texture_round_trips", s.texture_round_trips},
            {"in_order_waits", s.in_order_waits},
            {"loops", loops},
            {"samples", samples}};
}

nlohmann::json nir_json(const NirCost& n) {
    return {{"alu", n.alu}, {"alu_16bit", n.alu_16bit}, {"texture", n.texture}, {"intrinsics", n.intrinsics},
            {"loops", n.loops}, {"branches", n.branches}, {"ssa_values", n.ssa_values}};
}

std::string figure_text(double v, int digits) { return v >= 0.0 ? fixed(v, digits) : "-"; }

// The GPU figures compared between two variants, per target both have.
struct GpuMetric {
    std::string name;
    double a, b;
    int digits;
};
std::vector<GpuMetric> gpu_metrics(const VariantProfile& a, const VariantProfile& b) {
    std::vector<GpuMetric> out;
    for (const GpuFigures& ga : a.gpu)
        for (const GpuFigures& gb : b.gpu) {
            if (ga.target != gb.target) continue;
            const GpuSummary &x = ga.summary, &y = gb.summary;
            const auto add = [&](const std::string& what, double va, double vb, int digits) {
                if (va >= 0.0 && vb >= 0.0) out.push_back({ga.gpu + ": " + what, va, vb, digits});
            };
            add("fragment instructions", x.instructions, y.instructions, 0);
            add("fragment cycles (compiler's estimate)", x.cycles, y.cycles, 2);
            add("fragment threads", x.threads, y.threads, 0);
            add("fragment registers", x.registers, y.registers, 0);
            add("fragment loops left", x.loops, y.loops, 0);
            add("fragment spills", x.spills, y.spills, 0);
            add("fragment 16-bit share, %", x.narrow_share >= 0.0 ? 100.0 * x.narrow_share : -1.0,
                y.narrow_share >= 0.0 ? 100.0 * y.narrow_share : -1.0, 1);
            add("fragment width conversions", x.conversions, y.conversions, 0);
            add("vertex instructions", x.vertex_instructions, y.vertex_instructions, 0);
        }
    return out;
}

nlohmann::json optional_figure(double v) { return v >= 0.0 ? nlohmann::json(v) : nlohmann::json(); }

nlohmann::json gpu_json(const GpuFigures& g) {
    const GpuSummary& m = g.summary;
    nlohmann::json j = {{"target", g.target}, {"gpu", g.gpu},
                        {"summary", {{"fragment_instructions", optional_figure(m.instructions)},
                                     {"fragment_cycles", optional_figure(m.cycles)},
                                     {"bound", m.bound},
                                     {"threads", optional_figure(m.threads)},
                                     {"registers", optional_figure(m.registers)},
                                     {"spills", m.spills >= 0 ? nlohmann::json(m.spills) : nlohmann::json()},
                                     {"fills", m.fills >= 0 ? nlohmann::json(m.fills) : nlohmann::json()},
                                     {"loops", optional_figure(m.loops)},
                                     {"narrow_share", optional_figure(m.narrow_share)},
                                     {"conversions", m.conversions >= 0 ? nlohmann::json(m.conversions) : nlohmann::json()},
                                     {"vertex_instructions", optional_figure(m.vertex_instructions)}}},
                        {"stages", nlohmann::json::array()}};
    if (!g.program.error.empty()) j["error"] = g.program.error;
    for (const GpuStage& st : g.program.stages) {
        nlohmann::json figures = nlohmann::json::object();
        for (const GpuFigure& f : st.figures) figures[f.words] = f.value;
        nlohmann::json stage = {{"stage", st.stage}, {"fragment", st.fragment}, {"figures", figures}, {"line", st.line}};
        if (st.spills >= 0) stage["spills"] = st.spills;
        if (st.fills >= 0) stage["fills"] = st.fills;
        if (st.narrow_ops >= 0)
            stage["listing"] = {{"narrow", st.narrow_ops}, {"wide", st.wide_ops}, {"conversions", st.conversions}};
        j["stages"].push_back(stage);
    }
    return j;
}

nlohmann::json profile_json(const VariantProfile& p) {
    nlohmann::json j = {{"variant", p.name},
                        {"key_hash", p.key.hash()},
                        {"fragment", stage_json(p.fragment)},
                        {"vertex", stage_json(p.vertex)},
                        {"estimate", {{"fragment_shortest", cycles_json(p.fragment_shortest)},
                                      {"fragment_longest", cycles_json(p.fragment_longest)},
                                      {"vertex_longest", cycles_json(p.vertex_longest)}}}};
    if (p.nir_fragment) j["nir"]["fragment"] = nir_json(*p.nir_fragment);
    if (p.nir_vertex) j["nir"]["vertex"] = nir_json(*p.nir_vertex);
    if (!p.nir_note.empty()) j["nir_note"] = p.nir_note;
    for (const VendorFigures& v : p.vendor_fragment)
        j["vendor"].push_back({{"tool", v.tool}, {"target", v.target}, {"work_registers", v.work_registers},
                               {"fp16_percent", v.fp16_percent}, {"pipes", v.pipes}, {"total", v.total}, {"shortest", v.shortest},
                               {"longest", v.longest}, {"bound", v.bound}, {"cycles", v.cycles}});
    for (const GpuFigures& g : p.gpu) j["gpu"].push_back(gpu_json(g));
    if (p.measured)
        j["measured"] = {{"scene", p.measured->scene}, {"angle_deg", p.measured->angle_deg},
                         {"ns_per_pixel", p.measured->ns_per_pixel}, {"ratio_to_normal", p.measured->ratio_to_normal},
                         {"uv_error_mean", p.measured->uv_error_mean}, {"uv_error_p95", p.measured->uv_error_p95},
                         {"color_psnr_db", p.measured->color_psnr_db}};
    return j;
}

nlohmann::json context_json(const ReportContext& c) {
    nlohmann::json j = {{"command", c.command}, {"renderer", c.renderer}, {"vendor", c.vendor_line}};
    if (!c.gpu_lines.empty()) j["gpu"] = c.gpu_lines;
    if (c.model) {
        j["model"] = c.model->name;
        j["model_calibration"] = c.model->calibration.summary();
    }
    return j;
}

std::string header_lines(const ReportContext& c, ReportFormat format) {
    std::ostringstream s;
    const std::string bullet = format == ReportFormat::markdown ? "- " : "";
    if (!c.command.empty()) s << bullet << "Command: " << (format == ReportFormat::markdown ? "`" + c.command + "`" : c.command) << "\n";
    if (!c.renderer.empty()) s << bullet << "NIR and timing: " << c.renderer << "\n";
    if (c.model) s << bullet << "Cost model: " << c.model->name << "; " << c.model->calibration.summary() << "\n";
    if (!c.vendor_line.empty()) s << bullet << "Vendor compilers: " << c.vendor_line << "\n";
    for (const std::string& line : c.gpu_lines) s << bullet << "Real GPU compiler: " << line << "\n";
    return s.str();
}

}  // namespace

// A table as text (aligned columns) or Markdown.
std::string render_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                         ReportFormat format) {
    std::ostringstream s;
    if (format == ReportFormat::markdown) {
        s << "|";
        for (const std::string& h : header) s << " " << h << " |";
        s << "\n|";
        for (std::size_t i = 0; i < header.size(); ++i) s << (i == 0 ? " --- |" : " ---: |");
        s << "\n";
        for (const auto& r : rows) {
            s << "|";
            for (const std::string& c : r) s << " " << c << " |";
            s << "\n";
        }
        return s.str();
    }
    std::vector<std::size_t> width(header.size(), 0);
    for (std::size_t i = 0; i < header.size(); ++i) width[i] = header[i].size();
    for (const auto& r : rows)
        for (std::size_t i = 0; i < r.size() && i < width.size(); ++i) width[i] = std::max(width[i], r[i].size());
    auto line = [&](const std::vector<std::string>& r) {
        for (std::size_t i = 0; i < r.size(); ++i) {
            const std::string pad(width[i] - std::min(width[i], r[i].size()), ' ');
            s << (i == 0 ? r[i] + pad : pad + r[i]) << (i + 1 < r.size() ? "  " : "");
        }
        s << "\n";
    };
    line(header);
    for (const auto& r : rows) line(r);
    return s.str();
}

std::string agreement_report(const std::vector<VariantProfile>& profiles, const std::string& baseline, ReportFormat format) {
    const VariantProfile* base = nullptr;
    for (const VariantProfile& p : profiles)
        if (p.name == baseline && p.measured) base = &p;
    if (!base || base->fragment_longest.total <= 0.0) return "";
    std::vector<std::vector<std::string>> rows;
    std::string agree, part;
    for (const VariantProfile& p : profiles) {
        if (!p.measured || &p == base) continue;
        const double model = p.fragment_longest.total / base->fragment_longest.total;
        // The bench's interleaved per-round ratio to normal mapping: steadier
        // than a ratio of two medians on a shared machine.
        const double measured = p.measured->ratio_to_normal;
        const double ratio = measured > 0.0 ? model / measured : 0.0;
        rows.push_back({p.name, fixed(model, 2), fixed(measured, 2), fixed(ratio, 2)});
        std::string& list = ratio >= 0.5 && ratio <= 2.0 ? agree : part;
        list += (list.empty() ? "" : ", ") + p.name + " (" + fixed(ratio, 2) + ")";
    }
    std::ostringstream s;
    s << render_table({"variant", "model cycles / normal mapping", "llvmpipe time / normal mapping", "model / measured"},
                      rows, format);
    if (format == ReportFormat::markdown) s << "\n";
    s << "Within a factor of 2 of the measurement: " << (agree.empty() ? "none" : agree) << ".\n";
    if (format == ReportFormat::markdown) s << "\n";
    s << "Further apart: " << (part.empty() ? "none" : part) << ".\n";
    return s.str();
}

std::string model_section(const CostModel& m, ReportFormat format) {
    std::ostringstream s;
    const bool md = format == ReportFormat::markdown;
    s << (md ? "### " : "") << "Cost model: " << m.name << "\n\n";
    if (!m.about.empty()) s << m.about << "\n\n";
    s << "Calibration: " << m.calibration.summary() << ".\n\n";
    s << (md ? "| parameter | value |\n| --- | ---: |\n" : "");
    const std::pair<const char*, double> rows[] = {
        {"fp32 scalar ops per cycle", m.fp32_ops_per_cycle},
        {"fp16 (RelaxedPrecision) scalar ops per cycle", m.fp16_ops_per_cycle},
        {"cycles per transcendental", m.transcendental_cycles},
        {"cycles per branch", m.branch_cycles},
        {"texture samples per cycle", m.samples_per_cycle},
        {"texture latency, cycles", m.texture_latency_cycles},
        {"share of latency other threads hide", m.latency_hidden_share},
        {"varying components per cycle", m.varying_components_per_cycle},
        {"mediump/lowp varying components per cycle", m.varying_fp16_components_per_cycle},
        {"cycles per invocation (fixed)", m.fixed_cycles},
    };
    for (const auto& [name, value] : rows) s << (md ? "| " : "  ") << name << (md ? " | " : ": ") << parameter(value) << (md ? " |" : "") << "\n";
    s << "\n";
    for (const CostModel::LoopTrips& l : m.loop_trips)
        s << (md ? "- " : "  ") << "Loops in " << l.file << " counted " << l.trips << " times: " << l.why << "\n";
    for (const std::string& a : m.assumptions) s << (md ? "- " : "  ") << a << "\n";
    return s.str();
}

std::string profile_report(const std::vector<VariantProfile>& profiles, ReportFormat format, const ReportContext& context) {
    if (format == ReportFormat::json) {
        nlohmann::json j = {{"context", context_json(context)}, {"variants", nlohmann::json::array()}};
        for (const VariantProfile& p : profiles) j["variants"].push_back(profile_json(p));
        return j.dump(2) + "\n";
    }
    const std::vector<std::string> header = {"variant", "16-bit", "A", "T", "V", "bound", "shortest", "longest",
                                             "reads (dep)", "round trips", "waits", "loops", "VS cycles", "NIR alu/tex/16-bit",
                                             "vendor", "ns/px", "x normal"};
    std::vector<std::vector<std::string>> rows;
    for (const VariantProfile& p : profiles) {
        const PipeCycles& l = p.fragment_longest;
        std::string nir = "-";
        if (p.nir_fragment)
            nir = std::to_string(p.nir_fragment->alu) + "/" + std::to_string(p.nir_fragment->texture) + "/" +
                  percent(p.nir_fragment->alu_16bit_share());
        rows.push_back({p.name, percent(fp16_share(p.fragment.longest)), cycles(l.arithmetic), cycles(l.texture),
                        cycles(l.varying), l.bound, cycles(p.fragment_shortest.total), cycles(l.total),
                        std::to_string(p.fragment.samples.size()) + " (" + std::to_string(p.fragment.dependent_samples) + ")",
                        fixed(p.fragment.texture_round_trips, 0), std::to_string(p.fragment.in_order_waits),
                        loops_text(p.fragment), cycles(p.vertex_longest.total),
                        nir, vendor_text(p), p.measured ? fixed(p.measured->ns_per_pixel, 2) : "-",
                        p.measured ? fixed(p.measured->ratio_to_normal, 2) : "-"});
    }
    std::ostringstream s;
    s << header_lines(context, format);
    if (format == ReportFormat::markdown) s << "\n";
    s << render_table(header, rows, format);
    s << (format == ReportFormat::markdown ? "\n" : "")
      << "Fragment stage, estimated cycles per fragment: A arithmetic, T texture, V varying pipes on the longest path; "
         "shortest and longest include the exposed texture latency. 16-bit: RelaxedPrecision share of the longest "
         "path's arithmetic. reads (dep): texture reads in the code, and how many wait on another read's result. "
         "round trips: reads the longest path waits for one after another. waits: texture waits in program order "
         "(each loop once), reads issued back to back sharing one.\n";
    const std::string gpu = gpu_report(profiles, format);
    if (!gpu.empty()) s << (format == ReportFormat::markdown ? "\n" : "\n") << gpu;
    return s.str();
}

std::string gpu_report(const std::vector<VariantProfile>& profiles, ReportFormat format) {
    std::vector<std::vector<std::string>> rows;
    for (const VariantProfile& p : profiles)
        for (const GpuFigures& g : p.gpu) {
            const GpuSummary& m = g.summary;
            if (!g.program.error.empty() && m.instructions < 0.0) {
                rows.push_back({p.name, g.gpu, "failed: " + g.program.error.substr(0, 120), "", "", "", "", "", "", "", ""});
                continue;
            }
            rows.push_back({p.name, g.gpu, figure_text(m.instructions, 0), figure_text(m.cycles, 2),
                            m.bound.empty() ? "-" : m.bound, figure_text(m.threads, 0), figure_text(m.registers, 0),
                            m.spills >= 0 ? std::to_string(m.spills) + ":" + std::to_string(m.fills) : "-",
                            figure_text(m.loops, 0),
                            m.narrow_share >= 0.0 ? fixed(100.0 * m.narrow_share, 0) + " % (" + std::to_string(m.conversions) + ")"
                                                  : "-",
                            figure_text(m.vertex_instructions, 0)});
        }
    if (rows.empty()) return "";
    std::ostringstream s;
    s << (format == ReportFormat::markdown ? "**Real GPU compilers**\n\n" : "Real GPU compilers:\n");
    s << render_table({"variant", "GPU", "FS instr", "FS cycles", "bound", "threads", "registers", "spills:fills",
                       "loops", "16-bit (cvt)", "VS instr"},
                      rows, format);
    s << (format == ReportFormat::markdown ? "\n" : "")
      << "Each figure is the driver's own (Mesa's shader-db statistics, or ir3's disassembly summary): FS instr its "
         "\"inst\"/\"instr\"; FS cycles its \"cycles\" per fragment (Bifrost and Valhall only), bound the pipe whose "
         "cycles equal it; threads, registers (Midgard \"registers\", V3D \"max-temps\", Adreno \"full\"), spills:fills "
         "and loops (left after unrolling; a loop counts one pass) as printed; 16-bit (Bifrost, Valhall) counted from "
         "the compiler's last instruction listing (BIFROST_MESA_DEBUG=shaders): the share of its arithmetic and "
         "data-movement instructions that compute in 16 bits (type .f16, .v2f16, .i16, ...) against 32, and in brackets "
         "the conversions between widths (F16_TO_F32 and the like); VS instr every vertex stage it compiled "
         "(Panfrost's position and varying shaders, V3D's and Adreno's binning shader) together. The JSON report keeps "
         "each stage's line as printed.\n";
    return s.str();
}

std::string compare_report(const VariantProfile& a, const VariantProfile& b, ReportFormat format,
                           const ReportContext& context) {
    if (format == ReportFormat::json) {
        nlohmann::json deltas = nlohmann::json::array();
        for (const Metric& m : metrics()) {
            const std::optional<double> va = m.value(a), vb = m.value(b);
            if (!va || !vb) continue;
            deltas.push_back({{"metric", m.name}, {"a", *va}, {"b", *vb}, {"delta", *vb - *va},
                              {"ratio", *va != 0.0 ? nlohmann::json(*vb / *va) : nlohmann::json()}});
        }
        for (const GpuMetric& m : gpu_metrics(a, b))
            deltas.push_back({{"metric", m.name}, {"a", m.a}, {"b", m.b}, {"delta", m.b - m.a},
                              {"ratio", m.a != 0.0 ? nlohmann::json(m.b / m.a) : nlohmann::json()}});
        return nlohmann::json{{"context", context_json(context)}, {"a", profile_json(a)}, {"b", profile_json(b)},
                              {"deltas", deltas}}
                   .dump(2) +
               "\n";
    }
    std::vector<std::vector<std::string>> rows;
    for (const Metric& m : metrics()) {
        const std::optional<double> va = m.value(a), vb = m.value(b);
        if (!va || !vb) continue;
        const double d = *vb - *va;
        rows.push_back({m.name, fixed(*va, m.digits), fixed(*vb, m.digits), (d > 0 ? "+" : "") + fixed(d, m.digits),
                        *va != 0.0 ? fixed(*vb / *va, 2) : "-"});
    }
    for (const GpuMetric& m : gpu_metrics(a, b)) {
        const double d = m.b - m.a;
        rows.push_back({m.name, fixed(m.a, m.digits), fixed(m.b, m.digits), (d > 0 ? "+" : "") + fixed(d, m.digits),
                        m.a != 0.0 ? fixed(m.b / m.a, 2) : "-"});
    }
    std::ostringstream s;
    s << header_lines(context, format);
    s << (format == ReportFormat::markdown ? "- " : "") << "A: " << a.name << "\n"
      << (format == ReportFormat::markdown ? "- " : "") << "B: " << b.name << "\n";
    if (format == ReportFormat::markdown) s << "\n";
    s << render_table({"metric", "A", "B", "B - A", "B / A"}, rows, format);
    return s.str();
}

namespace {

// The ladder on each real compiler: per step, its fragment instructions and
// cycles (where the compiler estimates them) and whether the step saved
// against the step before it.
std::string ladder_gpu_section(const std::vector<VariantProfile>& steps, ReportFormat format) {
    std::vector<std::string> targets;
    for (const VariantProfile& p : steps)
        for (const GpuFigures& g : p.gpu)
            if (std::find(targets.begin(), targets.end(), g.gpu) == targets.end()) targets.push_back(g.gpu);
    if (targets.empty()) return "";
    std::vector<std::string> header = {"step", "change"};
    for (const std::string& t : targets) {
        header.push_back(t + " FS instr");
        header.push_back(t + " FS cycles");
    }
    std::vector<std::vector<std::string>> rows;
    std::vector<const GpuSummary*> previous(targets.size(), nullptr);
    std::vector<std::string> saved(steps.size() * targets.size());
    for (const VariantProfile& p : steps) {
        const LadderStep& info = ladder_step_info(p.key.ladder_step);
        std::vector<std::string> row = {info.step ? std::to_string(info.step) : "shipped", info.name};
        for (size_t t = 0; t < targets.size(); ++t) {
            const GpuFigures* g = nullptr;
            for (const GpuFigures& x : p.gpu)
                if (x.gpu == targets[t]) g = &x;
            if (!g || g->summary.instructions < 0.0) {
                row.push_back(g ? "failed" : "-");
                row.push_back("-");
                continue;
            }
            const GpuSummary& m = g->summary;
            std::string instr = figure_text(m.instructions, 0), cyc = figure_text(m.cycles, 2);
            if (previous[t] && info.step) {
                const double di = m.instructions - previous[t]->instructions;
                instr += " (" + std::string(di > 0 ? "+" : "") + fixed(di, 0) + ")";
                if (m.cycles >= 0.0 && previous[t]->cycles >= 0.0) {
                    const double dc = m.cycles - previous[t]->cycles;
                    cyc += " (" + std::string(dc > 0 ? "+" : "") + fixed(dc, 2) + ")";
                }
            }
            row.push_back(instr);
            row.push_back(cyc);
            if (info.step) previous[t] = &m;
        }
        rows.push_back(row);
    }
    std::ostringstream s;
    s << (format == ReportFormat::markdown ? "**The ladder on real compilers**\n\n" : "The ladder on real compilers:\n");
    s << render_table(header, rows, format);
    s << (format == ReportFormat::markdown ? "\n" : "")
      << "In brackets: the change from the step before (negative saves). Cycles are the compiler's own estimate "
         "(Bifrost, Valhall); elsewhere instructions are all it says.\n";
    if (format == ReportFormat::markdown) s << "\n";
    return s.str();
}

}  // namespace

std::string ladder_report(const std::vector<VariantProfile>& steps, ReportFormat format, const ReportContext& context) {
    if (format == ReportFormat::json) {
        nlohmann::json j = {{"context", context_json(context)}, {"steps", nlohmann::json::array()}};
        for (const VariantProfile& p : steps) {
            nlohmann::json row = profile_json(p);
            const LadderStep& info = ladder_step_info(p.key.ladder_step);
            row["step"] = info.step;
            row["step_name"] = info.name;
            row["change"] = info.change;
            j["steps"].push_back(row);
        }
        return j.dump(2) + "\n";
    }
    const std::vector<std::string> header = {"step", "change", "FS ops", "FS fp16", "FS transc.", "reads (dep)", "waits",
                                             "VS ops", "FS cycles", "d cycles", "VS cycles", "NIR FS alu",
                                             "ns/px", "x normal", "uv err (texels)", "PSNR dB"};
    std::vector<std::vector<std::string>> rows;
    const VariantProfile* previous = nullptr;
    for (const VariantProfile& p : steps) {
        const LadderStep& info = ladder_step_info(p.key.ladder_step);
        std::string delta = "-";
        if (previous) {
            const double d = p.fragment_longest.total - previous->fragment_longest.total;
            delta = (d > 0 ? "+" : "") + cycles(d);
        }
        rows.push_back({info.step ? std::to_string(info.step) : "shipped", info.name, fixed(p.fragment.longest.arithmetic, 0),
                        percent(fp16_share(p.fragment.longest)), fixed(p.fragment.longest.transcendental, 0),
                        std::to_string(p.fragment.samples.size()) + " (" + std::to_string(p.fragment.dependent_samples) + ")",
                        std::to_string(p.fragment.in_order_waits),
                        fixed(p.vertex.longest.arithmetic, 0), cycles(p.fragment_longest.total), delta,
                        cycles(p.vertex_longest.total), p.nir_fragment ? std::to_string(p.nir_fragment->alu) : "-",
                        p.measured ? fixed(p.measured->ns_per_pixel, 2) : "-",
                        p.measured ? fixed(p.measured->ratio_to_normal, 2) : "-",
                        p.measured ? fixed(p.measured->uv_error_mean, 3) : "-",
                        p.measured ? fixed(p.measured->color_psnr_db, 1) : "-"});
        if (info.step) previous = &p;
    }
    std::ostringstream s;
    s << header_lines(context, format);
    if (format == ReportFormat::markdown) s << "\n";
    s << render_table(header, rows, format);
    if (format == ReportFormat::markdown) s << "\n";
    s << ladder_gpu_section(steps, format);
    // The spread of what was measured and estimated across the whitepaper's steps.
    double t_lo = 1e300, t_hi = 0, r_lo = 1e300, r_hi = 0, c_first = 0, c_last = 0;
    int measured = 0;
    for (const VariantProfile& p : steps) {
        if (!p.key.ladder_step) continue;
        if (p.key.ladder_step == 1) c_first = p.fragment_longest.total;
        c_last = p.fragment_longest.total;
        if (!p.measured) continue;
        ++measured;
        t_lo = std::min(t_lo, p.measured->ns_per_pixel);
        t_hi = std::max(t_hi, p.measured->ns_per_pixel);
        r_lo = std::min(r_lo, p.measured->ratio_to_normal);
        r_hi = std::max(r_hi, p.measured->ratio_to_normal);
    }
    if (c_first > 0)
        s << "From the baseline to the last step the model's fragment cycles go from " << cycles(c_first) << " to "
          << cycles(c_last) << " (" << fixed(100.0 * (c_last - c_first) / c_first, 0) << "%)";
    if (measured)
        s << "; the measured llvmpipe time spans " << fixed(t_lo, 2) << " to " << fixed(t_hi, 2)
          << " ns per pixel over the steps, " << fixed(r_lo, 2) << " to " << fixed(r_hi, 2) << " times normal mapping";
    if (c_first > 0) s << ".\n";
    if (format == ReportFormat::markdown) s << "\n";
    for (const VariantProfile& p : steps) {
        const LadderStep& info = ladder_step_info(p.key.ladder_step);
        s << (format == ReportFormat::markdown ? "- " : "  ") << (info.step ? std::to_string(info.step) : "shipped") << ", "
          << info.name << ": " << info.change << ".\n";
    }
    return s.str();
}

}  // namespace px::profiling
