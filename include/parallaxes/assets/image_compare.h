// Comparing a rendered image with a golden one: the measure the golden tests
// (tests/gpu_golden_tests.cpp) and `parallax compare` / `render --golden`
// share, and the tolerance files that set its limits
// (tests/golden/tolerances.json explains the project's own).
#pragma once

#include <cstdint>
#include <string>

#include "parallaxes/assets/image.h"
#include "parallaxes/core/result.h"

namespace px {

// An image passes when at most max_differing_share of its pixels differ (a
// pixel differs when one of its colour channels is off by more than
// pixel_threshold levels) AND the mean difference over every colour channel
// of every pixel is at most max_mean_difference levels. The defaults are the
// limits most of the project's goldens use.
struct Tolerance {
    int pixel_threshold = 8;             // levels, 0..255
    double max_differing_share = 0.001;  // of all pixels, 0..1
    double max_mean_difference = 0.15;   // levels, 0..255
};

// A scene's entry in a tolerance file: a JSON object whose members are
// scene names, each an object with pixel_threshold, max_differing_share and
// max_mean_difference (all three required), and optionally overrides of any
// of them: "es2" / "es3" for that OpenGL ES version (applied when es_major
// is 2 or 3; es_major 0 applies none), and "x86_64", "i386", "arm64" or
// "armhf" for the CPU the renderer ran on (applied when `cpu` names it; a
// CPU's object may hold its own "es2" / "es3"). They apply in that order:
// the entry, its ES version's, its CPU's, its CPU's ES version's. Every
// override is checked, applied or not. Other members of an entry are
// ignored, and so are members of the file whose names start with '_' (the
// "_comment" notes, "_made_on"): they are never a scene's entry. An
// override holds those three fields only (a CPU's also its "es2"/"es3" and
// '_' notes). Errors name `origin` and the JSON path: malformed JSON (with
// line and column), an unknown scene (with the ones the file has), a wrong
// type, a negative or out-of-range value.
Result<Tolerance> parse_tolerances(const std::string& json_text, const std::string& origin,
                                   const std::string& scene, int es_major, const std::string& cpu = {});
// The same from a file (at most 1 MiB); errors name the file.
Result<Tolerance> load_tolerances(const std::string& path, const std::string& scene, int es_major,
                                  const std::string& cpu = {});
// The CPU this library was compiled for, as a tolerance file names it:
// "x86_64", "i386", "arm64", "armhf" (or "other").
const char* compiled_cpu();
// Whether a tolerance file can hold overrides for `cpu`.
bool is_tolerance_cpu(const std::string& cpu);

// What compare_images measured, and whether it is within its tolerance.
struct ImageComparison {
    Tolerance tolerance;
    int width = 0;
    int height = 0;
    std::int64_t pixels = 0;
    std::int64_t differing = 0;  // pixels with a colour channel off by more than the threshold
    double share = 0.0;          // differing / pixels
    double mean = 0.0;           // mean absolute difference over every colour channel, levels
    int max_difference = 0;      // largest colour channel difference, levels
    Image diff;                  // RGBA: the actual image's green / 4 as grey, red where a pixel differs

    bool share_within() const { return share <= tolerance.max_differing_share; }
    bool mean_within() const { return mean <= tolerance.max_mean_difference; }
    bool passed() const { return share_within() && mean_within(); }
};

// Compares the colour channels (alpha is ignored) of two images of the same
// size, each RGB or RGBA. A size mismatch, fewer than three channels, an
// empty image or a pixel buffer that does not match its size is an error
// naming the images by the names given.
Result<ImageComparison> compare_images(const Image& actual, const Image& golden, const Tolerance& tolerance,
                                       const std::string& actual_name = "actual image",
                                       const std::string& golden_name = "golden image");

}  // namespace px
