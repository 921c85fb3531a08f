#include "parallaxes/planner/cost_table.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "parallaxes/core/text.h"

namespace px {

namespace {

using json = nlohmann::json;

// Rows are arrays, to keep the shipped file small:
// [relief, angle, technique, samples, shadow, shadow_samples, error_p95, visibility_error, cost]
constexpr int kRowFields = 9;
constexpr double kMaxTableError = 1e6;
constexpr double kMaxTableCost = 1e4;

Result<double> number_at(const json& j, const std::string& path) {
    if (!j.is_number()) return make_error(path + ": expected a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) return make_error(path + ": not finite");
    return v;
}

// One relief of the table at `path`: its name and measured features.
Result<CostTableRelief> parse_relief(const json& r, const std::string& path) {
    if (!r.is_object() || !r.contains("name") || !r["name"].is_string())
        return make_error(path + ": expected an object with a name");
    CostTableRelief relief;
    relief.name = r["name"].get<std::string>();
    for (auto [key, out] : {std::pair{"depth_texels", &relief.features.depth_texels},
                            std::pair{"steepness", &relief.features.steepness},
                            std::pair{"thinnest_texels", &relief.features.thinnest_texels},
                            std::pair{"range", &relief.features.range}}) {
        if (!r.contains(key)) return make_error(path + "." + key + ": missing");
        Result<double> v = number_at(r[key], path + "." + key);
        if (!v) return v.error();
        if (*v < 0.0) return make_error(path + "." + key + ": negative");
        *out = *v;
    }
    if (r.contains("size") && r["size"].is_array() && r["size"].size() == 2 && r["size"][0].is_number_integer() &&
        r["size"][1].is_number_integer()) {
        relief.features.width = r["size"][0].get<int>();
        relief.features.height = r["size"][1].get<int>();
    }
    if (r.contains("hash") && r["hash"].is_string())
        relief.features.field_hash = std::strtoull(r["hash"].get<std::string>().c_str(), nullptr, 16);
    return relief;
}

// One row at `path`: [relief, angle, technique, samples, shadow,
// shadow_samples, error_p95, visibility_error, cost(, light_elevation)],
// its relief an index below `relief_count`.
Result<CostSample> parse_row(const json& r, const std::string& path, size_t relief_count) {
    if (!r.is_array() || (r.size() != kRowFields && r.size() != kRowFields + 1))
        return make_error(path + ": expected [relief, angle, technique, samples, shadow, shadow_samples, "
                                 "error_p95, visibility_error, cost(, light_elevation)]");
    CostSample s;
    if (!r[0].is_number_integer() || r[0].get<long long>() < 0 ||
        r[0].get<long long>() >= static_cast<long long>(relief_count))
        return make_error(path + "[0]: not a relief index");
    s.relief = r[0].get<int>();
    Result<double> angle = number_at(r[1], path + "[1]");
    if (!angle) return angle.error();
    if (*angle < 0.0 || *angle >= 90.0) return make_error(path + "[1]: angle outside [0, 90)");
    s.angle_deg = *angle;
    if (!r[2].is_string()) return make_error(path + "[2]: expected a technique name");
    Result<Technique> technique = parse_technique(r[2].get<std::string>());
    if (!technique) return make_error(path + "[2]: " + technique.error().message);
    s.technique = *technique;
    if (!r[3].is_number_integer() || r[3].get<long long>() < 0 || r[3].get<long long>() > 65535)
        return make_error(path + "[3]: expected a sample count");
    s.samples = r[3].get<int>();
    if (!r[4].is_string()) return make_error(path + "[4]: expected a shadow mode");
    Result<ShadowMode> shadow = parse_shadow_mode(r[4].get<std::string>());
    if (!shadow) return make_error(path + "[4]: " + shadow.error().message);
    s.shadow = *shadow;
    if (!r[5].is_number_integer() || r[5].get<long long>() < 0 || r[5].get<long long>() > 255)
        return make_error(path + "[5]: expected a shadow sample count");
    s.shadow_samples = r[5].get<int>();
    double* outs[] = {&s.error_p95, &s.visibility_error, &s.cost};
    for (int k = 0; k < 3; ++k) {
        Result<double> v = number_at(r[static_cast<size_t>(6 + k)], path + "[" + std::to_string(6 + k) + "]");
        if (!v) return v.error();
        if (*v < 0.0) return make_error(path + "[" + std::to_string(6 + k) + "]: negative");
        *outs[k] = *v;
    }
    // Past these a row is not a measurement: errors of a million
    // texels, a visibility difference outside [0, 1], a variant ten
    // thousand times normal mapping's time.
    if (s.error_p95 > kMaxTableError) return make_error(path + "[6]: a hit error over 1e6 texels");
    if (s.visibility_error > 1.0) return make_error(path + "[7]: a visibility difference over 1");
    if (!(s.cost > 0.0)) return make_error(path + "[8]: the cost must be positive");
    if (s.cost > kMaxTableCost) return make_error(path + "[8]: a cost over 10000 times normal mapping's");
    if (r.size() > kRowFields) {
        Result<double> e = number_at(r[kRowFields], path + "[9]");
        if (!e) return e.error();
        if (!(*e > 0.0 && *e <= 90.0)) return make_error(path + "[9]: the light's elevation must be within (0, 90]");
        s.light_elevation_deg = *e;
    }
    return s;
}

}  // namespace

Result<CostTable> parse_cost_table(const std::string& json_text, const std::string& origin) {
    json doc = json::parse(json_text, nullptr, false, true);
    if (doc.is_discarded() || !doc.is_object()) return make_error(origin + ": not a JSON object");
    CostTable t;
    auto str = [&](const char* key, std::string& out) -> Status {
        auto it = doc.find(key);
        if (it == doc.end() || !it->is_string()) return make_error(origin + ": " + key + ": expected a string");
        out = it->get<std::string>();
        return {};
    };
    for (auto [key, out] : {std::pair{"date", &t.date}, std::pair{"renderer", &t.renderer},
                            std::pair{"version", &t.version}, std::pair{"command", &t.command}}) {
        Status s = str(key, *out);
        if (!s) return s.error();
    }
    if (doc.contains("width") && doc["width"].is_number_integer()) t.width = doc["width"].get<int>();
    if (doc.contains("height") && doc["height"].is_number_integer()) t.height = doc["height"].get<int>();
    if (doc.contains("costs")) {
        const json& costs = doc["costs"];
        if (!costs.is_string() || (costs.get<std::string>() != "measured" && costs.get<std::string>() != "table"))
            return make_error(origin + ": costs: expected \"measured\" or \"table\"");
        t.costs_measured = costs.get<std::string>() == "measured";
    }
    if (doc.contains("prices")) {
        const json& prices = doc["prices"];
        if (!prices.is_string()) return make_error(origin + ": prices: expected a string");
        t.prices = prices.get<std::string>();
        if (t.prices.size() > 1000) return make_error(origin + ": prices: longer than 1000 characters");
    }
    const json& reliefs = doc.contains("reliefs") ? doc["reliefs"] : json();
    if (!reliefs.is_array() || reliefs.empty()) return make_error(origin + ": reliefs: expected a non-empty array");
    if (reliefs.size() > kMaxCostTableReliefs)
        return make_error(origin + ": reliefs: " + std::to_string(reliefs.size()) + " reliefs, more than the " +
                          std::to_string(kMaxCostTableReliefs) + " a cost table may hold");
    for (size_t i = 0; i < reliefs.size(); ++i) {
        Result<CostTableRelief> relief = parse_relief(reliefs[i], origin + ": reliefs[" + std::to_string(i) + "]");
        if (!relief) return relief.error();
        t.reliefs.push_back(std::move(*relief));
    }
    const json& rows = doc.contains("rows") ? doc["rows"] : json();
    if (!rows.is_array()) return make_error(origin + ": rows: expected an array");
    if (rows.size() > kMaxCostTableRows)
        return make_error(origin + ": rows: " + std::to_string(rows.size()) + " rows, more than the " +
                          std::to_string(kMaxCostTableRows) + " a cost table may hold");
    for (size_t i = 0; i < rows.size(); ++i) {
        Result<CostSample> row = parse_row(rows[i], origin + ": rows[" + std::to_string(i) + "]", t.reliefs.size());
        if (!row) return row.error();
        t.rows.push_back(*row);
    }
    return t;
}

std::string cost_table_json(const CostTable& t) {
    // Written by hand, one row per line and numbers to 6 significant
    // digits, so that a regenerated table diffs well.
    auto g = [](double x) {
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, "%.6g", x);
        return std::string(buffer);
    };
    std::string out = "{\n";
    out += "  \"date\": " + json(t.date).dump() + ",\n";
    out += "  \"renderer\": " + json(t.renderer).dump() + ",\n";
    out += "  \"version\": " + json(t.version).dump() + ",\n";
    out += "  \"command\": " + json(t.command).dump() + ",\n";
    out += "  \"width\": " + std::to_string(t.width) + ", \"height\": " + std::to_string(t.height) + ",\n";
    if (!t.costs_measured) out += "  \"costs\": \"table\",\n";
    if (!t.prices.empty()) out += "  \"prices\": " + json(t.prices).dump() + ",\n";
    out += "  \"reliefs\": [\n";
    for (size_t i = 0; i < t.reliefs.size(); ++i) {
        const CostTableRelief& r = t.reliefs[i];
        out += "    {\"name\": " + json(r.name).dump() + ", \"size\": [" + std::to_string(r.features.width) + ", " +
               std::to_string(r.features.height) + "], \"depth_texels\": " + g(r.features.depth_texels) +
               ", \"steepness\": " + g(r.features.steepness) + ", \"thinnest_texels\": " + g(r.features.thinnest_texels) +
               ", \"range\": " + g(r.features.range) + ", \"hash\": \"" + hash_hex(r.features.field_hash) + "\"}" +
               (i + 1 < t.reliefs.size() ? ",\n" : "\n");
    }
    out += "  ],\n  \"rows\": [\n";
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const CostSample& s = t.rows[i];
        out += "    [" + std::to_string(s.relief) + ", " + g(s.angle_deg) + ", \"" + technique_name(s.technique) + "\", " +
               std::to_string(s.samples) + ", \"" + shadow_mode_name(s.shadow) + "\", " + std::to_string(s.shadow_samples) +
               ", " + g(s.error_p95) + ", " + g(s.visibility_error) + ", " + g(s.cost) +
               (s.shadow != ShadowMode::none ? ", " + g(s.light_elevation_deg) : std::string()) + "]" +
               (i + 1 < t.rows.size() ? ",\n" : "\n");
    }
    out += "  ]\n}\n";
    return out;
}

extern const char* const kEmbeddedCostTable;

Result<const CostTable*> builtin_cost_table() {
    static const Result<CostTable> table = parse_cost_table(kEmbeddedCostTable, "src/planner/cost_table.json");
    if (!table) return table.error();
    return &*table;
}

}  // namespace px
