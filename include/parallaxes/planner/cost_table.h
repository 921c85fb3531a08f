// The planner's measured cost and error table: for reliefs of known
// character (planner/relief.h), view angles and candidate variants, the hit
// error against the exact reference and the frame time relative to normal
// mapping, as `parallax bench --planner-table` measured them. The library
// ships one (src/planner/cost_table.json, generated); `parallax plan
// --calibrate` measures a material's own relief into a table of the same form.
#pragma once

#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/effects/technique.h"
#include "parallaxes/planner/relief.h"

namespace px {

// What a cost table (or a calibration read from the cache) may hold: the
// built-in one has 5 reliefs and 1,070 rows; a bench run of every setting on
// a few more reliefs stays far below. Past these a table is refused.
inline constexpr std::size_t kMaxCostTableReliefs = 64;
inline constexpr std::size_t kMaxCostTableRows = 20000;

struct CostTableRelief {
    std::string name;  // bench scene, or "calibrated <hash>"
    ReliefFeatures features;
};

struct CostSample {
    int relief = 0;  // index into CostTable::reliefs
    double angle_deg = 0.0;
    Technique technique = Technique::normal;
    int samples = 0;  // max_samples (min = max: the bench's fixed count), or 0
    ShadowMode shadow = ShadowMode::none;
    int shadow_samples = 0;
    // Hit error over the image, base-level texels: the 95th percentile.
    double error_p95 = 0.0;
    // Shadow rows: mean |visibility difference| from the exact reference.
    double visibility_error = 0.0;
    // Median over interleaved rounds of (frame time / normal mapping's).
    double cost = 1.0;
    // The light's elevation above the surface (degrees) the row was
    // measured with: what a shadow's error depends on most.
    double light_elevation_deg = 35.0;
};

struct CostTable {
    std::string date;      // ISO 8601, when it was measured
    std::string renderer;  // GL_RENDERER
    std::string version;   // GL_VERSION
    std::string command;   // what regenerates it
    int width = 0, height = 0;
    // false: the rows' errors were measured, their costs were not (a
    // calibration without timing: `"costs": "table"` in the file); the
    // planner prices each candidate from the generic table's relief nearest
    // to this one, so the choice does not depend on this run's timing noise.
    bool costs_measured = true;
    // What the costs are: "" for frame times on `renderer` (the errors'
    // renderer too); otherwise how they were priced, e.g. a real GPU
    // compiler's cycle estimate per pixel (`parallax bench --planner-table
    // FILE --gpu NAME`): the planner prints it with every plan.
    std::string prices;
    std::vector<CostTableRelief> reliefs;
    std::vector<CostSample> rows;
};

// Errors name `origin` and the JSON path.
Result<CostTable> parse_cost_table(const std::string& json_text, const std::string& origin);
std::string cost_table_json(const CostTable& table);

// The table the library ships (parsed once; an error if the embedded text
// is broken, which a unit test rules out).
Result<const CostTable*> builtin_cost_table();

}  // namespace px
