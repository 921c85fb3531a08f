// Running the hard-case catalogue (include/parallaxes/profiling/reports/stability_catalogue.h) on the
// current context: every case, every technique, the precisions asked for.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "parallaxes/profiling/reports/stability_catalogue.h"
#include "parallaxes/render/renderer.h"

namespace px::profiling {

// The scene of one frame of a case: a plane at the origin facing +z, the
// camera `angle` degrees off its normal (or the case's explicit camera).
// `height_image`: the case's generated height image file (write_height_image),
// for a case with `image`; empty otherwise.
Result<SceneDesc> stability_scene(const StabilityCase& c, const std::string& technique, double angle,
                                  double distance, const std::string& height_image = "");
// Writes a case's non-square height image into `scratch_dir` once; returns its path.
Result<std::string> write_height_image(const StabilityCase& c, const std::string& scratch_dir);

// What the renderer is created with for a precision profile and the
// variant's ES version (the tool supplies shader transforms for emulated
// profiles; "native" must give plain options). An error skips nothing: it
// fails the run.
using RendererFactory = std::function<Result<RendererOptions>(const std::string& precision, int variant_es)>;

struct StabilityOptions {
    std::string cases_pattern;            // substring or glob (* ?) on case names; empty: all
    std::vector<std::string> precisions{"native"};
    int image_size = 128;
    bool full = false;                    // full_only cases and every sweep frame
    int sweep_pairs = 0;                  // > 0: at most this many neighbour pairs per sweep
    std::string scratch_dir;              // where generated height images go
    // When set: one PNG per row and frame, error against its bound per pixel
    // (black: not covered; green to yellow: within the bound; red: past it;
    // magenta: NaN or Inf), named CASE_TECHNIQUE_CONTEXT_PRECISION_FRAME.png.
    std::string image_dir;
    RendererFactory renderer_options;
};

using StabilityProgress = std::function<void(int done, int total, const std::string& what)>;

// Runs the catalogue on the current context for every technique it has
// (maxmip only with ES 3.0 variants); emulated precisions run the ES 3.0
// and the ES 2.0 variants through the factory's transforms on an ES 3.0
// context; "native" runs this context's own variants.
Result<std::vector<StabilityRow>> run_stability(const Catalogue& catalogue, const StabilityOptions& options,
                                                const StabilityProgress& progress);

}  // namespace px::profiling
