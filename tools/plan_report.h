// What `parallax plan` and `parallax render --explain` print of the
// planner's answers, and the calibration cache both read.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "parallaxes/planner/planner.h"
#include "parallaxes/render/renderer.h"

namespace px::tools {

// Per object: what it asked for, the variant chosen, the prediction and
// every note (what was dropped and why).
std::string plans_table(const std::vector<ObjectPlan>& plans);
// `prices`: what the candidates' costs are (the plan's cost table), "" to leave it out.
std::string plans_json(const std::vector<ObjectPlan>& plans, const std::string& scene, const std::string& context,
                       const std::string& prices = "");

// The prices a plan uses: --cost-target NAME (a GPU-priced table the
// program carries) or --cost-table FILE; null for the built-in table.
// Errors name the option and the file.
Result<std::shared_ptr<const CostTable>> chosen_cost_table(const std::string& cost_target, const std::string& cost_table);
// What a plan's costs are, for its header: the table's `prices` (or frame
// time on its renderer), its date and the command that made it.
std::string prices_line(const CostTable* table);

// The calibration cache: one JSON cost table per relief. "" or "off": none.
// Default: $XDG_CACHE_HOME/parallaxes/calibration (or ~/.cache/...).
std::string default_calibration_dir();
// The planner's lookup into `dir` (PlannerOptions::find_calibration): a
// material's calibration is the file `plan --calibrate` wrote for its
// relief (calibration_file), and only that file is read, bounded in size
// and rows; no other file of the folder is opened. One that cannot be
// read, parsed or planned with (no relief matching its name, no
// normal-mapping row) is not used, and the note says so. Null for "" or
// "off".
std::function<std::optional<CostTable>(const ReliefFeatures&, std::string&)> calibration_finder(const std::string& dir);
std::string calibration_file(const std::string& dir, const ReliefFeatures& features);

// `plan --verify` and `render --verify`: the scene camera's plan drawn (the
// renderer has the scene loaded), each object's hit error (p95, texels of the
// level sampled) and shadow error measured against the depth-composited
// exact reference and printed beside the prediction and the target. Returns
// the exit status: 1 when a target is missed (stderr says how many).
// `candidates`: also draw every candidate a planned object could have had
// (each technique and sample count the context runs, with the plan's other
// options), measure each one's error and frame time against the plan's
// (median of interleaved rounds), and print the cheapest that measures
// within the targets and the plan's time over its time ("spends 1.31x what
// it must").
int verify_plan(Renderer& renderer, const SceneDesc& scene, int width, int height, bool candidates = false);

}  // namespace px::tools
