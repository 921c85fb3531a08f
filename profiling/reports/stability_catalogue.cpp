#include "parallaxes/profiling/reports/stability_catalogue.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "parallaxes/core/limits.h"
#include "parallaxes/core/text.h"

// The GL-free half of the stability catalogue: reading it, judging rows,
// formatting reports (the unit tests link it without a context).
namespace px::profiling {

namespace {

using nlohmann::json;

// --- Reading the catalogue --------------------------------------------------

// Reads one JSON object, naming the JSON path in every error and refusing
// keys it does not know (a misspelt key must not be silently ignored).
class Reader {
public:
    Reader(const json& j, std::string path, std::string origin, std::string* error)
        : j_(j), path_(std::move(path)), origin_(std::move(origin)), error_(error) {
        if (!j_.is_object()) fail("must be an object");
    }
    bool ok() const { return error_->empty(); }
    const std::string& path() const { return path_; }
    void fail(const std::string& what, const std::string& key = "") {
        if (!error_->empty()) return;
        *error_ = origin_ + ": " + path_ + (key.empty() ? "" : "." + key) + ": " + what;
    }
    const json* get(const char* key) {
        seen_.insert(key);
        if (!j_.is_object()) return nullptr;
        auto it = j_.find(key);
        return it == j_.end() ? nullptr : &*it;
    }
    template <typename T>
    void number(const char* key, T& out, double lo, double hi) {
        const json* v = get(key);
        if (!v) return;
        if (!v->is_number()) return fail("must be a number", key);
        const double d = v->get<double>();
        if (!(d >= lo && d <= hi)) return fail("must be within " + num(lo) + ".." + num(hi) + ", got " + num(d), key);
        if constexpr (std::is_integral_v<T>) {
            if (d != std::floor(d)) return fail("must be a whole number, got " + num(d), key);
        }
        out = static_cast<T>(d);
    }
    void text(const char* key, std::string& out) {
        const json* v = get(key);
        if (!v) return;
        if (!v->is_string()) return fail("must be a string", key);
        out = v->get<std::string>();
    }
    void boolean(const char* key, bool& out) {
        const json* v = get(key);
        if (!v) return;
        if (!v->is_boolean()) return fail("must be true or false", key);
        out = v->get<bool>();
    }
    template <int N>
    void vec(const char* key, glm::vec<N, float>& out, double bound) {
        const json* v = get(key);
        if (!v) return;
        if (!v->is_array() || v->size() != N) return fail("must be an array of " + std::to_string(N) + " numbers", key);
        for (int i = 0; i < N; ++i) {
            const json& e = (*v)[static_cast<size_t>(i)];
            if (!e.is_number() || !(std::fabs(e.get<double>()) <= bound))
                return fail("components must be numbers within ±" + num(bound), key);
            out[i] = e.get<float>();
        }
    }
    void finish() {
        if (!ok() || !j_.is_object()) return;
        for (auto it = j_.begin(); it != j_.end(); ++it)
            if (!seen_.count(it.key())) return fail("unknown key '" + echo(it.key()) + "'");
    }
    Reader child(const char* key) {
        const json* v = get(key);
        static const json empty = json::object();
        return Reader(v ? *v : empty, path_ + "." + key, origin_, error_);
    }
    bool has(const char* key) const { return j_.is_object() && j_.contains(key); }

    static std::string num(double d) {
        char b[32];
        std::snprintf(b, sizeof b, "%g", d);
        return b;
    }

private:
    const json& j_;
    std::string path_, origin_;
    std::string* error_;
    std::set<std::string> seen_;
};

Result<BoundKind> parse_bound_kind(const std::string& s) {
    static const std::map<std::string, BoundKind> kinds = {
        {"zero", BoundKind::zero},     {"limited", BoundKind::limited},           {"parallax", BoundKind::parallax},
        {"step", BoundKind::step},     {"refined_step", BoundKind::refined_step}, {"exact", BoundKind::exact}};
    auto it = kinds.find(s);
    if (it == kinds.end())
        return make_error("unknown bound '" + echo(s) + "' (known: zero, limited, parallax, step, refined_step, exact)");
    return it->second;
}

void read_field(Reader r, FieldSpec& f) {
    std::string kind;
    r.text("kind", kind);
    if (!kind.empty()) {
        Result<FieldKind> k = parse_field_kind(kind);
        if (!k) return r.fail(k.error().message, "kind");
        f.kind = *k;
    }
    r.number("size", f.size, 1, kMaxTextureSize);
    r.number("level", f.level, 0, 1);
    r.number("count", f.count, 1, 256);
    r.number("frequency", f.frequency, 0, 256);
    r.number("mortar", f.mortar, 0, 0.5);
    r.number("line_width", f.line_width, 1, 256);
    r.number("radius", f.radius, 0, 0.5);
    r.text("text", f.text);
    r.finish();
}

// The relief, the angles and distances it is seen from, the camera.
void read_case_view(Reader& r, StabilityCase& c) {
    if (r.has("field")) read_field(r.child("field"), c.field);
    if (r.has("image")) {
        Reader im = r.child("image");
        int w = 0, h = 0;
        im.number("width", w, 1, kMaxTextureSize);
        im.number("height", h, 1, kMaxTextureSize);
        im.finish();
        if (w < 1 || h < 1) im.fail("needs width and height");
        c.image_width = w;
        c.image_height = h;
    }
    r.number("height_scale", c.height_scale, 0, kMaxHeightScale);
    if (r.has("height_bias")) {
        float b = 0;
        r.number("height_bias", b, -kMaxHeightScale, kMaxHeightScale);
        c.height_bias = b;
    }
    if (r.has("angle")) {
        double a = 0;
        r.number("angle", a, 0, 90);
        c.angles = {a};
    }
    if (const json* a = r.get("angles")) {
        if (!a->is_array() || a->empty() || a->size() > 64) return r.fail("must be an array of 1 to 64 angles", "angles");
        c.angles.clear();
        for (const json& e : *a) {
            if (!e.is_number() || !(e.get<double>() >= 0 && e.get<double>() <= 90))
                return r.fail("angles are degrees within 0..90", "angles");
            c.angles.push_back(e.get<double>());
        }
    }
    r.boolean("sweep", c.sweep);
    if (const json* d = r.get("distances")) {
        if (!d->is_array() || d->size() < 2 || d->size() > 64)
            return r.fail("must be an array of 2 to 64 distances", "distances");
        c.distances.clear();
        for (const json& e : *d) {
            if (!e.is_number() || !(e.get<double>() > 0 && e.get<double>() <= 1000))
                return r.fail("distances must be within (0, 1000]", "distances");
            c.distances.push_back(e.get<double>());
        }
    }
    r.number("distance", c.distance, 1e-4, 1000);
    r.number("azimuth", c.azimuth_deg, -360, 360);
    if (r.has("camera")) {
        Reader cam = r.child("camera");
        glm::vec3 p(0.0f), t(0.0f);
        cam.vec<3>("position", p, 1000);
        cam.vec<3>("target", t, 1000);
        cam.finish();
        c.camera_position = p;
        c.camera_target = t;
    }
}

// The frame: mesh, search, light and shadow, uv, model, LOD.
void read_case_draw(Reader& r, StabilityCase& c) {
    r.number("fov", c.fov_deg, 1, 170);
    r.number("plane_size", c.plane_size, kMinExtent, kMaxExtent);
    r.number("segments", c.segments, 1, 256);
    r.number("samples", c.samples, 1, 256);
    r.number("refine_steps", c.refine_steps, 0, 16);
    if (r.has("light")) {
        Reader l = r.child("light");
        l.number("elevation", c.light_elevation_deg, -90, 90);
        l.number("azimuth", c.light_azimuth_deg, -360, 360);
        l.finish();
    }
    std::string shadow;
    r.text("shadow", shadow);
    if (!shadow.empty()) {
        Result<ShadowMode> m = parse_shadow_mode(shadow);
        if (!m) return r.fail(m.error().message, "shadow");
        c.shadow = *m;
    }
    if (r.has("uv")) {
        Reader uv = r.child("uv");
        uv.vec<2>("scale", c.uv.scale, 1e5);
        uv.vec<2>("offset", c.uv.offset, 1e5);
        uv.number("rotation", c.uv.rotation_deg, -3600, 3600);
        uv.finish();
    }
    r.vec<3>("model_scale", c.model_scale, 1e4);
    for (auto [key, slot] : {std::pair{"tangent", &c.tangent}, std::pair{"normal", &c.normal}}) {
        if (!r.has(key)) continue;
        glm::vec3 v(0.0f);
        r.vec<3>(key, v, 1e5);
        *slot = v;
    }
    if (r.has("lod")) {
        Reader l = r.child("lod");
        c.lod = true;
        l.number("threshold", c.lod_threshold, 0, 16);
        l.number("band", c.lod_band, 0.01, 16);
        l.finish();
    }
    if (r.has("exact_view")) {
        bool e = false;
        r.boolean("exact_view", e);
        c.exact_view = e;
    }
}

// The techniques it runs and the limits each shows.
void read_case_techniques(Reader& r, StabilityCase& c) {
    if (const json* t = r.get("techniques")) {
        if (!t->is_array()) return r.fail("must be an array of technique names", "techniques");
        for (const json& e : *t) {
            if (!e.is_string() || !parse_technique(e.get<std::string>()))
                return r.fail("unknown technique (known: " + technique_names_joined() + ")", "techniques");
            c.techniques.push_back(e.get<std::string>());
        }
    }
    if (r.has("limits")) {
        const json* l = r.get("limits");
        if (!l->is_object()) return r.fail("must map technique names to the limit each shows", "limits");
        for (auto it = l->begin(); it != l->end(); ++it) {
            if (!parse_technique(it.key()))
                return r.fail("unknown technique '" + echo(it.key()) + "'", "limits");
            if (!it->is_string() || it->get<std::string>().empty())
                return r.fail("each limit is a sentence saying what the technique cannot do", "limits." + it.key());
            c.limits[it.key()] = it->get<std::string>();
        }
    }
}

void read_case(Reader r, StabilityCase& c, bool defaults) {
    if (!defaults) {
        r.text("name", c.name);
        if (c.name.empty()) r.fail("every case needs a name", "name");
        r.text("why", c.why);
    }
    read_case_view(r, c);
    read_case_draw(r, c);
    read_case_techniques(r, c);
    r.boolean("expect_dark", c.expect_dark);
    r.boolean("full_only", c.full_only);
    r.number("quick_stride", c.quick_stride, 1, 64);
    r.finish();
    if (!defaults && c.sweep && c.angles.size() < 2) r.fail("a sweep needs at least two angles", "angles");
}

}  // namespace

// The catalogue's text, embedded by CMake (generated/stability_catalogue.cpp).
extern const char* const kEmbeddedCatalogue;

const std::string& embedded_catalogue_text() {
    static const std::string text = kEmbeddedCatalogue;
    return text;
}

Result<Catalogue> parse_catalogue(const std::string& text, const std::string& origin) {
    json root;
    try {
        root = json::parse(text, nullptr, true, /*ignore_comments=*/true);
    } catch (const json::parse_error& e) {
        return make_error(origin + ": not valid JSON: " + echo(e.what(), 200));
    }
    std::string error;
    Catalogue cat;
    Reader top(root, "catalogue", origin, &error);
    {
        Reader b = top.child("bounds");
        b.number("slack_texels", cat.bounds.slack_texels, 0, 100);
        b.number("offset_relative_slack", cat.bounds.offset_relative_slack, 0, 1);
        b.number("violation_share", cat.bounds.violation_share, 0, 1);
        b.number("crest_flip_height", cat.bounds.crest_flip_height, 0, 1);
        Reader t = b.child("techniques");
        for (const TechniqueInfo& info : technique_table()) {
            if (!t.has(info.name)) {
                t.fail(std::string("no bounds for technique '") + info.name + "'");
                break;
            }
            Reader one = t.child(info.name);
            TechniqueBounds tb;
            for (auto [key, slot] : {std::pair{"error", &tb.error}, std::pair{"offset", &tb.offset}}) {
                std::string kind;
                one.text(key, kind);
                Result<BoundKind> k = parse_bound_kind(kind);
                if (!k) {
                    one.fail(k.error().message, key);
                    break;
                }
                *slot = *k;
            }
            one.finish();
            cat.bounds.techniques[info.name] = tb;
        }
        t.finish();
        b.finish();
    }
    StabilityCase defaults;
    if (top.has("defaults")) read_case(top.child("defaults"), defaults, true);
    const json* cases = top.get("cases");
    if (error.empty() && (!cases || !cases->is_array() || cases->empty()))
        top.fail("needs a non-empty array of cases", "cases");
    std::set<std::string> names;
    if (error.empty()) {
        for (size_t i = 0; i < cases->size() && error.empty(); ++i) {
            StabilityCase c = defaults;
            read_case(Reader((*cases)[i], "catalogue.cases[" + std::to_string(i) + "]", origin, &error), c, false);
            if (!error.empty()) break;
            if (!names.insert(c.name).second) {
                error = origin + ": catalogue.cases[" + std::to_string(i) + "].name: '" + echo(c.name) +
                        "' names another case too";
                break;
            }
            cat.cases.push_back(std::move(c));
        }
    }
    top.finish();
    if (!error.empty()) return make_error(error);
    return cat;
}

void judge(StabilityRow& row, const CatalogueBounds& bounds, const StabilityCase& c) {
    std::vector<std::string> failed;
    std::vector<std::string> limit;
    if (row.non_finite > 0) failed.push_back(std::to_string(row.non_finite) + " pixels NaN or Inf");
    if (row.offset_violations > 0)
        failed.push_back(std::to_string(row.offset_violations) + " pixels past the offset bound (max ratio " +
                         Reader::num(row.offset_ratio_max) + ")");
    if (row.dark_max > 0.0) failed.push_back("lit by a light below the horizon (visibility " + Reader::num(row.dark_max) + ")");
    // Accuracy is judged at fp32 (the native run and the fp32 emulation);
    // at fp16 and lowp the growth of the error is the finding, reported.
    const bool judged = row.precision == "native" || row.precision == "fp32";
    // On its own rays where they were read back (StabilityRow::own_error_mean).
    const bool own = row.own_error_mean >= 0.0;
    const double error_mean = own ? row.own_error_mean : row.error_mean;
    const double error_violations = own ? row.own_violations : row.error_violations;
    const double nominal_violations = own ? row.own_nominal_violations : row.nominal_violations;
    std::string own_note;
    if (judged && row.pixels > 0) {
        const std::string on = own ? " on its own rays" : "";
        // The derived bound holds whatever the technique's limits: past it
        // is a bug.
        if (error_mean > row.error_bound_mean)
            failed.push_back("mean error" + on + " " + Reader::num(error_mean) + " past its bound " +
                             Reader::num(row.error_bound_mean));
        if (error_violations > bounds.violation_share)
            failed.push_back(Reader::num(100.0 * error_violations) + " % of pixels past their error bound" + on);
        // What the camera's rays would have said: the rasteriser's share, named.
        if (own && (row.error_mean > row.error_bound_mean || row.error_violations > bounds.violation_share))
            own_note = "judged on its own rays (mean " + Reader::num(row.own_error_mean) + " texels, " +
                       Reader::num(100.0 * row.own_violations) + " % past); against the camera's rays mean " +
                       Reader::num(row.error_mean) + ", " + Reader::num(100.0 * row.error_violations) +
                       " % past: the rasteriser's inputs";
        if (row.continuity_max >= 0.0 && row.continuity_violations > bounds.violation_share)
            failed.push_back(Reader::num(100.0 * row.continuity_violations) +
                             " % of pixels jump past their continuity bound (max " + Reader::num(row.continuity_max) +
                             " texels)");
        // The nominal bound: missing it is a limit, which the case must name.
        const bool missed = error_mean > row.nominal_bound_mean || nominal_violations > bounds.violation_share;
        auto it = c.limits.find(row.technique);
        if (missed) {
            const std::string figure = "mean" + on + " " + Reader::num(error_mean) + " texels against " +
                                       Reader::num(row.nominal_bound_mean) + ", " +
                                       Reader::num(100.0 * nominal_violations) + " % of pixels past";
            if (it != c.limits.end())
                limit.push_back(it->second + " (" + figure + ")");
            else
                failed.push_back("misses its nominal bound (" + figure +
                                 "): a limit the catalogue does not document");
        }
    }
    std::string reasons;
    if (!failed.empty()) {
        row.verdict = "fail";
        for (const std::string& f : failed) reasons += (reasons.empty() ? "" : "; ") + f;
        if (!limit.empty()) reasons += "; (limit: " + limit.front() + ")";
    } else if (!limit.empty()) {
        row.verdict = "limit";
        reasons = limit.front();
    } else {
        row.verdict = row.pixels > 0 || row.non_finite > 0 ? "pass" : "n/a";
        if (row.verdict == "n/a") reasons = "nothing covered (no NaN, nothing to measure)";
    }
    if (!own_note.empty()) reasons = reasons.empty() ? own_note : reasons + "; " + own_note;
    row.reasons = reasons;
}

bool glob_match(const std::string& pattern, const std::string& text) {
    const bool wild = pattern.find_first_of("*?") != std::string::npos;
    if (!wild) return text.find(pattern) != std::string::npos;
    // Iterative glob with backtracking to the last star.
    size_t p = 0, t = 0, star = std::string::npos, mark = 0;
    while (t < text.size()) {
        if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == text[t])) {
            ++p;
            ++t;
        } else if (p < pattern.size() && pattern[p] == '*') {
            star = p++;
            mark = t;
        } else if (star != std::string::npos) {
            p = star + 1;
            t = ++mark;
        } else {
            return false;
        }
    }
    while (p < pattern.size() && pattern[p] == '*') ++p;
    return p == pattern.size();
}

namespace {

std::string fixed(double v, int digits = 3) {
    if (!std::isfinite(v)) return "-";
    char b[48];
    if (v != 0.0 && std::fabs(v) < 1e-3)
        std::snprintf(b, sizeof b, "%.1e", v);
    else
        std::snprintf(b, sizeof b, "%.*f", digits, v);
    return b;
}

std::string continuity_text(const StabilityRow& r) {
    if (r.continuity_max < 0.0) return "-";
    return fixed(r.continuity_max) + " (" + fixed(100.0 * r.continuity_violations, 1) + "%)";
}

}  // namespace

std::string format_table(const std::vector<StabilityRow>& rows) {
    std::ostringstream o;
    char line[512];
    std::snprintf(line, sizeof line, "%-26s %-14s %-4s %-8s %9s %9s %9s %6s %8s %17s %-6s %s\n", "case", "technique", "ctx",
                  "precision", "max err", "mean err", "bound", "NaN", "offset", "continuity", "verdict", "why");
    o << line;
    for (const StabilityRow& r : rows) {
        std::snprintf(line, sizeof line, "%-26s %-14s %-4s %-8s %9s %9s %9s %6ld %8s %17s %-6s %s\n",
                      r.case_name.c_str(), r.technique.c_str(), r.context.c_str(), r.precision.c_str(),
                      fixed(r.error_max).c_str(), fixed(r.error_mean).c_str(), fixed(r.error_bound_mean).c_str(),
                      r.non_finite, fixed(r.offset_ratio_max, 2).c_str(), continuity_text(r).c_str(),
                      r.verdict.c_str(), echo(r.reasons, 160).c_str());
        o << line;
    }
    return o.str();
}

std::string format_markdown(const std::vector<StabilityRow>& rows, const std::string& command) {
    std::ostringstream o;
    o << "Command: `" << command << "`\n\n";
    long counts[4] = {0, 0, 0, 0};
    for (const StabilityRow& r : rows)
        counts[r.verdict == "pass" ? 0 : r.verdict == "limit" ? 1 : r.verdict == "fail" ? 2 : 3]++;
    o << "**" << rows.size() << " rows:** " << counts[0] << " pass, " << counts[1] << " documented limits, "
      << counts[2] << " fail, " << counts[3] << " with nothing covered.\n\n";

    o << "### Failures\n\n";
    bool any = false;
    for (const StabilityRow& r : rows) {
        if (r.verdict != "fail") continue;
        if (!any) o << "| case | technique | ctx | precision | why |\n| --- | --- | --- | --- | --- |\n";
        any = true;
        o << "| " << r.case_name << " | " << r.technique << " | " << r.context << " | " << r.precision << " | "
          << r.reasons << " |\n";
    }
    if (!any) o << "None.\n";

    o << "\n### Documented limits, measured\n\n";
    o << "| case | technique | ctx | precision | mean err (texels) | its bound | max err | why |\n";
    o << "| --- | --- | --- | --- | ---: | ---: | ---: | --- |\n";
    for (const StabilityRow& r : rows) {
        if (r.verdict != "limit") continue;
        o << "| " << r.case_name << " | " << r.technique << " | " << r.context << " | " << r.precision << " | "
          << fixed(r.error_mean) << " | " << fixed(r.error_bound_mean) << " | " << fixed(r.error_max) << " | "
          << r.reasons << " |\n";
    }

    // Precision: the mean error of each case and technique under every
    // precision measured, side by side (NaN counts beside, where any).
    std::vector<std::string> precisions;
    for (const StabilityRow& r : rows)
        if (std::find(precisions.begin(), precisions.end(), r.precision) == precisions.end())
            precisions.push_back(r.precision);
    if (precisions.size() > 1) {
        o << "\n### Mean hit error (texels) by precision\n\n";
        o << "native: the driver with the shaders' declarations in force; fp32: everything highp (the "
             "shader rewritten without rounding); fp16, lowp, nohighp: emulated (docs/stability.md).\n\n";
        o << "| case | technique | ctx |";
        for (const std::string& p : precisions) o << " " << p << " |";
        o << "\n| --- | --- | --- |";
        for (size_t i = 0; i < precisions.size(); ++i) o << " ---: |";
        o << "\n";
        std::vector<std::string> keys;
        std::map<std::string, std::map<std::string, const StabilityRow*>> table;
        for (const StabilityRow& r : rows) {
            const std::string key = r.case_name + " | " + r.technique + " | " + r.context;
            if (!table.count(key)) keys.push_back(key);
            table[key][r.precision] = &r;
        }
        for (const std::string& key : keys) {
            o << "| " << key << " |";
            for (const std::string& p : precisions) {
                auto it = table[key].find(p);
                if (it == table[key].end()) {
                    o << " |";
                    continue;
                }
                const StabilityRow& r = *it->second;
                o << " " << (r.pixels ? fixed(r.error_mean) : std::string("-"));
                if (r.non_finite) o << " (" << r.non_finite << " NaN)";
                if (r.verdict == "fail") o << " **fail**";
                o << " |";
            }
            o << "\n";
        }
    }

    o << "\nEvery row, with its offset and continuity figures: `--format table` or `--format json`.\n";
    return o.str();
}

std::string format_json(const std::vector<StabilityRow>& rows) {
    json out = json::array();
    for (const StabilityRow& r : rows) {
        json j;
        j["case"] = r.case_name;
        j["technique"] = r.technique;
        j["context"] = r.context;
        j["precision"] = r.precision;
        j["pixels"] = r.pixels;
        j["non_finite"] = r.non_finite;
        j["error_max_texels"] = r.error_max;
        j["error_mean_texels"] = r.error_mean;
        j["error_bound_mean_texels"] = r.error_bound_mean;
        j["error_violation_share"] = r.error_violations;
        j["offset_ratio_max"] = r.offset_ratio_max;
        j["offset_violations"] = r.offset_violations;
        if (r.continuity_max >= 0.0) {
            j["continuity_max_texels"] = r.continuity_max;
            j["continuity_violation_share"] = r.continuity_violations;
            j["crest_flips"] = r.crest_flips;
        }
        if (r.dark_max >= 0.0) j["dark_max_visibility"] = r.dark_max;
        if (r.own_error_mean >= 0.0) {
            j["own_ray_error_mean_texels"] = r.own_error_mean;
            j["own_ray_error_max_texels"] = r.own_error_max;
            j["own_ray_error_violation_share"] = r.own_violations;
        }
        j["verdict"] = r.verdict;
        j["reasons"] = r.reasons;
        out.push_back(j);
    }
    return out.dump(1) + "\n";
}

}  // namespace px::profiling
