#include "parallaxes/planner/object_plan.h"

#include <algorithm>
#include <cmath>

#include "parallaxes/core/counters.h"
#include "parallaxes/core/text.h"

namespace px {

namespace {

bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

bool technique_has(Technique t, std::uint32_t flags) { return (technique_info(t).options & flags) != 0; }

// Why technique t draws no curved silhouette.
std::string silhouette_dropped_note(Technique t) {
    const std::string searches = technique_names_with(kOptSamples);
    if (technique_has(t, kOptSteps))
        return std::string("silhouette not drawn: ") + technique_name(t) +
               " could trace the mesh's own shape and does not yet (its walk runs over the flat tile); the linear "
               "searches (" + searches + ") draw it";
    return std::string("silhouette not drawn: ") + technique_name(t) + " has no search to follow the bend (" + searches +
           " draw it)";
}

std::string silhouette_drawn_note(const VariantKey& key) {
    return std::string("silhouette: the contour can be on screen; ") +
           (key.shape ? "the search traces the mesh's own shape and " : "the search follows the surface's fitted bend and ") +
           "rays that pass the relief are discarded";
}

}  // namespace

Status check_plan_view(const PlanView& frame, const SceneDesc& scene) {
    if (frame.width < 1 || frame.height < 1)
        return make_error("planner: image size " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                          " is empty");
    if (!frame.models.empty() && frame.models.size() != scene.objects.size())
        return make_error("planner: " + std::to_string(frame.models.size()) + " model transforms for " +
                          std::to_string(scene.objects.size()) + " objects");
    if (!finite(frame.view) || !finite(frame.projection))
        return make_error("planner: the view or projection matrix has a NaN or infinite entry");
    for (size_t i = 0; i < frame.models.size(); ++i)
        if (!finite(frame.models[i]))
            return make_error("planner: the model transform of object '" + echo(scene.objects[i].name) +
                              "' has a NaN or infinite entry");
    if (!(std::fabs(frame.projection[1][1]) > 0.0f) || glm::determinant(frame.view) == 0.0f)
        return make_error("planner: the projection or view matrix is degenerate (no finite pixel size)");
    return {};
}

glm::mat4 object_model(const PlanView& frame, const SceneDesc& scene, size_t i) {
    return frame.models.empty() ? scene.objects[i].transform.matrix() : frame.models[i];
}

OutlineRequest outline_request(const ObjectDesc& object, const MaterialDesc& material, double units_per_uv) {
    OutlineRequest r;
    r.asks_silhouette = material.silhouette && mesh_kind_is_curved(object.mesh.kind) && !object.mesh.displaced &&
                        material.height_scale > 0.0f;
    if (r.asks_silhouette) r.folds = relief_folds_through(object.mesh, material, units_per_uv);
    r.asks_bounded = material.bounded;
    r.relief_depth = static_cast<double>(material.height_scale) * units_per_uv /
                     std::max(1e-12, material.uv.area_scale<double>());
    return r;
}

bool silhouette_on_screen(const OutlineRequest& r, const ObjectDesc& object, const MaterialDesc& material,
                          const glm::mat4& model, const PlanView& frame) {
    if (!r.asks_silhouette || r.folds) return false;
    // A bounded cylinder is drawn longer at each end (build_widened_mesh).
    const float length = object.mesh.size * static_cast<float>(drawn_length_scale(object.mesh, material));
    return curved_outline_on_screen(model, object.mesh.kind, object.mesh.radius, object.mesh.tube_radius, length,
                                    r.relief_depth, frame.view, frame.projection);
}

bool bounded_on_screen(const OutlineRequest& r, const ObjectDesc& object, const glm::mat4& model, const PlanView& frame) {
    return r.asks_bounded && (object.mesh.kind != MeshKind::plane ||
                              bounded_outline_on_screen(model, object.mesh.size, r.relief_depth, frame.view,
                                                        frame.projection));
}

void plan_outlines(ObjectPlan& plan, const OutlineRequest& r, const ObjectDesc& object, const MaterialDesc& material,
                   const TextureLayout& layout, bool silhouette_visible, bool bounded_visible) {
    VariantKey& key = plan.key;
    if (r.asks_silhouette) {
        const bool marches = technique_has(key.technique, kOptSamples);
        key.curved = silhouette_visible && marches;
        key = with_curved_shape(key, object.mesh.kind);
        plan.notes.push_back(r.folds ? silhouette_folds_note(object.mesh, *r.folds)
                             : !silhouette_visible
                                 ? "silhouette off: the object's contour is off screen (the relief fills the view, or "
                                   "the object is outside it), so nothing is discarded"
                             : marches ? silhouette_drawn_note(key)
                                       : silhouette_dropped_note(key.technique));
        if (key.curved)
            if (std::optional<std::string> open = open_tube_ends_note(object.mesh, material)) plan.notes.push_back(*open);
    }
    key = key.with_layout(layout);
    if (!r.asks_bounded) return;
    if (!technique_has(key.technique, kOptHeight)) {
        key.bounded = false;
        if (material.height_scale > 0.0f)
            plan.notes.push_back(std::string("bounded outline not drawn: ") + technique_name(key.technique) +
                                 " traces no relief, so no ray leaves the tile and its outline is the polygon's edge "
                                 "(" + technique_names_with(kOptHeight) + " draw it)");
        return;
    }
    // A bounded relief's discard only where its outline can be on screen
    // (bounded_on_screen): a tile that fills the view keeps what a discard
    // costs a tile-based GPU.
    key.bounded = bounded_visible;
    plan.notes.push_back(!key.bounded
                             ? "bounded, silhouette off: every ray on screen stays inside the tile's bounds, so "
                               "nothing is discarded"
                         : object.mesh.kind == MeshKind::plane
                             ? "bounded: the tile's outline can be on screen; rays that leave its bounds are discarded"
                             : "bounded: the relief ends at the mesh's uv edges (a tube's rims); rays that leave "
                               "its bounds are discarded");
}

VariantKey named_object_key(const VariantPlan& material_plan, const OutlineRequest& r, const ObjectDesc& object,
                            const TextureLayout& layout) {
    VariantKey key = material_plan.key.with_layout(layout);
    key.bounded = r.asks_bounded;
    key.curved = r.asks_silhouette && !r.folds;
    return with_curved_shape(key, object.mesh.kind).canonical();
}

namespace {

class NamedPlanner : public FramePlanner {
public:
    Result<std::vector<ObjectPlan>> plan(const PlanView& frame) const override {
        if (Status s = check_plan_view(frame, scene_->desc); !s) return s.error();
        const SceneDesc& desc = scene_->desc;
        std::vector<ObjectPlan> plans;
        plans.reserve(desc.objects.size());
        for (size_t i = 0; i < desc.objects.size(); ++i) {
            const ObjectDesc& object = desc.objects[i];
            const size_t mi = scene_->objects[i]->material;
            const MaterialDesc& material = desc.materials[mi];
            ObjectPlan p;
            p.object = object.name;
            p.material = material.name;
            p.options = material.technique;
            p.key = material_plans_[mi].key;
            p.notes = material_plans_[mi].notes;
            // Outlines wherever the material asks for them (the effect planner
            // also leaves them out where they are off screen): this planner
            // stays small, for hosts that link no effect planner.
            const OutlineRequest& r = outlines_[i];
            plan_outlines(p, r, object, material, reliefs_[mi].layout, r.asks_silhouette && !r.folds, true);
            plans.push_back(std::move(p));
        }
        counters::count(counters::Step::object_plan, plans.size());
        return plans;
    }
    const std::vector<MaterialRelief>& reliefs() const override { return reliefs_; }
    const VariantPlan* material_plan(size_t i) const override {
        return i < material_plans_.size() ? &material_plans_[i] : nullptr;
    }
    std::vector<std::pair<size_t, VariantKey>> named_variants() const override {
        std::vector<std::pair<size_t, VariantKey>> out;
        for (size_t i = 0; i < scene_->objects.size(); ++i) {
            const size_t mi = scene_->objects[i]->material;
            out.emplace_back(i, named_object_key(material_plans_[mi], outlines_[i], scene_->desc.objects[i],
                                                 reliefs_[mi].layout));
        }
        return out;
    }

    std::shared_ptr<const PreparedScene> scene_;
    std::vector<VariantPlan> material_plans_;   // one per material
    std::vector<MaterialRelief> reliefs_;       // layouts and traced sizes only
    std::vector<OutlineRequest> outlines_;      // one per object
};

}  // namespace

Result<std::unique_ptr<FramePlanner>> named_planner(std::shared_ptr<const PreparedScene> prepared, const Caps& caps) {
    if (!prepared) return make_error("named_planner: no prepared scene");
    auto p = std::make_unique<NamedPlanner>();
    p->scene_ = std::move(prepared);  // shared, not copied
    const PreparedScene& scene = *p->scene_;
    const SceneDesc& desc = scene.desc;
    for (size_t i = 0; i < desc.materials.size(); ++i) {
        const MaterialDesc& m = desc.materials[i];
        if (m.effects)
            return make_error("material '" + echo(m.name) + "' (materials[" + std::to_string(i) +
                              "].effects) declares effects, and this renderer has no effect planner: link "
                              "ParallaxES::planner and set RendererOptions::effect_planner = px::effect_planner, "
                              "or name a technique");
        const MaterialImages& images = scene.materials[i]->images;
        Result<VariantPlan> plan = plan_variant(m, caps, images.field.width, images.field.height);
        if (!plan) return with_context("material '" + echo(m.name) + "'", plan.error());
        p->material_plans_.push_back(std::move(*plan));
        MaterialRelief r;
        r.layout = images.layout;
        r.traced_width = images.field.width;
        r.traced_height = images.field.height;
        p->reliefs_.push_back(std::move(r));
    }
    for (size_t i = 0; i < desc.objects.size(); ++i) {
        const PreparedObject& o = *scene.objects[i];
        p->outlines_.push_back(outline_request(desc.objects[i], desc.materials[o.material], o.mesh.units_per_uv));
    }
    return std::unique_ptr<FramePlanner>(std::move(p));
}

}  // namespace px
