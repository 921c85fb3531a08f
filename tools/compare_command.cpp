// parallax compare ACTUAL.png GOLDEN.png [--tolerances FILE --scene NAME [--es 2|3]]
//                  [--threshold N] [--max-share F] [--max-mean F] [--diff OUT.png] [--format text|json]
// The golden tests' measure (assets/image_compare.h) on two image files: a
// verdict, a diff image on request and an exit status for CI (README
// "Regression runs"). `render --golden` reuses everything here.
#include "compare_command.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "commands.h"
#include "parallaxes/core/text.h"

namespace px::tools {

namespace {

struct CompareArgs {
    std::string actual;
    std::string golden;
    std::string format = "text";
    GoldenOptions golden_options;
};

// A flag's number: all of the text, finite, within [0, limit].
bool parse_number(const std::string& text, double limit, double& out) {
    if (text.empty()) return false;
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (errno != 0 || end != text.c_str() + text.size() || !std::isfinite(v) || v < 0.0 || v > limit) return false;
    out = v;
    return true;
}

// The flags over `t`; an error names the flag and what it takes.
Status apply_flags(const GoldenOptions& o, Tolerance& t) {
    if (!o.threshold.empty()) {
        double v = 0.0;
        if (!parse_number(o.threshold, 255.0, v) || v != std::floor(v))
            return make_error("--threshold '" + echo(o.threshold) + "': expected an integer in 0..255 (levels)");
        t.pixel_threshold = static_cast<int>(v);
    }
    if (!o.max_share.empty() && !parse_number(o.max_share, 1.0, t.max_differing_share))
        return make_error("--max-share '" + echo(o.max_share) + "': expected a number in 0..1 (a share of the pixels)");
    if (!o.max_mean.empty() && !parse_number(o.max_mean, 255.0, t.max_mean_difference))
        return make_error("--max-mean '" + echo(o.max_mean) + "': expected a number in 0..255 (levels)");
    return {};
}

std::string format(const char* spec, double value) {
    char b[64];
    std::snprintf(b, sizeof b, spec, value);
    return b;
}

// "12 of 16384 pixels (0.073%) over 8 levels (allowed 0.1%), mean 0.041 (allowed 0.15), max 23"
std::string measures(const ImageComparison& c) {
    const Tolerance& t = c.tolerance;
    return std::to_string(c.differing) + " of " + std::to_string(c.pixels) + " pixels (" +
           format("%.3f", 100.0 * c.share) + "%) over " + std::to_string(t.pixel_threshold) + " levels (allowed " +
           format("%g", 100.0 * t.max_differing_share) + "%), mean " + format("%.3f", c.mean) + " (allowed " +
           format("%g", t.max_mean_difference) + "), max " + std::to_string(c.max_difference);
}

std::string verdict_line(const ImageComparison& c, const std::string& actual, const std::string& golden) {
    std::string line = std::string(c.passed() ? "PASS " : "FAIL ") + actual + " vs " + golden + ": " + measures(c);
    if (!c.share_within()) line += ": share of differing pixels over its limit";
    if (!c.mean_within()) line += std::string(c.share_within() ? ": " : ", ") + "mean difference over its limit";
    return line;
}

std::string verdict_json(const ImageComparison& c, const std::string& actual, const std::string& golden,
                         const std::string& diff) {
    nlohmann::json broken = nlohmann::json::array();
    if (!c.share_within()) broken.push_back("max_differing_share");
    if (!c.mean_within()) broken.push_back("max_mean_difference");
    const nlohmann::json j = {
        {"verdict", c.passed() ? "pass" : "fail"},
        {"actual", actual},
        {"golden", golden},
        {"width", c.width},
        {"height", c.height},
        {"pixels", c.pixels},
        {"differing", c.differing},
        {"share", c.share},
        {"mean", c.mean},
        {"max_difference", c.max_difference},
        {"tolerance",
         {{"pixel_threshold", c.tolerance.pixel_threshold},
          {"max_differing_share", c.tolerance.max_differing_share},
          {"max_mean_difference", c.tolerance.max_mean_difference}}},
        {"broken", broken},
        {"diff", diff.empty() ? nlohmann::json(nullptr) : nlohmann::json(diff)}};
    return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

int run_compare(const CompareArgs& a) {
    if (a.format != "text" && a.format != "json")
        return bad_input("--format '" + echo(a.format) + "': expected text or json");
    Result<Tolerance> tolerance = resolve_tolerance(a.golden_options);
    if (!tolerance) return bad_input(tolerance.error().message);
    Result<Image> actual = load_image(a.actual, 4);
    if (!actual) return bad_input("actual image: " + actual.error().message);
    return compare_with_golden(*actual, a.actual, a.golden, *tolerance, a.golden_options);
}

}  // namespace

int bad_input(const std::string& message) {
    fail(message);
    return kCompareBadInput;
}

void add_tolerance_options(CLI::App* cmd, GoldenOptions& o) {
    cmd->add_option("--tolerances", o.tolerances,
                    "Tolerance file (JSON; tests/golden/tolerances.json is the project's): take the limits from its "
                    "entry for the scene");
    cmd->add_option("--cpu", o.cpu,
                    "Apply the tolerance entry's override for this CPU: x86_64, i386, arm64 or armhf (default: the "
                    "CPU parallax was built for)")
        ->capture_default_str();
    cmd->add_option("--threshold", o.threshold,
                    "A pixel differs when a colour channel is off by more than this many levels (default 8)");
    cmd->add_option("--max-share", o.max_share, "Largest share of differing pixels that passes, 0..1 (default 0.001)");
    cmd->add_option("--max-mean", o.max_mean,
                    "Largest mean difference that passes, in levels over every colour channel (default 0.15)");
    cmd->add_option("--diff", o.diff,
                    "Write a diff image here, pass or fail: the actual image in dim grey, red where a pixel differs");
}

Result<Tolerance> resolve_tolerance(const GoldenOptions& o) {
    Tolerance t;
    if (o.es != 0 && o.es != 2 && o.es != 3) return make_error("--es " + std::to_string(o.es) + ": expected 2 or 3");
    if (!is_tolerance_cpu(o.cpu) && o.cpu != compiled_cpu())
        return make_error("--cpu " + echo(o.cpu) + ": expected x86_64, i386, arm64 or armhf");
    if (o.tolerances.empty() && !o.scene.empty()) return make_error("--scene names an entry of --tolerances FILE: give both");
    if (!o.tolerances.empty()) {
        if (o.scene.empty()) return make_error("--tolerances " + echo_path(o.tolerances) + " needs --scene NAME (its entry)");
        Result<Tolerance> from_file = load_tolerances(o.tolerances, o.scene, o.es, o.cpu);
        if (!from_file) return from_file.error();
        t = *from_file;
    }
    if (Status s = apply_flags(o, t); !s) return s.error();
    // The diff's destination before anything is compared (or rendered): a
    // verdict followed by a failure to write would read as a pass.
    if (!o.diff.empty())
        if (const std::string unwritable = check_output_file(o.diff); !unwritable.empty())
            return make_error("--diff: " + unwritable);
    return t;
}

int compare_with_golden(const Image& actual, const std::string& actual_name, const std::string& golden_path,
                        const Tolerance& tolerance, const GoldenOptions& o) {
    Result<Image> golden = load_image(golden_path, 4);
    if (!golden) return bad_input("golden image: " + golden.error().message);
    Result<ImageComparison> c = compare_images(actual, *golden, tolerance, echo_path(actual_name), echo_path(golden_path));
    if (!c) return bad_input(c.error().message);
    // The verdict first: a diff that cannot be written still leaves it in the log.
    if (o.json)
        std::fputs(verdict_json(*c, actual_name, golden_path, o.diff).c_str(), stdout);
    else
        std::printf("%s\n", verdict_line(*c, actual_name, golden_path).c_str());
    std::fflush(stdout);
    if (!o.diff.empty())
        if (Status s = write_png(o.diff, c->diff); !s) return bad_input("--diff: " + s.error().message);
    return c->passed() ? 0 : kCompareFailed;
}

void add_compare_command(CLI::App& app) {
    auto args = std::make_shared<CompareArgs>();
    CLI::App* cmd = app.add_subcommand(
        "compare",
        "Compare an image with a golden one as the golden tests do; exit 0 within the tolerances, 1 not, 2 when "
        "they cannot be compared (missing or unreadable file, size mismatch, bad tolerances)");
    cmd->add_option("actual", args->actual, "The image to check (PNG, JPEG or TGA)")->required();
    cmd->add_option("golden", args->golden, "The golden image it must match")->required();
    add_tolerance_options(cmd, args->golden_options);
    cmd->add_option("--scene", args->golden_options.scene, "The tolerance file's entry to use (with --tolerances)");
    cmd->add_option("--es", args->golden_options.es,
                    "Apply the entry's \"es2\" or \"es3\" override (2 or 3; default: the entry alone)");
    cmd->add_option("--format", args->format, "text (one verdict line) or json")->capture_default_str();
    cmd->callback([args]() {
        args->golden_options.json = args->format == "json";
        set_exit_status(run_compare(*args));
    });
}

}  // namespace px::tools
