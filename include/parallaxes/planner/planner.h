// The planner: turns what a material asks for into the shader variant each
// object is drawn with on a given context, camera and image size, and says
// why. A material either names its technique (plan_variant adjusts that
// request to the context) or declares effects (EffectRequest), and then the
// ScenePlanner chooses per object the cheapest variant predicted to meet the
// material's targets, from what the camera sees of the object: hit errors
// from the search model simulated on the material's own relief
// (planner/search_model.h), costs from the measured cost table
// (planner/cost_table.h). GL-free; about 0.7 to 0.8 ms per object and plan
// on this 2-core host, and about 80 ms per modelled material when the
// planner is made (docs/planner.md, "Planning time").
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "parallaxes/core/caps.h"
#include "parallaxes/core/result.h"
#include "parallaxes/effects/variant.h"
#include "parallaxes/planner/cost_table.h"
#include "parallaxes/planner/relief.h"
#include "parallaxes/planner/search_model.h"
#include "parallaxes/scene/prepared_scene.h"
#include "parallaxes/scene/scene.h"

namespace px {

// The planner's answer for one material: the variant, and why it differs
// from what the material asked for (one note per change).
struct VariantPlan {
    VariantKey key;
    std::vector<std::string> notes;
};

// Picks the variant for a material that names its technique, on a context
// with these capabilities: options the technique does not have are dropped,
// options the context cannot run are dropped with the reason (e.g. depth
// write on ES 2.0 without GL_EXT_frag_depth), a relief with zero depth falls
// back to normal mapping. Errors: the technique needs a newer ES version
// than the context has. `traced_width` and `traced_height`: the size of the
// height field the technique traces, when known (0: unknown); maxmip's
// pyramid halves every level exactly, so a field that is not a power of two
// in both gets the table's fallback, with the reason.
Result<VariantPlan> plan_variant(const MaterialDesc& material, const Caps& caps, int traced_width = 0,
                                 int traced_height = 0);

// Why this context cannot draw technique t on a traced field of this size
// (0 x 0: unknown), or "" where it can: an ES version below the technique's;
// an exact walk's pyramid on a field that is not a power of two each way;
// on GLSL ES 1.00, a pyramid atlas over GL_MAX_TEXTURE_SIZE. The planner
// draws the technique's fallback there. (Without fragment highp maxmip still
// runs: in mediump it is not exact, but it measured closer to the reference
// than its fallback on every hard case: docs/stability.md.)
std::string why_technique_cannot_run(Technique t, const Caps& caps, int traced_width = 0, int traced_height = 0);

// The plan's note for a variant that shades its hit at texture2D's own mip
// level (VariantKey::no_derivatives: GLSL ES 1.00 without
// GL_OES_standard_derivatives); "" for any other.
std::string no_derivatives_note(const VariantKey& key);

// Whether a bounded relief on a plane of side `size` (mesh units, model
// transform `model`) can show its outline in a `width` x `height` image of
// this view and projection: false only where every pixel's ray meets the
// plane's front, between the near and far planes, farther inside its
// bounds than the relief can carry a ray sideways (`depth`: the relief's
// depth in mesh units, the whole of it whatever the polygon's height, times
// the tangent of the ray's angle at the viewport's corners, where the angle
// over a plane seen in perspective is largest). Then no ray on screen
// leaves the bounds and the discard (PX_BOUNDED) can be left out.
bool bounded_outline_on_screen(const glm::mat4& model, float size, double depth, const glm::mat4& view,
                               const glm::mat4& projection);

// Whether a curved mesh's contour (a sphere, torus or cylinder of these
// sizes, model transform `model`) can be on screen in this view and
// projection: false where the mesh's bounding sphere (grown by `depth`, the
// relief's depth in mesh units) lies wholly outside the view volume, or,
// for a sphere, where every viewport corner's ray meets the sphere shrunk by
// `depth` in front of the camera (the projected sphere is convex, so the
// whole image is then relief and no ray passes it). Then the curved
// silhouette (PX_CURVED) can be left out.
bool curved_outline_on_screen(const glm::mat4& model, MeshKind kind, float radius, float tube_radius, float height,
                              double depth, const glm::mat4& view, const glm::mat4& projection);

// A curved-silhouette key (VariantKey::curved) for a mesh of this kind: the
// exact search of its shape (VariantKey::shape), on every context. Without
// fragment highp (every fragment float fp16, emulated) it measured 0.0 to
// 4.7 % of the contour on the sphere and torus, 0.6 to 12.4 % on the open
// tube, against the fitted quadric's 8.4 to 20.8 % (docs/silhouettes.md).
VariantKey with_curved_shape(VariantKey key, MeshKind kind);

// What the camera sees of one object, over the visible part of its surface
// (front-facing, inside the view frustum), from a few hundred points spread
// over its triangles and weighted by their area on screen.
struct ObjectView {
    bool visible = false;
    double pixels = 0.0;  // area on screen
    double angle_min_deg = 0.0, angle_max_deg = 0.0;  // view angle from the surface normal
    double distance_min = 0.0, distance_max = 0.0;
    double mip_min = 0.0, mip_max = 0.0;  // log2 of texels per pixel (GL's level selection)
    // Per-vertex view normalisation (the PowerVR whitepaper's saving): the
    // 95th percentile of the hit displacement it adds, in texels, on this
    // object's triangles at this distance.
    double per_vertex_view_error = 0.0;
    int lights_above_horizon = 0;  // lights that reach some visible point
};

// The planner's answer for one object.
struct ObjectPlan {
    std::string object;
    std::string material;
    bool planned = false;  // the material declared effects (else it named a technique)
    EffectRequest request;  // what it asked for (planned only)
    VariantKey key;
    // The options the draw uses with the key: sample range, LOD threshold.
    TechniqueOptions options;
    // Every decision, with its reason: dropped effects, the chosen
    // candidate against the others, the view vector's interpolation.
    std::vector<std::string> notes;
    ObjectView view;
    // Planned objects: the prediction behind the choice. -1: not predicted.
    double predicted_error = -1.0;         // texels of the level sampled, p95 (see EffectRequest)
    double predicted_cost = -1.0;          // per pixel, relative to normal mapping
    double predicted_shadow_error = -1.0;  // mean |visibility difference|
    // "search model on this relief (...)", "calibrated on this relief (...)"
    // or "table 'bricks' (...)".
    std::string prediction_source;
    // The material's relief as the planner measured it (planned objects):
    // its field's hash and depth name its calibration (`plan --calibrate`).
    ReliefFeatures relief;
    // Where a calibration changed the choice: what the planner picks without
    // it (from the search model, or the generic table).
    std::optional<VariantKey> generic_key;
    double generic_error = -1.0, generic_cost = -1.0;
};

// Per material, what the planner knows of its relief, measured once.
struct MaterialRelief {
    ReliefFeatures features;  // of the traced field as the GPU samples it
    int traced_width = 0, traced_height = 0;
    TextureLayout layout;     // applied to every variant the material draws with
    // Every candidate's search simulated on this very field
    // (planner/search_model.h): what the planner predicts hit errors from
    // where no calibration matches. Null: predicted from the generic
    // table's nearest relief (a material that names its technique, or a
    // relief given without one).
    std::shared_ptr<const SearchModel> search;
};

struct PlannerOptions {
    const CostTable* table = nullptr;  // null: the built-in table
    // Tables measured on single materials' reliefs (`parallax plan
    // --calibrate`): a material whose relief's hash and depth match one is
    // predicted from it instead of the generic table.
    // Shared and immutable, so that copying options (RendererOptions is
    // copied into each renderer) copies no table.
    std::shared_ptr<const std::vector<CostTable>> calibrations;
    // Or found per material: asked once for each material with a relief
    // to trace when the planner is made, it returns the calibration of that
    // relief if the host keeps one (nothing else need be read or parsed),
    // or nullopt; `note` says why one that matched could not be used (a
    // broken file, say), and the planner prints it in that material's plans.
    std::function<std::optional<CostTable>(const ReliefFeatures&, std::string& note)> find_calibration;
};

// What the planner plans for: one frame as the host draws it. The view and
// projection matrices are the host's (any perspective or orthographic
// projection; the eye is where the inverse view matrix puts it), `width` and
// `height` the viewport's size in pixels (texels per pixel depend on it), and
// `models` each object's model transform this frame, in scene order (empty:
// the scene's own transforms).
struct PlanView {
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f};
    int width = 0, height = 0;
    std::vector<glm::mat4> models;

    // The scene camera's view at this image size (what `parallax render` draws).
    static PlanView from_camera(const CameraDesc& camera, int width, int height);
};

// What the renderer plans each frame with, behind a virtual interface so that
// a renderer whose materials all name their technique links none of the
// effect planner (its survey, cost table and JSON parser): the renderer
// reaches ScenePlanner only through RendererOptions::effect_planner.
class FramePlanner {
public:
    virtual ~FramePlanner() = default;
    // One plan per scene object, in order, for this frame.
    virtual Result<std::vector<ObjectPlan>> plan(const PlanView& view) const = 0;
    // The relief measured for each material, in scene order.
    virtual const std::vector<MaterialRelief>& reliefs() const = 0;
    // For material `i` when it names its technique: its plan on this
    // context (plan_variant, run once, when the planner was made); null for
    // a material that declares effects (its variant is chosen per frame).
    virtual const VariantPlan* material_plan(size_t i) const = 0;
    // Each object whose material names its technique, with the variant it
    // draws wherever its outline is on screen (planner/object_plan.h
    // named_object_key): what load builds, so that a shader error surfaces
    // there rather than in a frame.
    virtual std::vector<std::pair<size_t, VariantKey>> named_variants() const = 0;
};

// Makes the effect planner of a prepared scene. `reliefs`: one per
// material, as reliefs() of an earlier planner of the scene; an entry with
// traced_width 0 (or an empty list) is measured here.
using EffectPlannerFactory = Result<std::unique_ptr<FramePlanner>> (*)(const PreparedScene& scene, const Caps& caps,
                                                                       const PlannerOptions& options,
                                                                       std::vector<MaterialRelief> reliefs);
// The effect planner (ParallaxES::planner): RendererOptions::effect_planner.
Result<std::unique_ptr<FramePlanner>> effect_planner(const PreparedScene& scene, const Caps& caps,
                                                     const PlannerOptions& options, std::vector<MaterialRelief> reliefs);

class ScenePlanner : public FramePlanner {
public:
    // The planner of a prepared scene: reliefs measured from its materials'
    // traced fields, surveys from the meshes that are drawn (a displaced
    // plane's displaced grid). Errors: a broken table.
    // `reliefs`: as reliefs() of a planner of this scene, where only some
    // materials changed (empty: every one measured here).
    static Result<std::unique_ptr<ScenePlanner>> create(const PreparedScene& scene, const Caps& caps,
                                                        PlannerOptions options = {},
                                                        std::vector<MaterialRelief> reliefs = {});
    // From a description alone (surveys the undisplaced meshes): `reliefs`,
    // one per scene material, in order. Errors: a broken table.
    static Result<std::unique_ptr<ScenePlanner>> create(const SceneDesc& scene, const Caps& caps,
                                                        std::vector<MaterialRelief> reliefs,
                                                        PlannerOptions options = {});
    ~ScenePlanner() override;
    // One plan per scene object, in order, for this camera and image size.
    // Errors name the object and the JSON path of the field: an impossible
    // target (no candidate reaches it here), a technique the context cannot run.
    Result<std::vector<ObjectPlan>> plan(const CameraDesc& camera, int width, int height) const;
    // The same for a host's frame. Errors also: a degenerate or non-finite
    // matrix, or a `models` list of the wrong length.
    Result<std::vector<ObjectPlan>> plan(const PlanView& view) const override;
    // The relief measured for each material, in scene order (to build a
    // planner again with one material replaced).
    const std::vector<MaterialRelief>& reliefs() const override;
    const VariantPlan* material_plan(size_t i) const override;
    std::vector<std::pair<size_t, VariantKey>> named_variants() const override;

    struct Impl;
    // For the factories in scene_planner.cpp.
    static std::unique_ptr<ScenePlanner> make_empty();
    Impl& impl() { return *impl_; }

private:
    ScenePlanner() = default;
    std::unique_ptr<Impl> impl_;
};

// Measures a material's relief the way the planner needs it, from its images.
MaterialRelief material_relief(const HeightField& traced_8bit, const MaterialDesc& material);

}  // namespace px
