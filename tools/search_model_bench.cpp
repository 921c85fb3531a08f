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
#include "parallaxes/core/files.h"
#include "parallaxes/planner/search_model.h"
#include "parallaxes/platform/headless_context.h"
#include "parallaxes/profiling/measurement/bench.h"
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

std::string plot_svg(const std::vector<Case>& cases) {
    const double lo = -2.0, hi = 2.5;  // log10 texels
    const int size = 520, pad = 60;
    auto pos = [&](double v) {
        const double l = std::clamp(std::log10(std::max(v, 1e-2)), lo, hi);
        return pad + (l - lo) / (hi - lo) * (size - 2 * pad);
    };
    std::ostringstream s;
    s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << size << "\" height=\"" << size
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    s << "<text x=\"" << size / 2 << "\" y=\"20\" text-anchor=\"middle\" font-weight=\"bold\">Search model: measured "
         "against predicted hit error p95 (texels)</text>\n";
    for (int e = -2; e <= 2; ++e) {
        const double v = std::pow(10.0, e);
        const double p = pos(v);
        s << "<line x1=\"" << p << "\" y1=\"" << pad << "\" x2=\"" << p << "\" y2=\"" << size - pad
          << "\" stroke=\"#eeeeee\"/><line x1=\"" << pad << "\" y1=\"" << size - p << "\" x2=\"" << size - pad
          << "\" y2=\"" << size - p << "\" stroke=\"#eeeeee\"/>\n";
        s << "<text x=\"" << p << "\" y=\"" << size - pad + 16 << "\" text-anchor=\"middle\">" << num(v, "%g")
          << "</text><text x=\"" << pad - 6 << "\" y=\"" << size - p + 4 << "\" text-anchor=\"end\">" << num(v, "%g")
          << "</text>\n";
    }
    // measured = k x predicted, over the plotted square.
    for (const auto& [k, dash] : {std::pair{1.0, ""}, std::pair{2.0, "4,4"}, std::pair{0.5, "4,4"}}) {
        const double x0 = 1e-2 * std::max(1.0, 1.0 / k), x1 = std::pow(10.0, hi) * std::min(1.0, 1.0 / k);
        s << "<line x1=\"" << pos(x0) << "\" y1=\"" << size - pos(k * x0) << "\" x2=\"" << pos(x1) << "\" y2=\""
          << size - pos(k * x1) << "\" stroke=\"#888888\" stroke-dasharray=\"" << dash << "\"/>\n";
    }
    // One group per set, points without tooltips (the CSV has every case):
    // 2,700 points stay about 100 KB.
    for (const bool fit : {true, false}) {
        s << "<g fill=\"" << (fit ? "#1f77b4" : "#ff7f0e") << "\" fill-opacity=\"0.5\">\n";
        for (const Case& c : cases) {
            if (c.fit != fit || (c.measured <= 1e-2 && c.predicted <= 1e-2)) continue;
            s << "<circle cx=\"" << num(pos(c.predicted), "%.1f") << "\" cy=\"" << num(size - pos(c.measured), "%.1f")
              << "\" r=\"2\"/>\n";
        }
        s << "</g>\n";
    }
    s << "<text x=\"" << size / 2 << "\" y=\"" << size - 18 << "\" text-anchor=\"middle\">predicted: max(p95 x scale, p97) + floor, simulated</text>\n";
    s << "<text x=\"16\" y=\"" << size / 2 << "\" text-anchor=\"middle\" transform=\"rotate(-90 16 " << size / 2
      << ")\">measured on the GPU</text>\n";
    s << "<text x=\"" << pad + 8 << "\" y=\"" << pad + 14 << "\" fill=\"#1f77b4\">fit reliefs</text><text x=\"" << pad + 8
      << "\" y=\"" << pad + 30 << "\" fill=\"#ff7f0e\">judge reliefs (not fitted on)</text>\n";
    s << "<text x=\"" << size - pad << "\" y=\"" << size - pad - 8
      << "\" text-anchor=\"end\" fill=\"#888888\">solid: equal; dashed: a factor of 2</text>\n</svg>\n";
    return s.str();
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

int run_search_model_bench(const std::string& folder, int width, int height, const std::string& out,
                           const std::string& command) {
    std::vector<std::pair<bool, std::string>> scenes;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
        const std::string name = entry.path().filename().string();
        if (entry.path().extension() != ".json") continue;
        if (name.rfind("fit_", 0) == 0) scenes.emplace_back(true, entry.path().string());
        else if (name.rfind("judge_", 0) == 0) scenes.emplace_back(false, entry.path().string());
    }
    if (ec) return fail("--search-model '" + folder + "': " + ec.message());
    if (scenes.empty()) return fail("--search-model '" + folder + "': no fit_*.json or judge_*.json scenes in it");
    std::sort(scenes.begin(), scenes.end(), [](const auto& a, const auto& b) {
        return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    std::filesystem::create_directories(out, ec);
    if (ec) return fail("cannot create '" + out + "': " + ec.message());

    platform::ContextOptions context_options;
    context_options.es_major = 3;
    auto context = platform::HeadlessContext::create(context_options);
    if (!context) return fail(context.error().message);
    auto target = OffscreenTarget::create(width, height);
    if (!target) return fail(target.error().message);

    profiling::BenchOptions o;
    o.angles = {0, 30, 60, 75, 85, 89};
    o.samples = {4, 8, 16, 32, 64, 128, 256};
    o.techniques = {"normal", "parallax", "offset_limited", "steep", "pom", "relief", "maxmip"};
    o.frames = 1;  // errors only: the time is not used
    o.width = width;
    o.height = height;
    o.command = command;

    std::vector<Case> cases;
    std::string date, renderer;
    for (size_t si = 0; si < scenes.size(); ++si) {
        const auto& [fit, path] = scenes[si];
        Result<SceneDesc> scene = load_scene(path);
        if (!scene) return fail(scene.error().message);
        if (scene->materials.empty()) return fail(path + ": no material");
        const MaterialDesc& material = scene->materials[0];
        const std::string relief = material.name;
        Result<MaterialImages> images = build_material_images(material, scene->base_dir);
        if (!images) return fail(path + ": " + images.error().message);
        // Simulated over the bench image's own rays, angle by angle, at
        // the quantiles compared (the library predicts from the p95 and
        // the p97, predicted_with_margin).
        SearchModel model;
        model.angles = o.angles;
        model.curves = search_candidates(o.samples);
        std::vector<std::vector<std::vector<double>>> by_angle;  // angle, quantile, curve
        for (double angle : o.angles)
            by_angle.push_back(simulate_rays(images->traced, material.height_scale, material.polygon_height(),
                                             bench_rays(angle, width, height, 2048, images->traced.width), o.samples,
                                             TechniqueOptions{}.refine_steps, kQuantiles));
        o.materials = {{relief, material, scene->base_dir, ShadowMode::none}};
        o.scenes.clear();
        const std::string label = "search model " + std::to_string(si + 1) + "/" + std::to_string(scenes.size()) + " " + relief;
        Result<profiling::BenchRun> run = profiling::run_bench(
            o, target->target(), [&target]() { return target->read_pixels(); },
            [&label](int done, int total, const std::string& what) { show_progress(label.c_str(), done, total, what); });
        if (!run) return fail(path + ": " + run.error().message);
        date = run->date;
        renderer = run->gl_renderer;
        for (const profiling::BenchRow& row : run->rows) {
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

    // The CSV: every case.
    std::string csv = "set,relief,angle_deg,technique,samples,measured_base_p95,measured_p95,simulated_p95,simulated_p98,simulated_p99,simulated_p97,predicted\n";
    for (const Case& c : cases)
        csv += std::string(c.fit ? "fit" : "judge") + "," + c.relief + "," + num(c.angle, "%g") + "," +
               technique_name(c.technique) + "," + std::to_string(c.samples) + "," + num(c.measured_base, "%.5g") + "," +
               num(c.measured, "%.5g") + "," + num(c.simulated_at[0], "%.5g") + "," + num(c.simulated_at[1], "%.5g") + "," +
               num(c.simulated_at[2], "%.5g") + "," + num(c.simulated_at[3], "%.5g") + "," + num(c.predicted, "%.5g") + "\n";

    // The fit, per technique, in texels of the level sampled: the floor is
    // what the GPU measures where the simulation says nothing is left (the
    // 90th percentile of measured error where simulated < 0.05), and the
    // scale the 95th percentile of (measured - floor) / simulated where the
    // simulation says a quarter of a texel or more is left (at least 1).
    std::ostringstream md;
    md << "# The search model against the GPU\n\nMeasured by `" << command << "` on " << date << " ("
       << width << "x" << height << ", " << renderer << ").\n\n";
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
    // The judgement: measured over predicted with the library's margin.
    md << "\n## Measured over predicted, with the library's margin\n\n"
       << "A case is one relief, view angle, technique and sample count. \"Within 2x\": measured / predicted in "
          "[0.5, 2], or both under "
       << kResolved << " texels. \"Under\": measured above both the prediction and " << kResolved
       << " texels (what the margin failed to cover).\n\n";
    md << "| set | relief | cases | within 2x | under | worst measured / predicted |\n|---|---|---|---|---|---|\n";
    std::map<std::pair<bool, std::string>, std::vector<const Case*>> by_relief;
    for (const Case& c : cases) by_relief[{!c.fit, c.relief}].push_back(&c);
    int judge_total = 0, judge_within = 0, judge_under = 0;
    for (const auto& [key, list] : by_relief) {
        int within = 0, under = 0;
        double worst = 0.0;
        std::string worst_case;
        for (const Case* c : list) {
            within += within_two(*c) ? 1 : 0;
            under += under_predicted(*c) ? 1 : 0;
            if (c->measured > kResolved) {
                const double r = c->measured / std::max(c->predicted, 1e-9);
                if (r > worst) {
                    worst = r;
                    worst_case = std::string(technique_name(c->technique)) + (c->samples ? " x" + std::to_string(c->samples) : "") +
                                 " at " + num(c->angle, "%g");
                }
            }
        }
        if (key.first) {
            judge_total += static_cast<int>(list.size());
            judge_within += within;
            judge_under += under;
        }
        md << "| " << (key.first ? "judge" : "fit") << " | " << key.second << " | " << list.size() << " | " << within
           << " | " << under << " | " << (worst_case.empty() ? "-" : num(worst, "%.2f") + " (" + worst_case + ")") << " |\n";
    }
    md << "\nJudge reliefs: " << judge_within << " of " << judge_total << " cases within a factor of 2 ("
       << num(judge_total ? 100.0 * judge_within / judge_total : 0.0, "%.1f") << " %), " << judge_under
       << " under-predicted beyond the margin.\n\n![measured against predicted](search_model.svg)\n";

    for (const auto& [name, text] : {std::pair{std::string("search_model.csv"), csv}, std::pair{std::string("search_model.md"), md.str()},
                                     std::pair{std::string("search_model.svg"), plot_svg(cases)}}) {
        Status s = write_file_atomically(out + "/" + name, text);
        if (!s) return fail(s.error().message);
    }
    std::printf("search model: %zu cases over %zu reliefs; judge reliefs %d of %d within 2x, %d under-predicted; wrote "
                "%s/search_model.md, .csv, .svg\n",
                cases.size(), scenes.size(), judge_within, judge_total, judge_under, out.c_str());
    return 0;
}

}  // namespace px::tools
