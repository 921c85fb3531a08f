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

}  // namespace px::profiling
