// The planner's cost table from benchmark runs: the generic table the
// library ships (`parallax bench --planner-table`), and the calibration of
// one material's own relief (`parallax plan --calibrate`).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "parallaxes/core/limits.h"
#include "parallaxes/planner/cost_table.h"
#include "parallaxes/profiling/measurement/bench.h"

namespace px::profiling {

// The grid the shipped table measures (docs/planner.md).
struct TableGrid {
    std::vector<std::string> scenes{"sine", "bricks", "text", "hemispheres", "lines"};
    std::vector<std::string> shadow_scenes{"bricks_shadowed", "bricks_soft", "text_shadowed", "text_soft"};
    std::vector<double> angles{0, 30, 60, 75, 85, 89};
    std::vector<int> samples = sample_grid();
    std::vector<int> shadow_samples{4, 8, 16, 32, 64};
    // Shadow rows: view angles, and the light's elevations above the plane
    // (a shadow's error depends on how low the light is most of all). Each
    // shadowed scene, angle and elevation needs its own soft-shadow
    // reference, the slowest part of the table: 64 of them here.
    std::vector<double> shadow_angles{0, 30, 60, 75};
    std::vector<double> light_elevations{10, 20, 35, 60};
    int frames = 5;
    int width = 256, height = 256;
    // false: errors only (no frame times: the rows are priced by `price`).
    bool timed = true;
    // Count every search's and shadow march's iterations (BenchOptions).
    bool count_every_search = false;
};

// Prices a measured run's rows (BenchRow::ratio_to_normal) otherwise than by
// its frame times, and says how in `prices` (CostTable::prices); called
// for each run in order, the unshadowed run first.
using RowPricer = std::function<Status(BenchRun& run, std::string& prices)>;

// The bench rows as a cost table: one relief per bench scene (a shadowed
// scene shares its unshadowed twin's relief), features measured from each
// scene's field as the GPU samples it.
Result<CostTable> cost_table_from_runs(const std::vector<BenchRun>& runs, const std::vector<BenchMaterial>& materials);

// Measures the generic grid (needs a current ES 3.0 context and a target of
// the grid's size). `command` is recorded in the table.
// `keep`: measure only the shadow rows and keep every other row of this table.
Result<CostTable> measure_cost_table(const TableGrid& grid, const std::string& command, const RenderTarget& target,
                                     const std::function<Result<Image>()>& read_color, const Progress& progress,
                                     const CostTable* keep = nullptr, const RowPricer& price = {});

// The planner tables priced in a real GPU compiler's cycles that the
// program carries (profiling/costs/planner_tables/, made by `parallax bench
// --planner-table FILE --gpu NAME`): the GPU names (profile --gpu list's)
// that have one, and the table of one. An unknown name or one without a
// table is an error saying which have one and how to make another.
std::vector<std::string> gpu_cost_table_names();
Result<const CostTable*> gpu_cost_table(const std::string& gpu_name);

// Measures one material's relief at these angles, every candidate of the
// grid (and its shadow mode's sample counts when it asks for a shadow).
Result<CostTable> calibrate_material(const MaterialDesc& material, const std::string& base_dir,
                                     const std::vector<double>& angles, const TableGrid& grid,
                                     const std::string& command, const RenderTarget& target,
                                     const std::function<Result<Image>()>& read_color, const Progress& progress);

}  // namespace px::profiling
