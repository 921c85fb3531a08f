#include "parallaxes/profiling/costs/vendor_compilers.h"

#include "parallaxes/core/interrupts.h"
#include "parallaxes/profiling/costs/process.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>


// The reports these parsers read, and where their layout comes from (neither
// tool is installed here; the samples under tests/data/vendor/ follow these):
//
// malioc text: Arm's "Get started with Mali Offline Compiler" guide
// (developer.arm.com, .../get-started-with-mali-offline-compiler, the
// performance report and its "Target-aware profiling" page) and reports of
// malioc 7.x/8.x runs quoted in public write-ups. A "Configuration" section
// (Hardware, Architecture, Driver, Shader type), then one section per variant
// ("Main shader"; for vertex shaders on GPUs with index-driven vertex
// shading, "Position variant" and "Varying variant", which real 7.x reports
// put as sub-sections of "Main shader" under '-' rules), each title
// underlined with '=' (or '-'). Real reports of malioc 7.4 to 8.8 on
// Midgard, Bifrost, Valhall and Arm 5th Generation GPUs are kept in
// tests/data/vendor/real/ (SOURCES.md names where each was published).
// A variant section has "Work registers: 32 (...)", "Uniform registers: 16
// (...)", "Stack spilling: false" (7.x) or "Stack use: N bytes" and
// " - Spill region: N bytes" (8.x), "16-bit arithmetic: 0%" (not on
// Midgard), and a cycles table: a header of pipe names ending in "Bound"
// (Valhall "A FMA CVT SFU LS V T Bound", Bifrost "A LS V T Bound", Midgard
// "A LS T Bound"), then the rows "Total instruction cycles:", "Shortest path
// cycles:", "Longest path cycles:" (older versions capitalise each word),
// one number or N/A per pipe, then the bounding pipe(s), "A" or "V, T" or
// N/A. "Shader properties" lists "Has uniform computation: true" and the like.
//
// malioc JSON (`--format json`): no public schema page was found; the layout
// is the one public tools reading malioc 7.x/8.x JSON agree on: {"schema":
// {"name": "performance"|"error", "version"}, "producer": {"name",
// "version": [7, 4, 0], "build"}, "shaders": [{"hardware": {"architecture",
// "core", "revision", "pipelines": [{"name", "display_name"}]}, "driver",
// "shader": {"api", "type"}, "properties": [{"name", "display_name",
// "value"}], "variants": [{"name": "Main", "performance": {"pipelines":
// ["arith_total", "arith_fma", "arith_cvt", "arith_sfu", "load_store",
// "varying", "texture"], "total_cycles": {"cycle_count": [...],
// "bound_pipelines": [...]}, "shortest_path_cycles": ..., "longest_path_cycles":
// ...}, "properties": [{"name": "work_registers_used", "value"}, ...]}],
// "errors": [...] (error reports)}]}. A cycle count may be null (the text's
// N/A), and a whole path may be null where the tool cannot bound it. The
// variant properties read are work_registers_used, uniform_registers_used,
// fp16_arithmetic (percent), has_stack_spilling and stack_spill_bytes.
//
// PowerVR: the PVRShaderEditor manual ("Compiler Output Window", docs.imgtec.com)
// names the profile's figures: "Global USC Instructions", "Per-line Cycle
// Estimate Total", "Performance estimate (Best)" and "(Worst)" (cycles
// emulated with the best and worst branch outcomes), "Ratio between cycles
// and instructions". Tools that script the compilers run
// `GLSLESCompiler_Rogue <in> <out> -f|-v -profile` and read the profile from
// `<out>.prof`. No page shows that file's exact layout, so the parser assumes
// only "label: number" (or "label = number") lines and matches labels by
// their documented words (see parse_powervr_output).

namespace px::profiling {

namespace {

using nlohmann::json;

constexpr std::size_t kOutputCap = 4u << 20;  // 4 MiB: a report is a few KiB; more is a runaway tool
constexpr int kMaxRegisters = 1 << 16;        // far above any GPU's register file: a bigger count is garbage

// The malioc pipe names of the JSON report, given the short names the text
// report's table and legend use ("A = Arithmetic, FMA = Arith FMA, ...").
struct PipeName {
    const char* json;
    const char* text;
};
constexpr PipeName kPipeNames[] = {
    {"arith_total", "A"}, {"arithmetic", "A"}, {"arith_fma", "FMA"}, {"arith_cvt", "CVT"},
    {"arith_sfu", "SFU"}, {"load_store", "LS"}, {"varying", "V"},    {"texture", "T"},
};

// The compilers looked for, in the order reports list them.
constexpr const char* kCandidateTools[] = {"malioc", "GLSLESCompiler_Rogue", "GLSLESCompiler_Series6XT",
                                           "GLSLESCompiler_Series6"};
constexpr const char* kPowerVrPrefix = "GLSLESCompiler_";

// --- Text helpers -----------------------------------------------------------

std::string trim(const std::string& s) {
    std::size_t begin = 0, end = s.size();
    while (begin < end && std::isspace(static_cast<unsigned char>(s[begin]))) ++begin;
    while (end > begin && std::isspace(static_cast<unsigned char>(s[end - 1]))) --end;
    return s.substr(begin, end - begin);
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool starts_with(const std::string& s, const std::string& prefix) {
    return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::vector<std::string> split_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::string line;
    std::istringstream in(text);
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        lines.push_back(line);
    }
    return lines;
}

std::vector<std::string> split_words(const std::string& text) {
    std::vector<std::string> words;
    std::istringstream in(text);
    std::string word;
    while (in >> word) words.push_back(word);
    return words;
}

std::string join(const std::vector<std::string>& parts, const std::string& separator) {
    std::string out;
    for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? separator : "") + parts[i];
    return out;
}

// A figure for notes and messages: "12", "2.5".
std::string figure(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%g", value);
    return buffer;
}

// The first lines of a tool's output for an error message, each cut short:
// enough to show the tool's own complaint without pasting a whole report.
std::string first_lines(const std::string& output, std::size_t count = 6) {
    std::vector<std::string> kept;
    for (const std::string& line : split_lines(output)) {
        std::string t = trim(line);
        if (t.empty()) continue;
        if (t.size() > 160) t = t.substr(0, 160) + "...";
        kept.push_back("  " + t);
        if (kept.size() == count) break;
    }
    return kept.empty() ? "  (no output)" : join(kept, "\n");
}

// "label: value" split at the first colon; false when the line has none.
bool split_field(const std::string& line, std::string& label, std::string& value) {
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) return false;
    label = trim(line.substr(0, colon));
    value = trim(line.substr(colon + 1));
    return true;
}

// --- Checked numbers ----------------------------------------------------------

// A cycle figure or percentage: a whole token that reads as a finite number >= 0.
Result<double> parse_figure(const std::string& token, const std::string& what) {
    if (token.empty()) return make_error(what + ": missing number");
    errno = 0;
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (end != token.c_str() + token.size() || errno == ERANGE)
        return make_error(what + ": '" + token + "' is not a number");
    if (!std::isfinite(value) || value < 0.0)
        return make_error(what + ": " + token + " is not a finite figure >= 0");
    return value;
}

// A register or byte count: a whole token of decimal digits, within `limit`.
Result<int> parse_count(const std::string& token, const std::string& what, long limit = kMaxRegisters) {
    if (token.empty()) return make_error(what + ": missing count");
    if (!std::all_of(token.begin(), token.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return make_error(what + ": '" + token + "' is not a whole number >= 0");
    if (token.size() > 9 || std::stol(token) > limit)
        return make_error(what + ": " + token + " is past any plausible count (" + std::to_string(limit) + ")");
    return static_cast<int>(std::stol(token));
}

Result<double> parse_percent(std::string token, const std::string& what) {
    if (!token.empty() && token.back() == '%') token.pop_back();
    auto value = parse_figure(token, what);
    if (!value) return value;
    if (*value > 100.0) return make_error(what + ": " + token + "% is over 100%");
    return value;
}

// A shader property's display name as a note: "Has uniform computation" ->
// "uniform computation", "Uses late ZS test" -> "uses late ZS test".
std::string property_note(std::string name) {
    name = trim(name);
    if (starts_with(lower(name), "has ")) name = name.substr(4);
    if (!name.empty()) name[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(name[0])));
    return name;
}

std::string target_name(const std::string& hardware, const std::string& architecture) {
    return architecture.empty() ? hardware : hardware + " (" + architecture + ")";
}

// The figure `bound` reports: the longest path's bounding pipe, the path
// Arm's guide reads first; the total's where the longest path is N/A (loops
// whose count the compiler cannot see).
std::string pick_bound(const std::string& longest_bound, const std::string& total_bound) {
    return longest_bound.empty() ? total_bound : longest_bound;
}

// --- malioc text ----------------------------------------------------------------

struct TextSection {
    std::string title;               // "" for the lines before the first title
    char rule = 0;                   // the title's underline: '=' (sections) or '-' (a vertex shader's variants)
    std::vector<std::string> lines;  // trimmed, title and underline left out
};

bool is_rule(const std::string& line, char c) {
    const std::string t = trim(line);
    return t.size() >= 3 && std::all_of(t.begin(), t.end(), [c](char x) { return x == c; });
}

std::vector<TextSection> split_sections(const std::string& output) {
    const std::vector<std::string> lines = split_lines(output);
    std::vector<TextSection> sections(1);
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (i + 1 < lines.size() && !trim(lines[i]).empty()) {
            const char rule = is_rule(lines[i + 1], '=') ? '=' : is_rule(lines[i + 1], '-') ? '-' : 0;
            if (rule) {
                sections.push_back(TextSection{trim(lines[i]), rule, {}});
                ++i;  // the underline
                continue;
            }
        }
        sections.back().lines.push_back(trim(lines[i]));
    }
    return sections;
}

// "Main shader" -> "Main", "Position variant" -> "Position"; "" when the
// title names no variant.
std::string variant_name(const std::string& title) {
    const std::string t = lower(title);
    for (const char* suffix : {" shader", " variant"})
        if (ends_with(t, suffix) && t.size() > std::strlen(suffix)) return title.substr(0, t.size() - std::strlen(suffix));
    return "";
}

bool has_content(const TextSection& s) {
    return std::any_of(s.lines.begin(), s.lines.end(), [](const std::string& l) { return !l.empty(); });
}

// One row of the cycles table: a figure (NaN for N/A) per pipe, then the bound.
Status parse_cycles_row(const std::string& line, const std::string& label, const std::string& values,
                        std::size_t pipe_count, std::vector<double>& figures, std::string& bound) {
    const std::vector<std::string> words = split_words(values);
    if (words.size() < pipe_count + 1)
        return make_error("'" + label + ":' has " + std::to_string(words.size()) + " values, expected " +
                          std::to_string(pipe_count) + " pipe figures and the bound: '" + line + "'");
    figures.clear();
    for (std::size_t i = 0; i < pipe_count; ++i) {
        if (words[i] == "N/A") {
            figures.push_back(std::numeric_limits<double>::quiet_NaN());
            continue;
        }
        auto value = parse_figure(words[i], "'" + label + ":' value " + std::to_string(i + 1));
        if (!value) return make_error(value.error().message + " in '" + line + "'");
        figures.push_back(*value);
    }
    bound = join(std::vector<std::string>(words.begin() + static_cast<std::ptrdiff_t>(pipe_count), words.end()), " ");
    if (bound == "N/A") bound.clear();
    return {};
}

// Whether a token reads as a figure or N/A (a table row's first value).
bool looks_like_figure(const std::string& token) {
    if (token == "N/A") return true;
    char* end = nullptr;
    (void)std::strtod(token.c_str(), &end);
    return !token.empty() && end == token.c_str() + token.size();
}

// A register count, or -1 for N/A.
Result<int> register_count(const std::string& first, const std::string& what) {
    if (first == "N/A") return -1;
    return parse_count(first, what);
}

// The lines of one variant's section: registers, spilling, 16-bit share and
// the cycles table.
Result<VendorVariant> parse_text_variant(const TextSection& section) {
    VendorVariant v;
    v.name = variant_name(section.title);
    bool have_header = false, have_work = false, have_uniform = false;
    bool have[3] = {false, false, false};  // total, shortest, longest
    for (const std::string& line : section.lines) {
        if (line.empty()) continue;
        std::string label, value;
        if (!split_field(line, label, value)) {
            const std::vector<std::string> words = split_words(line);
            if (words.size() >= 2 && lower(words.back()) == "bound") {
                v.pipes.assign(words.begin(), words.end() - 1);
                have_header = true;
            } else if (!contains(line, " = ") && std::any_of(words.begin(), words.end(), looks_like_figure)) {
                // Not a legend ("A = Arithmetic, ..."), not a header: figures in a layout not known here.
                return make_error("a line the parser does not know: '" + line + "'");
            }
            continue;
        }
        const std::string key = lower(label);
        const std::vector<std::string> words = split_words(value);
        const std::string first = words.empty() ? "" : words[0];
        if (key == "work registers" || key == "uniform registers") {
            auto count = register_count(first, "'" + label + ":'");
            if (!count) return make_error(count.error().message + " in '" + line + "'");
            (key[0] == 'w' ? v.work_registers : v.uniform_registers) = *count;
            (key[0] == 'w' ? have_work : have_uniform) = true;
        } else if (key == "16-bit arithmetic") {
            if (first != "N/A") {
                auto percent = parse_percent(first, "'16-bit arithmetic:'");
                if (!percent) return make_error(percent.error().message + " in '" + line + "'");
                v.fp16_percent = *percent;
            }
        } else if (key == "stack spilling") {
            // 7.x prints true/false; a byte count is read as spilling when above 0.
            if (lower(first) == "true" || lower(first) == "false") {
                v.stack_spilling = lower(first) == "true";
            } else if (first != "N/A") {
                auto bytes = parse_count(first, "'Stack spilling:'", std::numeric_limits<int>::max());
                if (!bytes) return make_error(bytes.error().message + " in '" + line + "'");
                v.stack_spilling = *bytes > 0;
                if (*bytes > 0) v.notes.push_back("stack spill " + std::to_string(*bytes) + " bytes");
            }
        } else if (key == "- spill region") {
            auto bytes = parse_count(first, "'Spill region:'", std::numeric_limits<int>::max());
            if (!bytes) return make_error(bytes.error().message + " in '" + line + "'");
            v.stack_spilling = *bytes > 0;
            if (*bytes > 0) v.notes.push_back("stack spill " + std::to_string(*bytes) + " bytes");
        } else if (key == "total instruction cycles" || key == "shortest path cycles" || key == "longest path cycles") {
            if (!have_header) return make_error("'" + line + "' comes before the cycles table's pipe header");
            const int row = key[0] == 't' ? 0 : key[0] == 's' ? 1 : 2;
            std::vector<double>& figures = row == 0 ? v.total : row == 1 ? v.shortest : v.longest;
            std::string& bound = row == 0 ? v.total_bound : row == 1 ? v.shortest_bound : v.longest_bound;
            Status parsed = parse_cycles_row(line, label, value, v.pipes.size(), figures, bound);
            if (!parsed) return parsed.error();
            have[row] = true;
        } else if (have_header && words.size() >= v.pipes.size() + 1 && looks_like_figure(first)) {
            // A row of the table under a name not known here (a new path, a renamed row).
            return make_error("a cycles row the parser does not know: '" + line + "'");
        }
        // Any other "label: value" (Stack use, per-variant properties) says nothing the profile reads.
    }
    if (!have_work) return make_error("no 'Work registers:' line");
    if (!have_uniform) return make_error("no 'Uniform registers:' line");
    if (!have_header) return make_error("no cycles table header (pipe names ending in 'Bound')");
    if (!have[0]) return make_error("no 'Total instruction cycles:' row");
    if (!have[1]) return make_error("no 'Shortest path cycles:' row");
    if (!have[2]) return make_error("no 'Longest path cycles:' row");
    v.bound = pick_bound(v.longest_bound, v.total_bound);
    return v;
}

// The primary variant: Main, else Position (a vertex shader's), else the first.
std::size_t primary_variant(const std::vector<VendorVariant>& variants) {
    for (const char* name : {"main", "position"})
        for (std::size_t i = 0; i < variants.size(); ++i)
            if (lower(variants[i].name) == name) return i;
    return 0;
}

// The report's variants as the primary's figures and the list.
void set_variants(VendorCycles& out, std::vector<VendorVariant> variants) {
    const std::size_t primary = primary_variant(variants);
    std::vector<std::string> shader_notes = std::move(out.notes);
    static_cast<VendorVariant&>(out) = variants[primary];
    if (variants.size() > 1) {
        std::vector<std::string> others;
        for (std::size_t i = 0; i < variants.size(); ++i)
            if (i != primary) others.push_back(variants[i].name + " variant");
        out.notes.push_back("figures of the " + variants[primary].name + " variant; the report also has " +
                            join(others, ", "));
    }
    out.notes.insert(out.notes.end(), shader_notes.begin(), shader_notes.end());
    out.variants = std::move(variants);
}

Result<VendorCycles> parse_malioc_text_inner(const std::string& output) {
    VendorCycles out;
    const std::vector<TextSection> sections = split_sections(output);

    // The banner: "Mali Offline Compiler v7.4.0 (Build 330167)", with "Arm " before it in some versions.
    const std::string banner = "Mali Offline Compiler v";
    for (const TextSection& section : sections) {
        for (const std::string& line : section.lines) {
            const std::size_t at = line.find(banner);
            if (at == std::string::npos || !out.tool.empty()) continue;
            const std::vector<std::string> words = split_words(line.substr(at + banner.size()));
            if (!words.empty()) out.tool = "malioc " + words[0];
        }
    }
    const TextSection* configuration = nullptr;
    const TextSection* properties = nullptr;
    std::vector<const TextSection*> variant_sections;
    for (const TextSection& section : sections) {
        const std::string title = lower(section.title);
        if (title == "configuration") configuration = &section;
        else if (title == "shader properties") properties = &section;
        else if (!variant_name(section.title).empty() && has_content(section)) variant_sections.push_back(&section);
    }
    // A report quoted from its Configuration section on (as Arm's guide
    // quotes one) has no banner: its version is then unknown.
    if (out.tool.empty() && !configuration) return make_error("no 'Mali Offline Compiler vX.Y.Z' banner");
    if (!configuration) return make_error("no 'Configuration' section");
    if (out.tool.empty()) {
        out.tool = "malioc";
        out.notes.push_back("no banner: the compiler's version is not in the report");
    }
    std::string hardware, architecture;
    for (const std::string& line : configuration->lines) {
        std::string label, value;
        if (!split_field(line, label, value)) continue;
        if (lower(label) == "hardware") hardware = value;
        if (lower(label) == "architecture") architecture = value;
        if (lower(label) == "shader type") out.shader_type = value;
    }
    if (hardware.empty()) return make_error("no 'Hardware:' line in the Configuration section");
    out.target = target_name(hardware, architecture);

    if (variant_sections.empty()) return make_error("no 'Main shader' (or 'Position variant') section with figures");
    std::vector<VendorVariant> variants;
    for (const TextSection* section : variant_sections) {
        Result<VendorVariant> v = parse_text_variant(*section);
        if (!v) return make_error(v.error().message + " in the " + section->title + " section");
        variants.push_back(std::move(*v));
    }
    if (properties) {
        for (const std::string& line : properties->lines) {
            std::string label, value;
            if (split_field(line, label, value) && lower(value) == "true") out.notes.push_back(property_note(label));
        }
    }
    set_variants(out, std::move(variants));
    return out;
}

// --- malioc JSON ------------------------------------------------------------------

const json* member(const json& object, const char* key) {
    if (!object.is_object()) return nullptr;
    auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
}

// The value of the property named `name` in a malioc properties array, or null.
const json* property(const json* properties, const std::string& name) {
    if (!properties || !properties->is_array()) return nullptr;
    for (const json& p : *properties) {
        const json* n = member(p, "name");
        if (n && n->is_string() && n->get<std::string>() == name) return member(p, "value");
    }
    return nullptr;
}

Result<int> json_count(const json* value, const std::string& what) {
    if (!value) return make_error("no " + what);
    if (!value->is_number()) return make_error(what + " is not a number");
    const double d = value->get<double>();
    if (!std::isfinite(d) || d < 0.0 || d != std::floor(d) || d > kMaxRegisters)
        return make_error(what + " is " + value->dump() + ", not a whole count within 0.." +
                          std::to_string(kMaxRegisters));
    return static_cast<int>(d);
}

std::string short_pipe_name(const std::string& name) {
    for (const PipeName& p : kPipeNames)
        if (name == p.json) return p.text;
    return name;  // a pipe this table does not know keeps the tool's name
}

// One path of `performance`: a cycle count per pipe and the bounding pipes.
// A null path is one the tool cannot bound (the text report's all-N/A row).
Status read_json_path(const json& performance, const char* key, std::size_t pipe_count, std::vector<double>& figures,
                      std::string& bound) {
    const json* path = member(performance, key);
    const std::string where = std::string("performance.") + key;
    if (!path) return make_error("no " + where);
    figures.clear();
    bound.clear();
    if (path->is_null()) {
        figures.assign(pipe_count, std::numeric_limits<double>::quiet_NaN());
        return {};
    }
    const json* counts = member(*path, "cycle_count");
    if (!counts || !counts->is_array()) return make_error("no " + where + ".cycle_count array");
    if (counts->size() != pipe_count)
        return make_error(where + ".cycle_count has " + std::to_string(counts->size()) + " values for " +
                          std::to_string(pipe_count) + " pipelines");
    for (std::size_t i = 0; i < counts->size(); ++i) {
        const json& c = (*counts)[i];
        const std::string what = where + ".cycle_count[" + std::to_string(i) + "]";
        if (c.is_null()) {
            figures.push_back(std::numeric_limits<double>::quiet_NaN());
            continue;
        }
        if (!c.is_number()) return make_error(what + " is not a number");
        const double d = c.get<double>();
        if (!std::isfinite(d) || d < 0.0) return make_error(what + " is " + c.dump() + ", not a finite figure >= 0");
        figures.push_back(d);
    }
    const json* bounds = member(*path, "bound_pipelines");
    if (!bounds || !bounds->is_array()) return make_error("no " + where + ".bound_pipelines array");
    std::vector<std::string> names;
    for (const json& b : *bounds) {
        if (b.is_null()) continue;  // no bound (the text's N/A)
        if (!b.is_string()) return make_error(where + ".bound_pipelines holds a non-string");
        names.push_back(short_pipe_name(b.get<std::string>()));
    }
    bound = join(names, ", ");
    return {};
}

// One entry of a shader's "variants": its own pipelines (their order may
// differ between variants), the three paths and its register properties.
Result<VendorVariant> parse_json_variant(const json& variant, const std::string& name) {
    VendorVariant out;
    out.name = name;
    const json* performance = member(variant, "performance");
    if (!performance || !performance->is_object()) return make_error("no performance");
    const json* pipelines = member(*performance, "pipelines");
    if (!pipelines || !pipelines->is_array() || pipelines->empty()) return make_error("no performance.pipelines");
    for (const json& p : *pipelines) {
        if (!p.is_string()) return make_error("performance.pipelines holds a non-string");
        out.pipes.push_back(short_pipe_name(p.get<std::string>()));
    }
    for (Status s : {read_json_path(*performance, "total_cycles", out.pipes.size(), out.total, out.total_bound),
                     read_json_path(*performance, "shortest_path_cycles", out.pipes.size(), out.shortest, out.shortest_bound),
                     read_json_path(*performance, "longest_path_cycles", out.pipes.size(), out.longest, out.longest_bound)})
        if (!s) return s.error();
    out.bound = pick_bound(out.longest_bound, out.total_bound);

    const json* properties = member(variant, "properties");
    if (!properties || !properties->is_array()) return make_error("no properties");
    for (auto [key, field] : {std::pair{"work_registers_used", &out.work_registers},
                              std::pair{"uniform_registers_used", &out.uniform_registers}}) {
        const json* value = property(properties, key);
        if (value && value->is_null()) continue;  // N/A
        auto count = json_count(value, key);
        if (!count) return count.error();
        *field = *count;
    }
    if (const json* fp16 = property(properties, "fp16_arithmetic"); fp16 && !fp16->is_null()) {
        if (!fp16->is_number()) return make_error("fp16_arithmetic is not a number");
        const double d = fp16->get<double>();
        if (!std::isfinite(d) || d < 0.0 || d > 100.0)
            return make_error("fp16_arithmetic is " + fp16->dump() + ", not a percentage");
        out.fp16_percent = d;
    }
    if (const json* spilling = property(properties, "has_stack_spilling"); spilling && spilling->is_boolean())
        out.stack_spilling = spilling->get<bool>();
    if (const json* spill = property(properties, "stack_spill_bytes"); spill && !spill->is_null()) {
        auto bytes = json_count(spill, "stack_spill_bytes");
        if (!bytes) return bytes.error();
        if (*bytes > 0) {
            out.stack_spilling = true;
            out.notes.push_back("stack spill " + std::to_string(*bytes) + " bytes");
        }
    }
    return out;
}

Result<VendorCycles> parse_malioc_json_inner(const std::string& output) {
    const json report = json::parse(output, nullptr, false);
    if (report.is_discarded()) return make_error("not valid JSON");
    if (!report.is_object()) return make_error("not a JSON object");

    const json* shaders = member(report, "shaders");
    const json* schema = member(report, "schema");
    const json* schema_name = schema ? member(*schema, "name") : nullptr;
    if (schema_name && schema_name->is_string() && schema_name->get<std::string>() != "performance") {
        // An error report: the compiler's messages say what failed.
        std::vector<std::string> errors;
        if (shaders && shaders->is_array())
            for (const json& s : *shaders)
                if (const json* e = member(s, "errors"); e && e->is_array())
                    for (const json& message : *e)
                        if (message.is_string()) errors.push_back(trim(message.get<std::string>()));
        return make_error("a '" + schema_name->get<std::string>() + "' report, not a performance report" +
                          (errors.empty() ? std::string() : ": " + join(errors, "; ")));
    }

    VendorCycles out;
    out.tool = "malioc";
    if (const json* producer = member(report, "producer")) {
        const json* version = member(*producer, "version");
        if (version && version->is_array() && !version->empty()) {
            std::vector<std::string> parts;
            for (const json& v : *version) {
                if (!v.is_number_integer() || v.get<long long>() < 0)
                    return make_error("producer.version holds " + v.dump() + ", not a version number");
                parts.push_back(std::to_string(v.get<long long>()));
            }
            out.tool += " " + join(parts, ".");
        }
    }

    if (!shaders || !shaders->is_array() || shaders->empty()) return make_error("no shaders array");
    const json& shader = (*shaders)[0];
    const json* hardware = member(shader, "hardware");
    const json* core = hardware ? member(*hardware, "core") : nullptr;
    if (!core || !core->is_string() || core->get<std::string>().empty()) return make_error("no shaders[0].hardware.core");
    std::string hardware_name = core->get<std::string>();
    if (const json* revision = member(*hardware, "revision"); revision && revision->is_string())
        hardware_name += " " + revision->get<std::string>();
    const json* architecture = member(*hardware, "architecture");
    out.target = target_name(hardware_name, architecture && architecture->is_string() ? architecture->get<std::string>() : "");

    if (const json* info = member(shader, "shader"); info && info->is_object()) {
        const json* api = member(*info, "api");
        const json* type = member(*info, "type");
        std::string t;
        if (api && api->is_string()) t = api->get<std::string>();
        if (type && type->is_string()) t += (t.empty() ? "" : " ") + type->get<std::string>();
        out.shader_type = t;
    }
    const json* variants = member(shader, "variants");
    if (!variants || !variants->is_array() || variants->empty()) return make_error("no shaders[0].variants");
    std::vector<VendorVariant> read;
    for (std::size_t i = 0; i < variants->size(); ++i) {
        const json* name = member((*variants)[i], "name");
        const std::string variant_name = name && name->is_string() ? name->get<std::string>() : "variant " + std::to_string(i);
        Result<VendorVariant> v = parse_json_variant((*variants)[i], variant_name);
        if (!v) return with_context("shaders[0].variants[" + std::to_string(i) + "] ('" + variant_name + "')", v.error());
        read.push_back(std::move(*v));
    }

    // Shader properties that hold (uniform computation, late ZS test, ...), by their display names.
    if (const json* shader_properties = member(shader, "properties"); shader_properties && shader_properties->is_array()) {
        for (const json& p : *shader_properties) {
            const json* value = member(p, "value");
            if (!value || !value->is_boolean() || !value->get<bool>()) continue;
            const json* display = member(p, "display_name");
            const json* name = member(p, "name");
            if (display && display->is_string()) out.notes.push_back(property_note(display->get<std::string>()));
            else if (name && name->is_string()) out.notes.push_back(property_note(name->get<std::string>()));
        }
    }
    set_variants(out, std::move(read));
    return out;
}

// --- PowerVR ----------------------------------------------------------------------

// The figures the profile may hold, matched on the words of their documented
// names (lowercase); the first in this order that is present becomes `cycles`.
enum class PowerVrFigure { worst, emulated, approximate, total, per_line, best, temporaries, usc_instructions, none };

PowerVrFigure classify_powervr_label(const std::string& label) {
    const std::string l = lower(label);
    if (contains(l, "performance estimate") && contains(l, "worst")) return PowerVrFigure::worst;
    if (contains(l, "performance estimate") && contains(l, "best")) return PowerVrFigure::best;
    if (contains(l, "per-line cycle")) return PowerVrFigure::per_line;
    if (contains(l, "emulated") && contains(l, "cycle")) return PowerVrFigure::emulated;
    if (contains(l, "approximate") && contains(l, "cycle")) return PowerVrFigure::approximate;
    if ((contains(l, "total") && contains(l, "cycle")) || l == "cycles" || l == "cycle count")
        return PowerVrFigure::total;
    if (contains(l, "temp") && contains(l, "register")) return PowerVrFigure::temporaries;
    if (contains(l, "usc instructions")) return PowerVrFigure::usc_instructions;
    return PowerVrFigure::none;
}

Result<VendorCycles> parse_powervr_inner(const std::string& output) {
    VendorCycles out;
    out.tool = "GLSLESCompiler";
    out.target = "PowerVR";
    double worst = -1, emulated = -1, approximate = -1, total = -1, per_line = -1, best = -1;
    int usc_instructions = -1;
    for (const std::string& raw : split_lines(output)) {
        const std::string line = trim(raw);
        // "label: value" or "label = value"; whichever separator comes first.
        const std::size_t at = line.find_first_of(":=");
        if (at == std::string::npos) continue;
        const std::string label = trim(line.substr(0, at));
        const PowerVrFigure kind = classify_powervr_label(label);
        if (kind == PowerVrFigure::none) continue;
        const std::vector<std::string> words = split_words(line.substr(at + 1));
        const std::string first = words.empty() ? "" : words[0];
        const std::string what = "'" + label + "'";
        if (kind == PowerVrFigure::temporaries || kind == PowerVrFigure::usc_instructions) {
            auto count = parse_count(first, what);
            if (!count) return count.error();
            (kind == PowerVrFigure::temporaries ? out.work_registers : usc_instructions) = *count;
            continue;
        }
        auto value = parse_figure(first, what);
        if (!value) return value.error();
        switch (kind) {
            case PowerVrFigure::worst: worst = *value; break;
            case PowerVrFigure::best: best = *value; break;
            case PowerVrFigure::per_line: per_line = *value; break;
            case PowerVrFigure::emulated: emulated = *value; break;
            case PowerVrFigure::approximate: approximate = *value; break;
            case PowerVrFigure::total: total = *value; break;
            default: break;
        }
    }
    // The worst-case emulated estimate, as malioc's longest path: what a
    // frame pays when the branches go badly.
    const std::pair<double, const char*> order[] = {
        {worst, "worst-case performance estimate"}, {emulated, "emulated cycles"},
        {approximate, "approximate cycles"},        {total, "total cycles"},
        {per_line, "per-line cycle estimate total"},
    };
    for (const auto& [value, name] : order) {
        if (value < 0) continue;
        out.cycles = value;
        out.notes.push_back(std::string("cycles: ") + name);
        break;
    }
    if (out.cycles < 0)
        return make_error("no cycle figure (looked for 'Performance estimate (Worst)', 'Emulated cycles', "
                          "'Approximate cycles', 'Total cycles', 'Per-line Cycle Estimate Total')");
    if (best >= 0) out.notes.push_back("best-case estimate " + figure(best) + " cycles");
    if (per_line >= 0 && out.cycles != per_line) out.notes.push_back("per-line estimate total " + figure(per_line) + " cycles");
    if (usc_instructions >= 0) out.notes.push_back("global USC instructions " + std::to_string(usc_instructions));
    return out;
}

// --- Running a tool -------------------------------------------------------------

struct ProcessOutcome {
    std::string output;   // stdout and stderr as they interleaved
    int exit_status = -1; // when the tool exited
    int signal = 0;       // when a signal ended it
    bool timed_out = false;
    bool over_cap = false;
};

std::string describe_end(const ProcessOutcome& outcome) {
    if (outcome.signal) return "killed by signal " + std::to_string(outcome.signal);
    return "exited with status " + std::to_string(outcome.exit_status);
}

// Runs argv[0] with stdout and stderr into one pipe (include/parallaxes/profiling/costs/process.h:
// its own process group, killed whole at the time limit or the output cap).
Result<ProcessOutcome> run_captured(const std::vector<std::string>& argv, std::chrono::milliseconds time_limit) {
    ProcessOptions options;
    options.timeout_s = std::chrono::duration<double>(time_limit).count();
    options.max_output = kOutputCap;
    Result<ProcessResult> ran = run_process(argv, options);
    if (!ran) return ran.error();
    ProcessOutcome outcome;
    outcome.output = std::move(ran->output);
    outcome.exit_status = ran->exit_status;
    outcome.signal = ran->signal;
    outcome.timed_out = ran->timed_out;
    outcome.over_cap = ran->truncated;
    return outcome;
}

bool write_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    return static_cast<bool>(out);
}

// What kind of file a mode is, for messages.
const char* file_kind(mode_t mode) {
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISDIR(mode)) return "a folder";
    if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

// A file a tool wrote (PowerVR's <out>.prof), read only if it is a regular
// file: O_NONBLOCK so that opening a FIFO planted at the name returns at
// once (then fstat refuses it, as it refuses a device that would never
// end), O_NOFOLLOW so that a symlink is not followed, at most kOutputCap
// bytes. A missing file is no text: the report may be on stdout.
Result<std::string> read_tool_file(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) {
        if (errno == ENOENT) return std::string();
        if (errno == ELOOP) return make_error(path + " is a symbolic link: not followed");
        return make_error("cannot open " + path + ": " + std::strerror(errno));
    }
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st;
    if (::fstat(fd, &st) != 0) return make_error("cannot read " + path + ": " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) return make_error(path + " is " + file_kind(st.st_mode) + ", not a regular file: not read");
    if (static_cast<std::uint64_t>(st.st_size) > kOutputCap)
        return make_error(path + " is " + std::to_string(st.st_size) + " bytes, past the " +
                          std::to_string(kOutputCap >> 20) + " MiB a report may have");
    std::string text(kOutputCap + 1, '\0');
    std::size_t got = 0;
    while (got < text.size()) {
        const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return make_error("cannot read " + path + ": " + std::strerror(errno));
        if (n == 0) break;
        got += static_cast<std::size_t>(n);
    }
    if (got > kOutputCap) return make_error(path + " grew past " + std::to_string(kOutputCap >> 20) + " MiB while read");
    text.resize(got);
    return text;
}

bool looks_like_json(const std::string& output) {
    const std::string t = trim(output);
    return !t.empty() && t[0] == '{';
}

// --- Text from a tool ------------------------------------------------------------

// The length of the valid UTF-8 sequence at s[i] and its code point; 0 when
// the bytes there are not one (a stray continuation byte, a truncated or
// overlong sequence, a surrogate, past U+10FFFF).
std::size_t utf8_sequence(const std::string& s, std::size_t i, char32_t& code) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char lead = byte(i);
    std::size_t length = 0;
    char32_t smallest = 0;
    if (lead < 0x80) {
        code = lead;
        return 1;
    }
    if ((lead & 0xE0) == 0xC0) {
        length = 2;
        smallest = 0x80;
    } else if ((lead & 0xF0) == 0xE0) {
        length = 3;
        smallest = 0x800;
    } else if ((lead & 0xF8) == 0xF0) {
        length = 4;
        smallest = 0x10000;
    } else {
        return 0;
    }
    code = lead & (0x7Fu >> length);  // the lead byte's payload bits
    if (i + length > s.size()) return 0;
    for (std::size_t k = 1; k < length; ++k) {
        if ((byte(i + k) & 0xC0) != 0x80) return 0;
        code = (code << 6) | (byte(i + k) & 0x3F);
    }
    if (code < smallest || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
    return length;
}

// Past a control sequence's parameters and final byte (ECMA-48 5.4): the
// index after it, from the index after "ESC [" (or the 8-bit CSI).
std::size_t skip_csi(const std::string& s, std::size_t i) {
    while (i < s.size() && s[i] >= 0x20 && s[i] <= 0x3F) ++i;
    if (i < s.size() && s[i] >= 0x40 && s[i] <= 0x7E) ++i;
    return i;
}

// Past a control string (OSC, DCS, ...: a terminal title, a hyperlink) up
// to its terminator, BEL or ST ("ESC \\", the 8-bit ST); a newline ends it
// here too, so that an unterminated one cannot swallow the whole report.
std::size_t skip_control_string(const std::string& s, std::size_t i) {
    for (; i < s.size(); ++i) {
        if (s[i] == '\a') return i + 1;
        if (s[i] == '\n') return i;
        if (s[i] == '\x1b' && i + 1 < s.size() && s[i + 1] == '\\') return i + 2;
        if (s.compare(i, 2, "\xc2\x9c") == 0) return i + 2;
    }
    return i;
}

// Past an escape sequence from the index after its ESC.
std::size_t skip_escape(const std::string& s, std::size_t i) {
    if (i >= s.size()) return i;
    if (s[i] == '[') return skip_csi(s, i + 1);
    if (s[i] == ']' || s[i] == 'P' || s[i] == 'X' || s[i] == '^' || s[i] == '_') return skip_control_string(s, i + 1);
    return s[i] >= 0x20 && s[i] <= 0x7E ? i + 1 : i;  // a two-byte escape (ESC c, ESC 7, ...)
}

}  // namespace

// --- Public entry points ------------------------------------------------------------

Result<VendorCycles> parse_malioc_text(const std::string& output) {
    auto parsed = out_of_memory_is_an_error("malioc report", [&] { return parse_malioc_text_inner(output); });
    if (!parsed) return with_context("malioc report", parsed.error());
    return parsed;
}

Result<VendorCycles> parse_malioc_json(const std::string& output) {
    auto parsed = out_of_memory_is_an_error("malioc JSON report", [&] { return parse_malioc_json_inner(output); });
    if (!parsed) return with_context("malioc JSON report", parsed.error());
    return parsed;
}

Result<VendorCycles> parse_powervr_output(const std::string& output) {
    auto parsed = out_of_memory_is_an_error("PowerVR profile", [&] { return parse_powervr_inner(output); });
    if (!parsed) return with_context("PowerVR profile", parsed.error());
    return parsed;
}

std::vector<VendorTool> find_vendor_tools() {
    std::vector<VendorTool> found;
    const char* path_variable = std::getenv("PATH");
    if (!path_variable) return found;
    std::vector<std::string> folders;
    std::string folder;
    std::istringstream in(path_variable);
    while (std::getline(in, folder, ':'))
        if (!folder.empty() && folder[0] == '/') folders.push_back(folder);  // relative entries would depend on the cwd
    for (const char* name : kCandidateTools) {
        for (const std::string& f : folders) {
            const std::string candidate = (std::filesystem::path(f) / name).string();
            std::error_code ec;
            if (std::filesystem::is_regular_file(candidate, ec) && access(candidate.c_str(), X_OK) == 0) {
                found.push_back(VendorTool{name, candidate});
                break;  // the first on PATH, as a shell would run it
            }
        }
    }
    return found;
}

std::string clean_tool_text(const std::string& raw) {
    std::string out;
    out.reserve(raw.size());
    std::size_t i = 0;
    while (i < raw.size()) {
        char32_t code = 0;
        const std::size_t length = utf8_sequence(raw, i, code);
        if (length == 0) {
            out += "\xEF\xBF\xBD";  // U+FFFD REPLACEMENT CHARACTER
            ++i;
        } else if (code == 0x1B) {
            i = skip_escape(raw, i + 1);
        } else if (code == 0x9B) {  // 8-bit CSI
            i = skip_csi(raw, i + length);
        } else if (code == 0x90 || code == 0x98 || code == 0x9D || code == 0x9E || code == 0x9F) {  // 8-bit DCS, SOS, OSC, PM, APC
            i = skip_control_string(raw, i + length);
        } else if ((code < 0x20 && code != '\n' && code != '\t') || (code >= 0x7F && code <= 0x9F)) {
            i += length;  // C0 (but newline and tab), DEL, C1
        } else {
            out.append(raw, i, length);
            i += length;
        }
    }
    return out;
}

namespace {

// The tool's command line for one source file in `folder`.
std::vector<std::string> tool_command(const VendorTool& tool, bool malioc, const std::string& source_path,
                                      const std::string& profile_base, ShaderStage stage) {
    std::vector<std::string> argv{tool.path};
    if (malioc) {
        // The stage is given as well as implied by the extension; JSON is
        // the format with named fields (older versions without it print
        // text, which the text parser reads).
        argv.insert(argv.end(), {stage == ShaderStage::vertex ? "--vertex" : "--fragment", "--format", "json", source_path});
    } else {
        // `<in> <out> -v|-f -profile`: the profile goes to <out>.prof.
        argv.insert(argv.end(), {source_path, profile_base, stage == ShaderStage::vertex ? "-v" : "-f", "-profile"});
    }
    return argv;
}

// The tool's figures from its (cleaned) output; `profile_base` for PowerVR's .prof.
Result<VendorCycles> parse_tool_output(const VendorTool& tool, bool malioc, const std::string& output,
                                       const std::string& profile_base) {
    if (malioc) return looks_like_json(output) ? parse_malioc_json(output) : parse_malioc_text(output);
    Result<std::string> profile = read_tool_file(profile_base + ".prof");
    if (!profile) return profile.error();
    Result<VendorCycles> parsed = parse_powervr_output(output + "\n" + clean_tool_text(*profile));
    if (parsed) {
        parsed->tool = tool.name;
        parsed->target = tool.name.substr(std::strlen(kPowerVrPrefix));
    }
    return parsed;
}

// run_vendor_tool, telling the caller whether the tool ran out of time.
Result<VendorCycles> run_tool_once(const VendorTool& tool, const std::string& source, ShaderStage stage, int es_major,
                                   std::chrono::milliseconds time_limit, bool& timed_out) {
    const std::string name = tool.name.empty() ? std::string("vendor compiler") : tool.name;
    const bool malioc = tool.name == "malioc";
    const bool powervr = starts_with(tool.name, kPowerVrPrefix) && tool.name.size() > std::strlen(kPowerVrPrefix);
    if (!malioc && !powervr) return make_error(name + ": not a vendor compiler this build knows");
    if (tool.path.empty() || tool.path[0] != '/') return make_error(name + ": needs an absolute path, got '" + tool.path + "'");
    // Both tools read the language version from the source's #version line;
    // es_major is checked so that a caller's mistake is not hidden.
    if (es_major != 2 && es_major != 3) return make_error(name + ": OpenGL ES " + std::to_string(es_major) + " is not 2 or 3");

    // Registered: an interrupt removes it too (core/interrupts.h).
    Result<interrupts::TempFolder> folder = interrupts::TempFolder::create("parallax-vendor-");
    if (!folder) return with_context(name, folder.error());
    const std::string source_path = folder->path() + (stage == ShaderStage::vertex ? "/shader.vert" : "/shader.frag");
    if (!write_file(source_path, source)) return make_error(name + ": cannot write " + source_path);
    const std::string profile_base = folder->path() + "/profile";

    auto ran = run_captured(tool_command(tool, malioc, source_path, profile_base, stage), time_limit);
    if (!ran) return with_context(name, ran.error());
    ProcessOutcome& outcome = *ran;
    // Whatever the tool printed, before any parser or message sees it.
    outcome.output = clean_tool_text(outcome.output);
    const std::string heading = name + " (" + tool.path + ")";
    timed_out = outcome.timed_out;
    if (outcome.timed_out)
        return make_error(heading + ": killed after the " + std::to_string(time_limit.count()) +
                          " ms limit; first lines of its output:\n" + first_lines(outcome.output));
    if (outcome.over_cap)
        return make_error(heading + ": killed, its output passed " + std::to_string(kOutputCap >> 20) +
                          " MiB; first lines:\n" + first_lines(outcome.output));
    if (outcome.signal != 0 || outcome.exit_status != 0) {
        std::string reason;
        if (malioc && looks_like_json(outcome.output)) {
            auto report = parse_malioc_json(outcome.output);
            if (!report) reason = " (" + report.error().message + ")";
        }
        return make_error(heading + ": " + describe_end(outcome) + reason + "; first lines of its output:\n" +
                          first_lines(outcome.output));
    }
    Result<VendorCycles> parsed = parse_tool_output(tool, malioc, outcome.output, profile_base);
    if (!parsed)
        return make_error(heading + ": " + describe_end(outcome) + " but " + parsed.error().message +
                          "; first lines of its output:\n" + first_lines(outcome.output));
    return parsed;
}

// Every string of a result or an error through clean_tool_text: names the
// tool's JSON carried (its escapes decode to any character), the tool's
// path from $PATH.
Result<VendorCycles> cleaned(Result<VendorCycles> r) {
    if (!r) return make_error(clean_tool_text(r.error().message));
    for (std::string* s : {&r->tool, &r->target, &r->bound}) *s = clean_tool_text(*s);
    for (std::string& s : r->pipes) s = clean_tool_text(s);
    for (std::string& s : r->notes) s = clean_tool_text(s);
    return r;
}

std::string seconds_text(std::chrono::steady_clock::duration d) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.1f s", std::chrono::duration<double>(d).count());
    return buffer;
}

}  // namespace

Result<VendorCycles> run_vendor_tool(const VendorTool& tool, const std::string& source, ShaderStage stage, int es_major,
                                     std::chrono::milliseconds time_limit) {
    bool timed_out = false;
    return cleaned(run_tool_once(tool, source, stage, es_major, time_limit, timed_out));
}

VendorRun::VendorRun(std::vector<VendorTool> tools, std::chrono::milliseconds budget)
    : tools_(std::move(tools)), budget_(budget) {}

Result<VendorCycles> VendorRun::run(const VendorTool& tool, const std::string& source, ShaderStage stage, int es_major) {
    const std::string name = clean_tool_text(tool.name);
    if (std::find(timed_out_.begin(), timed_out_.end(), tool.name) != timed_out_.end())
        return make_error("skipped: " + name + " ran out of time earlier in this run");
    using std::chrono::milliseconds;
    const auto left = std::chrono::duration_cast<milliseconds>(budget_ - used_);
    // Less than 100 ms is no time to start a compiler in.
    if (left < milliseconds(100)) {
        if (!budget_noted_)
            notes_.push_back("the vendor compilers' time (--vendor-timeout " + seconds_text(budget_) +
                             ") was spent: the remaining runs were skipped");
        budget_noted_ = true;
        return make_error("skipped: the vendor compilers' time (" + seconds_text(budget_) + ") was spent");
    }
    const milliseconds limit = std::min(left, std::max(milliseconds(100), budget_ / 2));
    const auto start = std::chrono::steady_clock::now();
    bool timed_out = false;
    Result<VendorCycles> r = cleaned(run_tool_once(tool, source, stage, es_major, limit, timed_out));
    used_ += std::chrono::steady_clock::now() - start;
    if (timed_out) {
        timed_out_.push_back(tool.name);
        notes_.push_back(name + " did not finish within " + seconds_text(limit) + " and was not run again (--vendor-timeout " +
                         seconds_text(budget_) + " in all)");
    }
    return r;
}

std::string vendor_tools_absent_line() {
    std::vector<std::string> names(std::begin(kCandidateTools), std::end(kCandidateTools));
    return "no vendor compiler on PATH (looked for " + join(names, ", ") + ")";
}

}  // namespace px::profiling
