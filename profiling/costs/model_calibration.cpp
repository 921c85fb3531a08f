#include "parallaxes/profiling/costs/model_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numeric>

#include <nlohmann/json.hpp>

#include "parallaxes/core/text.h"
#include "parallaxes/profiling/costs/json_input.h"

#include "parallaxes/profiling/costs/vendor_compilers.h"

namespace px::profiling {

namespace px_generated {
extern const char* const kEmbeddedCalibrationSet;
}

namespace {

using nlohmann::json;

std::string significant6(double v) { return significant_text(v, 6); }

constexpr std::size_t kMaxShaders = 10000;
constexpr std::size_t kMaxPipes = 16;

const char* stage_name(ShaderStage s) { return s == ShaderStage::vertex ? "vertex" : "fragment"; }

Result<std::string> string_at(const json& o, const char* key, const std::string& path) {
    const auto f = o.find(key);
    if (f == o.end() || !f->is_string() || f->get<std::string>().size() > 4096)
        return make_error(path + "." + key + ": missing or not a string (at most 4096 characters)");
    return f->get<std::string>();
}

// A whole number of components within [0, 4096].
Result<int> components_at(const json& o, const char* key, const std::string& path) {
    const auto f = o.find(key);
    if (f == o.end() || !f->is_number_integer() || f->get<long long>() < 0 || f->get<long long>() > 4096)
        return make_error(path + "." + key + ": missing or not a whole number within 0..4096");
    return static_cast<int>(f->get<long long>());
}

// A finite number within [0, 1e6].
Result<double> count_at(const json& o, const char* key, const std::string& path) {
    const auto f = o.find(key);
    if (f == o.end() || !f->is_number()) return make_error(path + "." + key + ": missing or not a number");
    const double v = f->get<double>();
    if (!std::isfinite(v) || v < 0.0 || v > 1e6) return make_error(path + "." + key + ": " + f->dump() + " is outside [0, 1e6]");
    return v;
}

Result<CalibrationShader> read_shader(const json& s, const std::string& path) {
    if (!s.is_object()) return make_error(path + ": must be an object");
    CalibrationShader c;
    Result<std::string> name = string_at(s, "name", path);
    if (!name) return name.error();
    c.name = *name;
    Result<std::string> stage = string_at(s, "stage", path);
    if (!stage) return stage.error();
    if (*stage != "fragment" && *stage != "vertex") return make_error(path + ".stage: \"" + *stage + "\" is not fragment or vertex");
    c.stage = *stage == "vertex" ? ShaderStage::vertex : ShaderStage::fragment;
    const auto ours = s.find("ours");
    if (ours == s.end() || !ours->is_object()) return make_error(path + ".ours: missing or not an object");
    const std::string op = path + ".ours";
    double* fields[] = {&c.counts.arithmetic, &c.counts.fp16, &c.counts.transcendental, &c.counts.samples, &c.counts.branches};
    const char* keys[] = {"arithmetic", "fp16", "transcendental", "samples", "branches"};
    for (int i = 0; i < 5; ++i) {
        Result<double> v = count_at(*ours, keys[i], op);
        if (!v) return v.error();
        *fields[i] = *v;
    }
    if (c.counts.fp16 > c.counts.arithmetic) return make_error(op + ".fp16: more than the arithmetic it is a share of");
    Result<int> varying = components_at(*ours, "varying_components", op);
    if (!varying) return varying.error();
    c.varying_components = *varying;
    if (ours->contains("relaxed_varying_components")) {
        Result<int> relaxed = components_at(*ours, "relaxed_varying_components", op);
        if (!relaxed) return relaxed.error();
        if (*relaxed > *varying) return make_error(op + ".relaxed_varying_components: more than the varying components");
        c.relaxed_varying_components = *relaxed;
    }
    const auto theirs = s.find("theirs");
    if (theirs == s.end() || !theirs->is_object()) return make_error(path + ".theirs: missing or not an object");
    const std::string tp = path + ".theirs";
    Result<std::string> row = string_at(*theirs, "row", tp);
    if (!row) return row.error();
    if (*row != "longest" && *row != "total") return make_error(tp + ".row: \"" + *row + "\" is not longest or total");
    c.row = *row;
    const auto pipes = theirs->find("pipes");
    const auto cycles = theirs->find("cycles");
    if (pipes == theirs->end() || !pipes->is_array() || pipes->empty() || pipes->size() > kMaxPipes)
        return make_error(tp + ".pipes: must be an array of 1 to 16 names");
    if (cycles == theirs->end() || !cycles->is_array() || cycles->size() != pipes->size())
        return make_error(tp + ".cycles: must be an array of one number per pipe");
    for (std::size_t i = 0; i < pipes->size(); ++i) {
        const std::string at = tp + ".pipes[" + std::to_string(i) + "]";
        if (!(*pipes)[i].is_string() || (*pipes)[i].get<std::string>().empty()) return make_error(at + ": must be a name");
        c.pipes.push_back((*pipes)[i].get<std::string>());
        const json& v = (*cycles)[i];
        const double x = v.is_number() ? v.get<double>() : -1.0;
        if (!std::isfinite(x) || x < 0.0 || x > 1e6)
            return make_error(tp + ".cycles[" + std::to_string(i) + "]: " + v.dump() + " is not a number within [0, 1e6]");
        c.cycles.push_back(x);
    }
    if (c.bound_cycles() <= 0.0) return make_error(tp + ".cycles: every pipe is 0 (nothing to fit or judge)");
    return c;
}


// The least-squares weights of `columns` (each column's values over the rows)
// for y, on the columns `use` selects, by the normal equations and Gaussian
// elimination with partial pivoting; empty when they are singular.
std::vector<double> least_squares(const std::vector<std::vector<double>>& columns, const std::vector<double>& y,
                                  const std::vector<std::size_t>& use) {
    const std::size_t n = use.size();
    std::vector<std::vector<double>> m(n, std::vector<double>(n + 1, 0.0));
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < n; ++j)
            for (std::size_t r = 0; r < y.size(); ++r) m[i][j] += columns[use[i]][r] * columns[use[j]][r];
        for (std::size_t r = 0; r < y.size(); ++r) m[i][n] += columns[use[i]][r] * y[r];
    }
    for (std::size_t c = 0; c < n; ++c) {
        std::size_t pivot = c;
        for (std::size_t r = c + 1; r < n; ++r)
            if (std::abs(m[r][c]) > std::abs(m[pivot][c])) pivot = r;
        if (std::abs(m[pivot][c]) < 1e-12 * std::max(1.0, std::abs(m[c][c]))) return {};
        std::swap(m[c], m[pivot]);
        for (std::size_t r = 0; r < n; ++r) {
            if (r == c) continue;
            const double f = m[r][c] / m[c][c];
            for (std::size_t k = c; k <= n; ++k) m[r][k] -= f * m[c][k];
        }
    }
    std::vector<double> w(n);
    for (std::size_t i = 0; i < n; ++i) w[i] = m[i][n] / m[i][i];
    return w;
}

// y ~ sum_j w_j x_j with every w_j >= 0: the unconstrained least squares on
// each subset of the columns (a handful: 2^n subsets), the best that is
// non-negative. Exact, where an iterative solver would stop short on
// columns as unlike as operation counts and a constant.
std::vector<double> nonnegative_least_squares(const std::vector<std::vector<double>>& columns, const std::vector<double>& y) {
    const std::size_t n = columns.size();
    std::vector<double> best(n, 0.0);
    double best_residual = 0.0;
    for (double v : y) best_residual += v * v;
    for (unsigned subset = 1; subset < (1u << n); ++subset) {
        std::vector<std::size_t> use;
        for (std::size_t j = 0; j < n; ++j)
            if (subset & (1u << j)) use.push_back(j);
        const std::vector<double> w = least_squares(columns, y, use);
        if (w.empty() || std::any_of(w.begin(), w.end(), [](double x) { return x < 0.0; })) continue;
        double residual = 0.0;
        for (std::size_t r = 0; r < y.size(); ++r) {
            double p = 0.0;
            for (std::size_t i = 0; i < use.size(); ++i) p += w[i] * columns[use[i]][r];
            residual += (y[r] - p) * (y[r] - p);
        }
        if (residual < best_residual - 1e-15) {
            best_residual = residual;
            std::fill(best.begin(), best.end(), 0.0);
            for (std::size_t i = 0; i < use.size(); ++i) best[use[i]] = w[i];
        }
    }
    return best;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

std::vector<double> ranks(const std::vector<double>& v) {
    std::vector<std::size_t> order(v.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
    std::vector<double> r(v.size());
    for (std::size_t i = 0; i < order.size();) {
        std::size_t j = i;
        while (j + 1 < order.size() && v[order[j + 1]] == v[order[i]]) ++j;
        for (std::size_t k = i; k <= j; ++k) r[order[k]] = 0.5 * double(i + j);
        i = j + 1;
    }
    return r;
}

// The pipe names of a report, as the model's three: "A", "T", "V"; others
// (LS) are the compiler's own and are predicted 0.
double real_pipe(const CalibrationShader& s, const char* name) {
    for (std::size_t i = 0; i < s.pipes.size(); ++i)
        if (s.pipes[i] == name) return s.cycles[i];
    return 0.0;
}

struct Weights {
    double fp32 = 0.0, fp16_ratio = 0.5, transcendental = 0.0, branch = 0.0, fixed = 0.0, sample = 0.0, varying = 0.0;
    double varying_fp16_ratio = 0.5;  // a mediump component's cost over a highp one's (the base model's)
};

std::pair<double, std::string> busiest(double a, double t, double v) {
    const double top = std::max({a, t, v});
    std::string pipe;
    const std::pair<const char*, double> pipes[] = {{"A", a}, {"V", v}, {"T", t}};
    for (const auto& [name, cycles] : pipes)
        if (top > 0.0 && cycles >= top * 0.999) pipe += (pipe.empty() ? "" : ", ") + std::string(name);
    return {top, pipe};
}

// Varying components with the mediump ones at the base model's ratio.
double varying_cost(const CalibrationShader& s, double fp16_ratio) {
    return (s.varying_components - s.relaxed_varying_components) + s.relaxed_varying_components * fp16_ratio;
}

std::pair<double, std::string> predict(const CalibrationShader& s, const Weights& w) {
    const OpCounts& c = s.counts;
    const double a = (c.arithmetic - c.fp16) * w.fp32 + c.fp16 * w.fp32 * w.fp16_ratio +
                     c.transcendental * w.transcendental + c.branches * w.branch + w.fixed;
    return busiest(a, c.samples * w.sample, varying_cost(s, w.varying_fp16_ratio) * w.varying);
}

CalibrationSummary summarise(const std::vector<CalibrationRow>& rows, bool held_out) {
    std::vector<double> real, predicted, uncalibrated, errors;
    for (const CalibrationRow& r : rows) {
        if (r.held_out != held_out) continue;
        real.push_back(r.real);
        predicted.push_back(r.predicted);
        uncalibrated.push_back(r.uncalibrated);
        errors.push_back(std::abs(r.error()));
    }
    CalibrationSummary s;
    s.shaders = static_cast<int>(real.size());
    s.spearman = spearman(predicted, real);
    s.spearman_uncalibrated = spearman(uncalibrated, real);
    s.median_abs_error = median(errors);
    s.worst_abs_error = errors.empty() ? 0.0 : *std::max_element(errors.begin(), errors.end());
    return s;
}

// Arithmetic fitted with the classes the fitting half uses enough; the rest
// tied to the fp32 weight by the base model's ratios.
void fit_arithmetic(const std::vector<const CalibrationShader*>& fit, const CostModel& base, Weights& w,
                    std::vector<std::string>& notes) {
    auto uses = [&](double OpCounts::*field) {
        return std::count_if(fit.begin(), fit.end(), [&](const CalibrationShader* s) { return s->counts.*field > 0.0; });
    };
    const bool fit_transcendental = uses(&OpCounts::transcendental) >= 3;
    const bool fit_branch = uses(&OpCounts::branches) >= 3;
    const double base_fp32 = 1.0 / base.fp32_ops_per_cycle;
    std::vector<std::vector<double>> columns(4);
    std::vector<double> y;
    for (const CalibrationShader* s : fit) {
        const OpCounts& c = s->counts;
        double weighted_ops = (c.arithmetic - c.fp16) + c.fp16 * w.fp16_ratio;
        if (!fit_transcendental) weighted_ops += c.transcendental * base.transcendental_cycles / base_fp32;
        if (!fit_branch) weighted_ops += c.branches * base.branch_cycles / base_fp32;
        columns[0].push_back(weighted_ops);
        columns[1].push_back(fit_transcendental ? c.transcendental : 0.0);
        columns[2].push_back(fit_branch ? c.branches : 0.0);
        columns[3].push_back(1.0);
        y.push_back(real_pipe(*s, "A"));
    }
    const std::vector<double> x = nonnegative_least_squares(columns, y);
    w.fp32 = x[0];
    w.transcendental = fit_transcendental ? x[1] : w.fp32 * base.transcendental_cycles / base_fp32;
    w.branch = fit_branch ? x[2] : w.fp32 * base.branch_cycles / base_fp32;
    w.fixed = x[3];
    if (!fit_transcendental)
        notes.push_back("transcendentals: fewer than three fitting shaders use them; kept at the base model's ratio to fp32");
    if (!fit_branch) notes.push_back("branches: fewer than three fitting shaders have them; kept at the base model's ratio to fp32");
}

double fit_one(const std::vector<const CalibrationShader*>& fit, const std::function<double(const CalibrationShader&)>& feature,
               const char* pipe) {
    std::vector<std::vector<double>> columns(1);
    std::vector<double> y;
    for (const CalibrationShader* s : fit) {
        columns[0].push_back(feature(*s));
        y.push_back(real_pipe(*s, pipe));
    }
    return nonnegative_least_squares(columns, y)[0];
}

// Every weight fitted on `fit`; an error where a pipe comes out free.
Result<Weights> fit_weights(const std::vector<const CalibrationShader*>& fit, const CostModel& base,
                            std::vector<std::string>& notes) {
    Weights w;
    w.fp16_ratio = base.fp32_ops_per_cycle / base.fp16_ops_per_cycle;
    fit_arithmetic(fit, base, w, notes);
    w.sample = fit_one(fit, [](const CalibrationShader& s) { return s.counts.samples; }, "T");
    w.varying_fp16_ratio = base.varying_components_per_cycle / base.varying_fp16_components_per_cycle;
    w.varying = fit_one(fit, [&](const CalibrationShader& s) { return varying_cost(s, w.varying_fp16_ratio); }, "V");
    if (w.fp32 <= 0.0 || w.sample <= 0.0 || w.varying <= 0.0)
        return make_error("the fit gave a pipe no cost (fp32 " + significant6(w.fp32) + ", sample " + significant6(w.sample) +
                          ", varying " + significant6(w.varying) + "): the set cannot calibrate this model");
    return w;
}

}  // namespace

double CalibrationShader::bound_cycles() const {
    return cycles.empty() ? 0.0 : *std::max_element(cycles.begin(), cycles.end());
}

std::string CalibrationShader::bound_pipe() const {
    const double top = bound_cycles();
    std::string pipe;
    for (std::size_t i = 0; i < pipes.size(); ++i)
        if (top > 0.0 && cycles[i] >= top * 0.999) pipe += (pipe.empty() ? "" : ", ") + pipes[i];
    return pipe;
}

double spearman(const std::vector<double>& a, const std::vector<double>& b) {
    if (a.size() != b.size() || a.size() < 2) return 0.0;
    const std::vector<double> ra = ranks(a), rb = ranks(b);
    const double n = double(a.size());
    const double ma = std::accumulate(ra.begin(), ra.end(), 0.0) / n, mb = std::accumulate(rb.begin(), rb.end(), 0.0) / n;
    double sab = 0.0, saa = 0.0, sbb = 0.0;
    for (std::size_t i = 0; i < ra.size(); ++i) {
        sab += (ra[i] - ma) * (rb[i] - mb);
        saa += (ra[i] - ma) * (ra[i] - ma);
        sbb += (rb[i] - mb) * (rb[i] - mb);
    }
    return saa > 0.0 && sbb > 0.0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

Result<CalibrationSet> parse_calibration_set(const std::string& text, const std::string& where) {
    Result<json> parsed = parse_json_object(text, where, "a calibration set");
    if (!parsed) return parsed.error();
    const json& root = *parsed;
    auto fail = [&](const Error& e) { return make_error(where + ": " + e.message); };
    CalibrationSet set;
    std::string* fields[] = {&set.gpu, &set.compiler, &set.source, &set.made_by};
    const char* keys[] = {"gpu", "compiler", "source", "made_by"};
    for (int i = 0; i < 4; ++i) {
        Result<std::string> v = string_at(root, keys[i], "$");
        if (!v) return fail(v.error());
        *fields[i] = *v;
    }
    const auto shaders = root.find("shaders");
    if (shaders == root.end() || !shaders->is_array() || shaders->size() > kMaxShaders)
        return make_error(where + ": $.shaders: must be an array (at most " + std::to_string(kMaxShaders) + ")");
    for (std::size_t i = 0; i < shaders->size(); ++i) {
        Result<CalibrationShader> s = read_shader((*shaders)[i], "$.shaders[" + std::to_string(i) + "]");
        if (!s) return fail(s.error());
        for (const CalibrationShader& other : set.shaders)
            if (other.name == s->name && other.stage == s->stage)
                return make_error(where + ": $.shaders[" + std::to_string(i) + "].name: \"" + s->name + "\" appears twice");
        set.shaders.push_back(std::move(*s));
    }
    return set;
}

std::string calibration_set_json(const CalibrationSet& set) {
    json shaders = json::array();
    for (const CalibrationShader& s : set.shaders) {
        // One line per shader: a diff of a remade set shows which changed.
        std::string line = "    {\"name\": " + json(s.name).dump() + ", \"stage\": \"" + stage_name(s.stage) +
                           "\", \"ours\": {\"arithmetic\": " + significant6(s.counts.arithmetic) +
                           ", \"fp16\": " + significant6(s.counts.fp16) +
                           ", \"transcendental\": " + significant6(s.counts.transcendental) +
                           ", \"samples\": " + significant6(s.counts.samples) +
                           ", \"branches\": " + significant6(s.counts.branches) +
                           ", \"varying_components\": " + std::to_string(s.varying_components) +
                           ", \"relaxed_varying_components\": " + std::to_string(s.relaxed_varying_components) +
                           "}, \"theirs\": {\"row\": \"" +
                           s.row + "\", \"pipes\": " + json(s.pipes).dump() + ", \"cycles\": [";
        for (std::size_t i = 0; i < s.cycles.size(); ++i) line += (i ? ", " : "") + significant6(s.cycles[i]);
        shaders.push_back(line + "]}}");
    }
    std::string out = "{\n";
    out += "  \"gpu\": " + json(set.gpu).dump() + ",\n";
    out += "  \"compiler\": " + json(set.compiler).dump() + ",\n";
    out += "  \"source\": " + json(set.source).dump() + ",\n";
    out += "  \"made_by\": " + json(set.made_by).dump() + ",\n";
    out += "  \"shaders\": [\n";
    for (std::size_t i = 0; i < shaders.size(); ++i)
        out += shaders[i].get<std::string>() + (i + 1 < shaders.size() ? ",\n" : "\n");
    return out + "  ]\n}\n";
}

const char* default_calibration_set_path() { return "profiling/costs/calibration/mali_g78_impeller.json"; }

const CalibrationSet& default_calibration_set() {
    static const CalibrationSet set = [] {
        Result<CalibrationSet> s = parse_calibration_set(px_generated::kEmbeddedCalibrationSet, default_calibration_set_path());
        // The file is checked by the unit tests; a broken one is a build defect.
        return s ? *s : CalibrationSet{};
    }();
    return set;
}

const CostModel& default_cost_model() {
    static const CostModel model = [] {
        // The carried set and base are checked by the unit tests (a fit that
        // fails is a build defect); the base is what is left then.
        Result<CalibrationFit> fit = fit_cost_model(default_calibration_set(), base_cost_model(), false);
        if (!fit) return base_cost_model();
        Result<CostModel> m = calibrated_model(base_cost_model(), *fit, default_calibration_set(), default_calibration_set_path());
        return m ? *m : base_cost_model();
    }();
    return model;
}

Result<VendorCycles> parse_malioc_report(const std::string& report) {
    const std::size_t first = report.find_first_not_of(" \t\r\n");
    return first != std::string::npos && report[first] == '{' ? parse_malioc_json(report) : parse_malioc_text(report);
}

Result<CalibrationShader> calibration_entry(const std::string& name, const std::string& source, ShaderStage stage,
                                            const std::string& report) {
    Result<VendorCycles> figures = parse_malioc_report(report);
    if (!figures) return make_error(name + " (report): " + figures.error().message);
    return calibration_entry(name, source, stage, *figures);
}

Result<CalibrationShader> calibration_entry(const std::string& name, const std::string& source, ShaderStage stage,
                                            const VendorCycles& figures) {
    Result<std::vector<std::uint32_t>> words = compile_spirv(source, stage);
    if (!words) return make_error(name + ": " + words.error().message);
    Result<StageCost> cost = analyse_spirv(*words, stage);
    if (!cost) return make_error(name + ": " + cost.error().message);
    const std::string want = stage == ShaderStage::vertex ? "Vertex" : "Fragment";
    if (!figures.shader_type.empty() && figures.shader_type.find(want) == std::string::npos)
        return make_error(name + " (report): a " + figures.shader_type + " report for a " + stage_name(stage) + " shader");
    CalibrationShader c;
    c.name = name;
    c.stage = stage;
    c.counts = cost->longest;
    c.varying_components = cost->varying_components;
    c.relaxed_varying_components = cost->relaxed_varying_components;
    c.pipes = figures.pipes;
    const bool longest_known = !figures.longest.empty() &&
                               std::none_of(figures.longest.begin(), figures.longest.end(), [](double v) { return std::isnan(v); });
    const bool total_known = !figures.total.empty() &&
                             std::none_of(figures.total.begin(), figures.total.end(), [](double v) { return std::isnan(v); });
    if (!longest_known && !total_known) return make_error(name + " (report): neither the longest path nor the total has figures");
    c.row = longest_known ? "longest" : "total";
    c.cycles = longest_known ? figures.longest : figures.total;
    if (c.cycles.size() != c.pipes.size()) return make_error(name + " (report): figures and pipes differ in number");
    if (c.bound_cycles() <= 0.0) return make_error(name + " (report): every pipe is 0 cycles");
    return c;
}

Result<CalibrationFit> fit_cost_model(const CalibrationSet& set, const CostModel& base, bool leave_one_out) {
    std::vector<const CalibrationShader*> shaders;
    for (const CalibrationShader& s : set.shaders)
        if (s.stage == ShaderStage::fragment) shaders.push_back(&s);
    std::sort(shaders.begin(), shaders.end(), [](const CalibrationShader* a, const CalibrationShader* b) { return a->name < b->name; });
    std::vector<const CalibrationShader*> fit, held;
    for (std::size_t i = 0; i < shaders.size(); ++i) (i % 2 ? held : fit).push_back(shaders[i]);
    if (fit.size() < 4 || held.size() < 4)
        return make_error("a calibration needs at least 8 fragment shaders (4 to fit, 4 held out); the set has " +
                          std::to_string(shaders.size()));
    CalibrationFit result;
    Result<Weights> w = fit_weights(fit, base, result.notes);
    if (!w) return w.error();
    result.fp32_op = w->fp32;
    result.transcendental = w->transcendental;
    result.branch = w->branch;
    result.fixed = w->fixed;
    result.sample = w->sample;
    result.varying_component = w->varying;
    std::vector<double> loo_real, loo_predicted, loo_errors;
    for (const CalibrationShader* s : shaders) {
        CalibrationRow r;
        r.name = s->name;
        r.held_out = std::find(held.begin(), held.end(), s) != held.end();
        r.real = s->bound_cycles();
        r.real_pipe = s->bound_pipe();
        std::tie(r.predicted, r.predicted_pipe) = predict(*s, *w);
        StageCost stage;
        stage.stage = s->stage;
        stage.varying_components = s->varying_components;
        stage.relaxed_varying_components = s->relaxed_varying_components;
        const PipeCycles u = estimate(stage, s->counts, 0.0, base);
        r.uncalibrated = std::max({u.arithmetic, u.texture, u.varying});
        result.rows.push_back(r);
        if (!leave_one_out) continue;
        // Leave-one-out: every other shader fits, this one is predicted.
        std::vector<const CalibrationShader*> others;
        for (const CalibrationShader* o : shaders)
            if (o != s) others.push_back(o);
        std::vector<std::string> ignored;
        if (Result<Weights> lw = fit_weights(others, base, ignored)) {
            loo_real.push_back(r.real);
            loo_predicted.push_back(predict(*s, *lw).first);
            loo_errors.push_back(std::abs(loo_predicted.back() - r.real) / r.real);
        }
    }
    result.fitted = summarise(result.rows, false);
    result.held_out = summarise(result.rows, true);
    result.leave_one_out.shaders = static_cast<int>(loo_real.size());
    result.leave_one_out.spearman = spearman(loo_predicted, loo_real);
    result.leave_one_out.median_abs_error = median(loo_errors);
    result.leave_one_out.worst_abs_error = loo_errors.empty() ? 0.0 : *std::max_element(loo_errors.begin(), loo_errors.end());
    if (std::any_of(set.shaders.begin(), set.shaders.end(), [](const CalibrationShader& s) { return s.stage != ShaderStage::fragment; }))
        result.notes.push_back("vertex shaders in the set are left out: the model has no load/store pipe, which bounds most of them");
    return result;
}

Result<CostModel> calibrated_model(const CostModel& base, const CalibrationFit& fit, const CalibrationSet& set,
                                   const std::string& set_path) {
    if (fit.fp32_op <= 0.0 || fit.sample <= 0.0 || fit.varying_component <= 0.0)
        return make_error("the fit has a zero rate; no model can be made from it");
    CostModel m = base;
    const double fp16_ratio = base.fp32_ops_per_cycle / base.fp16_ops_per_cycle;
    const double latency_in_samples = base.texture_latency_cycles * base.samples_per_cycle;
    m.name = "mobile-class GPU, per thread, weights fitted to " + set.gpu;
    m.about = "Turns the counts glslang's SPIR-V gives (include/parallaxes/profiling/costs/shader_costs.h) into estimated cycles per thread on "
              "each pipe, with weights fitted to a real compiler's figures for real shaders (`parallax profile "
              "--calibrate`, docs/profiling.md): a model of that GPU class, not the vendor's. `parallax profile --model "
              "FILE` takes another file of this shape, used as written.";
    m.fp32_ops_per_cycle = 1.0 / fit.fp32_op;
    m.fp16_ops_per_cycle = m.fp32_ops_per_cycle / fp16_ratio;
    m.transcendental_cycles = fit.transcendental;
    m.branch_cycles = fit.branch;
    m.fixed_cycles = fit.fixed;
    m.samples_per_cycle = 1.0 / fit.sample;
    m.texture_latency_cycles = latency_in_samples * fit.sample;
    m.varying_components_per_cycle = 1.0 / fit.varying_component;
    m.varying_fp16_components_per_cycle =
        m.varying_components_per_cycle * base.varying_fp16_components_per_cycle / base.varying_components_per_cycle;
    m.calibration.gpu = set.gpu;
    m.calibration.compiler = set.compiler;
    m.calibration.set = set_path;
    m.calibration.command = set_path == default_calibration_set_path() ? "parallax profile --calibrate"
                                                                        : "parallax profile --calibrate --calibration-set " + set_path;
    m.calibration.fitted = fit.fitted.shaders;
    m.calibration.held_out = fit.held_out.shaders;
    m.calibration.spearman = fit.held_out.spearman;
    m.calibration.median_abs_error = fit.held_out.median_abs_error;
    // The rate assumptions are restated from the fit; the others carry over.
    std::vector<std::string> kept;
    const char* restated[] = {"Rates:", "Latency:", "Fit:", "Arithmetic:", "Transcendentals", "Texture:", "Varyings:"};
    for (const std::string& a : base.assumptions)
        if (std::none_of(std::begin(restated), std::end(restated), [&](const char* p) { return a.rfind(p, 0) == 0; }))
            kept.push_back(a);
    const std::string per = " cycles per thread as " + set.compiler + " counts them on " + set.gpu;
    m.assumptions.clear();
    m.assumptions.push_back("Rates: fitted to " + set.compiler + "'s figures for " + std::to_string(fit.fitted.shaders) +
                            " fragment shaders (" + set.source + "), the other " + std::to_string(fit.held_out.shaders) +
                            " held out to judge the fit: arithmetic " + significant6(fit.fp32_op) + " per fp32 scalar operation (" +
                            significant6(fit.fp32_op * fp16_ratio) + " per mediump/lowp one, the base model's ratio), " +
                            significant6(fit.transcendental) + " per transcendental, " + significant6(fit.branch) +
                            " per branch, " + significant6(fit.fixed) + " per invocation; texture " + significant6(fit.sample) +
                            " per bilinear sample; varying " + significant6(fit.varying_component) +
                            " per interpolated highp component (mediump ones at the base model's ratio: the set's "
                            "varyings are all highp);" + per + ". The counts are of glslang's unoptimised SPIR-V, so a "
                            "weight absorbs what the vendor compiler folds away.");
    m.assumptions.push_back("Latency: not in the compiler's figures, so not fitted: each texture result the longest path waits for "
                            "in turn exposes " + significant6(latency_in_samples) + " sample times (" +
                            significant6(m.texture_latency_cycles) + " cycles), of which other threads hide " +
                            significant6(100.0 * m.latency_hidden_share) + " %.");
    for (const std::string& note : fit.notes) m.assumptions.push_back("Fit: " + note + ".");
    m.assumptions.insert(m.assumptions.end(), kept.begin(), kept.end());
    return m;
}

}  // namespace px::profiling
