// The part of planning that every object shares, whether its material names
// its technique or declares effects: the frame's checks, whether the
// object's outline (a curved silhouette, a bounded tile's edges) is on
// screen and so drawn, and the plan of a material that names its technique.
// One implementation, called by the effect planner (scene_planner.cpp) and
// by the named-technique planner below, which is what the renderer plans
// with when it has no effect planner: neither the renderer nor a host
// works a named material's variant out for itself.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "parallaxes/planner/planner.h"

namespace px {

// Errors for a frame no object can be planned for: an empty image, a NaN or
// infinite matrix, a degenerate projection or view, a `models` list of the
// wrong length for `scene`.
Status check_plan_view(const PlanView& frame, const SceneDesc& scene);

// The model transform of object `i` this frame.
glm::mat4 object_model(const PlanView& frame, const SceneDesc& scene, size_t i);

// What an object asks of its outline, fixed for the scene: whether its
// material asks for a curved silhouette on this mesh, and whether the relief
// folds through the shape's centre or axis (then none is drawn).
struct OutlineRequest {
    bool asks_silhouette = false;       // silhouette on a parallax-drawn sphere, torus or cylinder with relief
    std::optional<double> folds;        // relief_folds_through
    bool asks_bounded = false;          // MaterialDesc::bounded
    double relief_depth = 0.0;          // mesh units, the whole relief
};
OutlineRequest outline_request(const ObjectDesc& object, const MaterialDesc& material, double units_per_uv);

// Whether the object's curved contour can be on screen this frame (false
// where it asks for none, or its relief folds through).
bool silhouette_on_screen(const OutlineRequest& r, const ObjectDesc& object, const MaterialDesc& material,
                          const glm::mat4& model, const PlanView& frame);

// Sets the plan's curved silhouette (VariantKey::curved and shape) and
// bounded discard for this frame (where `silhouette_visible` and
// `bounded_visible` say they can show), each with its note, and the material's
// texture layout: a technique that cannot draw what the material asks for
// draws without it and the note says what was dropped (an override that
// asks for less than the material declares draws; it is never refused).
void plan_outlines(ObjectPlan& plan, const OutlineRequest& r, const ObjectDesc& object, const MaterialDesc& material,
                   const TextureLayout& layout, bool silhouette_visible, bool bounded_visible);
// Whether a bounded relief's outline can be on screen this frame (a tube's
// rims always count): false where it asks for none.
bool bounded_on_screen(const OutlineRequest& r, const ObjectDesc& object, const glm::mat4& model, const PlanView& frame);

// The key an object of a material that names its technique draws wherever
// its outline is on screen: the material's plan with the texture layout,
// bounded and curved as material and mesh ask (what load builds, so that a
// shader error surfaces there).
VariantKey named_object_key(const VariantPlan& material_plan, const OutlineRequest& r, const ObjectDesc& object,
                            const TextureLayout& layout);

// The planner the renderer uses where it has no effect planner
// (RendererOptions::effect_planner null): every material must name its
// technique (a scene that declares effects is refused, naming the material
// and its JSON path). plan_variant runs once per material, when it is made;
// each frame draws the outlines the materials ask for. Links none of the effect planner's
// survey, cost table or JSON parser.
Result<std::unique_ptr<FramePlanner>> named_planner(std::shared_ptr<const PreparedScene> scene, const Caps& caps);

}  // namespace px
