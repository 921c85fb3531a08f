// The effect planner: per object and frame, what the camera sees of the
// surface, which effects can matter there, and the cheapest candidate
// variant whose predicted error meets the material's target.
//
// Prediction (docs/planner.md): the cost table holds, per reference relief,
// view angle and candidate, the 95th percentile hit error in base texels
// and the time relative to normal mapping. A material is predicted from the
// table relief nearest in character (thinnest feature, steepness), its error
// scaled by the ratio of relief depths in texels; or from its own
// calibration. Each visible surface point gets the error at its view angle
// (linear between the table's angles), plus what the per-vertex view vector
// adds there, divided by the texels per pixel where the texture is minified
// (the error in texels of the level sampled); the object's prediction is
// the 95th percentile of that over its pixels.
#include "planner_detail.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "parallaxes/core/counters.h"
#include "parallaxes/core/text.h"

namespace px {

using namespace planning;


ScenePlanner::~ScenePlanner() = default;

std::unique_ptr<ScenePlanner> ScenePlanner::make_empty() {
    std::unique_ptr<ScenePlanner> p(new ScenePlanner());
    p->impl_ = std::make_unique<Impl>();
    return p;
}

MaterialRelief material_relief(const HeightField& traced_8bit, const MaterialDesc& material) {
    MaterialRelief r;
    r.layout.packed_height = material.pack_height_in_normal_alpha;
    r.traced_width = traced_8bit.width;
    r.traced_height = traced_8bit.height;
    r.features = measure_relief(traced_8bit, material.height_scale);
    if (material.effects && material.effects->parallax && material.height_scale > 0.0f && r.features.range > 0.0)
        r.search = std::make_shared<const SearchModel>(
            simulate_searches(traced_8bit, material.height_scale, material.polygon_height()));
    return r;
}

namespace {

// One planner of either kind: `meshes` are the objects' meshes in scene
// order, null where the description's own (undisplaced) mesh is built here.
Result<std::unique_ptr<ScenePlanner>> make_planner(const SceneDesc& scene, const Caps& caps,
                                                   std::vector<MaterialRelief> reliefs, PlannerOptions options,
                                                   const std::vector<const Mesh*>& meshes);

}  // namespace

Result<std::unique_ptr<ScenePlanner>> ScenePlanner::create(const PreparedScene& scene, const Caps& caps,
                                                           PlannerOptions options, std::vector<MaterialRelief> reliefs) {
    reliefs.resize(scene.materials.size());
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        if (reliefs[i].traced_width > 0) continue;  // measured before
        const MaterialImages& images = scene.materials[i]->images;
        reliefs[i] = material_relief(images.traced, scene.desc.materials[i]);
        reliefs[i].layout = images.layout;
    }
    std::vector<const Mesh*> meshes;
    for (const auto& o : scene.objects) meshes.push_back(&o->mesh);
    return make_planner(scene.desc, caps, std::move(reliefs), std::move(options), meshes);
}

Result<std::unique_ptr<ScenePlanner>> ScenePlanner::create(const SceneDesc& scene, const Caps& caps,
                                                           std::vector<MaterialRelief> reliefs,
                                                           PlannerOptions options) {
    return make_planner(scene, caps, std::move(reliefs), std::move(options), {});
}

const std::vector<MaterialRelief>& ScenePlanner::reliefs() const { return impl_->reliefs; }

Result<std::unique_ptr<FramePlanner>> effect_planner(const PreparedScene& scene, const Caps& caps,
                                                     const PlannerOptions& options, std::vector<MaterialRelief> reliefs) {
    Result<std::unique_ptr<ScenePlanner>> p = ScenePlanner::create(scene, caps, options, std::move(reliefs));
    if (!p) return p.error();
    return std::unique_ptr<FramePlanner>(std::move(*p));
}

namespace {

Result<std::unique_ptr<ScenePlanner>> make_planner(const SceneDesc& scene, const Caps& caps,
                                                   std::vector<MaterialRelief> reliefs, PlannerOptions options,
                                                   const std::vector<const Mesh*>& meshes) {
    if (reliefs.size() != scene.materials.size())
        return make_error("planner: " + std::to_string(reliefs.size()) + " reliefs for " +
                          std::to_string(scene.materials.size()) + " materials");
    if (!meshes.empty() && meshes.size() != scene.objects.size())
        return make_error("planner: " + std::to_string(meshes.size()) + " meshes for " +
                          std::to_string(scene.objects.size()) + " objects");
    std::unique_ptr<ScenePlanner> p = ScenePlanner::make_empty();
    ScenePlanner::Impl& m = p->impl();
    m.scene = scene;
    m.caps = caps;
    m.reliefs = std::move(reliefs);
    if (options.table) {
        m.generic = *options.table;
    } else {
        Result<const CostTable*> builtin = builtin_cost_table();
        if (!builtin) return builtin.error();
        m.generic = **builtin;
    }
    m.generic_curves = curves_of(m.generic);
    m.model_search_curves();
    m.find_calibrations(options);
    m.survey_objects(meshes);
    if (Status s = m.plan_named_materials(); !s) return s.error();
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        const size_t mi = scene.material_index(scene.objects[i].material);
        m.outlines.push_back(mi < scene.materials.size()
                                 ? outline_request(scene.objects[i], scene.materials[mi], m.units_per_uv[i])
                                 : OutlineRequest{});
    }
    return p;
}

// The generic curve of search model curve `sc` on table relief `nearest`
// (maxmip: at whatever step bound the table measured), with the sample
// count it was measured at.
std::pair<const Curve*, int> generic_cost_curve(const ScenePlanner::Impl::Curves& generic, int nearest,
                                                const SearchCurve& sc) {
    for (const auto& [key, c] : generic) {
        const auto& [relief, technique, n, shadow, shadow_samples, elevation] = key;
        (void)shadow_samples;
        (void)elevation;
        if (relief != nearest || technique != sc.technique || shadow != ShadowMode::none) continue;
        const bool steps = technique_info(technique).options & kOptSteps;
        if (n != sc.samples && !steps) continue;
        return {&c, n};
    }
    return {nullptr, sc.samples};
}

}  // namespace

// Each search model as a one-relief table: the simulated error with the
// margin, the cost the generic table measured for the candidate on its
// nearest relief (a candidate's time depends on its samples and the view
// far more than on the relief), at the model's angles.
void ScenePlanner::Impl::model_search_curves() {
    model_tables.resize(reliefs.size());
    model_curves.resize(reliefs.size());
    for (size_t mi = 0; mi < reliefs.size(); ++mi) {
        const MaterialRelief& r = reliefs[mi];
        if (!r.search || r.search->angles.empty()) continue;
        const int nearest = generic_source(r).relief;
        if (nearest < 0) continue;
        Curves curves;
        for (const SearchCurve& sc : r.search->curves) {
            if (sc.error.size() != r.search->angles.size() || sc.upper.size() != r.search->angles.size()) continue;
            const auto [cost, samples] = generic_cost_curve(generic_curves, nearest, sc);
            if (!cost || cost->angles.empty()) continue;
            Curve c;
            c.angles = r.search->angles;
            if (sc.levels.size() == c.angles.size()) c.levels = sc.levels;
            if (sc.sector_levels.size() == c.angles.size()) c.sector_levels = sc.sector_levels;
            for (size_t k = 0; k < c.angles.size(); ++k) {
                // The margin without its floor here; the floor (texels of
                // the level sampled) after the division by texels per
                // pixel, in predict_error.
                c.error.push_back(predicted_with_margin(sc.technique, sc.error[k], sc.upper[k]) -
                                  search_margin(sc.technique).floor);
                c.cost.push_back(interpolate(cost->angles, cost->cost, c.angles[k]));
                c.visibility.push_back(0.0);
            }
            curves.emplace(CurveKey{0, sc.technique, samples, ShadowMode::none, 0, 0}, std::move(c));
        }
        CostTable t;
        t.date = generic.date;
        t.renderer = generic.renderer;
        t.version = generic.version;
        t.reliefs.push_back({"search model", r.features});
        model_tables[mi] = std::move(t);
        model_curves[mi] = std::move(curves);
    }
}

void ScenePlanner::Impl::find_calibrations(const PlannerOptions& options) {
    if (options.calibrations) calibrations = *options.calibrations;
    calibration_notes.resize(reliefs.size());
    if (options.find_calibration) {
        // Once per relief: the field and its depth (two materials may share
        // a height map at different depths, and a calibration is of both).
        std::vector<std::pair<std::uint64_t, double>> asked;
        for (size_t mi = 0; mi < reliefs.size() && mi < scene.materials.size(); ++mi) {
            const ReliefFeatures& f = reliefs[mi].features;
            if (!(f.range > 0.0) || !scene.materials[mi].effects || !scene.materials[mi].effects->parallax) continue;
            const auto same = [&](const std::pair<std::uint64_t, double>& a) {
                return a.first == f.field_hash &&
                       std::fabs(a.second - f.depth_texels) <= 1e-3 * std::max(1.0, f.depth_texels);
            };
            if (std::find_if(asked.begin(), asked.end(), same) != asked.end()) continue;
            asked.emplace_back(f.field_hash, f.depth_texels);
            std::optional<CostTable> found = options.find_calibration(f, calibration_notes[mi]);
            if (found) calibrations.push_back(std::move(*found));
        }
    }
    for (const CostTable& c : calibrations) {
        calibration_curves.push_back(curves_of(c));
        // A generic table priced otherwise than by frame time (a GPU
        // compiler's cycles) prices every candidate: a calibration's times
        // are this renderer's, in another unit.
        if (!c.costs_measured || !generic.prices.empty())
            price_from_generic(c, calibration_curves.back(), generic, generic_curves);
    }
}

void ScenePlanner::Impl::survey_objects(const std::vector<const Mesh*>& meshes) {
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        if (!meshes.empty()) {
            units_per_uv.push_back(meshes[i]->units_per_uv);
            surveys.push_back(survey_mesh(*meshes[i]));
            continue;
        }
        const Mesh mesh = build_object_mesh(scene.objects[i].mesh);
        units_per_uv.push_back(mesh.units_per_uv);
        surveys.push_back(survey_mesh(mesh));
    }
}

Status ScenePlanner::Impl::plan_named_materials() {
    for (size_t mi = 0; mi < scene.materials.size(); ++mi) {
        const MaterialDesc& material = scene.materials[mi];
        named_plans.emplace_back();
        if (material.effects) continue;
        Result<VariantPlan> named = plan_variant(material, caps, reliefs[mi].traced_width, reliefs[mi].traced_height);
        if (!named) return with_context("material '" + echo(material.name) + "'", named.error());
        named_plans.back() = std::move(*named);
    }
    return {};
}

PlanView PlanView::from_camera(const CameraDesc& camera, int width, int height) {
    PlanView v;
    v.width = width;
    v.height = height;
    const float aspect = height > 0 ? static_cast<float>(width) / static_cast<float>(height) : 1.0f;
    v.view = glm::lookAt(camera.position, camera.target, camera.up);
    v.projection = glm::perspective(glm::radians(camera.fov_y_deg), aspect, camera.near_plane, camera.far_plane);
    return v;
}

ScenePlanner::Impl::Source ScenePlanner::Impl::generic_source(const MaterialRelief& r) const {
    Source s;
    s.table = &generic;
    s.curves = &generic_curves;
    std::vector<bool> eligible(generic.reliefs.size(), true);
    s.relief = nearest_relief(generic, r.features, eligible);
    if (s.relief >= 0) {
        const ReliefFeatures& t = generic.reliefs[static_cast<size_t>(s.relief)].features;
        s.depth_scale = t.depth_texels > 0.0 ? r.features.depth_texels / t.depth_texels : 1.0;
        s.label = "table '" + generic.reliefs[static_cast<size_t>(s.relief)].name + "' (" + describe(t) +
                  ") x" + fmt("%.2f", s.depth_scale) + " depth";
    }
    return s;
}

std::optional<ScenePlanner::Impl::Source> ScenePlanner::Impl::model_source(size_t mi) const {
    if (mi >= model_tables.size() || !model_tables[mi] || model_curves[mi].empty()) return std::nullopt;
    const MaterialRelief& r = reliefs[mi];
    Source s;
    s.table = &*model_tables[mi];
    s.curves = &model_curves[mi];
    s.relief = 0;
    s.simulated = true;
    const int nearest = generic_source(r).relief;
    s.label = "search model on this relief (" + describe(r.features) + "; " + std::to_string(r.search->rays) +
              " rays per angle and azimuth sector; margin fitted by `parallax bench --search-model`; costs from table '" +
              (nearest >= 0 ? generic.reliefs[static_cast<size_t>(nearest)].name : std::string("?")) + "')";
    return s;
}

std::optional<ScenePlanner::Impl::Source> ScenePlanner::Impl::calibrated_source(const MaterialRelief& r,
                                                                               double angle_max_deg,
                                                                               std::string* skipped) const {
    for (size_t c = 0; c < calibrations.size(); ++c)
        for (size_t i = 0; i < calibrations[c].reliefs.size(); ++i) {
            const ReliefFeatures& f = calibrations[c].reliefs[i].features;
            if (f.field_hash != r.features.field_hash ||
                std::fabs(f.depth_texels - r.features.depth_texels) > 1e-3 * std::max(1.0, f.depth_texels))
                continue;
            // Usable: normal mapping's curve (every cost is relative to it)
            // and at least one technique that traces the relief.
            bool normal = false, traced = false;
            for (const auto& [key, curve] : calibration_curves[c]) {
                const auto& [relief, technique, samples, shadow, shadow_samples, elevation] = key;
                (void)samples;
                (void)shadow_samples;
                (void)elevation;
                if (relief != static_cast<int>(i) || shadow != ShadowMode::none || curve.angles.empty()) continue;
                if (technique == Technique::normal) normal = true;
                else if (technique_info(technique).options & kOptHeight) traced = true;
            }
            const std::string fallback = "the planner predicts without it";
            if (!normal || !traced) {
                if (skipped)
                    *skipped = "the calibration of this relief (" + hash_hex(f.field_hash) + ", " + calibrations[c].date +
                               ") holds no " + (normal ? "technique that traces the relief" : "normal-mapping row") +
                               " to plan with: " + fallback;
                continue;
            }
            // What it measured: its timings are this renderer's only, its
            // errors at the view angles it was run at (past them a curve is
            // clamped, not known).
            if (!calibrations[c].renderer.empty() && !caps.renderer.empty() && calibrations[c].renderer != caps.renderer) {
                if (skipped)
                    *skipped = "the calibration of this relief (" + hash_hex(f.field_hash) + ") was measured on '" +
                               echo(calibrations[c].renderer) + "', not this renderer ('" + echo(caps.renderer) +
                               "'): " + fallback;
                continue;
            }
            double measured_max = 0.0;
            for (const CostSample& row : calibrations[c].rows)
                if (row.relief == static_cast<int>(i) && row.shadow == ShadowMode::none)
                    measured_max = std::max(measured_max, row.angle_deg);
            if (angle_max_deg > measured_max + 1.0) {
                if (skipped)
                    *skipped = "the calibration of this relief (" + hash_hex(f.field_hash) + ") measured view angles up to " +
                               fmt("%.1f", measured_max) + " degrees; this view reaches " + fmt("%.1f", angle_max_deg) +
                               ": " + fallback;
                continue;
            }
            Source s;
            s.table = &calibrations[c];
            s.curves = &calibration_curves[c];
            s.relief = static_cast<int>(i);
            s.depth_scale = 1.0;
            s.label = "calibrated on this relief (" + hash_hex(f.field_hash) + ", " + calibrations[c].date + ")";
            if (!calibrations[c].costs_measured || !generic.prices.empty()) {
                std::vector<bool> all(generic.reliefs.size(), true);
                const int near = nearest_relief(generic, f, all);
                s.label += "; errors measured, costs from table '" +
                           (near >= 0 ? generic.reliefs[static_cast<size_t>(near)].name : std::string("?")) + "'";
            }
            return s;
        }
    return std::nullopt;
}

Result<std::vector<ObjectPlan>> ScenePlanner::plan(const CameraDesc& camera, int width, int height) const {
    if (width < 1 || height < 1)
        return make_error("planner: image size " + std::to_string(width) + "x" + std::to_string(height) + " is empty");
    return plan(PlanView::from_camera(camera, width, height));
}

Result<std::vector<ObjectPlan>> ScenePlanner::plan(const PlanView& frame) const {
    const Impl& m = *impl_;
    if (Status s = check_plan_view(frame, m.scene); !s) return s.error();
    const size_t n = m.scene.objects.size();
    Impl::FrameViews views;
    views.views.resize(n);
    views.points.resize(n);
    views.screen_boxes.resize(n);
    views.world_boxes.resize(n);
    for (size_t i = 0; i < n; ++i)
        views.views[i] = m.view_object(i, frame, views.points[i], views.screen_boxes[i], views.world_boxes[i]);
    counters::count(counters::Step::object_plan, n);
    std::vector<ObjectPlan> plans;
    plans.reserve(n);
    for (size_t i = 0; i < n; ++i) {
        const ObjectDesc& object = m.scene.objects[i];
        const size_t mi = m.scene.material_index(object.material);
        if (mi >= m.scene.materials.size())
            return make_error("object '" + echo(object.name) + "': unknown material '" + echo(object.material) + "'");
        const MaterialDesc& material = m.scene.materials[mi];
        const glm::mat4 model = object_model(frame, m.scene, i);
        // A curved silhouette only where the object's contour can be on screen.
        const bool silhouette = silhouette_on_screen(m.outlines[i], object, material, model, frame);
        Result<ObjectPlan> p = m.plan_object(i, views, silhouette);
        if (!p) return p.error();
        plan_outlines(*p, m.outlines[i], object, material, m.reliefs[mi].layout, silhouette,
                      bounded_on_screen(m.outlines[i], object, model, frame));
        plans.push_back(std::move(*p));
    }
    return plans;
}

const VariantPlan* ScenePlanner::material_plan(size_t i) const {
    return i < impl_->named_plans.size() && impl_->named_plans[i] ? &*impl_->named_plans[i] : nullptr;
}

std::vector<std::pair<size_t, VariantKey>> ScenePlanner::named_variants() const {
    const Impl& m = *impl_;
    std::vector<std::pair<size_t, VariantKey>> out;
    for (size_t i = 0; i < m.scene.objects.size(); ++i) {
        const size_t mi = m.scene.material_index(m.scene.objects[i].material);
        if (mi >= m.named_plans.size() || !m.named_plans[mi]) continue;
        out.emplace_back(i, named_object_key(*m.named_plans[mi], m.outlines[i], m.scene.objects[i], m.reliefs[mi].layout));
    }
    return out;
}

}  // namespace px
