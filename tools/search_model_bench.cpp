// parallax bench --search-model FOLDER [--size WxH] [--out DIR]
//
// The planner's search model (planner/search_model.h) against the GPU: every
// scene of FOLDER named fit_*.json or judge_*.json holds one material; each
// is benched at the table's angles and sample counts (hit error p95 against
// the exact reference) and simulated on the CPU. Writes OUT/search_model.csv
// (every case), OUT/search_model.md (the margin the fit set suggests, and
// the judge set's measured over predicted with the library's margin) and
// OUT/search_model.svg (measured against predicted, log-log).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "cli_common.h"
#include "draw_surface.h"
#include "parallaxes/core/limits.h"
#include "parallaxes/core/files.h"
#include "parallaxes/planner/search_model.h"
#include "parallaxes/platform/headless_context.h"
#include "parallaxes/profiling/measurement/bench.h"
#include "parallaxes/profiling/reports/svg_plot.h"
#include "parallaxes/render/offscreen_target.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/scene/scene.h"

namespace px::tools {

namespace {

struct Case {
    bool fit = false;
    std::string relief;
    double angle = 0.0;
    Technique technique = Technique::normal;
    int samples = 0;
    double measured = 0.0, simulated = 0.0, predicted = 0.0;
    double measured_base = 0.0;  // in texels of the base level
    double simulated_at[4] = {0.0, 0.0, 0.0, 0.0};  // at kQuantiles
};

// The simulated quantiles recorded beside the GPU's p95 (the library
// predicts from the p95 and the p97).
const std::vector<double> kQuantiles{0.95, 0.98, 0.99, 0.97};

std::string num(double v, const char* f = "%.4g") {
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t k = std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * static_cast<double>(v.size()))) - 1);
    return v[k];
}

// Errors under this many texels agree whatever their ratio: a quarter of a
// texel is below what the bench's own measure resolves (a 256-pixel image of
// a 256-texel tile), and far below any target the planner is asked for.
constexpr double kResolved = 0.25;

bool within_two(const Case& c) {
    if (c.measured <= kResolved && c.predicted <= kResolved) return true;
    const double r = c.measured / std::max(c.predicted, 1e-9);
    return r >= 0.5 && r <= 2.0;
}
bool under_predicted(const Case& c) { return c.measured > kResolved && c.measured > c.predicted; }

// Measured against predicted, log-log, on the report's one chart module.
// Errors are drawn from a hundredth of a texel (smaller ones there); cases
// where both are below it are left out.
std::string plot_svg(const std::vector<Case>& cases) {
    profiling::PlotSeries fitted{"fit reliefs", "#1f77b4", {}, {}, {}, false, 2.0, 0.5};
    profiling::PlotSeries judged{"judge reliefs (not fitted on)", "#ff7f0e", {}, {}, {}, false, 2.0, 0.5};
    for (const Case& c : cases) {
        if (c.measured <= 1e-2 && c.predicted <= 1e-2) continue;
        profiling::PlotSeries& series = c.fit ? fitted : judged;
        series.x.push_back(std::max(c.predicted, 1e-2));
        series.y.push_back(std::max(c.measured, 1e-2));
    }
    profiling::PlotOptions o;
    o.title = "Search model: measured against predicted hit error p95 (texels)";
    o.subtitle = "one point per relief, view angle, technique and sample count";
    o.x_label = "predicted: max(p95 x scale, p97) + floor, simulated";
    o.y_label = "measured on the GPU";
    o.log_x = o.log_y = true;
    o.equality = true;
    o.band = 2.0;
    o.height = 620;
    return profiling::svg_plot({fitted, judged}, o);
}

// The rays of the bench's image at `angle_deg` (profiling/measurement/bench.cpp's
// camera: 2.2 units from the centre of a 2.4-unit plane, 45 degrees of
// field), one per cell of a grid over the image where the plane is seen:
// each pixel sees the plane at its own angle, so the bench's "angle" is the
// centre's, and its error p95 is over every angle of the image.
std::vector<SearchRay> bench_rays(double angle_deg, int width, int height, int limit, int texture_size) {
    const double a = glm::radians(angle_deg);
    const glm::dvec3 eye(0.0, -2.2 * std::sin(a), 2.2 * std::cos(a));
    const glm::dvec3 forward = glm::normalize(-eye);
    const glm::dvec3 up_hint = angle_deg < 1.0 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, up_hint));
    const glm::dvec3 up = glm::cross(right, forward);
    const double half = std::tan(glm::radians(45.0) / 2.0), aspect = static_cast<double>(width) / height;
    // Where the line through ndc (x, y) meets the plane z = 0, in texels.
    auto texel = [&](double x, double y, bool& ok) {
        const glm::dvec3 d = glm::normalize(forward + x * half * aspect * right + y * half * up);
        if (d.z >= -1e-12) {
            ok = false;
            return glm::dvec2(0.0);
        }
        const glm::dvec3 p = eye + (-eye.z / d.z) * d;
        return glm::dvec2(p.x / 2.4 + 0.5, p.y / 2.4 + 0.5) * static_cast<double>(texture_size);
    };
    // Every pixel that sees the plane, then at most `limit` of them evenly
    // spread in that order: the pixels the GPU's p95 is over (at grazing
    // angles a few rows of the image), thinned.
    std::vector<std::pair<int, int>> on_plane;
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            const double x = (i + 0.5) / width * 2.0 - 1.0, y = (j + 0.5) / height * 2.0 - 1.0;
            const glm::dvec3 d = glm::normalize(forward + x * half * aspect * right + y * half * up);
            if (d.z >= -1e-12) continue;
            const glm::dvec3 p = eye + (-eye.z / d.z) * d;
            if (std::fabs(p.x) <= 1.2 && std::fabs(p.y) <= 1.2) on_plane.emplace_back(i, j);
        }
    std::vector<SearchRay> rays;
    const size_t stride = std::max<size_t>(1, (on_plane.size() + static_cast<size_t>(limit) - 1) / static_cast<size_t>(limit));
    for (size_t k = 0; k < on_plane.size(); k += stride) {
        const auto [i, j] = on_plane[k];
        {
            const double x = (i + 0.5) / width * 2.0 - 1.0, y = (j + 0.5) / height * 2.0 - 1.0;
            bool ok = true;
            const glm::dvec2 centre = texel(x, y, ok);
            if (!ok) continue;
            const glm::dvec3 d = glm::normalize(forward + x * half * aspect * right + y * half * up);
            const glm::dvec3 p = eye + (-eye.z / d.z) * d;
            if (std::fabs(p.x) > 1.2 || std::fabs(p.y) > 1.2) continue;
            // GL's scale: texel differences across the pixel (half a pixel
            // each way), the larger of x and y.
            const double hx = 1.0 / width, hy = 1.0 / height;
            const glm::dvec2 dx = texel(x + hx, y, ok) - texel(x - hx, y, ok);
            const glm::dvec2 dy = texel(x, y + hy, ok) - texel(x, y - hy, ok);
            const double rho = ok ? std::sqrt(std::max(glm::dot(dx, dx), glm::dot(dy, dy))) : 1e9;
            (void)centre;
            rays.push_back({glm::dvec2(p.x / 2.4 + 0.5, p.y / 2.4 + 0.5), glm::normalize(eye - p), rho});
        }
    }
    return rays;
}

}  // namespace

namespace {

// FOLDER's fit_*.json and judge_*.json scenes, the fit set first, each set in name order.
Result<std::vector<std::pair<bool, std::string>>> search_model_scenes(const std::string& folder) {
    std::vector<std::pair<bool, std::string>> scenes;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
        const std::string name = entry.path().filename().string();
        if (entry.path().extension() != ".json") continue;
        if (name.rfind("fit_", 0) == 0) scenes.emplace_back(true, entry.path().string());
        else if (name.rfind("judge_", 0) == 0) scenes.emplace_back(false, entry.path().string());
    }
    if (ec) return make_error("--search-model '" + folder + "': " + ec.message());
    if (scenes.empty()) return make_error("--search-model '" + folder + "': no fit_*.json or judge_*.json scenes in it");
    std::sort(scenes.begin(), scenes.end(), [](const auto& a, const auto& b) {
        return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    return scenes;
}

profiling::BenchOptions search_model_bench_options(int width, int height, const std::string& command) {
    profiling::BenchOptions o;
    o.angles = {0, 30, 60, 75, 85, 89};
    o.samples = sample_grid();
    o.techniques = {"normal", "parallax", "offset_limited", "steep", "pom", "relief", "maxmip"};
    o.frames = 1;  // errors only: the time is not used
    o.width = width;
    o.height = height;
    o.command = command;
    return o;
}

// The GPU's rows of one relief beside the simulation of the same cases.
void add_cases(const profiling::BenchRun& run, const SearchModel& model,
               const std::vector<std::vector<std::vector<double>>>& by_angle, bool fit, const std::string& relief,
               std::vector<Case>& cases) {
    for (const profiling::BenchRow& row : run.rows) {
        Result<Technique> t = parse_technique(row.technique);
        if (!t) continue;
        const int samples = (technique_info(*t).options & kOptSamples) ? row.samples : 0;
        size_t curve = model.curves.size();
        for (size_t k = 0; k < model.curves.size(); ++k)
            if (model.curves[k].technique == *t && model.curves[k].samples == samples) curve = k;
        if (curve == model.curves.size()) continue;
        const auto at = std::find(model.angles.begin(), model.angles.end(), row.angle_deg);
        if (at == model.angles.end()) continue;
        const auto& sims = by_angle[static_cast<size_t>(at - model.angles.begin())];
        Case c;
        c.fit = fit;
        c.relief = relief;
        c.angle = row.angle_deg;
        c.technique = *t;
        c.samples = samples;
        c.measured = row.level_error_p95;
        c.measured_base = row.uv_error_p95;
        for (size_t q = 0; q < kQuantiles.size(); ++q) c.simulated_at[q] = sims[q][curve];
        c.simulated = c.simulated_at[0];
        c.predicted = predicted_with_margin(*t, c.simulated_at[0], c.simulated_at[3]);  // p95, p97
        cases.push_back(c);
    }
}

struct ReliefRun {
    std::string date, renderer;
};

// One scene's relief: simulated over the bench image's own rays, angle by
// angle, at the quantiles compared (the library predicts from the p95 and
// the p97, predicted_with_margin), and benched on the GPU.
Result<ReliefRun> measure_relief(bool fit, const std::string& path, const std::string& label, profiling::BenchOptions o,
                                 OffscreenTarget& target, std::vector<Case>& cases) {
    Result<SceneDesc> scene = load_scene(path);
    if (!scene) return scene.error();
    if (scene->materials.empty()) return make_error(path + ": no material");
    const MaterialDesc& material = scene->materials[0];
    Result<MaterialImages> images = build_material_images(material, scene->base_dir);
    if (!images) return make_error(path + ": " + images.error().message);
    SearchModel model;
    model.angles = o.angles;
    model.curves = search_candidates(o.samples);
    std::vector<std::vector<std::vector<double>>> by_angle;  // angle, quantile, curve
    for (double angle : o.angles)
        by_angle.push_back(simulate_rays(images->traced, material.height_scale, material.polygon_height(),
                                         bench_rays(angle, o.width, o.height, 2048, images->traced.width), o.samples,
                                         TechniqueOptions{}.refine_steps, kQuantiles));
    o.materials = {{material.name, material, scene->base_dir, ShadowMode::none}};
    o.scenes.clear();
    Result<profiling::BenchRun> run = profiling::run_bench(
        o, target.target(), [&target]() { return target.read_pixels(); },
        [&label](int done, int total, const std::string& what) { show_progress(label.c_str(), done, total, what); });
    if (!run) return make_error(path + ": " + run.error().message);
    add_cases(*run, model, by_angle, fit, material.name, cases);
    return ReliefRun{run->date, run->gl_renderer};
}

std::string cases_csv(const std::vector<Case>& cases) {
    std::string csv = "set,relief,angle_deg,technique,samples,measured_base_p95,measured_p95,simulated_p95,simulated_p98,simulated_p99,simulated_p97,predicted\n";
    for (const Case& c : cases)
        csv += std::string(c.fit ? "fit" : "judge") + "," + c.relief + "," + num(c.angle, "%g") + "," +
               technique_name(c.technique) + "," + std::to_string(c.samples) + "," + num(c.measured_base, "%.5g") + "," +
               num(c.measured, "%.5g") + "," + num(c.simulated_at[0], "%.5g") + "," + num(c.simulated_at[1], "%.5g") + "," +
               num(c.simulated_at[2], "%.5g") + "," + num(c.simulated_at[3], "%.5g") + "," + num(c.predicted, "%.5g") + "\n";
    return csv;
}

// The fit, per technique, in texels of the level sampled: the floor is
// what the GPU measures where the simulation says nothing is left (the
// 90th percentile of measured error where simulated < 0.05), and the
// scale the 95th percentile of (measured - floor) / simulated where the
// simulation says a quarter of a texel or more is left (at least 1).
std::string margin_markdown(const std::vector<Case>& cases) {
    std::ostringstream md;
    md << "## Margin suggested by the fit reliefs\n\n| technique | cases | floor (texels) | scale | library's floor | library's scale |\n|---|---|---|---|---|---|\n";
    std::map<Technique, std::vector<const Case*>> by_technique;
    for (const Case& c : cases)
        if (c.fit) by_technique[c.technique].push_back(&c);
    for (const auto& [t, list] : by_technique) {
        std::vector<double> flat, ratio;
        for (const Case* c : list)
            if (c->simulated < 0.05) flat.push_back(c->measured);
        const double floor = quantile(flat, 0.9);
        for (const Case* c : list)
            if (c->simulated >= kResolved) ratio.push_back((c->measured - floor) / c->simulated);
        const double scale = ratio.empty() ? 1.0 : std::max(1.0, quantile(ratio, 0.95));
        const SearchMargin m = search_margin(t);
        md << "| " << technique_name(t) << " | " << list.size() << " | " << num(floor, "%.3g") << " | "
           << num(scale, "%.3g") << " | " << num(m.floor, "%.3g") << " | " << num(m.scale, "%.3g") << " |\n";
    }
    return md.str();
}

struct Judgement {
    int total = 0, within = 0, under = 0;  // judge reliefs' cases
};

// The judgement: measured over predicted with the library's margin, per relief.
std::string judgement_markdown(const std::vector<Case>& cases, Judgement& judge) {
    std::ostringstream md;
    md << "\n## Measured over predicted, with the library's margin\n\n"
       << "A case is one relief, view angle, technique and sample count. \"Within 2x\": measured / predicted in "
          "[0.5, 2], or both under "
       << kResolved << " texels. \"Under\": measured above both the prediction and " << kResolved
       << " texels (what the margin failed to cover).\n\n";
    md << "| set | relief | cases | within 2x | under | worst measured / predicted |\n|---|---|---|---|---|---|\n";
    std::map<std::pair<bool, std::string>, std::vector<const Case*>> by_relief;
    for (const Case& c : cases) by_relief[{!c.fit, c.relief}].push_back(&c);
    for (const auto& [key, list] : by_relief) {
        int within = 0, under = 0;
        double worst = 0.0;
        std::string worst_case;
        for (const Case* c : list) {
            within += within_two(*c) ? 1 : 0;
            under += under_predicted(*c) ? 1 : 0;
            const double r = c->measured / std::max(c->predicted, 1e-9);
            if (c->measured > kResolved && r > worst) {
                worst = r;
                worst_case = std::string(technique_name(c->technique)) + (c->samples ? " x" + std::to_string(c->samples) : "") +
                             " at " + num(c->angle, "%g");
            }
        }
        if (key.first) {
            judge.total += static_cast<int>(list.size());
            judge.within += within;
            judge.under += under;
        }
        md << "| " << (key.first ? "judge" : "fit") << " | " << key.second << " | " << list.size() << " | " << within
           << " | " << under << " | " << (worst_case.empty() ? "-" : num(worst, "%.2f") + " (" + worst_case + ")") << " |\n";
    }
    md << "\nJudge reliefs: " << judge.within << " of " << judge.total << " cases within a factor of 2 ("
       << num(judge.total ? 100.0 * judge.within / judge.total : 0.0, "%.1f") << " %), " << judge.under
       << " under-predicted beyond the margin.\n\n![measured against predicted](search_model.svg)\n";
    return md.str();
}

}  // namespace

int run_search_model_bench(const std::string& folder, int width, int height, const std::string& out,
                           const std::string& command) {
    Result<std::vector<std::pair<bool, std::string>>> scenes = search_model_scenes(folder);
    if (!scenes) return fail(scenes.error().message);
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (ec) return fail("cannot create '" + out + "': " + ec.message());
    Result<DrawSurface> surface = make_draw_surface(width, height);
    if (!surface) return fail(surface.error().message);
    OffscreenTarget* target = &*surface->target;
    const profiling::BenchOptions options = search_model_bench_options(width, height, command);
    std::vector<Case> cases;
    ReliefRun last;
    for (size_t si = 0; si < scenes->size(); ++si) {
        const auto& [fit, path] = (*scenes)[si];
        const std::string label = "search model " + std::to_string(si + 1) + "/" + std::to_string(scenes->size()) + " " +
                                  std::filesystem::path(path).stem().string();
        Result<ReliefRun> run = measure_relief(fit, path, label, options, *target, cases);
        if (!run) return fail(run.error().message);
        last = *run;
    }
    Judgement judge;
    std::ostringstream md;
    md << "# The search model against the GPU\n\nMeasured by `" << command << "` on " << last.date << " ("
       << width << "x" << height << ", " << last.renderer << ").\n\n"
       << margin_markdown(cases) << judgement_markdown(cases, judge);
    for (const auto& [name, text] : {std::pair{std::string("search_model.csv"), cases_csv(cases)},
                                     std::pair{std::string("search_model.md"), md.str()},
                                     std::pair{std::string("search_model.svg"), plot_svg(cases)}}) {
        Status s = write_file_atomically(out + "/" + name, text);
        if (!s) return fail(s.error().message);
    }
    std::printf("search model: %zu cases over %zu reliefs; judge reliefs %d of %d within 2x, %d under-predicted; wrote "
                "%s/search_model.md, .csv, .svg\n",
                cases.size(), scenes->size(), judge.within, judge.total, judge.under, out.c_str());
    return 0;
}

}  // namespace px::tools
