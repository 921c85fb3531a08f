#include "parallaxes/profiling/reports/svg_plot.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>

namespace px::profiling {
namespace {

std::string num(double v) { return svg::number(v); }
using svg::escape;
using svg::line;
using svg::text;

// One axis: its range (in log10 where logarithmic) and the map to pixels.
struct Axis {
    bool log = false;
    double lo = 0.0, hi = 1.0;
    double a = 0.0, b = 1.0;  // pixel range
    bool usable(double v) const { return std::isfinite(v) && (!log || v > 0.0); }
    double t(double v) const { return log ? std::log10(v) : v; }
    double px(double v) const { return a + (t(v) - lo) / (hi - lo) * (b - a); }
};

void fit(Axis& axis, const std::vector<double>& values, bool pad_zero) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double v : values)
        if (axis.usable(v)) {
            lo = std::min(lo, axis.t(v));
            hi = std::max(hi, axis.t(v));
        }
    if (!std::isfinite(lo)) lo = 0.0, hi = 1.0;
    if (pad_zero && !axis.log) lo = std::min(lo, 0.0);
    if (hi - lo < 1e-9) hi = lo + 1.0;
    const double pad = 0.06 * (hi - lo);
    axis.lo = axis.log ? std::floor(lo - pad) : lo - (pad_zero && lo == 0.0 ? 0.0 : pad);
    axis.hi = axis.log ? std::ceil(hi + pad) : hi + pad;
}

// Ticks: svg::log_ticks on a log axis, about six round steps (all
// labelled) on a linear one.
std::vector<svg::Tick> ticks(const Axis& axis) {
    if (axis.log) return svg::log_ticks(axis.lo, axis.hi);
    std::vector<svg::Tick> out;
    const double raw = (axis.hi - axis.lo) / 6.0;
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    const double step = raw / mag < 1.5 ? mag : raw / mag < 3.5 ? 2.0 * mag : raw / mag < 7.5 ? 5.0 * mag : 10.0 * mag;
    for (double v = std::ceil(axis.lo / step) * step; v <= axis.hi + 1e-9; v += step) out.push_back({v, true});
    return out;
}

}  // namespace

std::string svg_plot(const std::vector<PlotSeries>& series, const PlotOptions& o) {
    const double left = 78, right = 190, top = o.subtitle.empty() ? 52 : 70, bottom = 62;
    Axis x{o.log_x, 0, 1, left, o.width - right}, y{o.log_y, 0, 1, o.height - bottom, top};
    std::vector<double> xs, ys;
    for (const PlotSeries& s : series) {
        xs.insert(xs.end(), s.x.begin(), s.x.end());
        ys.insert(ys.end(), s.y.begin(), s.y.end());
    }
    if (o.equality) {  // one range for both, so that y = x is the diagonal
        std::vector<double> both = xs;
        both.insert(both.end(), ys.begin(), ys.end());
        xs = ys = both;
    }
    fit(x, xs, false);
    fit(y, ys, !o.equality);
    if (!o.x_categories.empty()) x.lo = 0.5, x.hi = static_cast<double>(o.x_categories.size()) + 0.5;
    std::string out = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(o.width) + "\" height=\"" +
                      std::to_string(o.height) + "\" viewBox=\"0 0 " + std::to_string(o.width) + " " +
                      std::to_string(o.height) + "\" font-family=\"sans-serif\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    out += text(left, 24, o.title, "start", 15, "#111111", " font-weight=\"bold\"");
    if (!o.subtitle.empty()) out += text(left, 44, o.subtitle, "start", 12, "#444444");
    // Grid and ticks.
    if (o.x_categories.empty()) {
        for (const svg::Tick& t : ticks(x)) {
            out += line(x.px(t.value), y.a, x.px(t.value), t.labelled ? y.b : y.a - 4, t.labelled ? "#e5e5e5" : "#333333", 0.8);
            if (t.labelled) out += text(x.px(t.value), y.a + 18, num(t.value), "middle", 11, "#222222");
        }
    } else {
        for (size_t i = 0; i < o.x_categories.size(); ++i) {
            const double px = x.px(static_cast<double>(i + 1));
            out += line(px, y.a, px, y.b, "#eeeeee", 0.8);
            out += text(px, y.a + 18, o.x_categories[i], "middle", 11, "#222222");
        }
    }
    for (const svg::Tick& t : ticks(y)) {
        out += line(x.a, y.px(t.value), t.labelled ? x.b : x.a + 4, y.px(t.value), t.labelled ? "#e5e5e5" : "#333333", 0.8);
        if (t.labelled) out += text(x.a - 8, y.px(t.value) + 4, num(t.value), "end", 11, "#222222");
    }
    out += line(x.a, y.a, x.b, y.a, "#333333", 1.0) + line(x.a, y.a, x.a, y.b, "#333333", 1.0);
    out += text((x.a + x.b) / 2, o.height - 18, o.x_label, "middle", 12, "#222222");
    out += "<text x=\"18\" y=\"" + num((y.a + y.b) / 2) + "\" text-anchor=\"middle\" font-size=\"12\" fill=\"#222222\" " +
           "transform=\"rotate(-90 18 " + num((y.a + y.b) / 2) + ")\">" + escape(o.y_label) + "</text>\n";
    if (o.equality) {
        const double lo = std::max(x.lo, y.lo), hi = std::min(x.hi, y.hi);
        const auto at = [](const Axis& a, double t) { return a.a + (t - a.lo) / (a.hi - a.lo) * (a.b - a.a); };
        out += line(at(x, lo), at(y, lo), at(x, hi), at(y, hi), "#555555", 1.0);
        if (o.band > 1.0 && o.log_x && o.log_y) {
            const double d = std::log10(o.band);
            out += line(at(x, lo), at(y, lo + d), at(x, hi - d), at(y, hi), "#999999", 0.9, " stroke-dasharray=\"5 4\"");
            out += line(at(x, lo + d), at(y, lo), at(x, hi), at(y, hi - d), "#999999", 0.9, " stroke-dasharray=\"5 4\"");
        }
    }
    // Series, then the legend.
    double legend_y = top + 8;
    for (const PlotSeries& s : series) {
        std::string path;
        for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
            if (!x.usable(s.x[i]) || !y.usable(s.y[i])) continue;
            const double px = x.px(s.x[i]), py = y.px(s.y[i]);
            path += (path.empty() ? "M" : " L") + num(px) + " " + num(py);
            out += "<circle cx=\"" + num(px) + "\" cy=\"" + num(py) + "\" r=\"" + num(s.radius) + "\" fill=\"" + s.colour +
                   (s.opacity < 1.0 ? "\" fill-opacity=\"" + num(s.opacity) : std::string()) + "\"/>\n";
            if (i < s.labels.size() && !s.labels[i].empty())
                out += text(px + 6, py - 6, s.labels[i], "start", 10, "#444444");
        }
        if (s.lines && !path.empty())
            out += "<path d=\"" + path + "\" fill=\"none\" stroke=\"" + s.colour + "\" stroke-width=\"1.6\"/>\n";
        out += "<circle cx=\"" + num(o.width - right + 20) + "\" cy=\"" + num(legend_y - 4) + "\" r=\"4\" fill=\"" +
               s.colour + "\"/>\n";
        out += text(o.width - right + 30, legend_y, s.name, "start", 11, "#222222");
        legend_y += 18;
    }
    if (o.equality) {
        out += text(o.width - right + 12, legend_y + 4, "solid: equal", "start", 10, "#666666");
        if (o.band > 1.0) out += text(o.width - right + 12, legend_y + 18, "dashed: a factor of " + num(o.band), "start", 10, "#666666");
    }
    return out + "</svg>\n";
}

namespace svg {

std::string number(double v) {
    std::array<char, 64> buf{};
    auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::general, 6);
    return ec == std::errc() ? std::string(buf.data(), end) : std::string("0");
}

std::string escape(const std::string& s) {
    std::string out;
    out.reserve(s.size());
    for (const char c : s) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            case '\n':
            case '\r':
            case '\t': out += ' '; break;
            default: out += c;
        }
    }
    return out;
}

std::string text(double x, double y, const std::string& s, const std::string& anchor, double size, const std::string& fill,
                 const std::string& extra) {
    return "<text x=\"" + number(x) + "\" y=\"" + number(y) + "\"" +
           (anchor == "start" ? std::string() : " text-anchor=\"" + anchor + "\"") + " font-size=\"" + number(size) +
           "\" fill=\"" + fill + "\"" + extra + ">" + escape(s) + "</text>\n";
}

std::string line(double xa, double ya, double xb, double yb, const std::string& stroke, double width, const std::string& extra) {
    return "<line x1=\"" + number(xa) + "\" y1=\"" + number(ya) + "\" x2=\"" + number(xb) + "\" y2=\"" + number(yb) +
           "\" stroke=\"" + stroke + "\" stroke-width=\"" + number(width) + "\"" + extra + "/>\n";
}

std::vector<Tick> log_ticks(double lo, double hi) {
    const double span = hi - lo;
    std::vector<Tick> ticks;
    const int first = static_cast<int>(std::floor(lo)), last = static_cast<int>(std::ceil(hi));
    for (int decade = first; decade <= last; ++decade)
        for (int m = 1; m <= 9; ++m) {
            const double v = m * std::pow(10.0, decade);
            const double lv = std::log10(v);
            if (lv < lo - 1e-9 || lv > hi + 1e-9) continue;
            ticks.push_back({v, m == 1 || (span < 2.2 && (m == 2 || m == 5)) || (span < 1.2 && m == 3)});
        }
    return ticks;
}

}  // namespace svg

}  // namespace px::profiling
