// parallax stability [--cases PATTERN] [--precision native,fp32,fp16,lowp,nohighp|all]
//                    [--es 2|3|both] [--full] [--size N] [--format table|md|json] [--out FILE]
//                    [--catalogue FILE]
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli_common.h"
#include "commands.h"
#include "parallaxes/core/files.h"
#include "parallaxes/platform/headless_context.h"
#include "parallaxes/profiling/measurement/stability.h"
#include "stability_precision.h"

namespace px::tools {

namespace {

struct StabilityArgs {
    std::string cases;
    std::vector<std::string> precisions{"all"};
    std::string es = "both";
    bool full = false;
    int size = 0;
    int sweep_pairs = 0;
    std::string format = "table";
    std::string out;
    std::string catalogue;
    std::string images;
    std::string command;
};


// The precisions asked for: native (this driver, declarations in force) and
// the emulated profiles (the shaders rewritten with rounding, run on ES 3.0).
Result<std::vector<std::string>> stability_precisions(const StabilityArgs& a) {
    std::vector<std::string> precisions;
    for (const std::string& p : a.precisions) {
        if (p == "all") {
            for (const char* q : {"native", "fp32", "fp16", "lowp", "nohighp"})
                if (std::find(precisions.begin(), precisions.end(), q) == precisions.end()) precisions.push_back(q);
            continue;
        }
        if (p != "native" && !is_emulated_precision(p))
            return make_error("--precision '" + p + "': expected native, fp32, fp16, lowp, nohighp, lowp_all or all");
        if (std::find(precisions.begin(), precisions.end(), p) == precisions.end()) precisions.push_back(p);
    }
    return precisions;
}

// The built-in catalogue, or --catalogue's (at most 16 MiB).
Result<profiling::Catalogue> stability_catalogue(const StabilityArgs& a) {
    std::string text = profiling::embedded_catalogue_text();
    std::string origin = "built-in catalogue (tests/stability/catalogue.jsonc)";
    if (!a.catalogue.empty()) {
        Result<std::vector<std::uint8_t>> read = read_file_bounded(a.catalogue, 16u << 20, "catalogue");
        if (!read) return read.error();
        text.assign(read->begin(), read->end());
        origin = a.catalogue;
    }
    return profiling::parse_catalogue(text, origin);
}

int run(const StabilityArgs& a) {
    // The precisions: native (this driver, declarations in force) and the
    // emulated profiles (the shaders rewritten with rounding, run on ES 3.0).
    Result<std::vector<std::string>> asked = stability_precisions(a);
    if (!asked) return fail(asked.error().message);
    const std::vector<std::string>& precisions = *asked;
    if (a.es != "2" && a.es != "3" && a.es != "both") return fail("--es '" + a.es + "': expected 2, 3 or both");
    if (a.format != "table" && a.format != "md" && a.format != "json")
        return fail("--format '" + a.format + "': expected table, md or json");
    if (a.size != 0 && (a.size < 16 || a.size > 1024)) return fail("--size must be within 16..1024");
    if (!a.out.empty())
        if (const std::string unwritable = check_output_file(a.out); !unwritable.empty()) return fail("--out: " + unwritable);

    Result<profiling::Catalogue> catalogue = stability_catalogue(a);
    if (!catalogue) return fail(catalogue.error().message);

    profiling::StabilityOptions o;
    o.cases_pattern = a.cases;
    o.full = a.full;
    if (a.sweep_pairs < 0 || a.sweep_pairs > 64) return fail("--sweep-pairs must be within 0..64");
    o.sweep_pairs = a.sweep_pairs;
    o.image_size = a.size ? a.size : (a.full ? 256 : 128);
    std::error_code ec;
    const std::filesystem::path scratch = std::filesystem::temp_directory_path(ec) /
                                          ("parallax-stability-" + std::to_string(getpid()));
    o.scratch_dir = scratch.string();
    o.image_dir = a.images;
    o.renderer_options = make_renderer_factory(platform::HeadlessContext::proc_loader());

    std::vector<profiling::StabilityRow> rows;
    for (int es : {3, 2}) {
        if (a.es != "both" && a.es != std::to_string(es)) continue;
        // Emulated profiles run on the ES 3.0 context only.
        o.precisions.clear();
        for (const std::string& p : precisions)
            if (p == "native" || es == 3) o.precisions.push_back(p);
        if (o.precisions.empty()) continue;
        platform::ContextOptions co;
        co.es_major = es;
        auto context = platform::HeadlessContext::create(co);
        if (!context) return fail(context.error().message);
        auto result = profiling::run_stability(*catalogue, o, [](int done, int total, const std::string& what) {
            show_progress("stability", done, total, what);
        });
        if (!result) {
            std::filesystem::remove_all(scratch, ec);
            return fail(result.error().message);
        }
        rows.insert(rows.end(), result->begin(), result->end());
    }
    std::filesystem::remove_all(scratch, ec);

    std::string report = a.format == "json" ? profiling::format_json(rows)
                         : a.format == "md" ? profiling::format_markdown(rows, a.command)
                                            : profiling::format_table(rows);
    std::fputs(report.c_str(), stdout);
    if (!a.out.empty()) {
        Status written = write_file_atomically(a.out, report);
        if (!written) return fail(written.error().message);
    }
    long failed = 0, limits = 0, passed = 0;
    for (const profiling::StabilityRow& r : rows) {
        if (r.verdict == "fail") ++failed;
        else if (r.verdict == "limit") ++limits;
        else if (r.verdict == "pass") ++passed;
    }
    std::fprintf(stderr, "stability: %zu rows: %ld pass, %ld documented limits, %ld fail\n", rows.size(), passed,
                 limits, failed);
    return failed ? 1 : 0;
}

}  // namespace

void add_stability_command(CLI::App& app, int argc, char** argv) {
    auto args = std::make_shared<StabilityArgs>();
    std::ostringstream command;
    for (int i = 0; i < argc; ++i) command << (i ? " " : "") << (i == 0 ? "parallax" : argv[i]);
    args->command = command.str();
    CLI::App* cmd = app.add_subcommand("stability", "Run the hard-case catalogue; exit 1 when a case fails");
    cmd->add_option("--cases", args->cases, "Case names: a substring, or a glob with * and ?");
    cmd->add_option("--precision", args->precisions, "native, fp32, fp16, lowp, nohighp, lowp_all (the whitepaper's all-lowp fragment stage) or all (every one but lowp_all; the default)")
        ->delimiter(',');
    cmd->add_option("--es", args->es, "OpenGL ES contexts: 2, 3 or both")->capture_default_str();
    cmd->add_flag("--full", args->full, "Every sweep frame and the full-only cases, at 256 pixels");
    cmd->add_option("--size", args->size, "Image side in pixels (default 128; 256 with --full)");
    cmd->add_option("--sweep-pairs", args->sweep_pairs,
                    "At most this many neighbouring-frame pairs per sweep (default: every 'quick_stride'-th; --full: all)");
    cmd->add_option("--format", args->format, "table, md or json")->capture_default_str();
    cmd->add_option("--out", args->out, "Also write the report to this file");
    cmd->add_option("--catalogue", args->catalogue, "A catalogue file instead of the built-in one");
    cmd->add_option("--images", args->images,
                    "Write per-pixel error/bound maps here (green within, red past, magenta NaN)");
    cmd->callback([args]() { set_exit_status(run(*args)); });
}

}  // namespace px::tools
