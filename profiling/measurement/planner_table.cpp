#include "parallaxes/profiling/measurement/planner_table.h"

#include <algorithm>
#include <cctype>
#include <map>

#include "parallaxes/scene/material_images.h"

namespace px::profiling {

namespace {

// "bricks_shadowed" and "bricks_soft" are the bricks relief, shadowed.
std::string relief_name(const std::string& scene) {
    const size_t cut = scene.find('_');
    if (cut != std::string::npos && (scene.substr(cut) == "_shadowed" || scene.substr(cut) == "_soft"))
        return scene.substr(0, cut);
    return scene;
}

Result<ReliefFeatures> features_of(const SceneDesc& scene) {
    Result<MaterialImages> images = build_material_images(scene.materials[0], scene.base_dir);
    if (!images) return images.error();
    return measure_relief(images->traced, scene.materials[0].height_scale);
}

}  // namespace

Result<CostTable> cost_table_from_runs(const std::vector<BenchRun>& runs, const std::vector<BenchMaterial>& materials) {
    CostTable table;
    std::map<std::string, int> relief_index;
    for (const BenchRun& run : runs) {
        if (table.date.empty()) {
            table.date = run.date;
            table.renderer = run.gl_renderer;
            table.version = run.gl_version;
            table.width = run.width;
            table.height = run.height;
        }
        for (const BenchRow& row : run.rows) {
            if (row.technique == kDisplacedMesh) continue;
            bool custom_row = false;
            for (const BenchMaterial& m : materials) custom_row = custom_row || m.name == row.scene;
            const std::string relief = custom_row ? row.scene : relief_name(row.scene);
            auto it = relief_index.find(relief);
            if (it == relief_index.end()) {
                Result<SceneDesc> scene = make_error("");
                bool custom = false;
                for (const BenchMaterial& m : materials)
                    if (m.name == row.scene) {
                        scene = bench_scene_of(m.name, m.material, m.base_dir, 0.0, 1);
                        custom = true;
                    }
                if (!custom) scene = bench_scene(relief, 0.0, 1);
                if (!scene) return scene.error();
                Result<ReliefFeatures> f = features_of(*scene);
                if (!f) return f.error();
                table.reliefs.push_back({relief, *f});
                it = relief_index.emplace(relief, static_cast<int>(table.reliefs.size() - 1)).first;
            }
            CostSample s;
            s.relief = it->second;
            s.angle_deg = row.angle_deg;
            Result<Technique> t = parse_technique(row.technique);
            if (!t) return t.error();
            s.technique = *t;
            s.samples = (technique_info(*t).options & (kOptSamples | kOptSteps)) ? row.samples : 0;
            if (technique_info(*t).options & kOptSteps && s.samples == 0) s.samples = TechniqueOptions{}.max_steps;
            s.shadow = row.shadow;
            s.shadow_samples = row.shadow_samples;
            s.error_p95 = row.uv_error_p95;
            s.visibility_error = row.shadow_disagreement;
            s.cost = row.ratio_to_normal > 0.0 ? row.ratio_to_normal : 1.0;
            s.light_elevation_deg = row.light_elevation_deg;
            table.rows.push_back(s);
        }
    }
    if (table.reliefs.empty()) return make_error("no bench rows to make a table of");
    return table;
}

namespace {

BenchOptions grid_options(const TableGrid& grid, const std::string& command) {
    BenchOptions o;
    o.angles = grid.angles;
    o.samples = grid.samples;
    o.frames = grid.frames;
    o.timed = grid.timed;
    o.count_every_search = grid.count_every_search;
    o.width = grid.width;
    o.height = grid.height;
    o.command = command;
    o.techniques.clear();
    for (const TechniqueInfo& info : technique_table())
        if (info.benched) o.techniques.push_back(info.name);
    return o;
}

}  // namespace

Result<CostTable> measure_cost_table(const TableGrid& grid, const std::string& command, const RenderTarget& target,
                                     const std::function<Result<Image>()>& read_color, const Progress& progress,
                                     const CostTable* keep, const RowPricer& price) {
    if (!grid.timed && !price) return make_error("a table measured without timing needs its rows priced otherwise");
    std::string prices;
    const auto priced = [&](BenchRun& run) -> Status { return price ? price(run, prices) : Status{}; };
    BenchOptions plain = grid_options(grid, command);
    plain.scenes = grid.scenes;
    const int plain_total = keep ? 0
                                 : static_cast<int>(plain.scenes.size() * plain.angles.size() *
                                                    (3 + 3 * plain.samples.size() + 1));
    const int shadow_total = static_cast<int>(grid.shadow_scenes.size() * grid.shadow_angles.size() *
                                              grid.shadow_samples.size() * grid.light_elevations.size());
    std::vector<BenchRun> runs;
    if (!keep) {
        Result<BenchRun> a = run_bench(plain, target, read_color, [&](int done, int, const std::string& what) {
            if (progress) progress(done, plain_total + shadow_total, what);
        });
        if (!a) return a.error();
        if (Status p = priced(*a); !p) return p.error();
        runs.push_back(std::move(*a));
    }
    // Shadow rows: POM at 32 samples under each shadow sample count and
    // light elevation (the planner adds the shadow's cost over its
    // unshadowed twin to any technique).
    int done_before = plain_total;
    for (double elevation : grid.light_elevations) {
        BenchOptions shadowed = grid_options(grid, command);
        shadowed.scenes = grid.shadow_scenes;
        shadowed.angles = grid.shadow_angles;
        shadowed.techniques = {"pom"};
        shadowed.samples = {32};
        shadowed.shadow_samples = grid.shadow_samples;
        shadowed.light_elevation_deg = elevation;
        Result<BenchRun> b = run_bench(shadowed, target, read_color, [&](int done, int, const std::string& what) {
            if (progress) progress(done_before + done, plain_total + shadow_total, what);
        });
        if (!b) return b.error();
        if (Status p = priced(*b); !p) return p.error();
        done_before += static_cast<int>(b->rows.size());
        runs.push_back(std::move(*b));
    }
    Result<CostTable> table = cost_table_from_runs(runs, {});
    if (!table) return table.error();
    table->command = command;
    table->prices = prices;
    if (!keep) return table;
    if (keep->prices != prices)
        return make_error("the kept table's rows are priced as '" + (keep->prices.empty() ? "frame time" : keep->prices) +
                          "', the new shadow rows as '" + (prices.empty() ? "frame time" : prices) +
                          "': one table holds one kind of price");
    // Every row of `keep` but its shadow rows, then the new shadow rows,
    // their reliefs matched by name.
    CostTable merged = *keep;
    merged.rows.erase(std::remove_if(merged.rows.begin(), merged.rows.end(),
                                     [](const CostSample& s) { return s.shadow != ShadowMode::none; }),
                      merged.rows.end());
    for (CostSample s : table->rows) {
        const std::string& name = table->reliefs[static_cast<size_t>(s.relief)].name;
        int index = -1;
        for (size_t i = 0; i < merged.reliefs.size(); ++i)
            if (merged.reliefs[i].name == name) index = static_cast<int>(i);
        if (index < 0) {
            merged.reliefs.push_back(table->reliefs[static_cast<size_t>(s.relief)]);
            index = static_cast<int>(merged.reliefs.size() - 1);
        }
        s.relief = index;
        merged.rows.push_back(s);
    }
    // Both runs stay on record: the kept rows' command and date, then these.
    merged.command = keep->command + " (" + keep->date + "); shadow rows: " + command + " (" + table->date + ")";
    return merged;
}

namespace px_generated {
extern const char* const kEmbeddedMaliG57Table;
extern const char* const kEmbeddedMaliG52Table;
}  // namespace px_generated

namespace {

struct EmbeddedTable {
    const char* name;
    const char* const* text;
    const char* file;
};

const EmbeddedTable kGpuTables[] = {
    {"mali-g52", &px_generated::kEmbeddedMaliG52Table, "profiling/costs/planner_tables/mali_g52.json"},
    {"mali-g57", &px_generated::kEmbeddedMaliG57Table, "profiling/costs/planner_tables/mali_g57.json"},
};

}  // namespace

std::vector<std::string> gpu_cost_table_names() {
    std::vector<std::string> names;
    for (const EmbeddedTable& t : kGpuTables) names.push_back(t.name);
    return names;
}

Result<const CostTable*> gpu_cost_table(const std::string& gpu_name) {
    std::string lower = gpu_name;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    static std::map<std::string, Result<CostTable>> parsed;  // parsed on first use, kept
    for (const EmbeddedTable& t : kGpuTables) {
        if (lower != t.name) continue;
        auto it = parsed.find(t.name);
        if (it == parsed.end()) it = parsed.emplace(t.name, parse_cost_table(*t.text, t.file)).first;
        if (!it->second) return it->second.error();
        return &*it->second;
    }
    std::string known;
    for (const EmbeddedTable& t : kGpuTables) known += std::string(known.empty() ? "" : ", ") + t.name;
    return make_error("no planner table priced for GPU '" + gpu_name + "' (this program carries: " + known +
                      "); make one with `parallax bench --planner-table FILE --gpu NAME` (a GPU whose compiler "
                      "estimates cycles: parallax profile --gpu list) and pass it with --cost-table FILE");
}

Result<CostTable> calibrate_material(const MaterialDesc& material, const std::string& base_dir,
                                     const std::vector<double>& angles, const TableGrid& grid,
                                     const std::string& command, const RenderTarget& target,
                                     const std::function<Result<Image>()>& read_color, const Progress& progress) {
    BenchOptions o = grid_options(grid, command);
    o.angles = angles;
    o.scenes.clear();
    o.timed = grid.frames > 0;
    o.frames = std::max(1, grid.frames);
    const std::string name = "calibrated " + material.name;
    o.materials = {{name, material, base_dir, ShadowMode::none}};
    std::vector<BenchRun> runs;
    Result<BenchRun> plain = run_bench(o, target, read_color, progress);
    if (!plain) return plain.error();
    runs.push_back(std::move(*plain));
    std::vector<BenchMaterial> materials = o.materials;
    if (material.effects && material.effects->shadow != ShadowMode::none) {
        // As the generic table: every shadow sample count at each light elevation.
        for (double elevation : grid.light_elevations) {
            BenchOptions s = o;
            s.materials = {{name, material, base_dir, material.effects->shadow}};
            s.techniques = {"pom"};
            s.samples = {32};
            s.shadow_samples = grid.shadow_samples;
            s.light_elevation_deg = elevation;
            Result<BenchRun> shadowed = run_bench(s, target, read_color, progress);
            if (!shadowed) return shadowed.error();
            runs.push_back(std::move(*shadowed));
        }
    }
    Result<CostTable> table = cost_table_from_runs(runs, materials);
    if (!table) return table.error();
    table->command = command;
    table->costs_measured = o.timed;
    return table;
}

}  // namespace px::profiling
