// One object's plan this frame (docs/planner.md): normal mapping where no
// relief can show, else the sources of prediction, the effects the scene
// or context rule out, the shadow's sample count, the cheapest candidate
// meeting the target, and depth correction where other geometry meets the
// relief. Each step says what it decided in the plan's notes.
#include "planner_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "parallaxes/core/text.h"

namespace px {

using namespace planning;

namespace {

// Normal mapping, with `why` and what it drops.
ObjectPlan finish_normal(ObjectPlan plan, std::string why) {
    plan.key.technique = Technique::normal;
    plan.options.technique = Technique::normal;
    plan.notes.push_back(std::move(why));
    if (plan.request.shadow != ShadowMode::none)
        plan.notes.push_back(std::string("shadow=") + shadow_mode_name(plan.request.shadow) +
                             " dropped: normal mapping traces no relief to cast it");
    plan.key = plan.key.canonical();
    return plan;
}

// Why no relief can show (normal mapping draws it), or empty.
std::string why_no_relief(const EffectRequest& request, const MaterialDesc& material, const MaterialRelief& relief,
                          const ObjectView& view) {
    if (!request.parallax) return "normal mapping: the material asks for no parallax";
    if (!(material.height_scale > 0.0f)) return "normal mapping: height_scale is 0, so there is no relief to trace";
    if (!(relief.features.range > 0.0)) return "normal mapping: the height field is flat, so there is no relief to trace";
    if (!view.visible) return "normal mapping: no part of the surface faces the camera inside the view";
    return {};
}

// The key and options of a material that declares effects, before any
// technique is chosen: this context's precision and derivatives, normal
// mapping, the request's LOD band.
void start_effect_plan(ObjectPlan& plan, const MaterialDesc& material, const MaterialRelief& relief, const Caps& caps) {
    const EffectRequest& request = *material.effects;
    plan.planned = true;
    plan.request = request;
    plan.relief = relief.features;
    VariantKey& key = plan.key;
    key.es_major = static_cast<std::uint8_t>(caps.es_major);
    key.no_fragment_highp = caps.es_major < 3 && !caps.fragment_highp;
    key.no_derivatives = !caps.derivatives();
    key.packed_height = material.pack_height_in_normal_alpha;
    key.technique = Technique::normal;
    TechniqueOptions& options = plan.options;
    options = TechniqueOptions{};
    options.technique = Technique::normal;
    options.lod_threshold = request.lod_threshold;
    options.lod_band = request.lod_band;
}

// What the per-vertex view vector would add over the object (p95, texels).
double per_vertex_view_error(const MaterialRelief& relief, const std::vector<PointView>& points) {
    std::vector<std::pair<double, double>> added;
    for (const PointView& p : points)
        added.emplace_back(relief.features.depth_texels * p.pv_parallax / std::max(1.0, p.rho), p.weight);
    return weighted_p95(added);
}

std::string shadow_dropped(ShadowMode mode, const std::string& why) {
    return std::string("shadow=") + shadow_mode_name(mode) + " dropped: " + why;
}

// Every visible pixel past the LOD threshold: normal mapping, where its
// error holds (auto) or whenever asked (on); the reason, with the plan's
// prediction set, or empty. Not where a shadow is wanted and could fall:
// normal mapping casts none, and the shadow's own target would be missed.
std::string why_normal_past_lod(ObjectPlan& plan, ObjectPredictor& predictor, const Source& source, bool lod_possible,
                                bool want_shadow) {
    const EffectRequest& request = plan.request;
    const ObjectView& view = plan.view;
    if (!lod_possible || !(view.mip_min >= request.lod_threshold)) return {};
    const Prediction normal = predictor.predict(source, {Technique::normal, 0, true, false});
    if (request.lod_fade != EffectSwitch::on &&
        !(normal.known && normal.error <= request.max_error_texels && !want_shadow))
        return {};
    plan.predicted_error = normal.error;
    plan.predicted_cost = 1.0;
    return "normal mapping: every visible pixel samples mip level " + fmt("%.1f", view.mip_min) +
           " or coarser, past the lod_fade threshold " + fmt("%g", request.lod_threshold) + " (predicted " +
           fmt("%.3g", normal.error) + " texels)";
}

// The hit target: with a shadow, no looser than POM x32's prediction here
// (the shadow rows were measured over POM x32's hits: their prediction
// holds for a primary search at least as accurate as that).
double hit_target(ObjectPredictor& predictor, const Source& source, const EffectRequest& request, bool want_shadow,
                  std::vector<std::string>& notes) {
    double target = request.max_error_texels;
    if (!want_shadow) return target;
    const double pom32 = predictor.predict_error(source, {Technique::pom, 32, true, false});
    if (std::isfinite(pom32) && pom32 < target) {
        target = pom32;
        notes.push_back("hit target tightened to " + fmt("%.3g", pom32) +
                        " texels (POM x32's here): the shadow's prediction holds for hits as accurate as "
                        "those its table rows were measured with");
    }
    return target;
}

// Why no candidate meets the target (the best one's prediction, and the
// fp16 uv's floor where that is what stops it).
Error no_candidate(const Choice& choice, const std::string& who, const std::string& field_path,
                   const EffectRequest& request, const ObjectView& view, const Caps& caps, const MaterialRelief& relief,
                   double uv_floor, const std::string& source_label) {
    if (choice.best_name.empty())
        return make_error(who + ": the cost table (" + source_label + ") measured no candidate this context runs");
    return make_error(who + ": " + field_path + ".parallax.max_error_texels: " + fmt("%g", request.max_error_texels) +
                      " texels is below what any technique reaches on this relief at view angles up to " +
                      fmt("%.1f", view.angle_max_deg) + " degrees on this OpenGL ES " + std::to_string(caps.es_major) +
                      " context (best: " + choice.best_name + ", predicted " + fmt("%.3g", choice.best_error) +
                      " texels)" +
                      (uv_floor > 0.0 && choice.best_error <= uv_floor
                           ? "; without fragment highp the uv is fp16, which places no hit closer than " +
                                 fmt("%.3g", uv_floor) + " texels on this " + std::to_string(relief.traced_width) + "x" +
                                 std::to_string(relief.traced_height) + " height map"
                           : std::string()));
}

// The key and options of candidate `pick`.
void apply_pick(VariantKey& key, TechniqueOptions& options, const Candidate& pick) {
    const TechniqueInfo& info = technique_info(pick.technique);
    key.technique = pick.technique;
    options.technique = pick.technique;
    if (info.options & kOptSamples) {
        key.max_samples = static_cast<std::uint16_t>(pick.samples);
        options.min_samples = options.max_samples = pick.samples;  // the table measured min = max
    }
    if (info.options & kOptSteps) {
        key.max_samples = static_cast<std::uint16_t>(pick.samples);
        options.max_steps = pick.samples;
    }
    if (info.options & kOptRefine) key.refine_steps = static_cast<std::uint8_t>(options.refine_steps);
    key.exact_view = pick.exact_view;
    options.exact_view = pick.exact_view;
    key.lod = pick.lod;
    options.lod = pick.lod;
}

// The notes on the pick: why it, its view vector, its LOD fade.
void note_pick(ObjectPlan& plan, const Candidate& pick, const Prediction& chosen, double target, bool lod_possible,
               double fade_start, const std::string& source_label) {
    const EffectRequest& request = plan.request;
    const ObjectView& view = plan.view;
    const TechniqueInfo& info = technique_info(pick.technique);
    const std::string target_text =
        target < request.max_error_texels
            ? fmt("%.3g", target) + " texels (the hit target tightened for the shadow; asked " +
                  fmt("%g", request.max_error_texels) + ")"
            : fmt("%g", request.max_error_texels) + " texels";
    plan.notes.push_back(candidate_name(pick) + ": the cheapest candidate predicted within " + target_text + " (" +
                         fmt("%.3g", chosen.error) + ", x" + fmt("%.2f", chosen.cost) + " normal mapping per pixel; " +
                         source_label + ")");
    if (info.options & kOptHeight && !info.always_exact_view)
        plan.notes.push_back(pick.exact_view
                                 ? "view vector exact per pixel: the per-vertex normalisation would add up to " +
                                       fmt("%.3g", view.per_vertex_view_error) + " texels on these triangles"
                                 : "view vector normalised per vertex (the PowerVR whitepaper's saving): it adds " +
                                       fmt("%.3g", view.per_vertex_view_error) + " texels here, within the target");
    if (pick.lod)
        plan.notes.push_back("lod_fade on: the surface reaches mip level " + fmt("%.1f", view.mip_max) +
                             ", past the fade's start at " + fmt("%g", fade_start));
    else if (request.lod_fade != EffectSwitch::off && lod_possible && (info.options & kOptLod))
        plan.notes.push_back(view.mip_max <= fade_start
                                 ? "lod_fade not needed: the finest pixels sample mip level " + fmt("%.1f", view.mip_max) +
                                       ", before the fade starts at " + fmt("%g", fade_start)
                                 : "lod_fade off: fading would not lower the cost within the target");
}

void apply_shadow(ObjectPlan& plan, const ShadowChoice& shadow) {
    const EffectRequest& request = plan.request;
    plan.key.shadow = request.shadow;
    plan.key.shadow_samples = static_cast<std::uint8_t>(shadow.samples);
    plan.options.shadow = request.shadow;
    plan.options.shadow_samples = shadow.samples;
    plan.predicted_shadow_error = shadow.error;
    plan.notes.push_back(std::string("shadow=") + shadow_mode_name(request.shadow) + " x" +
                         std::to_string(shadow.samples) + ": the fewest shadow samples predicted within " +
                         fmt("%g", request.shadow_max_error) + " (" + fmt("%.3g", shadow.error) + ")");
}

}  // namespace

Result<ObjectPlan> ScenePlanner::Impl::plan_object(size_t oi, const FrameViews& frame, bool silhouette_on_screen) const {
    const ObjectDesc& object = scene.objects[oi];
    const size_t mi = scene.material_index(object.material);
    if (mi >= scene.materials.size())
        return make_error("object '" + echo(object.name) + "': unknown material '" + echo(object.material) + "'");
    const MaterialDesc& material = scene.materials[mi];
    const MaterialRelief& relief = reliefs[mi];
    const std::string field_path = "materials[" + std::to_string(mi) + "].effects";
    const std::string who = "object '" + echo(object.name) + "' (material '" + echo(material.name) + "')";

    ObjectPlan plan;
    plan.object = object.name;
    plan.material = material.name;
    plan.view = frame.views[oi];
    plan.options = material.technique;
    if (!material.effects) {  // its plan_variant, made with the planner
        if (mi >= named_plans.size() || !named_plans[mi]) return make_error(who + ": the material was not planned");
        plan.key = named_plans[mi]->key;
        plan.notes = named_plans[mi]->notes;
        return plan;
    }
    start_effect_plan(plan, material, relief, caps);
    const EffectRequest& request = *material.effects;
    const ObjectView& view = frame.views[oi];
    if (std::string why = why_no_relief(request, material, relief, view); !why.empty())
        return finish_normal(std::move(plan), std::move(why));
    const std::vector<PointView>& points = frame.points[oi];
    plan.view.per_vertex_view_error = per_vertex_view_error(relief, points);

    const Sources sources = prediction_sources(mi, view, plan.notes);
    const Source& source = sources.chosen();
    if (source.relief < 0) return make_error(who + ": the cost table has no relief to predict from");
    plan.prediction_source = source.label;

    const bool want_shadow = shadow_wanted(request, view, relief, points, plan.notes);
    const bool lod_possible = request.lod_fade != EffectSwitch::off && caps.derivatives();
    if (request.lod_fade == EffectSwitch::on && !caps.derivatives())
        plan.notes.push_back("lod_fade dropped: this OpenGL ES 2.0 context lacks GL_OES_standard_derivatives");
    const double fade_start = request.lod_threshold - request.lod_band;
    ObjectPredictor predictor(relief, points, request, caps, sources.table);
    const std::vector<Candidate> candidates =
        this->candidates(source, relief, want_shadow, silhouette_on_screen, lod_possible, view, fade_start);

    if (std::string why = why_normal_past_lod(plan, predictor, source, lod_possible, want_shadow); !why.empty())
        return finish_normal(std::move(plan), std::move(why));

    ShadowChoice shadow;
    if (want_shadow) {
        Result<ShadowChoice> chosen =
            choose_shadow_samples(source, sources.table, relief.features, request, points, who, field_path);
        if (!chosen) return chosen.error();
        shadow = *chosen;
    }
    const double target = hit_target(predictor, source, request, want_shadow, plan.notes);
    const Choice choice = predictor.choose(source, candidates, target);
    if (!choice.pick)
        return no_candidate(choice, who, field_path, request, view, caps, relief, predictor.uv_floor(), source.label);
    if (sources.calibrated) note_calibration_change(plan, predictor, sources, candidates, target, *choice.pick);

    apply_pick(plan.key, plan.options, *choice.pick);
    plan.predicted_error = choice.chosen.error;
    plan.predicted_cost = choice.chosen.cost + shadow.cost;
    note_pick(plan, *choice.pick, choice.chosen, target, lod_possible, fade_start, source.label);
    if (want_shadow) apply_shadow(plan, shadow);
    plan_depth(plan, oi, frame);
    plan.key = plan.key.canonical();
    if (std::string note = no_derivatives_note(plan.key); !note.empty()) plan.notes.push_back(note);
    return plan;
}

ScenePlanner::Impl::Sources ScenePlanner::Impl::prediction_sources(size_t mi, const ObjectView& view,
                                                                   std::vector<std::string>& notes) const {
    // The material's own calibration first; else the search model (where
    // the material has one) predicts hits; else the table's nearest relief
    // (which also holds the shadow rows).
    const MaterialRelief& relief = reliefs[mi];
    Sources s;
    s.table = generic_source(relief);
    s.modelled = model_source(mi);
    std::string skipped;
    s.calibrated = calibrated_source(relief, view.visible ? view.angle_max_deg : 0.0, &skipped);
    if (!s.calibrated && !skipped.empty()) notes.push_back(skipped);
    if (!s.calibrated && mi < calibration_notes.size() && !calibration_notes[mi].empty())
        notes.push_back(calibration_notes[mi]);
    return s;
}

bool ScenePlanner::Impl::shadow_wanted(const EffectRequest& request, const ObjectView& view, const MaterialRelief& relief,
                                       const std::vector<PointView>& points, std::vector<std::string>& notes) const {
    if (request.shadow == ShadowMode::none) return false;
    if (scene.lights.empty()) {
        notes.push_back(shadow_dropped(request.shadow, "the scene has no light"));
        return false;
    }
    if (view.lights_above_horizon == 0) {
        notes.push_back(shadow_dropped(request.shadow,
                                       "every light is behind the surface or below its horizon wherever it is seen"));
        return false;
    }
    // A height field whose slopes are all below the light's elevation
    // cannot shadow itself: with |grad h| <= S everywhere, h rises less
    // than S t over a distance t, and the ray to the light rises
    // tan(elevation) t. S: the steepest rise between neighbouring texels,
    // in texels of height per texel, times sqrt(2) for the diagonals of a
    // bilinear surface. A soft light's disc reaches its angular radius lower.
    const double slope_deg =
        glm::degrees(std::atan(std::sqrt(2.0) * relief.features.steepness * relief.features.depth_texels));
    double lowest = 90.0;
    for (const PointView& p : points)
        if (p.lit) lowest = std::min(lowest, p.light_elevation_deg);
    double radius = 0.0;
    if (request.shadow == ShadowMode::soft)
        for (const LightDesc& l : scene.lights) radius = std::max(radius, static_cast<double>(l.angular_radius_deg));
    if (lowest - radius > slope_deg) {
        notes.push_back(shadow_dropped(request.shadow, "the light is " + fmt("%.1f", lowest - radius) +
                                                           " degrees or more above the surface wherever it is "
                                                           "seen, steeper than the relief's steepest slope (" +
                                                           fmt("%.1f", slope_deg) +
                                                           " degrees): nothing on it can cast a shadow"));
        return false;
    }
    return true;
}

std::vector<Candidate> ScenePlanner::Impl::candidates(const Source& source, const MaterialRelief& relief,
                                                      bool want_shadow, bool silhouette_on_screen, bool lod_possible,
                                                      const ObjectView& view, double fade_start) const {
    std::vector<Candidate> out;
    for (const auto& [k, c] : *source.curves) {
        const auto& [r, t, samples, shadow, shadow_samples, elevation] = k;
        (void)c;
        (void)elevation;
        (void)shadow_samples;
        if (r != source.relief || shadow != ShadowMode::none) continue;
        const TechniqueInfo& info = technique_info(t);
        if (!why_technique_cannot_run(t, caps, relief.traced_width, relief.traced_height).empty()) continue;
        if (want_shadow && !(info.options & kOptShadow)) continue;
        // A curved silhouette on screen: a search that can follow the bend.
        if (silhouette_on_screen && !(info.options & kOptSamples)) continue;
        if (samples > info.max_samples_limit) continue;
        for (int exact = 1; exact >= 0; --exact) {
            if (!exact && (info.always_exact_view || !(info.options & kOptHeight))) continue;
            for (int lod = 0; lod < 2; ++lod) {
                if (lod && (!lod_possible || !(info.options & kOptLod) || view.mip_max <= fade_start)) continue;
                out.push_back({t, samples, exact != 0, lod != 0});
            }
        }
    }
    return out;
}

void ScenePlanner::Impl::note_calibration_change(ObjectPlan& plan, ObjectPredictor& predictor, const Sources& sources,
                                                 const std::vector<Candidate>& candidates, double target,
                                                 const Candidate& pick) const {
    const Choice alone = predictor.choose(sources.uncalibrated(), candidates, target);
    const std::optional<Candidate>& g_pick = alone.pick;
    if (g_pick && g_pick->technique == pick.technique && g_pick->samples == pick.samples &&
        g_pick->exact_view == pick.exact_view && g_pick->lod == pick.lod)
        return;
    VariantKey g = plan.key;
    if (g_pick) {
        g.technique = g_pick->technique;
        g.max_samples = static_cast<std::uint16_t>(g_pick->samples);
        g.exact_view = g_pick->exact_view;
        g.lod = g_pick->lod;
        // As the chosen key is completed: the refinements the draw uses (a
        // relief search refines options.refine_steps times).
        if (technique_info(g.technique).options & kOptRefine)
            g.refine_steps = static_cast<std::uint8_t>(plan.options.refine_steps);
        plan.generic_error = alone.chosen.error;
        plan.generic_cost = alone.chosen.cost;
    }
    plan.generic_key = g.canonical();
    plan.notes.push_back(std::string("the calibration changed the choice: ") +
                         (sources.modelled ? "the search model alone picks " : "the generic table alone picks ") +
                         (g_pick ? candidate_name(*g_pick) : std::string("nothing that meets the target")));
}

std::pair<glm::vec3, glm::vec3> ScenePlanner::Impl::relief_world_box(size_t oi) const {
    const ObjectDesc& object = scene.objects[oi];
    const MaterialDesc& material = scene.materials[scene.material_index(object.material)];
    const float units_per_tile = units_per_uv[oi] / material.uv.area_scale<float>();
    const float bottom = material.bias() * units_per_tile;
    const float top = (material.bias() + material.height_scale) * units_per_tile;
    glm::vec3 box_lo = surveys[oi].box_min, box_hi = surveys[oi].box_max;
    if (object.mesh.kind == MeshKind::plane) {
        box_lo.z = std::min({bottom, top, 0.0f});
        box_hi.z = std::max({bottom, top, 0.0f});
    } else {
        const float grow = material.height_scale * units_per_tile;
        box_lo -= glm::vec3(grow);
        box_hi += glm::vec3(grow);
    }
    return transformed_box(box_lo, box_hi, object.transform.matrix());
}

void ScenePlanner::Impl::plan_depth(ObjectPlan& plan, size_t oi, const FrameViews& frame) const {
    const EffectRequest& request = plan.request;
    const TechniqueInfo& info = technique_info(plan.key.technique);
    if (!(info.options & kOptDepth)) {
        if (request.depth_correction == EffectSwitch::on)
            plan.notes.push_back(std::string("depth correction dropped: ") + info.name + " finds no hit depth");
        return;
    }
    bool want_depth = request.depth_correction == EffectSwitch::on;
    if (request.depth_correction == EffectSwitch::automatic) {
        const auto [lo, hi] = relief_world_box(oi);
        const glm::vec4& sb = frame.screen_boxes[oi];
        std::string other;
        for (size_t j = 0; j < scene.objects.size() && other.empty(); ++j) {
            if (j == oi || !frame.views[j].visible) continue;
            const auto& [olo, ohi] = frame.world_boxes[j];
            const bool meets =
                olo.x <= hi.x && ohi.x >= lo.x && olo.y <= hi.y && ohi.y >= lo.y && olo.z <= hi.z && ohi.z >= lo.z;
            const glm::vec4& ob = frame.screen_boxes[j];
            const bool overlaps = ob.x <= sb.z && ob.z >= sb.x && ob.y <= sb.w && ob.w >= sb.y;
            if (meets && overlaps) other = scene.objects[j].name;
        }
        want_depth = !other.empty();
        plan.notes.push_back(want_depth ? "depth written: object '" + echo(other) +
                                              "' meets this surface's relief and overlaps it on screen"
                                        : "no depth written: no other object meets or overlaps this relief");
    }
    if (want_depth && !caps.frag_depth()) {
        plan.notes.push_back("depth correction dropped: this OpenGL ES 2.0 context lacks GL_EXT_frag_depth");
        want_depth = false;
    }
    plan.key.depth_write = want_depth;
    plan.options.depth_write = want_depth;
}

}  // namespace px
