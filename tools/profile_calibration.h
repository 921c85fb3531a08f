// parallax profile --calibrate [--calibration-set FILE] [--model FILE] [--model-out FILE] [--format table|md|json]
// parallax profile --make-calibration-set OUT --shaders DIR --reports DIR [--set-source TEXT]
//
// The cost model against a real vendor compiler (profiling/costs/
// model_calibration.h): the fit and how it does on the shaders held out of
// it, and the making of a calibration set at asset-build time from shader
// sources and the compiler's reports of them. GL-free.
#pragma once

#include <sstream>
#include <string>

#include "parallaxes/core/result.h"
#include "parallaxes/profiling/costs/cost_model.h"

namespace px::tools {

struct CalibrationArgs {
    std::string set_file;    // empty: the carried set
    std::string model_file;  // the base to fit; empty: the carried base (profiling/costs/cost_model.json)
    std::string model_out;   // write the fitted model here
    std::string format = "table";
    std::string make_set;    // write a set here from --shaders and --reports
    std::string shaders, reports, source;
    std::string command;
};

int run_calibrate(const CalibrationArgs& a);

// The model a set calibrates: `base_file` (empty: profiling/costs/
// cost_model.json) fitted to `set_file`, for `parallax profile
// --calibration-set FILE` without --calibrate. An error names the file and
// why the set cannot calibrate the model (a compiler without a varying pipe).
Result<profiling::CostModel> model_fitted_to(const std::string& set_file, const std::string& base_file);
int run_make_calibration_set(const CalibrationArgs& a);

// docs/profiling.md's section: the carried set's fit as a table and a
// scatter written beside the doc.
Status doc_calibration(std::ostringstream& doc, const std::string& doc_path);

}  // namespace px::tools
