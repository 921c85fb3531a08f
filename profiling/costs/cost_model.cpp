#include "parallaxes/profiling/costs/cost_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "parallaxes/core/text.h"
#include "parallaxes/profiling/costs/json_input.h"

namespace px::profiling {

namespace px_generated {
extern const char* const kEmbeddedCostModel;
}

namespace {

using nlohmann::json;

// A positive finite number at `path` of `object`.
Status read_number(const json& object, const char* key, const std::string& path, double& out, bool allow_zero = false) {
    const auto found = object.find(key);
    if (found == object.end()) return make_error(path + "." + key + ": missing");
    if (!found->is_number()) return make_error(path + "." + key + ": must be a number");
    const double v = found->get<double>();
    if (!std::isfinite(v) || v < 0.0 || (!allow_zero && v == 0.0) || v > 1e6)
        return make_error(path + "." + key + ": " + found->dump() + " is outside " + (allow_zero ? "[0" : "(0") + ", 1e6]");
    out = v;
    return {};
}

Result<const json*> member(const json& object, const char* key, const std::string& path) {
    const auto found = object.find(key);
    if (found == object.end() || !found->is_object()) return make_error(path + "." + key + ": missing or not an object");
    return &*found;
}

// The optional "calibration" object: which real compiler the weights were
// fitted to, and how well they did on the shaders held out of the fit.
Status read_calibration(const json& c, CostModel::Calibration& out) {
    if (!c.is_object()) return make_error("$.calibration: must be an object");
    for (const char* key : {"gpu", "compiler", "set", "command"}) {
        const auto found = c.find(key);
        if (found == c.end() || !found->is_string() || found->get<std::string>().size() > 4096)
            return make_error(std::string("$.calibration.") + key + ": missing or not a string");
    }
    out.gpu = c["gpu"].get<std::string>();
    out.compiler = c["compiler"].get<std::string>();
    out.set = c["set"].get<std::string>();
    out.command = c["command"].get<std::string>();
    if (out.gpu.empty()) return make_error("$.calibration.gpu: empty");
    for (const char* key : {"fitted", "held_out"}) {
        const auto found = c.find(key);
        if (found == c.end() || !found->is_number_integer() || found->get<long long>() < 0 || found->get<long long>() > 100000)
            return make_error(std::string("$.calibration.") + key + ": must be an integer within 0..100000");
    }
    out.fitted = static_cast<int>(c["fitted"].get<long long>());
    out.held_out = static_cast<int>(c["held_out"].get<long long>());
    for (Status s : {read_number(c, "spearman", "$.calibration", out.spearman, true),
                     read_number(c, "median_abs_error", "$.calibration", out.median_abs_error, true)})
        if (!s) return s;
    if (out.spearman > 1.0) return make_error("$.calibration.spearman: must be within [-1, 1]");
    return {};
}


}  // namespace

std::string CostModel::Calibration::summary() const {
    if (!present()) return "not calibrated against a real compiler (rates chosen by hand)";
    return "calibrated against " + gpu + ", " + compiler + ": on " + std::to_string(held_out) +
           " shaders held out of the fit, Spearman " + fixed_text(spearman, 2) + ", median error of the bound pipe's cycles " +
           fixed_text(100.0 * median_abs_error, 0) + " %";
}

std::string cost_model_json(const CostModel& m) {
    json root = json::object();
    root["name"] = m.name;
    root["about"] = m.about;
    if (m.calibration.present())
        root["calibration"] = {{"gpu", m.calibration.gpu},           {"compiler", m.calibration.compiler},
                               {"set", m.calibration.set},           {"command", m.calibration.command},
                               {"fitted", m.calibration.fitted},     {"held_out", m.calibration.held_out},
                               {"spearman", m.calibration.spearman}, {"median_abs_error", m.calibration.median_abs_error}};
    root["arithmetic"] = {{"fp32_ops_per_cycle", m.fp32_ops_per_cycle},
                          {"fp16_ops_per_cycle", m.fp16_ops_per_cycle},
                          {"transcendental_cycles", m.transcendental_cycles},
                          {"branch_cycles", m.branch_cycles},
                          {"fixed_cycles", m.fixed_cycles}};
    root["texture"] = {{"samples_per_cycle", m.samples_per_cycle},
                       {"latency_cycles", m.texture_latency_cycles},
                       {"latency_hidden_share", m.latency_hidden_share},
                       {"compiler_reorders_reads", m.compiler_reorders_reads}};
    root["varying"] = {{"components_per_cycle", m.varying_components_per_cycle},
                       {"fp16_components_per_cycle", m.varying_fp16_components_per_cycle}};
    json trips = json::array();
    for (const CostModel::LoopTrips& l : m.loop_trips) trips.push_back({{"file", l.file}, {"trips", l.trips}, {"why", l.why}});
    root["loop_trips"] = trips;
    root["assumptions"] = m.assumptions;
    return root.dump(2) + "\n";
}

std::map<std::string, int> CostModel::trip_overrides() const {
    std::map<std::string, int> m;
    for (const LoopTrips& l : loop_trips) m[l.file] = l.trips;
    return m;
}

Result<CostModel> parse_cost_model(const std::string& text, const std::string& where) {
    Result<json> parsed = parse_json_object(text, where, "the cost model");
    if (!parsed) return parsed.error();
    const json& root = *parsed;
    auto fail = [&](const Error& e) { return make_error(where + ": " + e.message); };
    CostModel m;
    if (root.contains("name") && root["name"].is_string()) m.name = root["name"].get<std::string>();
    if (root.contains("about") && root["about"].is_string()) m.about = root["about"].get<std::string>();
    Result<const json*> arithmetic = member(root, "arithmetic", "$");
    if (!arithmetic) return fail(arithmetic.error());
    Result<const json*> texture = member(root, "texture", "$");
    if (!texture) return fail(texture.error());
    Result<const json*> varying = member(root, "varying", "$");
    if (!varying) return fail(varying.error());
    for (Status s : {read_number(**arithmetic, "fp32_ops_per_cycle", "$.arithmetic", m.fp32_ops_per_cycle),
                     read_number(**arithmetic, "fp16_ops_per_cycle", "$.arithmetic", m.fp16_ops_per_cycle),
                     read_number(**arithmetic, "transcendental_cycles", "$.arithmetic", m.transcendental_cycles, true),
                     read_number(**arithmetic, "branch_cycles", "$.arithmetic", m.branch_cycles, true),
                     read_number(**texture, "samples_per_cycle", "$.texture", m.samples_per_cycle),
                     read_number(**texture, "latency_cycles", "$.texture", m.texture_latency_cycles, true),
                     read_number(**texture, "latency_hidden_share", "$.texture", m.latency_hidden_share, true),
                     read_number(**varying, "components_per_cycle", "$.varying", m.varying_components_per_cycle)})
        if (!s) return fail(s.error());
    // Optional (files from before it): twice the 32-bit rate.
    m.varying_fp16_components_per_cycle = 2.0 * m.varying_components_per_cycle;
    if ((*varying)->contains("fp16_components_per_cycle")) {
        if (Status s = read_number(**varying, "fp16_components_per_cycle", "$.varying", m.varying_fp16_components_per_cycle); !s)
            return fail(s.error());
    }
    if ((*arithmetic)->contains("fixed_cycles")) {
        if (Status s = read_number(**arithmetic, "fixed_cycles", "$.arithmetic", m.fixed_cycles, true); !s) return fail(s.error());
    }
    if (root.contains("calibration")) {
        if (Status s = read_calibration(root["calibration"], m.calibration); !s) return fail(s.error());
    }
    const json& tex = **texture;
    if (tex.contains("compiler_reorders_reads")) {
        if (!tex["compiler_reorders_reads"].is_boolean())
            return make_error(where + ": $.texture.compiler_reorders_reads: must be true or false");
        m.compiler_reorders_reads = tex["compiler_reorders_reads"].get<bool>();
    }
    if (m.latency_hidden_share > 1.0) return make_error(where + ": $.texture.latency_hidden_share: must be within [0, 1]");
    if (root.contains("loop_trips")) {
        const json& trips = root["loop_trips"];
        if (!trips.is_array() || trips.size() > 256) return make_error(where + ": $.loop_trips: must be an array (at most 256)");
        for (std::size_t i = 0; i < trips.size(); ++i) {
            const std::string path = "$.loop_trips[" + std::to_string(i) + "]";
            const json& t = trips[i];
            if (!t.is_object() || !t.contains("file") || !t["file"].is_string())
                return make_error(where + ": " + path + ".file: missing or not a string");
            if (!t.contains("trips") || !t["trips"].is_number_integer() || t["trips"].get<long long>() < 0 ||
                t["trips"].get<long long>() > 65535)
                return make_error(where + ": " + path + ".trips: must be an integer within 0..65535");
            CostModel::LoopTrips l;
            l.file = t["file"].get<std::string>();
            l.trips = static_cast<int>(t["trips"].get<long long>());
            if (t.contains("why") && t["why"].is_string()) l.why = t["why"].get<std::string>();
            m.loop_trips.push_back(l);
        }
    }
    if (root.contains("assumptions")) {
        const json& a = root["assumptions"];
        if (!a.is_array()) return make_error(where + ": $.assumptions: must be an array of strings");
        for (std::size_t i = 0; i < a.size(); ++i) {
            if (!a[i].is_string()) return make_error(where + ": $.assumptions[" + std::to_string(i) + "]: must be a string");
            m.assumptions.push_back(a[i].get<std::string>());
        }
    }
    return m;
}

const CostModel& base_cost_model() {
    static const CostModel model = [] {
        Result<CostModel> m = parse_cost_model(px_generated::kEmbeddedCostModel, "profiling/costs/cost_model.json");
        // The file is checked by the unit tests; a broken one is a build defect.
        return m ? *m : CostModel{};
    }();
    return model;
}

PipeCycles estimate(const StageCost& stage, const OpCounts& path, double round_trips, const CostModel& model) {
    PipeCycles c;
    const double fp16 = std::min(path.fp16, path.arithmetic);
    c.arithmetic = (path.arithmetic - fp16) / model.fp32_ops_per_cycle + fp16 / model.fp16_ops_per_cycle +
                   path.transcendental * model.transcendental_cycles + path.branches * model.branch_cycles +
                   model.fixed_cycles;
    c.texture = path.samples / model.samples_per_cycle;
    const int relaxed = std::min(stage.relaxed_varying_components, stage.varying_components);
    c.varying = stage.stage == ShaderStage::fragment
                    ? (stage.varying_components - relaxed) / model.varying_components_per_cycle +
                          relaxed / model.varying_fp16_components_per_cycle
                    : 0.0;
    const double waits = model.compiler_reorders_reads || round_trips <= 0.0
                             ? round_trips
                             : std::max(round_trips, static_cast<double>(stage.in_order_waits));
    c.latency = waits * model.texture_latency_cycles * (1.0 - model.latency_hidden_share);
    const double busiest = std::max({c.arithmetic, c.texture, c.varying});
    c.total = busiest + c.latency;
    const std::pair<const char*, double> pipes[] = {{"A", c.arithmetic}, {"T", c.texture}, {"V", c.varying}};
    for (const auto& [name, cycles] : pipes)
        if (busiest > 0.0 && cycles >= busiest * 0.999) c.bound += (c.bound.empty() ? "" : ", ") + std::string(name);
    return c;
}

}  // namespace px::profiling
