// One small SVG chart for the reports (profile, search model): points per
// series on linear or logarithmic axes, joined by lines or not, with a
// legend, and for scatters of predicted against measured the line of
// equality and a band of a factor. Self-contained SVG text, no scripts, the
// same bytes for the same input (numbers through std::to_chars).
#pragma once

#include <string>
#include <vector>

namespace px::profiling {

struct PlotSeries {
    std::string name;                 // in the legend
    std::string colour = "#1f77b4";   // any SVG colour
    std::vector<double> x, y;         // one point each; non-finite (or <= 0 on a log axis) points are left out
    std::vector<std::string> labels;  // optional, one per point, written beside it
    bool lines = false;               // join the points in order
    double radius = 4.0;              // of each point's circle
    double opacity = 1.0;             // of each point (many overlapping points: below 1)
};

struct PlotOptions {
    std::string title, subtitle;
    std::string x_label, y_label;
    bool log_x = false, log_y = false;
    // x tick labels at x = 1, 2, ... in place of numbers (a category axis: the steps of a ladder).
    std::vector<std::string> x_categories;
    // A scatter of predicted against measured: the line y = x, and dashed
    // lines at y = x * band and y = x / band when band > 1.
    bool equality = false;
    double band = 0.0;
    int width = 760, height = 440;
};

std::string svg_plot(const std::vector<PlotSeries>& series, const PlotOptions& options);

// The pieces every chart of the reports is drawn with (svg_plot above and
// the benchmark's Pareto panels, bench_report.cpp).
namespace svg {

// Text for an attribute or element: & < > " ' escaped, line breaks and tabs
// as spaces, so that no name or tooltip can break the document.
std::string escape(const std::string& s);
// Up to six significant digits, the shortest form (std::to_chars).
std::string number(double v);
// <text>: `anchor` start, middle or end; `extra` more attributes (" class=...").
std::string text(double x, double y, const std::string& s, const std::string& anchor, double size, const std::string& fill,
                 const std::string& extra = "");
std::string line(double xa, double ya, double xb, double yb, const std::string& stroke, double width,
                 const std::string& extra = "");

// Ticks of a logarithmic axis spanning [lo, hi] in log10: the decades
// labelled; 2 and 5 labelled too where it spans few decades (and 3 on a
// short one); the other multiples as unlabelled minor ticks.
struct Tick {
    double value;
    bool labelled;
};
std::vector<Tick> log_ticks(double lo, double hi);

}  // namespace svg

}  // namespace px::profiling
