// Report writers for the accuracy/time benchmark (bench_results.h): CSV, JSON,
// a Pareto plot as a self-contained SVG, and a markdown summary.
//
// Every writer builds its whole text in memory, writes it to path + ".tmp" and
// renames that over path, so a failure never leaves a partial file behind.
// Numbers are formatted with std::to_chars, which ignores the C locale.
#include "parallaxes/profiling/reports/bench_results.h"
#include "parallaxes/profiling/reports/svg_plot.h"

#include "parallaxes/core/files.h"
#include "parallaxes/core/numeric.h"
#include "parallaxes/effects/technique.h"

#include <algorithm>
#include <map>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace px::profiling {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Whether the run's times are llvmpipe's (Mesa's CPU rasteriser, the stand-in
// for a mobile GPU) rather than a real GPU's: the report says which.
bool on_llvmpipe(const BenchRun& run) { return run.gl_renderer.find("llvmpipe") != std::string::npos; }

// ------------------------------------------------------------------ output

// ----------------------------------------------------------------- numbers

std::string to_chars_string(double v, std::chars_format format, int precision) {
    std::array<char, 400> buf{};  // fixed notation of 1e308 needs 309 digits
    const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v, format, precision);
    if (ec != std::errc()) return "?";
    std::string s(buf.data(), end);
    // "-0.00" reads as a sign error; a value that rounds to zero has none.
    if (s.size() > 1 && s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
    return s;
}

// %.Ng without the locale.
std::string general(double v, int significant = 6) {
    return to_chars_string(v, std::chars_format::general, significant);
}

// %.Nf without the locale.
std::string fixed(double v, int decimals) { return to_chars_string(v, std::chars_format::fixed, decimals); }

// For people: NaN as "n/a", infinities as signs.
std::string human(const std::string& formatted, double v) {
    if (std::isnan(v)) return "n/a";
    if (std::isinf(v)) return v > 0 ? "∞" : "−∞";
    return formatted;
}
std::string human_fixed(double v, int decimals) { return human(fixed(v, decimals), v); }
// `significant` digits, but never an exponent for values up to 1e6.
std::string human_sig(double v, int significant = 3) {
    if (std::isfinite(v) && std::fabs(v) >= std::pow(10.0, significant) && std::fabs(v) < 1e6) return human_fixed(v, 0);
    return human(general(v, significant), v);
}

std::string angle_text(double deg) { return human(general(deg, 6), deg) + "°"; }

// NaN compares as +inf, so it sorts last and never wins a minimum.
double or_inf(double v) { return std::isnan(v) ? kInf : v; }

bool same_angle(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

// bench --gpu: a row's cycles per pixel over normal mapping's at the same
// scene and angle; NaN where either is missing.
double gpu_ratio_to_normal(const BenchRun& run, const BenchRow& r) {
    double normal = std::numeric_limits<double>::quiet_NaN();
    for (const BenchRow& n : run.rows)
        if (n.technique == "normal" && n.scene == r.scene && same_angle(n.angle_deg, r.angle_deg))
            normal = n.gpu_cycles_per_pixel;
    return normal > 0.0 ? r.gpu_cycles_per_pixel / normal : std::numeric_limits<double>::quiet_NaN();
}
bool angle_less(double a, double b) { return or_inf(a) < or_inf(b) || (!std::isnan(a) && std::isnan(b)); }

// ------------------------------------------------------------ row fields

struct Measure {
    const char* name;
    double BenchRow::*member;
};

// The floating-point fields after scene, angle_deg, technique, samples, pixels.
constexpr std::array<Measure, 23> kMeasures{{
    {"uv_error_mean", &BenchRow::uv_error_mean},
    {"uv_error_p95", &BenchRow::uv_error_p95},
    {"input_floor_p95", &BenchRow::input_floor_p95},
    {"own_ray_error_p95", &BenchRow::own_ray_error_p95},
    {"uv_error_max", &BenchRow::uv_error_max},
    {"wrong_surface_share", &BenchRow::wrong_surface_share},
    {"depth_error_mean", &BenchRow::depth_error_mean},
    {"depth_error_max", &BenchRow::depth_error_max},
    {"shadow_disagreement", &BenchRow::shadow_disagreement},
    {"color_psnr_db", &BenchRow::color_psnr_db},
    {"frame_ms_median", &BenchRow::frame_ms_median},
    {"frame_ms_min", &BenchRow::frame_ms_min},
    {"frame_ms_max", &BenchRow::frame_ms_max},
    {"ns_per_pixel", &BenchRow::ns_per_pixel},
    {"ratio_to_normal", &BenchRow::ratio_to_normal},
    {"iterations_median", &BenchRow::iterations_median},
    {"iterations_p90", &BenchRow::iterations_p90},
    {"iterations_p99", &BenchRow::iterations_p99},
    {"iterations_max", &BenchRow::iterations_max},
    {"fetches_median", &BenchRow::fetches_median},
    {"gpu_cycles", &BenchRow::gpu_cycles},
    {"gpu_loops", &BenchRow::gpu_loops},
    {"gpu_cycles_per_pixel", &BenchRow::gpu_cycles_per_pixel},
}};

// ------------------------------------------------------------- techniques

enum class Marker { circle, square, triangle_up, triangle_down, diamond, pentagon, hexagon, star, cross, plus };

struct TechniqueStyle {
    const char* colour;
    Marker marker;
};

// The catalogue's techniques in table order (effects/technique.h), then the
// displaced-mesh baseline; matplotlib's tab10 colours.
constexpr std::array<TechniqueStyle, 8> kCatalogueStyles{{
    {"#7f7f7f", Marker::circle},
    {"#1f77b4", Marker::square},
    {"#ff7f0e", Marker::triangle_up},
    {"#bcbd22", Marker::triangle_down},
    {"#2ca02c", Marker::diamond},
    {"#d62728", Marker::pentagon},
    {"#9467bd", Marker::hexagon},
    {"#17becf", Marker::star},
}};
static_assert(kCatalogueStyles.size() >= static_cast<size_t>(kTechniqueCount), "a style per catalogue technique");
constexpr TechniqueStyle kBaselineStyle{"#8c564b", Marker::cross};

// For names outside the catalogue, in order of appearance.
constexpr std::array<const char*, 6> kExtraColours{{"#e377c2", "#393b79", "#637939", "#8c6d31", "#843c39", "#7b4173"}};
constexpr std::array<Marker, 4> kExtraMarkers{{Marker::plus, Marker::circle, Marker::square, Marker::diamond}};

struct TechniqueEntry {
    std::string name;
    std::string colour;
    Marker marker;
};

// The techniques in the run: catalogue order, then unknown names in order of
// appearance, each with its colour and marker.
std::vector<TechniqueEntry> techniques_in(const BenchRun& run) {
    std::vector<TechniqueEntry> out;
    auto add_if_present = [&](const std::string& name, const TechniqueStyle& style) {
        const bool present =
            std::any_of(run.rows.begin(), run.rows.end(), [&](const BenchRow& r) { return r.technique == name; });
        if (present) out.push_back({name, style.colour, style.marker});
    };
    for (const TechniqueInfo& info : technique_table())
        add_if_present(info.name, kCatalogueStyles[static_cast<size_t>(info.id)]);
    add_if_present(kDisplacedMesh, kBaselineStyle);
    size_t extra = 0;
    for (const BenchRow& row : run.rows) {
        const bool seen =
            std::any_of(out.begin(), out.end(), [&](const TechniqueEntry& t) { return t.name == row.technique; });
        if (seen) continue;
        out.push_back(
            {row.technique, kExtraColours[extra % kExtraColours.size()], kExtraMarkers[extra % kExtraMarkers.size()]});
        ++extra;
    }
    return out;
}

size_t technique_index(const std::vector<TechniqueEntry>& techniques, const std::string& name) {
    for (size_t i = 0; i < techniques.size(); ++i)
        if (techniques[i].name == name) return i;
    return techniques.size();
}

std::vector<std::string> scenes_in(const BenchRun& run) {
    std::vector<std::string> out;
    for (const BenchRow& row : run.rows)
        if (std::find(out.begin(), out.end(), row.scene) == out.end()) out.push_back(row.scene);
    return out;
}

size_t scene_index(const std::vector<std::string>& scenes, const std::string& name) {
    return static_cast<size_t>(std::find(scenes.begin(), scenes.end(), name) - scenes.begin());
}

// "pom, 16 samples"; just the name where the technique has no sample count.
std::string setting_text(const BenchRow& row) {
    if (row.samples <= 0) return row.technique;
    return row.technique + ", " + std::to_string(row.samples) + (row.samples == 1 ? " sample" : " samples");
}

// ------------------------------------------------------------------- text

// Number of code points (display width estimates).
size_t utf8_length(const std::string& s) {
    return static_cast<size_t>(
        std::count_if(s.begin(), s.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}


// One line, with '|' escaped, for a markdown table cell or list item.
std::string md_text(const std::string& s) {
    std::string out;
    for (const char c : s) {
        if (c == '|')
            out += "\\|";
        else if (c == '\n' || c == '\r')
            out += ' ';
        else
            out += c;
    }
    return out;
}

// `s` as a markdown code span, whatever backticks it holds.
std::string md_code(const std::string& s) {
    std::string text;
    for (const char c : s) text += (c == '\n' || c == '\r') ? ' ' : c;
    size_t longest = 0, run = 0;
    for (const char c : text) {
        run = c == '`' ? run + 1 : 0;
        longest = std::max(longest, run);
    }
    const std::string fence(longest + 1, '`');
    const bool pad = !text.empty() && (text.front() == '`' || text.back() == '`');
    return fence + (pad ? " " : "") + text + (pad ? " " : "") + fence;
}

// ==================================================================== CSV

std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
    std::string out = "\"";
    for (const char c : s) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

// NaN as an empty (missing) field; infinities as inf/-inf, which spreadsheet
// and dataframe readers parse.
std::string csv_number(double v) {
    if (std::isnan(v)) return "";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    return general(v, 6);
}

std::string csv_text(const BenchRun& run) {
    std::string out =
        "date,gl_renderer,gl_version,threads,width,height,frames,scene,angle_deg,technique,samples,pixels";
    for (const Measure& m : kMeasures) out += std::string(",") + m.name;
    out += '\n';
    // The run-level columns repeat on every row, so each row stands alone.
    const std::string run_columns = csv_field(run.date) + "," + csv_field(run.gl_renderer) + "," +
                                    csv_field(run.gl_version) + "," + std::to_string(run.threads) + "," +
                                    std::to_string(run.width) + "," + std::to_string(run.height) + "," +
                                    std::to_string(run.frames);
    for (const BenchRow& row : run.rows) {
        out += run_columns;
        out += "," + csv_field(row.scene) + "," + csv_number(row.angle_deg) + "," + csv_field(row.technique) + "," +
               std::to_string(row.samples) + "," + std::to_string(row.pixels);
        for (const Measure& m : kMeasures) out += "," + csv_number(row.*m.member);
        out += '\n';
    }
    return out;
}

// =================================================================== JSON

nlohmann::ordered_json json_number(double v) {
    return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

std::string json_text(const BenchRun& run) {
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (const BenchRow& row : run.rows) {
        nlohmann::ordered_json r = nlohmann::ordered_json::object();
        r["scene"] = row.scene;
        r["angle_deg"] = json_number(row.angle_deg);
        r["technique"] = row.technique;
        r["samples"] = row.samples;
        r["pixels"] = row.pixels;
        for (const Measure& m : kMeasures) r[m.name] = json_number(row.*m.member);
        if (!row.iteration_histogram.empty()) r["iteration_histogram"] = row.iteration_histogram;
        rows.push_back(std::move(r));
    }
    nlohmann::ordered_json doc = nlohmann::ordered_json::object();
    doc["date"] = run.date;
    doc["command"] = run.command;
    doc["gl_renderer"] = run.gl_renderer;
    doc["gl_version"] = run.gl_version;
    doc["threads"] = run.threads;
    doc["width"] = run.width;
    doc["height"] = run.height;
    doc["frames"] = run.frames;
    if (!run.gpu.empty()) doc["gpu"] = run.gpu;
    doc["rows"] = std::move(rows);
    // Keys in the order above. Invalid UTF-8 (a command line can hold anything) becomes U+FFFD instead of throwing.
    return doc.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

// ==================================================================== SVG

constexpr double kMinError = 0.01;  // texels; lower errors are drawn here
constexpr std::array<double, 4> kGuides{{1.0, 0.5, 0.25, 0.1}};
constexpr std::array<const char*, 3> kAngleClasses{{"0-30°", "45-60°", "75-89°"}};

// Angles between the classes go to the nearer one (boundaries at 37.5° and
// 67.5°); the panel's subtitle lists the angles it holds.
size_t angle_class(double deg) {
    const double a = std::fabs(deg);
    if (a < 37.5) return 0;
    if (a < 67.5) return 1;
    return 2;
}

// Layout, in px.
constexpr double kPlotW = 390, kPlotH = 330;
constexpr double kLeft = 78;       // left of the first plot: y tick labels and axis label
constexpr double kPanelGap = 62;   // between plots: the next panel's y tick labels
constexpr double kLegendGap = 28;  // last plot to legend
constexpr double kLegendW = 190;
constexpr double kRightPad = 16;
constexpr double kMinWidth = 760;
constexpr double kFont = 12;       // body text
constexpr double kSmallFont = 10;  // point and guide labels
constexpr const char* kFontFamily = "DejaVu Sans, Bitstream Vera Sans, Helvetica, Arial, sans-serif";
constexpr std::array<const char*, 4> kSceneDashes{{"", "7 3", "2 2.5", "9 3 2 3"}};

// Rough width of `text` in a DejaVu-like sans-serif.
double text_width(const std::string& text, double font) { return static_cast<double>(utf8_length(text)) * font * 0.61; }

// `text`, cut with an ellipsis to fit `width` px.
std::string fit(const std::string& text, double width, double font) {
    if (text_width(text, font) <= width) return text;
    std::string out;
    for (const char c : text) {
        const bool starts_code_point = (static_cast<unsigned char>(c) & 0xC0) != 0x80;
        if (starts_code_point && text_width(out + "…", font) > width - font * 0.61) break;
        out += c;
    }
    return out + "…";
}

// Greedy word wrap to `width` px.
std::vector<std::string> wrap(const std::string& text, double width, double font) {
    std::vector<std::string> lines;
    std::string line;
    size_t start = 0;
    while (start < text.size()) {
        size_t end = text.find(' ', start);
        if (end == std::string::npos) end = text.size();
        const std::string word = text.substr(start, end - start);
        start = end + 1;
        if (word.empty()) continue;
        const std::string candidate = line.empty() ? word : line + " " + word;
        if (!line.empty() && text_width(candidate, font) > width) {
            lines.push_back(line);
            line = word;
        } else {
            line = candidate;
        }
    }
    if (!line.empty()) lines.push_back(line);
    return lines;
}

std::string num(double v) { return fixed(v, 1); }

struct Rect {
    double x0, y0, x1, y1;
    bool overlaps(const Rect& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

// A log10 axis range.
struct LogAxis {
    double lo = 0, hi = 1;  // log10 of the ends
    double fraction(double v) const { return (std::log10(v) - lo) / (hi - lo); }
};

// [min, max] of log10(values) with `must_include` added, padded by 5% of the
// span each side (matplotlib's margins), at least a decade wide.
LogAxis log_axis(const std::vector<double>& values, const std::vector<double>& must_include, double floor_value) {
    double lo = kInf, hi = -kInf;
    for (const double v : values) {
        lo = std::min(lo, std::log10(v));
        hi = std::max(hi, std::log10(v));
    }
    for (const double v : must_include) {
        lo = std::min(lo, std::log10(v));
        hi = std::max(hi, std::log10(v));
    }
    if (hi - lo < 1.0) {
        const double mid = 0.5 * (lo + hi);
        lo = mid - 0.5;
        hi = mid + 0.5;
    }
    const double pad = 0.05 * (hi - lo);
    LogAxis axis;
    axis.lo = std::max(lo - pad, std::log10(floor_value) - pad);
    axis.hi = hi + pad;
    return axis;
}

using Tick = svg::Tick;

// The shared log ticks (svg_plot.h) on this axis.
std::vector<Tick> log_ticks(const LogAxis& axis) { return svg::log_ticks(axis.lo, axis.hi); }

std::string tick_label(double v) { return general(v, 3); }

// The SVG shape for a marker centred on (x, y), with radius about r: filled
// with `colour`, or white with a `colour` edge when hollow.
std::string marker_svg(Marker marker, double x, double y, double r, const std::string& colour, bool hollow) {
    const std::string style = hollow ? " fill=\"#ffffff\" stroke=\"" + colour + "\" stroke-width=\"1.4\"/>"
                                     : " fill=\"" + colour + "\" stroke=\"#ffffff\" stroke-width=\"0.8\"/>";
    auto polygon = [&](const std::vector<std::pair<double, double>>& unit) {
        std::string points;
        for (const auto& [ux, uy] : unit)
            points += (points.empty() ? "" : " ") + num(x + r * ux) + "," + num(y + r * uy);
        return "<polygon points=\"" + points + "\"" + style;
    };
    auto regular = [&](int n, double rotation, double scale) {
        std::vector<std::pair<double, double>> unit;
        for (int i = 0; i < n; ++i) {
            const double a = rotation + 2.0 * kPi<double> * i / n;
            unit.emplace_back(scale * std::sin(a), -scale * std::cos(a));
        }
        return polygon(unit);
    };
    switch (marker) {
        case Marker::circle:
            return "<circle cx=\"" + num(x) + "\" cy=\"" + num(y) + "\" r=\"" + num(r) + "\"" + style;
        case Marker::square:
            return regular(4, kPi<double> / 4, 1.25);
        case Marker::triangle_up:
            return regular(3, 0, 1.3);
        case Marker::triangle_down:
            return regular(3, kPi<double>, 1.3);
        case Marker::diamond:
            return regular(4, 0, 1.3);
        case Marker::pentagon:
            return regular(5, 0, 1.15);
        case Marker::hexagon:
            return regular(6, 0, 1.12);
        case Marker::star: {
            std::vector<std::pair<double, double>> unit;
            for (int i = 0; i < 10; ++i) {
                const double a = kPi<double> * i / 5;
                const double s = i % 2 == 0 ? 1.45 : 0.6;
                unit.emplace_back(s * std::sin(a), -s * std::cos(a));
            }
            return polygon(unit);
        }
        case Marker::cross:
        case Marker::plus: {
            // A filled plus (12 corners), turned 45° for the cross.
            const double w = 0.38, l = 1.2;
            // clang-format off
            const std::array<std::pair<double, double>, 12> plus{{
                {-w, -l}, {w, -l}, {w, -w}, {l, -w}, {l, w}, {w, w},
                {w, l}, {-w, l}, {-w, w}, {-l, w}, {-l, -w}, {-w, -w}}};
            // clang-format on
            const double a = marker == Marker::cross ? kPi<double> / 4 : 0.0;
            std::vector<std::pair<double, double>> unit;
            for (const auto& [px, py] : plus)
                unit.emplace_back(px * std::cos(a) - py * std::sin(a), px * std::sin(a) + py * std::cos(a));
            return polygon(unit);
        }
    }
    return "";
}

struct PlotPoint {
    const BenchRow* row;
    double x, y;            // ratio to normal; mean error clamped to kMinError
    double sx = 0, sy = 0;  // on the page
    bool frontier = false;
};

// Points of one technique on one scene at one angle, by sample count.
struct Series {
    size_t technique, scene;
    double angle;
    std::vector<size_t> points;
};

struct Panel {
    size_t angle_class;
    std::vector<PlotPoint> points;
    std::vector<Series> series;
    std::vector<double> angles;    // sorted
    std::vector<size_t> frontier;  // point indices, by time
};

// Points not dominated in both time and error (on the drawn values), by
// increasing time and so decreasing error; exact duplicates appear once.
std::vector<size_t> pareto_frontier(const std::vector<PlotPoint>& points) {
    std::vector<size_t> order(points.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        if (points[a].x != points[b].x) return points[a].x < points[b].x;
        return points[a].y < points[b].y;
    });
    std::vector<size_t> frontier;
    double best = kInf;
    for (const size_t i : order) {
        if (points[i].y < best) {
            frontier.push_back(i);
            best = points[i].y;
        }
    }
    return frontier;
}

class SvgWriter {
public:
    // `gpu`: the cost axis is the real GPU compiler's cycles per pixel over
    // normal mapping's (bench --gpu) instead of the measured time ratio.
    explicit SvgWriter(const BenchRun& run, bool gpu = false)
        : run_(run), techniques_(techniques_in(run)), scenes_(scenes_in(run)), gpu_(gpu) {}

    std::string text() {
        collect();
        layout();
        out_ += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(width_) + "\" height=\"" + num(height_) +
                "\" viewBox=\"0 0 " + num(width_) + " " + num(height_) + "\" font-family=\"" + kFontFamily +
                "\" font-size=\"" + num(kFont) + "\">\n";
        out_ += "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
        header();
        if (panels_.empty()) {
            out_ += svg::text(kLeft, top_ + 40, "No rows with a finite, positive time ratio and error to plot.", "start",
                             kFont, "#444444", "");
        }
        for (size_t i = 0; i < panels_.size(); ++i) panel(i);
        if (!panels_.empty()) out_ += legend().first;
        footnotes();
        out_ += "</svg>\n";
        return out_;
    }

private:
    // Sorts the rows into panels and series, and sets the shared axes.
    void collect() {
        std::array<Panel, kAngleClasses.size()> by_class{};
        for (size_t c = 0; c < by_class.size(); ++c) by_class[c].angle_class = c;
        for (const BenchRow& row : run_.rows) {
            const double cost = gpu_ ? gpu_ratio(row) : row.ratio_to_normal;
            const bool plottable = std::isfinite(row.angle_deg) && std::isfinite(cost) && cost > 0 &&
                                   std::isfinite(row.uv_error_mean) && row.uv_error_mean >= 0;
            if (!plottable) {
                ++unplotted_;
                continue;
            }
            const bool clamped = row.uv_error_mean < kMinError;
            clamped_ += clamped ? 1 : 0;
            Panel& panel = by_class[angle_class(row.angle_deg)];
            panel.points.push_back({&row, cost, clamped ? kMinError : row.uv_error_mean});
        }
        std::vector<double> xs, ys;
        for (Panel& panel : by_class) {
            if (panel.points.empty()) continue;
            for (size_t i = 0; i < panel.points.size(); ++i) {
                const PlotPoint& p = panel.points[i];
                xs.push_back(p.x);
                ys.push_back(p.y);
                if (std::find(panel.angles.begin(), panel.angles.end(), p.row->angle_deg) == panel.angles.end())
                    panel.angles.push_back(p.row->angle_deg);
                const size_t t = technique_index(techniques_, p.row->technique);
                const size_t s = scene_index(scenes_, p.row->scene);
                auto it = std::find_if(panel.series.begin(), panel.series.end(), [&](const Series& series) {
                    return series.technique == t && series.scene == s && series.angle == p.row->angle_deg;
                });
                if (it == panel.series.end())
                    it = panel.series.insert(panel.series.end(), Series{t, s, p.row->angle_deg, {}});
                it->points.push_back(i);
            }
            std::sort(panel.angles.begin(), panel.angles.end());
            for (Series& series : panel.series) {
                std::stable_sort(series.points.begin(), series.points.end(), [&](size_t a, size_t b) {
                    return panel.points[a].row->samples < panel.points[b].row->samples;
                });
            }
            std::stable_sort(panel.series.begin(), panel.series.end(), [](const Series& a, const Series& b) {
                return std::tie(a.technique, a.scene) < std::tie(b.technique, b.scene);
            });
            panel.frontier = pareto_frontier(panel.points);
            for (const size_t i : panel.frontier) panel.points[i].frontier = true;
            panels_.push_back(std::move(panel));
        }
        // Shared axes, so the panels compare at a glance; 1 (normal mapping)
        // and the guides always in view.
        x_axis_ = log_axis(xs, {1.0}, 1e-300);
        y_axis_ = log_axis(ys, {kGuides.front(), kGuides.back()}, kMinError);
    }

    void layout() {
        const double n = static_cast<double>(panels_.size());
        const double plots_right = kLeft + n * kPlotW + std::max(0.0, n - 1) * kPanelGap;
        legend_x_ = plots_right + kLegendGap;
        width_ = std::max(kMinWidth, legend_x_ + kLegendW + kRightPad);
        const double text_w = width_ - kLeft - kRightPad;

        const std::string title = "Parallax mapping: accuracy against cost — " +
                                  (gpu_ ? run_.gpu + " (errors on " + run_.gl_renderer + ")"
                                        : run_.gl_renderer.empty() ? "unknown renderer" : run_.gl_renderer) + ", " +
                                  (run_.date.empty() ? "undated" : run_.date) + ", " + std::to_string(run_.width) +
                                  "×" + std::to_string(run_.height);
        title_lines_ = wrap(title, text_w, 15);
        subtitle_lines_ = wrap(
            "One point per technique and sample count; a line joins one technique's sample counts on one scene "
            "(labels: samples). Black step line: the Pareto frontier of each panel, across all techniques and "
            "scenes in it: settings that no other setting beats in both time and error.",
            text_w, kFont);
        top_ = 24 + 19.0 * static_cast<double>(title_lines_.size()) +
               16.0 * static_cast<double>(subtitle_lines_.size()) + 44;  // panel title and its angle line
        std::vector<std::string> notes;
        notes.push_back("Mean hit-uv error below " + general(kMinError) + " texel is drawn at " + general(kMinError) +
                        " (" + std::to_string(clamped_) + (clamped_ == 1 ? " point" : " points") +
                        "); the frontier uses the drawn values. Dashed lines: 1, 0.5, 0.25 and 0.1 texel.");
        if (gpu_)
            notes.push_back("Cost: the GPU compiler's cycles per pixel relative to normal mapping's at the same scene "
                            "and angle: its static estimate, with a kept loop's share of it taken once per counted "
                            "median iteration. Errors measured on " + run_.gl_renderer + ".");
        else
        notes.push_back("Time: frame time relative to normal mapping (median of interleaved per-round ratios), " +
                        std::to_string(run_.frames) + " frames per setting, " +
                        (on_llvmpipe(run_) ? std::to_string(run_.threads) +
                                                 " llvmpipe threads. llvmpipe (Mesa's CPU rasteriser) stands in for a "
                                                 "mobile GPU: compare ratios, not absolute times."
                                           : "on " + run_.gl_renderer + ": compare ratios, not absolute times."));
        if (unplotted_ > 0)
            notes.push_back(std::to_string(unplotted_) + (unplotted_ == 1 ? " row" : " rows") +
                            (gpu_ ? " without a finite angle, GPU cycles per pixel or error not plotted."
                                  : " without a finite angle, positive time ratio or error not plotted."));
        for (const std::string& note : notes)
            for (std::string& line : wrap(note, text_w, 11)) footnote_lines_.push_back(std::move(line));
        const double plot_bottom = top_ + (panels_.empty() ? 60 : kPlotH);
        footnote_y_ = plot_bottom + (panels_.empty() ? 20 : 58);
        const double legend_bottom = panels_.empty() ? 0.0 : top_ + legend().second;
        height_ = std::max(footnote_y_ + 15.0 * static_cast<double>(footnote_lines_.size()), legend_bottom) + 14;
    }

    void header() {
        double y = 26;
        for (const std::string& line : title_lines_) {
            out_ += svg::text(kLeft, y, line, "start", 15, "#111111", " font-weight=\"bold\" class=\"title\"");
            y += 19;
        }
        y += 1;
        for (const std::string& line : subtitle_lines_) {
            out_ += svg::text(kLeft, y, line, "start", kFont, "#444444", " class=\"subtitle\"");
            y += 16;
        }
    }

    double plot_x(size_t panel_index) const { return kLeft + static_cast<double>(panel_index) * (kPlotW + kPanelGap); }
    double sx(double x, double x0) const { return x0 + x_axis_.fraction(x) * kPlotW; }
    double sy(double y) const { return top_ + (1.0 - y_axis_.fraction(y)) * kPlotH; }

    // One panel: title, grid, guides, series lines, the frontier, markers,
    // labels, frame and axes, in that order (later ones drawn on top).
    void panel(size_t index) {
        Panel& p = panels_[index];
        const double x0 = plot_x(index), x1 = x0 + kPlotW, y0 = top_, y1 = top_ + kPlotH;
        out_ += "<g class=\"panel\">\n";
        panel_title(p, x0, y0);
        const std::vector<Tick> xt = log_ticks(x_axis_), yt = log_ticks(y_axis_);
        panel_grid(xt, yt, x0, x1, y0, y1);
        std::vector<Rect> taken = panel_guides(x1, x0);  // spots labels must avoid
        for (PlotPoint& pt : p.points) {
            pt.sx = sx(pt.x, x0);
            pt.sy = sy(pt.y);
            taken.push_back({pt.sx - 5.5, pt.sy - 5.5, pt.sx + 5.5, pt.sy + 5.5});
        }
        panel_series(p);
        panel_frontier(p, x1, taken);
        panel_markers(p);
        panel_labels(p, Rect{x0, y0, x1, y1}, taken);
        panel_axes(xt, yt, index, x0, y0, y1);
        out_ += "</g>\n";
    }

    // The angle class, then the angles it holds.
    void panel_title(const Panel& p, double x0, double y0) {
        out_ += svg::text(x0 + kPlotW / 2, y0 - 24, kAngleClasses[p.angle_class], "middle", 13, "#111111",
                         " font-weight=\"bold\" class=\"panel-title\"");
        std::string angles;
        for (const double a : p.angles) angles += (angles.empty() ? "" : ", ") + angle_text(a);
        out_ += svg::text(x0 + kPlotW / 2, y0 - 9, "view " + angles, "middle", 11, "#555555", "");
    }

    // Grid at the labelled ticks.
    void panel_grid(const std::vector<Tick>& xt, const std::vector<Tick>& yt, double x0, double x1, double y0, double y1) {
        for (const Tick& t : xt) {
            const double x = sx(t.value, x0);
            if (t.labelled) out_ += svg::line(x, y0, x, y1, "#e5e5e5", 0.8, "");
        }
        for (const Tick& t : yt) {
            const double y = sy(t.value);
            if (t.labelled) out_ += svg::line(x0, y, x1, y, "#e5e5e5", 0.8, "");
        }
    }

    // Error guides, labelled at the right; returns where their labels are.
    std::vector<Rect> panel_guides(double x1, double x0) {
        std::vector<Rect> taken;
        for (const double g : kGuides) {
            const double y = sy(g);
            out_ += svg::line(x0, y, x1, y, "#8a8a8a", 0.9, " stroke-dasharray=\"5 4\" class=\"guide\"");
            const std::string label = g == 1.0 ? "1 texel" : general(g);
            out_ += svg::text(x1 - 4, y - 3, label, "end", kSmallFont, "#777777", "");
            taken.push_back({x1 - 4 - text_width(label, kSmallFont), y - 3 - 8, x1 - 4, y - 3 + 1});
        }
        return taken;
    }

    // Series lines, dashed per scene.
    void panel_series(const Panel& p) {
        for (const Series& s : p.series) {
            if (s.points.size() < 2) continue;
            std::string pts;
            for (const size_t i : s.points)
                pts += (pts.empty() ? "" : " ") + num(p.points[i].sx) + "," + num(p.points[i].sy);
            const char* dash = kSceneDashes[s.scene % kSceneDashes.size()];
            out_ += "<polyline points=\"" + pts + "\" fill=\"none\" stroke=\"" + techniques_[s.technique].colour +
                    "\" stroke-width=\"1.4\" stroke-opacity=\"0.85\" stroke-linejoin=\"round\"" +
                    (*dash != '\0' ? std::string(" stroke-dasharray=\"") + dash + "\"" : std::string()) + "/>\n";
        }
    }

    // The frontier as a step line: from each point across to the next
    // one's time, then down to its error; on to the right edge. Its
    // segments are kept free of labels.
    void panel_frontier(const Panel& p, double x1, std::vector<Rect>& taken) {
        if (p.frontier.empty()) return;
        std::string d;
        for (size_t k = 0; k < p.frontier.size(); ++k) {
            const PlotPoint& pt = p.points[p.frontier[k]];
            d += k == 0 ? "M" + num(pt.sx) + "," + num(pt.sy) : " H" + num(pt.sx) + " V" + num(pt.sy);
            const double next_x = k + 1 < p.frontier.size() ? p.points[p.frontier[k + 1]].sx : x1;
            taken.push_back({pt.sx, pt.sy - 1.5, next_x, pt.sy + 1.5});
            if (k + 1 < p.frontier.size())
                taken.push_back({next_x - 1.5, pt.sy, next_x + 1.5, p.points[p.frontier[k + 1]].sy});
        }
        d += " H" + num(x1);
        out_ += "<path class=\"frontier\" d=\"" + d +
                "\" fill=\"none\" stroke=\"#111111\" stroke-width=\"1.8\" stroke-opacity=\"0.8\"/>\n";
    }

    // Markers, each with a tooltip; frontier points ringed. Where the
    // panel holds several angles, its highest (hardest) is drawn filled
    // and the lower ones hollow.
    void panel_markers(const Panel& p) {
        for (const PlotPoint& pt : p.points) {
            const bool hollow = pt.row->angle_deg < p.angles.back();
            const TechniqueEntry& t = techniques_[technique_index(techniques_, pt.row->technique)];
            const std::string tip = setting_text(*pt.row) + " — " + pt.row->scene + " at " +
                                    angle_text(pt.row->angle_deg) + ": " + human_sig(pt.row->uv_error_mean) +
                                    " texels, " + human_fixed(pt.x, 2) + (gpu_ ? "× normal (GPU cycles)" : "× normal");
            out_ += std::string("<g class=\"point") + (pt.frontier ? " on-frontier" : "") + "\"><title>" +
                    svg::escape(tip) + "</title>";
            if (pt.frontier)
                out_ += "<circle cx=\"" + num(pt.sx) + "\" cy=\"" + num(pt.sy) +
                        "\" r=\"8\" fill=\"none\" stroke=\"#111111\" stroke-width=\"1\"/>";
            out_ += marker_svg(t.marker, pt.sx, pt.sy, 4.6, t.colour, hollow) + "</g>\n";
        }
    }

    // Sample-count labels where there is room; frontier points first. In a
    // panel with several angles, the last label of a line names its angle.
    void panel_labels(const Panel& p, const Rect& area, std::vector<Rect>& taken) {
        std::vector<size_t> order;
        for (const size_t i : p.frontier) order.push_back(i);
        for (size_t i = 0; i < p.points.size(); ++i)
            if (!p.points[i].frontier) order.push_back(i);
        for (const size_t i : order) {
            const PlotPoint& pt = p.points[i];
            std::string label = pt.row->samples > 0 ? std::to_string(pt.row->samples) : "";
            if (p.angles.size() > 1) {
                for (const Series& s : p.series)
                    if (s.points.size() > 1 && s.points.back() == i)
                        label += (label.empty() ? "" : " · ") + angle_text(pt.row->angle_deg);
            }
            if (label.empty()) continue;
            place_label(pt.sx, pt.sy, label, area, taken);
        }
    }

    // Frame and axes; the y axis's title on the first panel only.
    void panel_axes(const std::vector<Tick>& xt, const std::vector<Tick>& yt, size_t index, double x0, double y0, double y1) {
        out_ += "<rect x=\"" + num(x0) + "\" y=\"" + num(y0) + "\" width=\"" + num(kPlotW) + "\" height=\"" +
                num(kPlotH) + "\" fill=\"none\" stroke=\"#333333\" stroke-width=\"0.9\"/>\n";
        for (const Tick& t : xt) {
            const double x = sx(t.value, x0);
            out_ += svg::line(x, y1, x, y1 + (t.labelled ? 5 : 3), "#333333", 0.8, "");
            if (t.labelled) out_ += svg::text(x, y1 + 18, tick_label(t.value) + "×", "middle", kFont, "#222222", "");
        }
        for (const Tick& t : yt) {
            const double y = sy(t.value);
            out_ += svg::line(x0 - (t.labelled ? 5 : 3), y, x0, y, "#333333", 0.8, "");
            if (t.labelled) out_ += svg::text(x0 - 8, y + 4, tick_label(t.value), "end", kFont, "#222222", "");
        }
        out_ += svg::text(x0 + kPlotW / 2, y1 + 38,
                          gpu_ ? "GPU cycles per pixel ÷ normal mapping's (log scale)"
                               : "frame time ÷ normal mapping (log scale)",
                          "middle", kFont,
                         "#222222", "");
        if (index == 0) {
            const double lx = x0 - 56, ly = y0 + kPlotH / 2;
            out_ += "<text x=\"" + num(lx) + "\" y=\"" + num(ly) +
                    "\" text-anchor=\"middle\" fill=\"#222222\" transform=\"rotate(-90 " + num(lx) + " " + num(ly) +
                    ")\">mean hit-uv error, texels (log scale)</text>\n";
        }
    }

    // Puts `label` next to (x, y) in the first free spot inside `area`, or not at all.
    void place_label(double x, double y, const std::string& label, const Rect& area, std::vector<Rect>& taken) {
        struct Spot {
            double dx, dy;  // of the anchor from the point; dy to the baseline
            const char* anchor;
        };
        static constexpr std::array<Spot, 8> kSpots{{{7, 3.5, "start"},
                                                     {-7, 3.5, "end"},
                                                     {0, -8, "middle"},
                                                     {0, 14, "middle"},
                                                     {5, -6, "start"},
                                                     {5, 13, "start"},
                                                     {-5, -6, "end"},
                                                     {-5, 13, "end"}}};
        const double w = text_width(label, kSmallFont);
        for (const Spot& spot : kSpots) {
            const double ax = x + spot.dx, base = y + spot.dy;
            const std::string anchor = spot.anchor;
            const double left = anchor == "start" ? ax : anchor == "end" ? ax - w : ax - w / 2;
            const Rect r{left - 1, base - 8.5, left + w + 1, base + 1.5};
            if (r.x0 < area.x0 + 2 || r.x1 > area.x1 - 2 || r.y0 < area.y0 + 2 || r.y1 > area.y1 - 2) continue;
            if (std::any_of(taken.begin(), taken.end(), [&](const Rect& t) { return t.overlaps(r); })) continue;
            taken.push_back(r);
            out_ += svg::text(ax, base, label, anchor, kSmallFont, "#333333",
                             " class=\"point-label\" stroke=\"#ffffff\" stroke-width=\"2.5\" paint-order=\"stroke\"");
            return;
        }
    }

    bool several_scenes() const { return scenes_.size() > 1; }
    bool several_angles() const {
        return std::any_of(panels_.begin(), panels_.end(), [](const Panel& p) { return p.angles.size() > 1; });
    }

    // The legend beside the last panel, and its height.
    std::pair<std::string, double> legend() const {
        const double x = legend_x_;
        double y = top_;
        std::string body;
        auto heading = [&](const std::string& text, double gap) {
            y += gap;
            body += svg::text(x + 10, y, text, "start", kFont, "#111111", " font-weight=\"bold\"");
        };
        auto label = [&](const std::string& text) { body += svg::text(x + 46, y, text, "start", kFont, "#222222", ""); };

        heading("technique", 20);
        for (const TechniqueEntry& t : techniques_) {
            y += 20;
            body += "<g class=\"legend-entry\">";
            body += svg::line(x + 10, y - 4, x + 38, y - 4, t.colour, 1.4, "");
            body += marker_svg(t.marker, x + 24, y - 4, 4.6, t.colour, false);
            label(fit(t.name, kLegendW - 52, kFont));
            body += "</g>\n";
        }
        if (several_scenes()) {
            heading("scene (line style)", 28);
            for (size_t s = 0; s < scenes_.size(); ++s) {
                y += 20;
                const char* dash = kSceneDashes[s % kSceneDashes.size()];
                body += svg::line(x + 10, y - 4, x + 38, y - 4, "#555555", 1.4,
                                 *dash != '\0' ? std::string(" stroke-dasharray=\"") + dash + "\"" : std::string());
                label(fit(scenes_[s], kLegendW - 52, kFont));
            }
        }
        if (several_angles()) {
            heading("view angle in a panel", 28);
            y += 20;
            body += marker_svg(Marker::circle, x + 24, y - 4, 4.6, "#555555", false);
            label("its highest");
            y += 20;
            body += marker_svg(Marker::circle, x + 24, y - 4, 4.6, "#555555", true);
            label("lower ones");
        }
        y += 28;
        body += svg::line(x + 10, y - 7, x + 24, y - 7, "#111111", 1.8, "");
        body += svg::line(x + 24, y - 7, x + 24, y - 1, "#111111", 1.8, "");
        body += svg::line(x + 24, y - 1, x + 38, y - 1, "#111111", 1.8, "");
        label("Pareto frontier");
        y += 20;
        body += "<circle cx=\"" + num(x + 24) + "\" cy=\"" + num(y - 4) +
                "\" r=\"8\" fill=\"none\" stroke=\"#111111\" stroke-width=\"1\"/>";
        body += marker_svg(Marker::circle, x + 24, y - 4, 4.6, "#555555", false);
        label("on the frontier");
        y += 20;
        body += svg::line(x + 10, y - 4, x + 38, y - 4, "#8a8a8a", 0.9, " stroke-dasharray=\"5 4\"");
        label("error guides");
        const double height = y + 12 - top_;
        const std::string frame = "<rect x=\"" + num(x) + "\" y=\"" + num(top_) + "\" width=\"" + num(kLegendW) +
                                  "\" height=\"" + num(height) +
                                  "\" rx=\"3\" fill=\"#ffffff\" stroke=\"#cccccc\" stroke-width=\"0.8\"/>\n";
        return {"<g class=\"legend\">\n" + frame + body + "</g>\n", height};
    }

    void footnotes() {
        double y = footnote_y_;
        for (const std::string& line : footnote_lines_) {
            out_ += svg::text(kLeft, y, line, "start", 11, "#555555", " class=\"footnote\"");
            y += 15;
        }
    }

    double gpu_ratio(const BenchRow& row) const { return gpu_ratio_to_normal(run_, row); }

    const BenchRun& run_;
    std::vector<TechniqueEntry> techniques_;
    std::vector<std::string> scenes_;
    bool gpu_ = false;
    std::vector<Panel> panels_;
    LogAxis x_axis_, y_axis_;
    size_t clamped_ = 0, unplotted_ = 0;
    std::vector<std::string> title_lines_, subtitle_lines_, footnote_lines_;
    double width_ = 0, height_ = 0, top_ = 0, legend_x_ = 0, footnote_y_ = 0;
    std::string out_;
};

// =============================================================== markdown

constexpr std::array<double, 3> kTargets{{1.0, 0.5, 0.25}};

std::string target_text(double target) { return general(target) + " texel"; }

// An error for "(best: ...)": enough digits not to read as the target itself.
std::string best_error_text(double best, double target) {
    for (int digits = 3; digits <= 8; ++digits) {
        const std::string s = human_sig(best, digits);
        if (s != general(target)) return s;
    }
    return general(best, 9);
}

struct SceneAngle {
    std::string scene;
    double angle;
    std::vector<const BenchRow*> rows;
};

// Rows grouped by scene (in order of appearance) and angle (ascending).
std::vector<SceneAngle> scene_angle_groups(const BenchRun& run) {
    std::vector<SceneAngle> groups;
    for (const std::string& scene : scenes_in(run)) {
        std::vector<double> angles;
        for (const BenchRow& row : run.rows) {
            if (row.scene != scene) continue;
            if (std::none_of(angles.begin(), angles.end(), [&](double a) { return same_angle(a, row.angle_deg); }))
                angles.push_back(row.angle_deg);
        }
        std::sort(angles.begin(), angles.end(), angle_less);
        for (const double angle : angles) {
            SceneAngle group{scene, angle, {}};
            for (const BenchRow& row : run.rows)
                if (row.scene == scene && same_angle(row.angle_deg, angle)) group.rows.push_back(&row);
            groups.push_back(std::move(group));
        }
    }
    return groups;
}

// The lowest ratio to normal mapping among rows whose mean error reaches
// `target`; ties go to the faster median, then fewer samples.
const BenchRow* cheapest_reaching(const std::vector<const BenchRow*>& rows, double target) {
    const BenchRow* best = nullptr;
    for (const BenchRow* row : rows) {
        if (!(row->uv_error_mean <= target)) continue;  // NaN never reaches
        if (best == nullptr ||
            std::make_tuple(or_inf(row->ratio_to_normal), or_inf(row->frame_ms_median), row->samples) <
                std::make_tuple(or_inf(best->ratio_to_normal), or_inf(best->frame_ms_median), best->samples))
            best = row;
    }
    return best;
}

// The row with the lowest finite mean error, or null.
const BenchRow* most_accurate(const std::vector<const BenchRow*>& rows) {
    const BenchRow* best = nullptr;
    for (const BenchRow* row : rows) {
        if (std::isnan(row->uv_error_mean)) continue;
        if (best == nullptr || row->uv_error_mean < best->uv_error_mean) best = row;
    }
    return best;
}

std::string ratio_text(double ratio) { return human_fixed(ratio, 2) + "×"; }
std::string ms_text(double ms) { return human_sig(ms, 3); }

// llvmpipe unrolls loops of up to 32 iterations completely, so the cost of a
// marching technique does not rise smoothly with its sample count: the median
// over scenes and angles of time(2n) / time(n) per doubling says where it bends.
std::string unrolling_section(const BenchRun& run) {
    std::map<std::string, std::map<int, std::vector<double>>> steps;  // technique -> n -> ratios
    for (const BenchRow& a : run.rows) {
        if (a.samples < 1) continue;
        for (const BenchRow& b : run.rows)
            if (b.technique == a.technique && b.scene == a.scene && b.angle_deg == a.angle_deg &&
                b.samples == 2 * a.samples && a.frame_ms_median > 0.0)
                steps[a.technique][a.samples].push_back(b.frame_ms_median / a.frame_ms_median);
    }
    if (steps.empty()) return "";
    std::string out = "## Where loop unrolling bends the cost curves\n\n";
    out += std::string(on_llvmpipe(run) ? "llvmpipe unrolls loops of up to 32 iterations completely: up to 32 samples "
                                          "a search is straight-line code, past it a real loop. "
                                        : "A compiler may unroll short loops completely and keep long ones as loops. ") +
           "Median over scenes and angles of the frame-time ratio per doubling of "
           "the sample count:\n\n| technique | doubling | time ratio |\n| --- | --- | ---: |\n";
    for (auto& [technique, by_n] : steps)
        for (auto& [n, ratios] : by_n) {
            std::sort(ratios.begin(), ratios.end());
            out += "| " + md_text(technique) + " | " + std::to_string(n) + " → " + std::to_string(2 * n) + " | " +
                   human_fixed(ratios[ratios.size() / 2], 2) + "× |\n";
        }
    return out + "\n";
}

// Per technique and angle: the most accurate setting's mean error and its
// cost, as the median over scenes: the whole sweep in one table.
std::string summary_section(const BenchRun& run) {
    std::map<std::string, std::map<double, std::vector<std::pair<double, double>>>> best;  // technique -> angle -> (error, ratio)
    std::map<std::string, std::map<double, std::map<std::string, const BenchRow*>>> pick;
    for (const BenchRow& r : run.rows) {
        const BenchRow*& slot = pick[r.technique][r.angle_deg][r.scene];
        if (slot == nullptr || r.uv_error_mean < slot->uv_error_mean) slot = &r;
    }
    std::vector<double> angles;
    for (const BenchRow& r : run.rows)
        if (std::find(angles.begin(), angles.end(), r.angle_deg) == angles.end()) angles.push_back(r.angle_deg);
    std::sort(angles.begin(), angles.end());
    if (pick.empty()) return "";
    std::string out = "## Summary: each technique at its most accurate setting\n\n";
    out += "Median over scenes of the lowest mean hit-uv error (texels) a technique reaches at each view angle, "
           "with that setting's frame time relative to normal mapping.\n\n| technique |";
    for (double a : angles) out += " " + angle_text(a) + " |";
    out += "\n| --- |";
    for (size_t i = 0; i < angles.size(); ++i) out += " ---: |";
    out += "\n";
    auto median_of = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v.empty() ? 0.0 : v[v.size() / 2];
    };
    for (auto& [technique, by_angle] : pick) {
        out += "| " + md_text(technique) + " |";
        for (double a : angles) {
            auto it = by_angle.find(a);
            if (it == by_angle.end()) {
                out += " – |";
                continue;
            }
            std::vector<double> errors, ratios;
            for (auto& [scene, row] : it->second) {
                errors.push_back(row->uv_error_mean);
                ratios.push_back(row->ratio_to_normal);
            }
            out += " " + human_sig(median_of(errors)) + " @ " + human_fixed(median_of(ratios), 1) + "× |";
        }
        out += "\n";
    }
    return out + "\n";
}

// For each scene and angle: the cheapest setting per error target, and
// the techniques that never reach one.
std::string cheapest_section(const std::vector<TechniqueEntry>& techniques,
                             const std::vector<SceneAngle>& groups) {
    std::string out;
    out += "## Cheapest setting per error target\n\n";
    out +=
        "For each scene and view angle (from the normal): the setting with the lowest ratio to normal mapping "
        "whose mean error is at most the target.\n";
    if (groups.empty()) out += "\nNo rows.\n";
    for (const SceneAngle& g : groups) {
        out += "\n### " + md_text(g.scene) + " at " + angle_text(g.angle) + "\n\n";
        out += "| target (mean error) | cheapest setting | mean error (texels) | ratio to normal | ms (median) |\n";
        out += "| --- | --- | ---: | ---: | ---: |\n";
        for (const double target : kTargets) {
            out += "| ≤ " + target_text(target) + " | ";
            if (const BenchRow* row = cheapest_reaching(g.rows, target)) {
                out += md_text(setting_text(*row)) + " | " + human_sig(row->uv_error_mean) + " | " +
                       ratio_text(row->ratio_to_normal) + " | " + ms_text(row->frame_ms_median) + " |\n";
            } else if (const BenchRow* best = most_accurate(g.rows)) {
                out += "not reached (best: " + md_text(setting_text(*best)) + ", " +
                       best_error_text(best->uv_error_mean, target) + " texels) | | | |\n";
            } else {
                out += "not reached (no error measured) | | | |\n";
            }
        }
        std::vector<std::string> misses;
        for (const TechniqueEntry& t : techniques) {
            std::vector<const BenchRow*> rows;
            for (const BenchRow* row : g.rows)
                if (row->technique == t.name) rows.push_back(row);
            if (rows.empty()) continue;
            const BenchRow* best = most_accurate(rows);
            // Only the loosest target missed: missing 1 texel implies missing 0.5 and 0.25.
            for (const double target : kTargets) {
                if (cheapest_reaching(rows, target) != nullptr) continue;
                misses.push_back(md_text(t.name) + " never reaches " + target_text(target) + " at " +
                                 angle_text(g.angle) + " on " + md_text(g.scene) +
                                 (best != nullptr
                                      ? " (best: " + best_error_text(best->uv_error_mean, target) + " texels)"
                                      : std::string(" (no error measured)")));
                break;
            }
        }
        if (misses.empty()) {
            out += "\nEvery technique here reaches " + target_text(kTargets.back()) + ".\n";
        } else {
            out += "\n";
            for (const std::string& line : misses) out += "- " + line + "\n";
        }
    }

    return out;
}

// Every row, grouped by scene and angle, techniques in the table's order.
std::string all_settings_section(const std::vector<TechniqueEntry>& techniques, const std::vector<SceneAngle>& groups) {
    std::string out;
    out += "\n## All settings\n\n";
    out +=
        "Errors against the exact reference: hit uv in texels; *wrong surface* is the share of pixels more than "
        "one texel off; depth in units of the relief depth (mean / max); shadow disagreement is the mean "
        "|visibility difference| of the first light; PSNR over covered pixels (99 = identical).\n\n";
    out +=
        "| scene | angle | technique | samples | uv mean | uv p95 | uv max | wrong surface | depth error (mean / max) "
        "| shadow disagreement | PSNR (dB) | ms median [min–max] | ratio to normal |\n";
    out += "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    std::vector<const BenchRow*> rows;
    for (const SceneAngle& g : groups) {
        std::vector<const BenchRow*> sorted = g.rows;
        std::stable_sort(sorted.begin(), sorted.end(), [&](const BenchRow* a, const BenchRow* b) {
            return std::make_pair(technique_index(techniques, a->technique), a->samples) <
                   std::make_pair(technique_index(techniques, b->technique), b->samples);
        });
        rows.insert(rows.end(), sorted.begin(), sorted.end());
    }
    for (const BenchRow* r : rows) {
        out += "| " + md_text(r->scene) + " | " + angle_text(r->angle_deg) + " | " + md_text(r->technique) + " | " +
               (r->samples > 0 ? std::to_string(r->samples) : "–") + " | " + human_sig(r->uv_error_mean) + " | " +
               human_sig(r->uv_error_p95) + " | " + human_sig(r->uv_error_max) + " | " +
               human_fixed(100.0 * r->wrong_surface_share, 1) + " % | " + human_sig(r->depth_error_mean) + " / " +
               human_sig(r->depth_error_max) + " | " + human_sig(r->shadow_disagreement) + " | " +
               human_fixed(r->color_psnr_db, 1) + " | " + ms_text(r->frame_ms_median) + " [" +
               ms_text(r->frame_ms_min) + "–" + ms_text(r->frame_ms_max) + "] | " + ratio_text(r->ratio_to_normal) +
               " |\n";
    }
    return out;
}

// The exact walk's iterations per pixel, where the run counted them: what
// its time is made of (include/parallaxes/profiling/measurement/work.h).
std::string work_section(const BenchRun& run) {
    std::vector<const BenchRow*> counted;
    for (const BenchRow& row : run.rows)
        if (!row.iteration_histogram.empty()) counted.push_back(&row);
    if (counted.empty()) return {};
    std::string out = "## Work per pixel of the exact walk\n\n";
    out += "Loop iterations and texture fetches per drawn pixel, counted by the shader itself (`PX_COUNT_WORK`); "
           "the histogram gives the share of pixels with 0-1, 2-3, 4-7, ... iterations. Pixels shaded together in "
           "SIMD lanes (on a GPU, and on llvmpipe) run as long as the slowest of them, so the tail costs more "
           "than its share. The *fp32 floor* is how far the exact hit moves, p95 over the same pixels, when the "
           "ray's uv moves by one float ulp or its view vector turns by 2^-24 (`reference::fp32_input_floor`): "
           "a tracer fed 32-bit varyings cannot be held below it. *Own ray* is the hit error against the exact "
           "reference of the ray each pixel's trace was handed (its fp32 uv and parallax vector, read back): the "
           "trace's error alone (– where not read: ES 2.0 has no float read-back).\n\n";
    out += "| scene | angle | technique | hit error p95 (texels) | fp32 floor p95 | own ray p95 | iterations p50 / p90 / p99 / max | fetches p50 | "
           "histogram (0-1, 2-3, 4-7, ...) | ratio to normal |\n";
    out += "| --- | ---: | --- | ---: | ---: | ---: | --- | ---: | --- | ---: |\n";
    for (const BenchRow* r : counted) {
        std::size_t total = 0;
        for (std::size_t n : r->iteration_histogram) total += n;
        std::size_t last = r->iteration_histogram.size();
        while (last > 0 && r->iteration_histogram[last - 1] == 0) --last;
        std::string histogram;
        for (std::size_t i = 0; i < last; ++i) {
            const double share = total ? 100.0 * static_cast<double>(r->iteration_histogram[i]) / static_cast<double>(total) : 0.0;
            histogram += (i ? " " : "") + human_fixed(share, 0) + "%";
        }
        out += "| " + md_text(r->scene) + " | " + human_fixed(r->angle_deg, 0) + "° | " + md_text(r->technique) + " | " +
               human_sig(r->uv_error_p95) + " | " + human_sig(r->input_floor_p95) + " | " +
               (std::isnan(r->own_ray_error_p95) ? std::string("–") : human_sig(r->own_ray_error_p95)) + " | " + human_fixed(r->iterations_median, 0) + " / " + human_fixed(r->iterations_p90, 0) + " / " +
               human_fixed(r->iterations_p99, 0) + " / " + human_fixed(r->iterations_max, 0) + " | " +
               human_fixed(r->fetches_median, 0) + " | " + histogram + " | " + ratio_text(r->ratio_to_normal) + " |\n";
    }
    return out + "\n";
}

// bench --gpu: each setting's error beside what the real compiler says the
// variant costs per pixel, and that against normal mapping's, per scene and
// angle; empty when the run has no GPU figures.
std::string gpu_section(const BenchRun& run) {
    if (run.gpu.empty()) return "";
    std::string out = "## On a real GPU compiler\n\n";
    out += "Compiled by " + md_text(run.gpu) + " (`parallax bench --gpu`, docs/gpu-compilers.md). GPU cycles: the "
           "compiler's static estimate per fragment of the variant compiled for the bench's one light (its lights "
           "loop bound at 1: `profile --gpu` reports the shipped program, bound at 4); a loop it kept (loops) counts "
           "one pass there, so per pixel takes the loop's share of the compiler's instruction listing once per "
           "median loop iteration the shader's own work counters read back (the searches' steps and their shadow "
           "marches'), the rest once (without a listing: the whole estimate times the iterations, an upper bound); "
           "– where a kept loop's iterations were not counted. x normal: per-pixel cycles over normal mapping's at the same "
           "scene and angle, beside llvmpipe's measured ratio. pareto_gpu.svg plots the error against x normal (GPU).\n\n";
    out += "| scene | angle | technique | samples | hit error p95 (texels) | GPU cycles | loops | per pixel | x normal (GPU) | "
           "x normal (llvmpipe) |\n";
    out += "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    for (const BenchRow& r : run.rows) {
        if (std::isnan(r.gpu_cycles)) continue;
        const double ratio = gpu_ratio_to_normal(run, r);
        out += "| " + md_text(r.scene) + " | " + human_fixed(r.angle_deg, 0) + "° | " + md_text(r.technique) + " | " +
               std::to_string(r.samples) + " | " + human_sig(r.uv_error_p95) + " | " + human_sig(r.gpu_cycles) + " | " +
               human_fixed(r.gpu_loops, 0) + " | " +
               (std::isnan(r.gpu_cycles_per_pixel) ? std::string("–") : human_sig(r.gpu_cycles_per_pixel)) + " | " +
               (std::isnan(ratio) ? std::string("–") : human_sig(ratio)) + " | " + ratio_text(r.ratio_to_normal) + " |\n";
    }
    return out + "\n";
}

std::string markdown_text(const BenchRun& run) {
    const std::vector<TechniqueEntry> techniques = techniques_in(run);
    std::string out = "# ParallaxES benchmark: accuracy against cost\n\n";
    out += "- **Date:** " + md_text(run.date.empty() ? "unknown" : run.date) + "\n";
    out += "- **Command:** " + (run.command.empty() ? std::string("unknown") : md_code(run.command)) + "\n";
    out += "- **Renderer:** " + md_text(run.gl_renderer.empty() ? "unknown" : run.gl_renderer) + "\n";
    out += "- **GL version:** " + md_text(run.gl_version.empty() ? "unknown" : run.gl_version) + "\n";
    const bool llvmpipe = on_llvmpipe(run);
    if (llvmpipe) out += "- **llvmpipe threads:** " + std::to_string(run.threads) + "\n";
    out += "- **Image size:** " + std::to_string(run.width) + "×" + std::to_string(run.height) + "\n";
    out += "- **Frames:** " + std::to_string(run.frames) + " timed per setting, after a warm-up\n\n";
    out += std::string(llvmpipe ? "Frame times come from llvmpipe, Mesa's rasteriser running on the CPU, standing in for a "
                                  "mobile GPU: "
                                : "Frame times come from the renderer above (wall clock around glFinish): ") +
           "the ratios to normal mapping matter, not the absolute times. Error is the mean hit-uv error in texels "
        "against the exact reference; *ratio* is frame time relative to normal mapping (the median of "
        "interleaved per-round ratios); *ms* is the median frame time.\n\n";

    out += summary_section(run);
    out += unrolling_section(run);
    const std::vector<SceneAngle> groups = scene_angle_groups(run);
    out += cheapest_section(techniques, groups);
    out += work_section(run);
    out += gpu_section(run);
    out += all_settings_section(techniques, groups);
    return out;
}

// Runs a text builder, turning an exception into an error naming the path.
template <typename Build>
Status write_built(const std::string& path, Build build) {
    std::string text;
    try {
        text = build();
    } catch (const std::exception& e) {
        return make_error(path + ": cannot build the report: " + e.what());
    }
    return write_file_atomically(path, text);
}

}  // namespace

Status write_csv(const BenchRun& run, const std::string& path) {
    return write_built(path, [&] { return csv_text(run); });
}

Status write_json(const BenchRun& run, const std::string& path) {
    return write_built(path, [&] { return json_text(run); });
}

Status write_pareto_svg(const BenchRun& run, const std::string& path) {
    return write_built(path, [&] { return SvgWriter(run).text(); });
}

Status write_pareto_gpu_svg(const BenchRun& run, const std::string& path) {
    if (run.gpu.empty()) return make_error("the run has no GPU figures to plot (bench --gpu)");
    return write_built(path, [&] { return SvgWriter(run, true).text(); });
}

Status write_report_md(const BenchRun& run, const std::string& path) {
    return write_built(path, [&] { return markdown_text(run); });
}

}  // namespace px::profiling
