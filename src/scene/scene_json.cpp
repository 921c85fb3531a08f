// Scene files: JSON text -> SceneDesc. Errors name the origin plus the line
// and column for malformed JSON, or the JSON path of the offending field
// otherwise; the format is described in docs/scene-format.md. The value
// checks are scene.cpp's validate_scene.
#include "parallaxes/scene/scene.h"
#include "parallaxes/core/text.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <memory>
#include <set>
#include <sstream>
#include <string_view>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "parallaxes/core/files.h"
#include "parallaxes/core/limits.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/scene/scene_format.h"

namespace px {

namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

// The material an object without "material" uses; created with the defaults
// below when the scene does not define it.
constexpr const char* kDefaultMaterial = "default";

using namespace scene_format;

// How a JSON value reads after "got": the type, and the value when short.
std::string describe(const json& j) {
    switch (j.type()) {
        case json::value_t::null: return "null";
        case json::value_t::boolean: return j.get<bool>() ? "boolean true" : "boolean false";
        case json::value_t::string: {
            return "string \"" + echo(j.get<std::string>(), 40) + "\"";
        }
        case json::value_t::number_integer:
        case json::value_t::number_unsigned: return "integer " + j.dump();
        case json::value_t::number_float: return "number " + num(j.get<double>());
        case json::value_t::array: return "array of " + std::to_string(j.size());
        case json::value_t::object: return "object";
        default: return j.type_name();
    }
}

// Levenshtein distance, case-insensitive: "did you mean" for misspelt keys.
std::size_t edit_distance(std::string_view a, std::string_view b) {
    const auto lower = [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); };
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            const std::size_t substitute = diagonal + (lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1);
            row[j] = std::min({above + 1, row[j - 1] + 1, substitute});
            diagonal = above;
        }
    }
    return row[b.size()];
}

std::string unknown_field_message(const std::string& key, const std::string& path,
                                  const std::vector<std::string>& known) {
    std::string message = "unknown field '" + echo(key) + "' " + (path.empty() ? "at the top level" : "in " + path);
    std::string_view best;
    std::size_t best_distance = 3;  // suggest only within an edit distance of 2
    for (const std::string& k : known) {
        // The edit distance is at least the difference in length: skip the
        // quadratic search for a key that cannot be within 2 edits (a
        // hostile 10 MB key costs nothing).
        if (key.size() > k.size() + 2 || k.size() > key.size() + 2) continue;
        const std::size_t d = edit_distance(key, k);
        if (d < best_distance) {
            best = k;
            best_distance = d;
        }
    }
    if (!best.empty()) message += " (did you mean '" + std::string(best) + "'?)";
    return message;
}

// nlohmann reports the 1-based index of the last byte it read (size + 1 at the
// end of input); the offending character is the one before that index.
// Columns count characters, not UTF-8 continuation bytes, as editors do.
std::pair<std::size_t, std::size_t> line_column(const std::string& text, std::size_t byte) {
    const std::size_t end = std::min(byte > 0 ? byte - 1 : 0, text.size());
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < end; ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c == '\n') {
            ++line;
            column = 1;
        } else if ((c & 0xC0) != 0x80) {
            ++column;
        }
    }
    return {line, column};
}

// nlohmann's what() is "[json.exception.parse_error.101] parse error at line L,
// column C: <reason>"; we give our own position, so keep only the reason.
std::string parse_error_reason(const json::parse_error& e) {
    const std::string what = e.what();
    const std::size_t at = what.find("parse error");
    const std::size_t colon = at == std::string::npos ? std::string::npos : what.find(": ", at);
    std::string reason = colon == std::string::npos ? what : what.substr(colon + 2);
    // "...; last read: '<the token so far>'" quotes the whole token, which an
    // unterminated string or comment makes as long as the file: keep its start.
    const std::string marker = "; last read: '";
    const std::size_t last = reason.find(marker);
    if (last != std::string::npos) {
        std::string token = reason.substr(last + marker.size());
        if (!token.empty() && token.back() == '\'') token.pop_back();
        reason = reason.substr(0, last) + marker + echo(token, 40) + "'";
    }
    return echo(reason, 400);
}

// nlohmann keeps the last of repeated keys silently; a repeated
// "height_scale" is a likely editing slip, so this parser callback records
// the first repeat and the JSON path of the object that holds it.
class DuplicateKeyFinder {
public:
    bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
        switch (event) {
            case json::parse_event_t::object_start:
            case json::parse_event_t::array_start:
                enter_element();
                frames_.push_back(Frame{event == json::parse_event_t::array_start, 0, {}, {}});
                break;
            case json::parse_event_t::object_end:
            case json::parse_event_t::array_end:
                frames_.pop_back();
                break;
            case json::parse_event_t::key: {
                Frame& top = frames_.back();
                top.key = parsed.get<std::string>();
                if (!top.keys.insert(top.key).second && message_.empty()) {
                    const std::string path = object_path();
                    message_ = "duplicate field '" + echo(top.key) + "' " +
                               (path.empty() ? "at the top level" : "in " + path);
                }
                break;
            }
            case json::parse_event_t::value:
                enter_element();
                break;
        }
        return true;
    }
    const std::string& message() const { return message_; }

private:
    struct Frame {
        bool is_array;
        std::size_t count;     // arrays: elements begun so far
        std::string key;       // objects: the key being read
        std::set<std::string> keys;
    };

    void enter_element() {
        if (!frames_.empty() && frames_.back().is_array) ++frames_.back().count;
    }
    // Path of the innermost object: each enclosing frame contributes the key or
    // index that leads into the next.
    std::string object_path() const {
        std::string path;
        for (std::size_t i = 0; i + 1 < frames_.size(); ++i)
            path = frames_[i].is_array ? index_path(path, frames_[i].count - 1) : field_path(path, frames_[i].key);
        return path;
    }

    std::vector<Frame> frames_;
    std::string message_;
};

// --- Named values -----------------------------------------------------------------

Result<LightKind> parse_light_kind(const std::string& name) {
    if (name == "directional") return LightKind::directional;
    if (name == "point") return LightKind::point;
    return make_error("unknown light type '" + echo(name) + "' (known: directional, point)");
}

Result<HeightConvention> parse_convention(const std::string& name) {
    if (name == "height") return HeightConvention::height;
    if (name == "depth") return HeightConvention::depth;
    return make_error("unknown height convention '" + echo(name) + "' (known: height, depth)");
}

// --- Reading JSON -----------------------------------------------------------------

// Typed reads that record the first error; once one is recorded every later
// read is skipped, so the parser reads straight through and reports that one.
class Reader {
public:
    explicit Reader(std::string origin) : origin_(std::move(origin)) {}

    bool failed() const { return error_.has_value(); }
    const Error& error() const { return *error_; }
    void fail(const std::string& path, const std::string& what) { fail_message(path + ": " + what); }
    void fail_message(const std::string& message) {
        if (!error_) error_ = make_error(origin_ + ": " + message);
    }

    void value(const json& j, const std::string& path, float& out) {
        if (failed()) return;
        if (!j.is_number()) return fail(path, "expected a number, got " + describe(j));
        const double d = j.get<double>();
        // Finite as a double may still overflow a float (1e39).
        const auto f = static_cast<float>(d);
        if (!std::isfinite(f)) return fail(path, "expected a finite number, got " + num(d));
        out = f;
    }

    void value(const json& j, const std::string& path, int& out) {
        if (failed()) return;
        const auto range_error = [&] { fail(path, "integer " + j.dump() + " is out of range"); };
        if (j.is_number_unsigned()) {
            const auto u = j.get<std::uint64_t>();
            if (u > static_cast<std::uint64_t>(INT_MAX)) return range_error();
            out = static_cast<int>(u);
        } else if (j.is_number_integer()) {
            const auto i = j.get<std::int64_t>();
            if (i < INT_MIN || i > INT_MAX) return range_error();
            out = static_cast<int>(i);
        } else if (j.is_number_float() && std::floor(j.get<double>()) == j.get<double>() &&
                   std::abs(j.get<double>()) <= INT_MAX) {
            out = static_cast<int>(j.get<double>());  // 32.0 from a tool that writes every number as a float
        } else {
            fail(path, "expected an integer, got " + describe(j));
        }
    }

    void value(const json& j, const std::string& path, bool& out) {
        if (failed()) return;
        if (!j.is_boolean()) return fail(path, "expected true or false, got " + describe(j));
        out = j.get<bool>();
    }

    void value(const json& j, const std::string& path, std::string& out) {
        if (failed()) return;
        if (!j.is_string()) return fail(path, "expected a string, got " + describe(j));
        out = j.get<std::string>();
    }

    template <glm::length_t N>
    void value(const json& j, const std::string& path, glm::vec<N, float, glm::defaultp>& out) {
        if (failed()) return;
        if (!j.is_array() || j.size() != static_cast<std::size_t>(N))
            return fail(path, "expected an array of " + std::to_string(N) + " numbers, got " + describe(j));
        glm::vec<N, float, glm::defaultp> v;
        for (glm::length_t i = 0; i < N; ++i)
            value(j[static_cast<std::size_t>(i)], index_path(path, static_cast<std::size_t>(i)), v[i]);
        if (!failed()) out = v;
    }

    // A scale: one number for all components, or one per component.
    template <glm::length_t N>
    void scale(const json& j, const std::string& path, glm::vec<N, float, glm::defaultp>& out) {
        if (failed()) return;
        if (j.is_number()) {
            float s = 1.0f;
            value(j, path, s);
            if (!failed()) out = glm::vec<N, float, glm::defaultp>(s);
        } else if (j.is_array()) {
            value(j, path, out);
        } else {
            fail(path, "expected a number or an array of " + std::to_string(N) + " numbers, got " + describe(j));
        }
    }

    // A string naming one of an enumeration; the parse function's message lists the names.
    template <typename T>
    void named(const json& j, const std::string& path, Result<T> (*parse)(const std::string&), T& out) {
        std::string name;
        value(j, path, name);
        if (failed()) return;
        Result<T> parsed = parse(name);
        if (!parsed) return fail(path, parsed.error().message);
        out = *parsed;
    }

    // Calls read(element, path) for each element of an array.
    template <typename F>
    void each(const json& j, const std::string& path, F&& read) {
        if (failed()) return;
        if (!j.is_array()) return fail(path, "expected an array, got " + describe(j));
        for (std::size_t i = 0; i < j.size() && !failed(); ++i) read(j[i], index_path(path, i));
    }

private:
    std::string origin_;
    std::optional<Error> error_;
};

// One JSON object at a path. The keys it may hold are the keys read from it:
// every get, has and read records its key, and when the reading is done
// (finish(), or at the end of the scope) any other key in the object is an
// unknown field, with a did-you-mean among the recorded ones. So each key is
// written once, where it is read. A null `j` stands for an absent object,
// whose reads keep their defaults.
class Fields {
public:
    Fields(Reader& r, const json* j, std::string path) : r_(r), path_(std::move(path)) {
        if (!j || r_.failed()) return;
        if (!j->is_object()) {
            r_.fail(path_, "expected an object, got " + describe(*j));
            return;
        }
        j_ = j;
    }
    ~Fields() { finish(); }
    Fields(const Fields&) = delete;
    Fields& operator=(const Fields&) = delete;

    // Reports the first key of the object that no read asked for.
    void finish() {
        if (!j_ || finished_) return;
        finished_ = true;
        if (r_.failed()) return;
        for (auto it = j_->begin(); it != j_->end(); ++it)
            if (std::find(asked_.begin(), asked_.end(), it.key()) == asked_.end()) {
                r_.fail_message(unknown_field_message(it.key(), path_, asked_));
                return;
            }
    }

    const json* get(const std::string& key) {
        if (std::find(asked_.begin(), asked_.end(), key) == asked_.end()) asked_.push_back(key);
        if (!j_ || r_.failed()) return nullptr;
        const auto it = j_->find(key);
        return it == j_->end() ? nullptr : &*it;
    }
    bool has(const std::string& key) { return get(key) != nullptr; }
    std::string sub(const std::string& key) const { return field_path(path_, key); }

    template <typename T>
    void read(const std::string& key, T& out) {
        if (const json* v = get(key)) r_.value(*v, sub(key), out);
    }
    template <typename T>
    void read_scale(const std::string& key, T& out) {
        if (const json* v = get(key)) r_.scale(*v, sub(key), out);
    }
    template <typename T>
    void read_named(const std::string& key, Result<T> (*parse)(const std::string&), T& out) {
        if (const json* v = get(key)) r_.named(*v, sub(key), parse, out);
    }

private:
    Reader& r_;
    std::string path_;
    const json* j_ = nullptr;
    std::vector<std::string> asked_;
    bool finished_ = false;
};

MaterialDesc default_material(std::string name) {
    MaterialDesc m;
    m.name = std::move(name);
    m.albedo.kind = TextureSource::Kind::color;
    m.albedo.color = glm::vec3(0.8f);
    m.height.kind = TextureSource::Kind::procedural;
    m.height.field.kind = FieldKind::flat;
    m.height.field.level = 1.0f;
    return m;
}

// Which slot a source fills: what its keys may say. `any`: a scratch read
// that records every key some slot knows.
enum class Slot { albedo, height, normal, any };
bool fills(Slot slot, Slot wanted) { return slot == wanted || slot == Slot::any; }

// One word-valued key of a file source: allowed in the `wanted` slot only
// (else `wrong_slot`), and one of `words` (else the word and `unknown`).
template <typename T>
void read_word(Reader& r, Fields& f, const char* key, Slot slot, Slot wanted, const char* wrong_slot,
               std::initializer_list<std::pair<const char*, T>> words, T& out, const char* unknown) {
    if (r.failed() || !f.has(key)) return;
    if (!fills(slot, wanted)) return r.fail(f.sub(key), wrong_slot);
    std::string word;
    f.read(key, word);
    if (r.failed()) return;
    for (const auto& [name, value] : words)
        if (word == name) {
            out = value;
            return;
        }
    r.fail(f.sub(key), "\"" + echo(word) + "\" " + unknown);
}

// The three object forms of a texture source. Each reads its own keys; a
// source in no known form reads all three into a scratch value, so that the
// keys any form knows are recorded and only truly unknown ones are reported.
void read_file_form(Reader& r, Fields& f, Slot slot, TextureSource& out) {
    f.read("file", out.path);
    if (f.has("convention") && !fills(slot, Slot::height))
        return r.fail(f.sub("convention"), "only a height map has a convention (height or depth)");
    f.read_named("convention", parse_convention, out.convention);
    using Source = TextureSource;
    read_word(r, f, "channel", slot, Slot::height, "only a height map names a channel (where in the file its height is)",
              {{"grey", Source::Channel::grey}, {"r", Source::Channel::r}, {"g", Source::Channel::g},
               {"b", Source::Channel::b}, {"a", Source::Channel::a}},
              out.channel,
              "is not a channel (known: \"r\", \"g\", \"b\", \"a\", or \"grey\" for an image's grey, the default)");
    read_word(r, f, "green", slot, Slot::normal,
              "only a normal map has a green convention (\"up\": OpenGL, \"down\": DirectX)",
              {{"up", Source::Green::up}, {"down", Source::Green::down}}, out.green,
              "is not \"up\" (OpenGL style: green is +v) or \"down\" (DirectX style: green is -v)");
    for (const char* key : {"color_space", "colour_space"})
        read_word(r, f, key, slot, Slot::albedo,
                  "only a colour texture (albedo) has a colour space: height and normal maps are data, always read "
                  "as linear",
                  {{"srgb", Source::ColorSpace::srgb}, {"sRGB", Source::ColorSpace::srgb},
                   {"linear", Source::ColorSpace::linear}},
                  out.color_space, "is not \"srgb\" or \"linear\"");
    if (r.failed()) return;
    if (f.has("first_row")) {
        std::string row;
        f.read("first_row", row);
        if (row == "top") out.first_row = TextureSource::FirstRow::top;
        else if (row == "bottom") out.first_row = TextureSource::FirstRow::bottom;
        else if (!r.failed())
            return r.fail(f.sub("first_row"), "\"" + echo(row) + "\" is not \"top\" or \"bottom\" (which stored row of "
                                              "the texture file is the top of the image)");
        if (!r.failed() && !is_texture_file(out.path))
            return r.fail(f.sub("first_row"), "'" + echo_path(out.path) +
                                                  "' is an image file, which always stores the top row first; "
                                                  "first_row applies to texture containers (.ktx, .ktx2, .pvr, .astc)");
    }
}

void read_procedural_form(Fields& f, TextureSource& out) {
    f.read_named("procedural", parse_field_kind, out.field.kind);
    f.read("size", out.field.size);
    f.read("level", out.field.level);
    f.read("count", out.field.count);
    f.read("frequency", out.field.frequency);
    f.read("mortar", out.field.mortar);
    f.read("line_width", out.field.line_width);
    f.read("radius", out.field.radius);
    f.read("text", out.field.text);
    f.read("low", out.low);
    f.read("high", out.high);
    f.read("grain", out.grain);
}

void read_color_form(Fields& f, TextureSource& out) { f.read("color", out.color); }

// SOURCE: "path" | {"file", "convention", "first_row", "channel", "green", "color_space"} |
//         {"procedural", FieldSpec fields...} | {"color"}.
void read_source(Reader& r, const json& j, const std::string& path, Slot slot, TextureSource& out) {
    if (r.failed()) return;
    out = TextureSource{};
    if (j.is_string()) {
        out.kind = TextureSource::Kind::file;
        out.path = j.get<std::string>();
        return;
    }
    if (!j.is_object())
        return r.fail(path, "expected a file path, or an object with \"file\", \"procedural\" or \"color\", got " +
                                describe(j));
    const int forms = int(j.contains("file")) + int(j.contains("procedural")) + int(j.contains("color"));
    if (forms > 1) return r.fail(path, "give one of \"file\", \"procedural\" or \"color\", not several");

    Fields f(r, &j, path);
    if (j.contains("file")) {
        out.kind = TextureSource::Kind::file;
        read_file_form(r, f, slot, out);
    } else if (j.contains("procedural")) {
        out.kind = TextureSource::Kind::procedural;
        read_procedural_form(f, out);
    } else if (j.contains("color")) {
        out.kind = TextureSource::Kind::color;
        read_color_form(f, out);
    } else {
        // Reading every form's keys first turns {"fiel": ...} into a "did you
        // mean 'file'"; keys valid in some form ({"size": 64}) get the message
        // below instead.
        TextureSource scratch;
        read_file_form(r, f, Slot::any, scratch);
        read_procedural_form(f, scratch);
        read_color_form(f, scratch);
        f.finish();
        r.fail(path, "needs one of \"file\", \"procedural\" or \"color\"");
    }
}

void read_camera(Reader& r, const json* j, CameraDesc& cam) {
    Fields f(r, j, "camera");
    f.read("position", cam.position);
    f.read("target", cam.target);
    f.read("up", cam.up);
    f.read("fov_y_deg", cam.fov_y_deg);
    f.read("near", cam.near_plane);
    f.read("far", cam.far_plane);
}

void read_light(Reader& r, const json& j, const std::string& path, LightDesc& light) {
    Fields f(r, &j, path);
    f.read_named("type", parse_light_kind, light.kind);
    f.read("direction", light.direction);
    f.read("position", light.position);
    f.read("color", light.color);
    f.read("intensity", light.intensity);
    f.read("angular_radius_deg", light.angular_radius_deg);
}

void read_options(Reader& r, const json* j, const std::string& path, TechniqueOptions& t) {
    Fields f(r, j, path);
    f.read("min_samples", t.min_samples);
    f.read("max_samples", t.max_samples);
    f.read("refine_steps", t.refine_steps);
    f.read("max_steps", t.max_steps);
    f.read("exact_view", t.exact_view);
    f.read_named("shadow", parse_shadow_mode, t.shadow);
    f.read("shadow_samples", t.shadow_samples);
    f.read("depth_write", t.depth_write);
    f.read("lod", t.lod);
    f.read("lod_threshold", t.lod_threshold);
    f.read("lod_band", t.lod_band);
}

// "parallax": {"max_error_texels": 0.5} or "off"; "shadow": "soft" or
// {"mode": "soft", "max_error": 0.05}; "depth_correction" and "lod_fade":
// "auto", "on" or "off" (lod_fade also {"mode", "threshold", "band"}).
void read_effects(Reader& r, const json& j, const std::string& path, EffectRequest& e) {
    Fields f(r, &j, path);
    if (const json* p = f.get("parallax")) {
        if (p->is_string()) {
            if (p->get<std::string>() != "off")
                return r.fail(f.sub("parallax"), "expected \"off\" or an object such as {\"max_error_texels\": 0.5}, got " +
                                                     describe(*p));
            e.parallax = false;
        } else {
            Fields pf(r, p, f.sub("parallax"));
            pf.read("max_error_texels", e.max_error_texels);
        }
    }
    if (const json* s = f.get("shadow")) {
        if (s->is_string()) {
            r.named(*s, f.sub("shadow"), parse_shadow_mode, e.shadow);
        } else {
            Fields sf(r, s, f.sub("shadow"));
            sf.read_named("mode", parse_shadow_mode, e.shadow);
            sf.read("max_error", e.shadow_max_error);
        }
    }
    f.read_named("depth_correction", parse_effect_switch, e.depth_correction);
    if (const json* l = f.get("lod_fade")) {
        if (l->is_string()) {
            r.named(*l, f.sub("lod_fade"), parse_effect_switch, e.lod_fade);
        } else {
            Fields lf(r, l, f.sub("lod_fade"));
            lf.read_named("mode", parse_effect_switch, e.lod_fade);
            lf.read("threshold", e.lod_threshold);
            lf.read("band", e.lod_band);
        }
    }
}

void read_material(Reader& r, const json& j, const std::string& path, MaterialDesc& m) {
    Fields f(r, &j, path);
    f.read("name", m.name);
    if (const json* s = f.get("albedo")) read_source(r, *s, f.sub("albedo"), Slot::albedo, m.albedo);
    if (const json* s = f.get("height")) read_source(r, *s, f.sub("height"), Slot::height, m.height);
    if (const json* s = f.get("normal")) read_source(r, *s, f.sub("normal"), Slot::normal, m.normal);
    f.read("height_scale", m.height_scale);
    if (f.has("height_bias")) {
        float bias = 0.0f;
        f.read("height_bias", bias);
        m.height_bias = bias;
    }
    f.read("pack_height_in_normal_alpha", m.pack_height_in_normal_alpha);
    f.read("specular", m.specular);
    f.read("shininess", m.shininess);
    f.read("bounded", m.bounded);
    f.read("silhouette", m.silhouette);

    Fields uv(r, f.get("uv"), f.sub("uv"));
    uv.read_scale("scale", m.uv.scale);
    uv.read("offset", m.uv.offset);
    uv.read("rotation_deg", m.uv.rotation_deg);

    // A material names its technique (and options), or declares the effects
    // it needs and lets the planner choose: not both.
    const bool explicit_technique = f.has("technique") || f.has("options");
    if (const json* e = f.get("effects")) {
        if (explicit_technique)
            return r.fail(f.sub("effects"), std::string("a material declares effects or names a technique, not both (") +
                                                (f.has("technique") ? "\"technique\"" : "\"options\"") +
                                                " is set too)");
        read_effects(r, *e, f.sub("effects"), m.effects.emplace());
        return;
    }
    f.read_named("technique", parse_technique, m.technique.technique);
    read_options(r, f.get("options"), f.sub("options"), m.technique);
}

void read_object(Reader& r, const json& j, const std::string& path, ObjectDesc& o) {
    Fields f(r, &j, path);
    f.read("name", o.name);
    f.read("material", o.material);

    Fields mesh(r, f.get("mesh"), f.sub("mesh"));
    mesh.read_named("type", parse_mesh_kind, o.mesh.kind);
    mesh.read("size", o.mesh.size);
    mesh.read("segments", o.mesh.segments);
    mesh.read("radius", o.mesh.radius);
    mesh.read("tube_radius", o.mesh.tube_radius);
    mesh.read("displaced", o.mesh.displaced);
    mesh.read("vertices_per_texel", o.mesh.vertices_per_texel);
    for (auto [key, out] : {std::pair{"tangent", &o.mesh.tangent}, std::pair{"normal", &o.mesh.normal}})
        if (mesh.has(key)) {
            glm::vec3 v(0.0f);
            mesh.read(key, v);
            *out = v;
        }

    Fields t(r, f.get("transform"), f.sub("transform"));
    t.read("translate", o.transform.translate);
    t.read("rotate_deg", o.transform.rotate_deg);
    t.read_scale("scale", o.transform.scale);
}

void read_scene(Reader& r, const json& doc, SceneDesc& scene) {
    if (!doc.is_object()) return r.fail_message("a scene must be a JSON object, got " + describe(doc));
    Fields root(r, &doc, "");
    root.read("name", scene.name);
    read_camera(r, root.get("camera"), scene.camera);
    root.read("ambient", scene.ambient);
    root.read("background", scene.background);

    if (const json* lights = root.get("lights")) {
        r.each(*lights, "lights", [&](const json& e, const std::string& path) {
            read_light(r, e, path, scene.lights.emplace_back());
        });
    } else {
        scene.lights.emplace_back();  // one directional light, straight down
    }
    if (const json* materials = root.get("materials")) {
        r.each(*materials, "materials", [&](const json& e, const std::string& path) {
            read_material(r, e, path, scene.materials.emplace_back(default_material(kDefaultMaterial)));
        });
    }
    if (const json* objects = root.get("objects")) {
        r.each(*objects, "objects", [&](const json& e, const std::string& path) {
            ObjectDesc& o = scene.objects.emplace_back();
            o.name = "object" + std::to_string(scene.objects.size() - 1);
            o.material = kDefaultMaterial;
            read_object(r, e, path, o);
        });
    }
}

// --- Files ------------------------------------------------------------------------

Result<std::string> read_text_file(const std::string& path) {
    Result<std::vector<std::uint8_t>> bytes = read_file_bounded(path, kMaxSceneFileBytes, "scene file");
    if (!bytes) return bytes.error();
    return std::string(bytes->begin(), bytes->end());
}

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

namespace {
Result<SceneDesc> parse_scene_text(const std::string& json_text, const std::string& origin, bool validate);
}  // namespace

static Result<SceneDesc> parse_scene_limited(const std::string& json_text, const std::string& origin, bool validate) {
    if (json_text.size() > kMaxSceneFileBytes)
        return make_error(echo_path(origin) + ": the scene is larger than the limit of " +
                          std::to_string(kMaxSceneFileBytes >> 20) + " MiB");
    return out_of_memory_is_an_error(echo_path(origin), [&] { return parse_scene_text(json_text, origin, validate); });
}

Result<SceneDesc> parse_scene(const std::string& json_text, const std::string& origin) {
    return parse_scene_limited(json_text, origin, true);
}

namespace {

Result<SceneDesc> parse_scene_text(const std::string& json_text, const std::string& origin, bool validate) {
    const auto at = [&](std::size_t byte) {
        const auto [line, column] = line_column(json_text, byte);
        return origin + ":" + std::to_string(line) + ":" + std::to_string(column);
    };
    json doc;
    DuplicateKeyFinder duplicates;
    try {
        // The callback is copied into the parser: hold it by reference.
        doc = json::parse(
            json_text, [&](int depth, json::parse_event_t event, json& parsed) { return duplicates(depth, event, parsed); },
            true, /*ignore_comments=*/true);
    } catch (const json::parse_error& e) {
        return make_error(at(e.byte) + ": malformed JSON: " + parse_error_reason(e));
    } catch (const json::exception& e) {
        // Number overflow ("1e999") comes without a position; find the quoted literal.
        const std::string what = e.what();
        const std::string reason = what.substr(what.find("] ") == std::string::npos ? 0 : what.find("] ") + 2);
        const std::size_t open = reason.find('\''), close = reason.rfind('\'');
        const std::size_t pos = open < close ? json_text.find(reason.substr(open + 1, close - open - 1))
                                             : std::string::npos;
        return make_error((pos == std::string::npos ? origin : at(pos + 1)) + ": malformed JSON: " + echo(reason, 400));
    }
    if (!duplicates.message().empty()) return make_error(origin + ": " + duplicates.message());
    Reader r(origin);
    SceneDesc scene;
    read_scene(r, doc, scene);
    if (r.failed()) return r.error();

    // Objects that name no material use "default": supply it if the file does not.
    const bool wants_default = std::any_of(scene.objects.begin(), scene.objects.end(),
                                           [](const ObjectDesc& o) { return o.material == kDefaultMaterial; });
    if (wants_default && !scene.find_material(kDefaultMaterial))
        scene.materials.push_back(default_material(kDefaultMaterial));

    if (!validate) return scene;  // prepare_scene validates it
    if (Status s = validate_scene(scene); !s) return with_context(origin, s.error());
    // Procedural sizes now; files' headers once their paths are resolved.
    if (Status s = check_scene_resources(scene, false); !s) return with_context(origin, s.error());
    return scene;
}

}  // namespace

Result<SceneDesc> load_scene_file(const std::string& path, SceneChecks checks) {
    Result<std::string> text = read_text_file(path);
    if (!text) return text.error();
    const bool validate = checks == SceneChecks::validate;
    Result<SceneDesc> scene = parse_scene_limited(*text, path, validate);
    if (!scene) return scene;

    std::error_code ec;
    fs::path dir = fs::absolute(fs::path(path), ec).parent_path();
    if (ec) dir = fs::path(path).parent_path();
    scene->base_dir = dir.lexically_normal().string();
    scene->source = path;
    if (scene->name.empty()) scene->name = fs::path(path).stem().string();

    // Resolve texture paths here so that a missing file is reported with its
    // JSON path now rather than by the renderer later. Absolute results also
    // make a later base_dir / path join harmless.
    for (std::size_t i = 0; i < scene->materials.size(); ++i) {
        MaterialDesc& m = scene->materials[i];
        const std::pair<TextureSource*, const char*> slots[] = {
            {&m.albedo, "albedo"}, {&m.height, "height"}, {&m.normal, "normal"}};
        for (auto [source, slot] : slots) {
            if (source->kind != TextureSource::Kind::file) continue;
            const fs::path resolved = (dir / fs::path(source->path)).lexically_normal();
            if (!fs::is_regular_file(resolved, ec))
                return make_error(path + ": " + index_path("materials", i) + "." + slot + ": no such texture file '" +
                                  source->path + "' (looked for " + resolved.string() + ")");
            source->path = resolved.string();
        }
    }
    if (!validate) return scene;
    if (Status s = check_scene_resources(*scene, true); !s) return with_context(path, s.error());
    return scene;
}

Result<SceneDesc> load_scene(const std::string& name_or_path, SceneChecks checks) {
    const std::vector<std::string> builtins = builtin_scene_names();
    if (std::find(builtins.begin(), builtins.end(), name_or_path) != builtins.end())
        return builtin_scene(name_or_path);
    std::error_code ec;
    if (ends_with(name_or_path, ".json") || fs::is_regular_file(name_or_path, ec))
        return load_scene_file(name_or_path, checks);
    return make_error("unknown scene '" + echo_path(name_or_path) + "': neither a built-in scene (" + joined(builtins) +
                      ") nor a scene file");
}

}  // namespace px
