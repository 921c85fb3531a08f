#include "plan_report.h"
#include "draw_surface.h"

#include <map>
#include <set>

#include "cli_common.h"
#include "parallaxes/core/limits.h"
#include "parallaxes/reference/metrics.h"
#include "parallaxes/reference/reference_image.h"
#include "parallaxes/render/surface_capture.h"
#include "parallaxes/render/offscreen_target.h"
#include "parallaxes/platform/headless_context.h"
#include "parallaxes/gl/gl.h"
#include "parallaxes/profiling/measurement/interleaved.h"
#include "parallaxes/profiling/measurement/planner_table.h"
#include <algorithm>
#include <chrono>
#include <cmath>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "parallaxes/core/files.h"

namespace px::tools {

namespace {

std::string asked(const ObjectPlan& p) {
    if (!p.planned) return std::string("technique ") + technique_name(p.options.technique) + " (named by the material)";
    const EffectRequest& r = p.request;
    std::string s;
    if (!r.parallax) {
        s = "parallax off";
    } else {
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, "parallax within %g texels", r.max_error_texels);
        s = buffer;
    }
    if (r.shadow != ShadowMode::none) {
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, ", %s shadow within %g", shadow_mode_name(r.shadow), r.shadow_max_error);
        s += buffer;
    }
    s += std::string(", depth correction ") + effect_switch_name(r.depth_correction) + ", lod fade " +
         effect_switch_name(r.lod_fade);
    return s;
}

}  // namespace

std::string plans_table(const std::vector<ObjectPlan>& plans) {
    std::string out;
    char line[512];
    for (const ObjectPlan& p : plans) {
        std::snprintf(line, sizeof line, "object     %s (material %s)\n", p.object.c_str(), p.material.c_str());
        out += line;
        out += "  asked    " + asked(p) + "\n";
        out += "  variant  " + p.key.describe() + "\n";
        if (p.view.visible) {
            std::snprintf(line, sizeof line,
                          "  view     %.0f px, angles %.1f..%.1f deg, distance %.2f..%.2f, mip %.1f..%.1f, %d light(s) above its horizon\n",
                          p.view.pixels, p.view.angle_min_deg, p.view.angle_max_deg, p.view.distance_min,
                          p.view.distance_max, p.view.mip_min, p.view.mip_max, p.view.lights_above_horizon);
        } else {
            std::snprintf(line, sizeof line, "  view     not visible\n");
        }
        out += line;
        if (p.predicted_error >= 0.0) {
            std::snprintf(line, sizeof line, "  predict  %.3g texels (target %g), x%.2f normal mapping per pixel", p.predicted_error,
                          p.request.max_error_texels, p.predicted_cost);
            out += line;
            if (p.predicted_shadow_error >= 0.0) {
                std::snprintf(line, sizeof line, ", shadow %.3g (target %g)", p.predicted_shadow_error, p.request.shadow_max_error);
                out += line;
            }
            out += "\n";
        }
        if (!p.prediction_source.empty()) out += "  from     " + p.prediction_source + "\n";
        if (p.generic_key) {
            std::snprintf(line, sizeof line, "  generic  %s (predicted %.3g texels, x%.2f)\n", p.generic_key->describe().c_str(),
                          p.generic_error, p.generic_cost);
            out += line;
        }
        for (const std::string& n : p.notes) out += "  note     " + n + "\n";
    }
    return out;
}

// --cost-target NAME or --cost-table FILE: the table they name, or null
// for the built-in one.
Result<std::shared_ptr<const CostTable>> chosen_cost_table(const std::string& target, const std::string& file) {
    if (!target.empty() && !file.empty()) return make_error("--cost-target and --cost-table both name the prices: give one");
    if (!target.empty()) {
        Result<const CostTable*> t = profiling::gpu_cost_table(target);
        if (!t) return make_error("--cost-target: " + t.error().message);
        return std::make_shared<const CostTable>(**t);
    }
    if (file.empty()) return std::shared_ptr<const CostTable>();
    Result<std::vector<std::uint8_t>> bytes = read_file_bounded(file, 64u << 20, "cost table");
    if (!bytes) return make_error("--cost-table: " + bytes.error().message);
    Result<CostTable> t = parse_cost_table(std::string(bytes->begin(), bytes->end()), file);
    if (!t) return make_error("--cost-table: " + t.error().message);
    return std::make_shared<const CostTable>(std::move(*t));
}

std::string prices_line(const CostTable* table) {
    const CostTable* t = table;
    if (!t) {
        Result<const CostTable*> builtin = builtin_cost_table();
        if (!builtin) return "the built-in table (broken: " + builtin.error().message + ")";
        t = *builtin;
    }
    const std::string what = t->prices.empty() ? "frame time relative to normal mapping on " + t->renderer : t->prices;
    return what + " (" + (table ? "table" : "built-in table") + " of " + t->date + ": " + t->command + ")";
}

std::string plans_json(const std::vector<ObjectPlan>& plans, const std::string& scene, const std::string& context,
                       const std::string& prices) {
    nlohmann::json j;
    j["scene"] = scene;
    j["context"] = context;
    if (!prices.empty()) j["prices"] = prices;
    j["objects"] = nlohmann::json::array();
    for (const ObjectPlan& p : plans) {
        nlohmann::json o;
        o["object"] = p.object;
        o["material"] = p.material;
        o["planned"] = p.planned;
        o["asked"] = asked(p);
        o["variant"] = p.key.describe();
        o["technique"] = technique_name(p.key.technique);
        o["max_samples"] = p.key.max_samples;
        o["shadow"] = shadow_mode_name(p.key.shadow);
        o["shadow_samples"] = p.key.shadow_samples;
        o["depth_write"] = p.key.depth_write;
        o["lod"] = p.key.lod;
        o["exact_view"] = p.key.exact_view;
        o["view"] = {{"visible", p.view.visible},
                     {"pixels", p.view.pixels},
                     {"angle_deg", {p.view.angle_min_deg, p.view.angle_max_deg}},
                     {"distance", {p.view.distance_min, p.view.distance_max}},
                     {"mip", {p.view.mip_min, p.view.mip_max}},
                     {"per_vertex_view_error", p.view.per_vertex_view_error},
                     {"lights_above_horizon", p.view.lights_above_horizon}};
        if (p.planned) {
            o["target_texels"] = p.request.max_error_texels;
            o["predicted_error_texels"] = p.predicted_error;
            o["predicted_cost"] = p.predicted_cost;
            if (p.request.shadow != ShadowMode::none) o["shadow_target"] = p.request.shadow_max_error;
            if (p.predicted_shadow_error >= 0.0) o["predicted_shadow_error"] = p.predicted_shadow_error;
            o["prediction_source"] = p.prediction_source;
            if (p.relief.range > 0.0) {
                // What names its calibration file: <hash>-depth<depth>.json.
                const std::string file = calibration_file("", p.relief);
                o["relief"] = {{"hash", hash_hex(p.relief.field_hash)},
                               {"depth_texels", p.relief.depth_texels},
                               {"steepness", p.relief.steepness},
                               {"thinnest_texels", p.relief.thinnest_texels},
                               {"calibration_file", file.substr(1)}};
            }
            if (p.generic_key) {
                o["generic_variant"] = p.generic_key->describe();
                o["generic_predicted_error_texels"] = p.generic_error;
                o["generic_predicted_cost"] = p.generic_cost;
            }
        }
        o["notes"] = p.notes;
        j["objects"].push_back(o);
    }
    return j.dump(2) + "\n";
}

std::string default_calibration_dir() {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    if (xdg && *xdg) return std::string(xdg) + "/parallaxes/calibration";
    const char* home = std::getenv("HOME");
    if (home && *home) return std::string(home) + "/.cache/parallaxes/calibration";
    return "";
}

namespace {

// Why a calibration that matched by name cannot plan, or "" if it can:
// it must describe this relief and hold normal mapping (every cost is
// relative to it) and a technique that traces it, unshadowed.
std::string unusable_calibration(const CostTable& table, const ReliefFeatures& f) {
    int relief = -1;
    for (size_t i = 0; i < table.reliefs.size(); ++i) {
        const ReliefFeatures& r = table.reliefs[i].features;
        if (r.field_hash == f.field_hash && std::fabs(r.depth_texels - f.depth_texels) <= 1e-3 * std::max(1.0, f.depth_texels))
            relief = static_cast<int>(i);
    }
    if (relief < 0) return "it holds no relief with this field's hash and depth";
    bool normal = false, traced = false;
    for (const CostSample& s : table.rows) {
        if (s.relief != relief || s.shadow != ShadowMode::none) continue;
        if (s.technique == Technique::normal) normal = true;
        else if (technique_info(s.technique).options & kOptHeight) traced = true;
    }
    if (!normal) return "it holds no normal-mapping row for this relief (every cost is relative to one)";
    if (!traced) return "it holds no row of a technique that traces the relief";
    return "";
}

}  // namespace

std::function<std::optional<CostTable>(const ReliefFeatures&, std::string&)> calibration_finder(const std::string& dir) {
    if (dir.empty() || dir == "off") return nullptr;
    return [dir](const ReliefFeatures& features, std::string& note) -> std::optional<CostTable> {
        const std::string file = calibration_file(dir, features);
        std::error_code ec;
        if (!std::filesystem::exists(std::filesystem::symlink_status(file, ec))) return std::nullopt;
        const std::string fallback = ": the planner predicts without it";
        // A table of kMaxCostTableRows rows is about 1.6 MB as cost_table_json writes it.
        Result<std::vector<std::uint8_t>> bytes = read_file_bounded(file, 4u << 20, "calibration");
        if (!bytes) {
            note = "calibration not used: " + bytes.error().message + fallback;
            return std::nullopt;
        }
        Result<CostTable> table = parse_cost_table(std::string(bytes->begin(), bytes->end()), file);
        if (!table) {
            note = "calibration not used: " + table.error().message + fallback;
            return std::nullopt;
        }
        const std::string why = unusable_calibration(*table, features);
        if (!why.empty()) {
            note = "calibration not used: " + file + ": " + why + fallback;
            return std::nullopt;
        }
        return std::move(*table);
    };
}

std::string calibration_file(const std::string& dir, const ReliefFeatures& features) {
    char depth[32];
    std::snprintf(depth, sizeof depth, "%.4f", features.depth_texels);
    return dir + "/" + hash_hex(features.field_hash) + "-depth" + depth + ".json";
}

namespace {

std::string texels(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.3g", v);
    return b;
}

}  // namespace

// --verify: the plan drawn, each object's hit error (p95, texels of the
// level sampled) and shadow error (mean |visibility difference|) measured
// against the depth-composited exact reference, beside the prediction and
// the target. Returns 1 when a target is missed.
namespace {

// One candidate a planned object could have been drawn with.
struct Tried {
    std::string name;
    double hit = 0.0, shadow = 0.0;  // measured
    double time_ratio = 0.0;         // its frame time / the plan's, median of rounds
    bool within = false;
};

// Every technique and sample count the context runs, drawn in the plan's
// place for object `index` (the plan's other options kept), measured
// against the same references, and timed against the plan in interleaved
// rounds.
Result<std::vector<Tried>> try_candidates(Renderer& planned, const SceneDesc& scene, size_t index, int width, int height,
                                          const std::map<ShadowMode, reference::ReferenceImage>& truths) {
    const ObjectPlan& plan = planned.reports()[index].plan;
    const MaterialDesc* m = scene.find_material(scene.objects[index].material);
    if (!m || !m->effects) return std::vector<Tried>{};
    const Caps& caps = planned.caps();
    RendererOptions options = program_renderer_options();
    Result<std::unique_ptr<Renderer>> other = Renderer::create(options);
    if (!other) return other.error();
    Status loaded = (*other)->load(planned.prepared());
    if (!loaded) return loaded.error();
    auto target = OffscreenTarget::create(width, height);
    if (!target) return target.error();
    const int rounds = 5;
    std::vector<Tried> out;
    const std::vector<int> counts = sample_grid();
    for (Technique t : {Technique::normal, Technique::parallax, Technique::offset_limited, Technique::steep,
                        Technique::pom, Technique::relief, Technique::maxmip}) {
        const TechniqueInfo& info = technique_info(t);
        if (!why_technique_cannot_run(t, caps).empty()) continue;
        const bool sampled = info.options & kOptSamples;
        for (int n : sampled ? counts : std::vector<int>{0}) {
            if (sampled && n > info.max_samples_limit) continue;
            MaterialDesc named = *m;
            named.technique = plan.options;
            (void)force_technique(named, t);  // what t cannot draw is dropped, not refused
            if (sampled) named.technique.min_samples = named.technique.max_samples = n;
            if (!(info.options & kOptShadow)) named.technique.shadow = ShadowMode::none;
            if (!(info.options & kOptDepth)) named.technique.depth_write = false;
            Status replaced = (*other)->replace_material(named);
            if (!replaced) continue;  // the context cannot run it (said by the plan's own checks)
            Result<int> viewed = (*other)->set_view(scene.camera, width, height);
            if (!viewed) return viewed.error();
            Result<SurfaceImage> drawn = capture_surfaces(**other, width, height);
            if (!drawn) return drawn.error();
            Tried c;
            c.name = technique_name(t) + (sampled ? " x" + std::to_string(n) : std::string());
            Result<reference::ObjectError> e = reference::compare_object(*drawn, truths.at(ShadowMode::none), static_cast<int>(index));
            if (!e) return e.error();
            c.hit = e->level_error_p95;
            c.within = c.hit <= m->effects->max_error_texels;
            if (m->effects->shadow != ShadowMode::none) {
                Result<reference::ObjectError> s = reference::compare_object(*drawn, truths.at(m->effects->shadow), static_cast<int>(index));
                if (!s) return s.error();
                c.shadow = s->visibility_error_mean;
                c.within = c.within && c.shadow <= m->effects->shadow_max_error;
            }
            // Time against the plan, both warm, interleaved.
            Result<profiling::InterleavedTimes> timed = profiling::time_interleaved(
                [&] { return planned.draw(target->target()); }, [&] { return (*other)->draw(target->target()); }, rounds);
            if (!timed) return timed.error();
            std::vector<double> ratios = timed->ratios;
            std::sort(ratios.begin(), ratios.end());
            c.time_ratio = ratios[ratios.size() / 2];
            std::fprintf(stderr, "verify: candidate %s: hit %.3g, x%.2f of the plan's time\n", c.name.c_str(), c.hit, c.time_ratio);
            out.push_back(c);
        }
    }
    return out;
}

}  // namespace

// --candidates: every candidate drawn and timed against the plan, and the
// cheapest that measures within the targets.
Status print_candidates(Renderer& renderer, const SceneDesc& scene, size_t i, int width, int height,
                        const std::map<ShadowMode, reference::ReferenceImage>& truths, ShadowMode asked) {
    Result<std::vector<Tried>> tried = try_candidates(renderer, scene, i, width, height, truths);
    if (!tried) return make_error("--candidates: " + tried.error().message);
    const Tried* cheapest = nullptr;
    for (const Tried& c : *tried) {
        std::printf("    candidate %-18s hit %-8s%s x%.2f of the plan's time%s\n", c.name.c_str(), texels(c.hit).c_str(),
                    asked != ShadowMode::none ? (" shadow " + texels(c.shadow)).c_str() : "", c.time_ratio,
                    c.within ? ", within the targets" : "");
        if (c.within && (!cheapest || c.time_ratio < cheapest->time_ratio)) cheapest = &c;
    }
    if (cheapest)
        std::printf("    cheapest within the targets: %s at x%.2f of the plan's time: the plan spends %.2fx what it must\n",
                    cheapest->name.c_str(), cheapest->time_ratio, 1.0 / std::max(cheapest->time_ratio, 1e-9));
    else
        std::printf("    no candidate measured within the targets\n");
    return {};
}

// The exact reference of every shadow mode the scene asks for, composited by depth.
Result<std::map<ShadowMode, reference::ReferenceImage>> verify_references(Renderer& renderer, const SceneDesc& scene,
                                                                          int width, int height) {
    std::set<ShadowMode> modes = {ShadowMode::none};
    for (const MaterialDesc& m : scene.materials)
        if (m.effects) modes.insert(m.effects->shadow);
        else modes.insert(m.technique.shadow);
    std::map<ShadowMode, reference::ReferenceImage> truths;
    for (ShadowMode mode : modes) {
        reference::ReferenceOptions ro;
        ro.shadow = mode;
        ro.depth_composite = true;
        std::fprintf(stderr, "verify: exact reference, shadow %s ...\n", shadow_mode_name(mode));
        Result<reference::ReferenceImage> truth = reference::render_reference(*renderer.prepared(), width, height, ro);
        if (!truth) return truth.error();
        truths.emplace(mode, std::move(*truth));
    }
    return truths;
}

int verify_plan(Renderer& renderer, const SceneDesc& scene, int width, int height, bool candidates) {
    Result<int> viewed = renderer.set_view(scene.camera, width, height);
    if (!viewed) return fail(in_scene_file(scene.source, viewed.error().message));
    Result<SurfaceImage> drawn = capture_surfaces(renderer, width, height);
    if (!drawn) return fail(in_scene_file(scene.source, "--verify: " + drawn.error().message));
    Result<std::map<ShadowMode, reference::ReferenceImage>> references = verify_references(renderer, scene, width, height);
    if (!references) return fail(in_scene_file(scene.source, "--verify: " + references.error().message));
    const std::map<ShadowMode, reference::ReferenceImage>& truths = *references;
    int missed = 0;
    std::printf("verify     %dx%d against the depth-composited exact reference; hit error p95 in texels of the "
                "level sampled, shadow error mean |visibility difference|\n",
                width, height);
    const std::vector<DrawReport>& reports = renderer.reports();
    for (size_t i = 0; i < scene.objects.size() && i < reports.size(); ++i) {
        const ObjectPlan& plan = reports[i].plan;
        const MaterialDesc* m = scene.find_material(scene.objects[i].material);
        const int index = static_cast<int>(i);
        Result<reference::ObjectError> e = reference::compare_object(*drawn, truths.at(ShadowMode::none), index);
        if (!e) return fail(e.error().message);
        std::string line = "  " + scene.objects[i].name + " (" + reports[i].variant.describe() + "): ";
        if (e->pixels == 0) {
            std::printf("%snot in view: nothing to measure\n", line.c_str());
            continue;
        }
        const bool has_target = m && m->effects && m->effects->parallax;
        const double target = has_target ? m->effects->max_error_texels : -1.0;
        line += "hit " + texels(e->level_error_p95) + " measured";
        if (plan.predicted_error >= 0.0) line += ", " + texels(plan.predicted_error) + " predicted";
        bool met = true;
        if (has_target) {
            met = e->level_error_p95 <= target;
            line += ", target " + texels(target) + (met ? ": met" : ": MISSED");
        } else {
            line += m && !m->effects ? " (technique named: no target)" : " (no parallax asked)";
        }
        const ShadowMode asked = m ? (m->effects ? m->effects->shadow : m->technique.shadow) : ShadowMode::none;
        if (asked != ShadowMode::none) {
            Result<reference::ObjectError> s = reference::compare_object(*drawn, truths.at(asked), index);
            if (!s) return fail(s.error().message);
            line += "; shadow " + texels(s->visibility_error_mean) + " measured";
            if (plan.predicted_shadow_error >= 0.0) line += ", " + texels(plan.predicted_shadow_error) + " predicted";
            if (m->effects) {
                const bool shadow_met = s->visibility_error_mean <= m->effects->shadow_max_error;
                line += ", target " + texels(m->effects->shadow_max_error) + (shadow_met ? ": met" : ": MISSED");
                met = met && shadow_met;
            }
        }
        if (!met) ++missed;
        std::printf("%s (%ld px)\n", line.c_str(), e->pixels);
        if (candidates && m && m->effects) {
            Status shown = print_candidates(renderer, scene, i, width, height, truths, asked);
            if (!shown) return fail(in_scene_file(scene.source, shown.error().message));
        }
    }
    if (missed) {
        std::fprintf(stderr, "parallax: plan --verify: %d object(s) missed their target\n", missed);
        return 1;
    }
    std::printf("verify     every target met\n");
    return 0;
}

}  // namespace px::tools
