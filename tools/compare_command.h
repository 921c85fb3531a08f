// What `parallax compare` and `parallax render --golden` share: the
// tolerance options, their resolution (defaults, then a tolerance file's
// entry, then flags) and the verdict. The measure is the library's
// (assets/image_compare.h), the one the golden tests use.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "parallaxes/assets/image_compare.h"

namespace px::tools {

// Exit statuses of both commands: 0 within the tolerances, 1 not, 2 when no
// comparison could be made (a missing or unreadable image, a size mismatch,
// a bad tolerance file or flag, an image or diff that could not be written).
constexpr int kCompareFailed = 1;
constexpr int kCompareBadInput = 2;

struct GoldenOptions {
    std::string tolerances;  // a tolerance file; empty: none
    std::string scene;       // its entry
    int es = 0;              // apply the entry's "es2"/"es3" override; 0: none
    std::string cpu = compiled_cpu();  // apply the entry's override for this CPU ("arm64", ...)
    std::string threshold;   // flags as given (empty: not given), checked by resolve_tolerance
    std::string max_share;
    std::string max_mean;
    std::string diff;        // write the diff image here; empty: none
    bool json = false;       // the verdict as a JSON object instead of a line
};

// --tolerances, --cpu, --threshold, --max-share, --max-mean and --diff (the caller
// adds --scene and --es where it has them).
void add_tolerance_options(CLI::App* cmd, GoldenOptions& o);

// Defaults, then the file's entry, then the flags. Errors name the file and
// JSON path, or the flag.
Result<Tolerance> resolve_tolerance(const GoldenOptions& o);

// Compares `actual` (named actual_name in messages) with the golden file
// under `tolerance`, prints the verdict on stdout, writes the diff image when
// asked, and returns the exit status (0, kCompareFailed, kCompareBadInput).
int compare_with_golden(const Image& actual, const std::string& actual_name, const std::string& golden_path,
                        const Tolerance& tolerance, const GoldenOptions& o);

// Prints "parallax: error: MESSAGE" and returns kCompareBadInput.
int bad_input(const std::string& message);

}  // namespace px::tools
