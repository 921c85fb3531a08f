// The golden-image measure and tolerance files (image_compare.h).
#include "parallaxes/assets/image_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "parallaxes/core/files.h"
#include "parallaxes/core/text.h"

namespace px {

namespace {

using json = nlohmann::json;

constexpr std::size_t kMaxToleranceFileBytes = std::size_t{1} << 20;
constexpr const char* kFields[] = {"pixel_threshold", "max_differing_share", "max_mean_difference"};
// The CPUs an entry may hold overrides for (Debian's architecture names).
constexpr const char* kToleranceCpus[] = {"x86_64", "i386", "arm64", "armhf"};

// How a JSON value reads after "got": its type, and its value when short.
std::string describe(const json& j) {
    switch (j.type()) {
        case json::value_t::string: return "string \"" + echo(j.get<std::string>(), 40) + "\"";
        case json::value_t::boolean: return j.get<bool>() ? "boolean true" : "boolean false";
        case json::value_t::number_integer:
        case json::value_t::number_unsigned:
        case json::value_t::number_float: return "number " + echo(j.dump(), 40);
        case json::value_t::array: return "array of " + std::to_string(j.size());
        default: return j.type_name();
    }
}

// "FILE:LINE:COLUMN" of the byte nlohmann stopped at (1-based, one past the
// offending character).
std::string position(const std::string& text, const std::string& origin, std::size_t byte) {
    const std::size_t end = std::min(byte > 0 ? byte - 1 : 0, text.size());
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < end; ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) {
            ++column;
        }
    }
    return origin + ":" + std::to_string(line) + ":" + std::to_string(column);
}

// One field of an entry into t, when the entry has it; the limits are those
// of Tolerance.
Status read_field(const json& entry, const char* field, const std::string& path, Tolerance& t) {
    if (!entry.contains(field)) return {};
    const json& v = entry.at(field);
    const std::string where = path + "." + field;
    if (std::string(field) == "pixel_threshold") {
        if (!v.is_number_integer() || v.get<std::int64_t>() < 0 || v.get<std::int64_t>() > 255)
            return make_error(where + ": expected an integer in 0..255 (levels), got " + describe(v));
        t.pixel_threshold = v.get<int>();
        return {};
    }
    const double limit = std::string(field) == "max_differing_share" ? 1.0 : 255.0;
    if (!v.is_number() || !(v.get<double>() >= 0.0) || v.get<double>() > limit) {
        std::ostringstream range;
        range << "expected a number in 0.." << limit << (limit == 1.0 ? " (a share of the pixels)" : " (levels)");
        return make_error(where + ": " + range.str() + ", got " + describe(v));
    }
    (std::string(field) == "max_differing_share" ? t.max_differing_share : t.max_mean_difference) = v.get<double>();
    return {};
}

// One override object (an "es2"/"es3" or a CPU's) read into `into`: it holds
// the three fields and, in a CPU's, its own "es2"/"es3" (`nested`) and notes
// named with a leading '_'; anything else is an error, since a misspelt
// field would silently not apply.
Status read_override(const json& sub, const std::string& path, bool nested, Tolerance& into) {
    if (!sub.is_object()) return make_error(path + ": expected an object, got " + describe(sub));
    for (auto it = sub.begin(); it != sub.end(); ++it) {
        const std::string& key = it.key();
        const bool field = std::find(std::begin(kFields), std::end(kFields), key) != std::end(kFields);
        if (field || (nested && (key == "es2" || key == "es3" || (!key.empty() && key[0] == '_')))) continue;
        return make_error(path + ": unknown field '" + echo(key) + "' (an override holds pixel_threshold, " +
                          "max_differing_share, max_mean_difference" + (nested ? "; a CPU's also es2 and es3)" : ")"));
    }
    for (const char* field : kFields)
        if (Status s = read_field(sub, field, path, into); !s) return s.error();
    return {};
}

// The "es2"/"es3" overrides of `entry` over `base`: both checked, the one for
// es_major applied.
Result<Tolerance> apply_es(const json& entry, const std::string& path, int es_major, const Tolerance& base) {
    Tolerance applied = base;
    for (int es : {2, 3}) {
        const std::string key = "es" + std::to_string(es);
        if (!entry.contains(key)) continue;
        Tolerance scratch = base;
        if (Status s = read_override(entry.at(key), path + "." + key, false, es == es_major ? applied : scratch); !s)
            return s.error();
    }
    return applied;
}

// A scene's entry: the three fields required, then its "es2"/"es3" objects,
// then its CPUs' objects (each with its own "es2"/"es3"), every one checked
// whichever is applied, the ones for es_major and cpu applied in that order.
Result<Tolerance> read_entry(const json& entry, const std::string& path, int es_major, const std::string& cpu) {
    if (!entry.is_object()) return make_error(path + ": expected an object, got " + describe(entry));
    Tolerance t;
    for (const char* field : kFields) {
        if (!entry.contains(field)) return make_error(path + ": missing \"" + field + "\"");
        if (Status s = read_field(entry, field, path, t); !s) return s.error();
    }
    Result<Tolerance> applied = apply_es(entry, path, es_major, t);
    if (!applied) return applied;
    for (const char* name : kToleranceCpus) {
        if (!entry.contains(name)) continue;
        const json& sub = entry.at(name);
        const std::string at = path + "." + name;
        Tolerance over = *applied;
        if (Status s = read_override(sub, at, true, over); !s) return s.error();
        Result<Tolerance> with_es = apply_es(sub, at, es_major, over);
        if (!with_es) return with_es;
        if (cpu == name) applied = with_es;
    }
    return applied;
}

// The scenes a file has, for "unknown scene" errors.
std::string scene_names(const json& doc) {
    std::string names;
    for (auto it = doc.begin(); it != doc.end(); ++it) {
        if (!it.value().is_object() || (!it.key().empty() && it.key()[0] == '_')) continue;
        names += (names.empty() ? "" : ", ") + echo(it.key());
    }
    return names.empty() ? "none" : names;
}

// The largest colour channel difference of one pixel, and their sum.
int pixel_difference(const std::uint8_t* a, const std::uint8_t* b, double& sum) {
    int worst = 0;
    for (int ch = 0; ch < 3; ++ch) {
        const int d = std::abs(int(a[ch]) - int(b[ch]));
        worst = std::max(worst, d);
        sum += d;
    }
    return worst;
}

Status check_comparable(const Image& image, const std::string& name) {
    if (image.width <= 0 || image.height <= 0)
        return make_error(name + ": empty image (" + std::to_string(image.width) + "x" + std::to_string(image.height) + ")");
    if (image.channels < 3 || image.channels > 4)
        return make_error(name + ": " + std::to_string(image.channels) + " channel(s); comparing needs RGB or RGBA");
    const std::size_t expected = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) *
                                 static_cast<std::size_t>(image.channels);
    if (image.pixels.size() != expected)
        return make_error(name + ": pixel buffer holds " + std::to_string(image.pixels.size()) + " bytes, expected " +
                          std::to_string(expected));
    return {};
}

}  // namespace

bool is_tolerance_cpu(const std::string& cpu) {
    return std::find(std::begin(kToleranceCpus), std::end(kToleranceCpus), cpu) != std::end(kToleranceCpus);
}

const char* compiled_cpu() {
#if defined(__x86_64__)
    return "x86_64";
#elif defined(__i386__)
    return "i386";
#elif defined(__aarch64__)
    return "arm64";
#elif defined(__arm__)
    return "armhf";
#else
    return "other";
#endif
}

Result<Tolerance> parse_tolerances(const std::string& json_text, const std::string& origin, const std::string& scene,
                                   int es_major, const std::string& cpu) {
    json doc;
    try {
        doc = json::parse(json_text, nullptr, true, /*ignore_comments=*/true);
    } catch (const json::parse_error& e) {
        // what() is "[json.exception.parse_error.101] parse error at line L, column C: REASON"; the
        // position is ours.
        const std::string what = e.what();
        const std::size_t at = what.find(": ", what.find("parse error"));
        return make_error(position(json_text, origin, e.byte) + ": malformed JSON: " +
                          echo(at == std::string::npos ? what : what.substr(at + 2), 200));
    } catch (const json::exception& e) {
        return make_error(origin + ": malformed JSON: " + echo(e.what(), 200));
    }
    if (!doc.is_object())
        return make_error(origin + ": expected an object of scene entries at the top level, got " + describe(doc));
    // Members named with a leading '_' are notes ("_comment", "_made_on"), never entries.
    if (!doc.contains(scene) || (!scene.empty() && scene[0] == '_'))
        return make_error(origin + ": no entry for scene '" + echo(scene) + "' (the file has: " + scene_names(doc) + ")");
    Result<Tolerance> t = read_entry(doc.at(scene), echo(scene), es_major, cpu);
    if (!t) return with_context(origin, t.error());
    return t;
}

Result<Tolerance> load_tolerances(const std::string& path, const std::string& scene, int es_major,
                                  const std::string& cpu) {
    Result<std::vector<std::uint8_t>> bytes = read_file_bounded(path, kMaxToleranceFileBytes, "tolerance file");
    if (!bytes) return bytes.error();
    return parse_tolerances(std::string(bytes->begin(), bytes->end()), echo_path(path), scene, es_major, cpu);
}

Result<ImageComparison> compare_images(const Image& actual, const Image& golden, const Tolerance& tolerance,
                                       const std::string& actual_name, const std::string& golden_name) {
    if (Status s = check_comparable(actual, actual_name); !s) return s.error();
    if (Status s = check_comparable(golden, golden_name); !s) return s.error();
    if (actual.width != golden.width || actual.height != golden.height)
        return make_error("size mismatch: " + actual_name + " is " + std::to_string(actual.width) + "x" +
                          std::to_string(actual.height) + ", " + golden_name + " is " + std::to_string(golden.width) +
                          "x" + std::to_string(golden.height));
    ImageComparison c;
    c.tolerance = tolerance;
    c.width = actual.width;
    c.height = actual.height;
    c.pixels = std::int64_t{actual.width} * actual.height;
    c.diff = make_solid_image(actual.width, actual.height, 0, 0, 0);
    double sum = 0.0;
    for (int y = 0; y < actual.height; ++y)
        for (int x = 0; x < actual.width; ++x) {
            const int worst = pixel_difference(actual.texel(x, y), golden.texel(x, y), sum);
            c.max_difference = std::max(c.max_difference, worst);
            const bool differs = worst > tolerance.pixel_threshold;
            if (differs) ++c.differing;
            std::uint8_t* p = c.diff.texel(x, y);
            const auto grey = static_cast<std::uint8_t>(actual.texel(x, y)[1] / 4);
            p[0] = differs ? 255 : grey;
            p[1] = p[2] = differs ? 0 : grey;
            p[3] = 255;
        }
    c.share = static_cast<double>(c.differing) / static_cast<double>(c.pixels);
    c.mean = sum / (3.0 * static_cast<double>(c.pixels));
    return c;
}

}  // namespace px
