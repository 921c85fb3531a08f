#include "parallaxes/planner/planner.h"

#include "parallaxes/core/counters.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <tuple>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "parallaxes/core/text.h"

namespace px {

namespace {
bool power_of_two(int n) { return n > 0 && (n & (n - 1)) == 0; }

// The four viewport corners' rays in model space, from the near plane
// (origin) to the far plane (origin + direction); false where the
// projection or view is degenerate there.
struct CornerRay {
    glm::dvec3 origin;
    glm::dvec3 direction;
};
bool corner_rays(const glm::mat4& model, const glm::mat4& view, const glm::mat4& projection, CornerRay (&rays)[4]) {
    const glm::dmat4 to_world = glm::inverse(glm::dmat4(projection) * glm::dmat4(view));
    const glm::dmat4 to_model = glm::inverse(glm::dmat4(model));
    int k = 0;
    for (const glm::dvec2 corner : {glm::dvec2(-1, -1), glm::dvec2(1, -1), glm::dvec2(1, 1), glm::dvec2(-1, 1)}) {
        const glm::dvec4 near_h = to_world * glm::dvec4(corner, -1.0, 1.0);
        const glm::dvec4 far_h = to_world * glm::dvec4(corner, 1.0, 1.0);
        if (!(std::fabs(near_h.w) > 0.0) || !(std::fabs(far_h.w) > 0.0)) return false;
        const glm::dvec3 o = glm::dvec3(to_model * glm::dvec4(glm::dvec3(near_h) / near_h.w, 1.0));
        rays[k++] = {o, glm::dvec3(to_model * glm::dvec4(glm::dvec3(far_h) / far_h.w, 1.0)) - o};
    }
    return true;
}
}  // namespace

bool bounded_outline_on_screen(const glm::mat4& model, float size, double depth, const glm::mat4& view,
                               const glm::mat4& projection) {
    const double half = 0.5 * static_cast<double>(size);
    if (!(half > 0.0) || !std::isfinite(depth) || depth < 0.0) return true;
    // The viewport's corners: the image maps onto the plane projectively, so
    // if all four land well inside the (convex) bounds, every pixel does;
    // the sideways reach is largest at one of them.
    CornerRay rays[4];
    if (!corner_rays(model, view, projection, rays)) return true;
    glm::dvec2 hits[4];
    double reach = 0.0;
    int k = 0;
    for (const CornerRay& ray : rays) {
        const glm::dvec3 o = ray.origin, d = ray.direction;
        if (!(d.z < 0.0)) return true;  // the corner sees the back, or along the plane
        const double s = -o.z / d.z;
        if (!(s >= 0.0 && s <= 1.0)) return true;  // the plane is behind the near or past the far plane there
        hits[k++] = glm::dvec2(o + s * d);
        reach = std::max(reach, depth * glm::length(glm::dvec2(d)) / -d.z);
    }
    const double margin = half - reach;
    for (const glm::dvec2& q : hits)
        if (!(std::fabs(q.x) < margin && std::fabs(q.y) < margin)) return true;
    return false;
}

VariantKey with_curved_shape(VariantKey key, MeshKind kind) {
    key.shape = 0;
    if (!key.curved) return key;
    key.shape = kind == MeshKind::sphere     ? kShapeSphere
                : kind == MeshKind::cylinder ? kShapeCylinder
                : kind == MeshKind::torus    ? kShapeTorus
                                             : 0;
    return key;
}

bool curved_outline_on_screen(const glm::mat4& model, MeshKind kind, float radius, float tube_radius, float height,
                              double depth, const glm::mat4& view, const glm::mat4& projection) {
    if (!std::isfinite(depth) || depth < 0.0) return true;
    const double r = radius, t = tube_radius, h = height;
    const double bound = (kind == MeshKind::torus      ? r + t
                          : kind == MeshKind::cylinder ? std::sqrt(r * r + 0.25 * h * h)
                                                       : r) + depth;
    // The bounding sphere against the view volume's six planes (Gribb and
    // Hartmann: rows of projection * view), in world space.
    const glm::dmat4 clip = glm::dmat4(projection) * glm::dmat4(view);
    const glm::dmat3 model3(model);
    const double scale = std::max({glm::length(model3[0]), glm::length(model3[1]), glm::length(model3[2])});
    const glm::dvec4 centre(glm::dvec3(glm::dmat4(model)[3]), 1.0);
    const double world_bound = bound * scale;
    if (!std::isfinite(world_bound) || !std::isfinite(centre.x + centre.y + centre.z)) return true;
    for (int axis = 0; axis < 3; ++axis)
        for (double side : {1.0, -1.0}) {
            glm::dvec4 plane;
            for (int c = 0; c < 4; ++c) plane[c] = clip[c][3] + side * clip[c][axis];
            const double n = glm::length(glm::dvec3(plane));
            if (!(n > 0.0)) continue;
            if (glm::dot(plane, centre) / n < -world_bound) return false;  // wholly outside this plane
        }
    if (kind != MeshKind::sphere) return true;
    // The corners' rays against the shrunk sphere, in model space.
    const double inner = r - depth;
    if (!(inner > 0.0)) return true;
    CornerRay rays[4];
    if (!corner_rays(model, view, projection, rays)) return true;
    for (const CornerRay& ray : rays) {
        const glm::dvec3 o = ray.origin, d = ray.direction;
        // |o + s d| = inner at s in [0, 1], with o outside the sphere.
        const double a = glm::dot(d, d), b = glm::dot(o, d), c = glm::dot(o, o) - inner * inner;
        if (!(a > 0.0) || !(c > 0.0)) return true;  // degenerate, or the near plane inside the sphere
        const double disc = b * b - a * c;
        if (!(disc >= 0.0)) return true;  // this corner's ray passes the sphere
        const double s = (-b - std::sqrt(disc)) / a;
        if (!(s >= 0.0 && s <= 1.0)) return true;
    }
    return false;
}

std::string no_derivatives_note(const VariantKey& key) {
    if (!key.canonical().no_derivatives) return {};
    return "shading at the hit at texture2D's own mip level: this OpenGL ES 2.0 context lacks "
           "GL_OES_standard_derivatives, so along the relief's rims the albedo and normal map read a blurred mip";
}

std::string why_technique_cannot_run(Technique t, const Caps& caps, int traced_width, int traced_height) {
    const TechniqueInfo& info = technique_info(t);
    if (info.min_es_major > caps.es_major)
        return std::string(info.name) + " needs OpenGL ES " + std::to_string(info.min_es_major) +
               ".0 and this context is " + caps.version;
    if (!(info.options & kOptSteps)) return {};
    const std::string size = std::to_string(traced_width) + "x" + std::to_string(traced_height);
    if (traced_width != 0 && !(power_of_two(traced_width) && power_of_two(traced_height)))
        return std::string(info.name) + "'s max pyramid halves every level exactly, and the height map is " + size +
               ", not a power of two in both sides";
    if (caps.es_major >= 3) return {};
    const long long atlas_width = static_cast<long long>(traced_width) + std::max(1, traced_width / 2);
    if (traced_width != 0 && (atlas_width > caps.max_texture_size || traced_height > caps.max_texture_size))
        return std::string(info.name) + "'s pyramid atlas for a " + size + " height map is " +
               std::to_string(atlas_width) + " texels wide, over this context's GL_MAX_TEXTURE_SIZE of " +
               std::to_string(caps.max_texture_size);
    return {};
}

Result<VariantPlan> plan_variant(const MaterialDesc& material, const Caps& caps, int traced_width,
                                 int traced_height) {
    counters::count(counters::Step::material_plan);
    const TechniqueOptions& o = material.technique;
    VariantPlan plan;
    VariantKey& k = plan.key;
    k.technique = o.technique;
    k.es_major = static_cast<std::uint8_t>(caps.es_major);
    k.no_fragment_highp = caps.es_major < 3 && !caps.fragment_highp;
    k.no_derivatives = !caps.derivatives();

    const TechniqueInfo& asked = technique_info(o.technique);
    const std::string why_not = why_technique_cannot_run(o.technique, caps, traced_width, traced_height);
    if (!why_not.empty()) {
        // The most accurate technique this context runs (the table's fallback).
        k.technique = asked.fallback;
        plan.notes.push_back(std::string(asked.name) + " -> " + technique_name(asked.fallback) + " with " +
                             std::to_string(std::max(o.max_samples, asked.fallback_min_samples)) + " samples: " +
                             why_not);
    }
    if ((asked.options & kOptHeight) && material.height_scale <= 0.0f) {
        plan.notes.clear();
        plan.notes.push_back(std::string(asked.name) +
                             " -> normal: height_scale is 0, so there is no relief to trace and normal "
                             "mapping draws the same image");
        k.technique = Technique::normal;
    }
    const Technique t = k.technique;
    const TechniqueInfo& info = technique_info(t);
    if ((info.options & kOptSteps) && k.no_fragment_highp)
        plan.notes.push_back(std::string(info.name) +
                             " without fragment highp (this OpenGL ES 2.0 context lacks GL_FRAGMENT_PRECISION_HIGH): "
                             "its walk runs in mediump and is no longer exact, though still the most accurate "
                             "technique here (docs/stability.md, nohighp)");

    k.packed_height = material.pack_height_in_normal_alpha;
    // canonical() turns it on where the technique always takes the exact view vector.
    k.exact_view = o.exact_view;
    if (info.options & kOptSamples)
        k.max_samples = static_cast<std::uint16_t>(t == o.technique ? o.max_samples : std::max(o.max_samples, asked.fallback_min_samples));
    if (info.options & kOptSteps) k.max_samples = static_cast<std::uint16_t>(o.max_steps);
    if (info.options & kOptRefine) k.refine_steps = static_cast<std::uint8_t>(o.refine_steps);

    if (o.shadow != ShadowMode::none) {
        if (info.options & kOptShadow) {
            k.shadow = o.shadow;
            k.shadow_samples = static_cast<std::uint8_t>(o.shadow_samples);
        } else if (t == o.technique) {
            plan.notes.push_back(std::string("shadow=") + shadow_mode_name(o.shadow) + " ignored: " + info.name +
                                 " casts no shadow ray (" + technique_names_with(kOptShadow) + " do)");
        }
    }
    if (o.depth_write) {
        if (!(info.options & kOptDepth)) {
            if (t == o.technique)
                plan.notes.push_back(std::string("depth_write ignored: ") + info.name +
                                     " finds no hit depth (" + technique_names_with(kOptDepth) + " do)");
        } else if (!caps.frag_depth()) {
            plan.notes.push_back("depth_write dropped: this OpenGL ES 2.0 context lacks GL_EXT_frag_depth");
        } else {
            k.depth_write = true;
        }
    }
    if (o.lod) {
        if (!(info.options & kOptLod)) {
            if (t == o.technique)
                plan.notes.push_back(std::string("lod ignored: ") + info.name + " has no parallax to fade out");
        } else if (!caps.derivatives()) {
            plan.notes.push_back(
                "lod dropped: this OpenGL ES 2.0 context lacks GL_OES_standard_derivatives (the mip level needs them)");
        } else {
            k.lod = true;
        }
    }
    plan.key = k.canonical();
    if (std::string note = no_derivatives_note(plan.key); !note.empty()) plan.notes.push_back(note);
    return plan;
}

}  // namespace px
