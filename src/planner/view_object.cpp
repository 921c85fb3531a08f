// What the camera sees of one object this frame: its surveyed points that
// face the camera inside the view, each with its view angle, texels per
// pixel, pixels, what a per-vertex view vector would add, and the lights
// above its horizon; and the object's ranges of those, its world and
// screen boxes.
#include "planner_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_inverse.hpp>

namespace px {

using namespace planning;

namespace {

// What every point of one object shares this frame.
struct ObjectFrame {
    glm::mat4 model;
    glm::mat3 model3;
    glm::mat3 normal_matrix;
    glm::mat4 view_matrix;
    glm::mat4 view_projection;
    // The eye, and for an orthographic projection (w' independent of z)
    // the direction back along the parallel rays.
    glm::vec3 eye;
    bool orthographic = false;
    glm::vec3 back;
    // A pixel's size across the screen at clip w: 2 w / (P[1][1] height)
    // (glm::perspective: w is the depth, and P[1][1] = 1 / tan(fov / 2)).
    double pixel_per_w = 0.0;
    double texels_per_unit = 1.0;  // along the surface, where a triangle has no uv area
    glm::dmat2 uv_to_texels{1.0};  // mesh uv to texels of the traced texture
    const MaterialDesc* material = nullptr;
    double handed = 1.0;           // the model's handedness (-1: mirrored)
};

// Per triangle (its points are consecutive): the unit vectors from its
// corners to the eye, its texel density and its world-to-object area scale.
struct TriangleFrame {
    std::size_t triangle = static_cast<std::size_t>(-1);
    glm::dvec3 corner_to_eye[3];
    double density = 0.0;
    double area_scale = 1.0;
};

void update_triangle(TriangleFrame& tf, const SurfacePoint& sp, const ObjectFrame& f) {
    if (sp.triangle == tf.triangle) return;
    tf.triangle = sp.triangle;
    // Texels per world unit on this triangle: from its area in the texture
    // (uv transform and texture size) over its area in the world.
    glm::vec3 c[3];
    for (int k = 0; k < 3; ++k) {
        c[k] = glm::vec3(f.model * glm::vec4(sp.corners[k], 1.0f));
        const glm::dvec3 to = f.orthographic ? glm::dvec3(f.back) : glm::dvec3(f.eye - c[k]);
        const double len = glm::length(to);
        tf.corner_to_eye[k] = len > 0.0 ? to / len : glm::dvec3(0.0);
    }
    const double world_triangle = 0.5 * glm::length(glm::cross(c[1] - c[0], c[2] - c[0]));
    const glm::dvec2 t1 = f.uv_to_texels * glm::dvec2(sp.corner_uvs[1] - sp.corner_uvs[0]);
    const glm::dvec2 t2 = f.uv_to_texels * glm::dvec2(sp.corner_uvs[2] - sp.corner_uvs[0]);
    const double texel_triangle = 0.5 * std::fabs(t1.x * t2.y - t1.y * t2.x);
    tf.density = world_triangle > 0.0 && texel_triangle > 0.0 ? std::sqrt(texel_triangle / world_triangle)
                                                              : f.texels_per_unit;
    const double object_triangle =
        0.5 * static_cast<double>(glm::length(glm::cross(sp.corners[1] - sp.corners[0], sp.corners[2] - sp.corners[0])));
    tf.area_scale = world_triangle / std::max(1e-30, object_triangle);
}

// The view vector in the point's tangent frame, exact and as interpolated
// from the corners (per vertex): what a per-vertex view adds, and the
// view's azimuth sector in the field's uv.
void view_in_tangent_frame(PointView& pv, const SurfacePoint& sp, const glm::vec3& n, const glm::vec3& to_eye,
                           const TriangleFrame& tf, const ObjectFrame& f) {
    glm::vec3 t = glm::vec3(f.model3 * glm::vec3(sp.tangent));
    t = t - n * glm::dot(n, t);
    t = glm::length(t) > 0.0f ? glm::normalize(t) : glm::vec3(1.0f, 0.0f, 0.0f);
    const glm::vec3 b = glm::cross(n, t);
    auto in_frame = [&](const glm::vec3& v) { return glm::dvec3(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)); };
    const glm::dvec3 exact = glm::normalize(in_frame(to_eye));
    // The frame is orthonormal: interpolate the corners' unit vectors in
    // the world, then express the result in it.
    const glm::dvec3 mixed = static_cast<double>(sp.bary.x) * tf.corner_to_eye[0] +
                             static_cast<double>(sp.bary.y) * tf.corner_to_eye[1] +
                             static_cast<double>(sp.bary.z) * tf.corner_to_eye[2];
    const glm::dvec3 interpolated(glm::dot(mixed, glm::dvec3(t)), glm::dot(mixed, glm::dvec3(b)),
                                  glm::dot(mixed, glm::dvec3(n)));
    // The view's azimuth in the field's uv (as the search model's rays are
    // given): the frame's x is +u, its y +v with the mesh's handedness
    // (surface.vert), then the material's uv transform.
    const double handed = (sp.tangent.w < 0.0f ? -1.0 : 1.0) * f.handed;
    const glm::dvec2 mesh_uv(exact.x, exact.y * handed);
    const glm::dvec2 in_uv = f.material ? f.material->uv.matrix<double>() * mesh_uv : mesh_uv;
    pv.sector = search_sector(in_uv.x, in_uv.y);
    if (interpolated.z > 1e-9) {
        pv.pv_parallax = glm::length(glm::dvec2(interpolated) / interpolated.z - glm::dvec2(exact) / exact.z);
        pv.pv_offset = glm::length(glm::dvec2(interpolated) - glm::dvec2(exact));
    } else {
        pv.pv_parallax = pv.pv_offset = 1e9;
    }
}

// The lights above the point's horizon (a bit each, the first 32) and the
// lowest one's elevation.
void light_point(PointView& pv, const glm::vec3& p, const glm::vec3& n, const std::vector<LightDesc>& lights) {
    pv.lit = 0;
    pv.light_elevation_deg = 90.0;
    const size_t light_count = std::min<size_t>(lights.size(), 32);
    for (size_t l = 0; l < light_count; ++l) {
        const LightDesc& light = lights[l];
        const glm::vec3 to_light = light.kind == LightKind::point ? light.position - p : -light.direction;
        const float length = glm::length(to_light);
        if (!(length > 0.0f)) continue;
        const float sine = glm::dot(n, to_light) / length;
        // A light's disc (soft shadows) reaches its angular radius below
        // its centre: part of it is above the horizon until the centre is
        // that far below (the renderer's soft visibility and the exact
        // reference both light that part).
        const double reach = std::sin(glm::radians(std::clamp(static_cast<double>(light.angular_radius_deg), 0.0, 90.0)));
        if (sine > -reach && (sine > 0.0f || reach > 0.0)) {
            pv.lit |= 1u << l;
            pv.light_elevation_deg =
                std::min(pv.light_elevation_deg, glm::degrees(std::asin(std::clamp(static_cast<double>(sine), -1.0, 1.0))));
        }
    }
}

// The ranges of an object's visible points.
struct ViewRanges {
    double angle_lo = 90.0, angle_hi = 0.0, dist_lo = std::numeric_limits<double>::max(), dist_hi = 0.0;
    double mip_lo = std::numeric_limits<double>::max(), mip_hi = -std::numeric_limits<double>::max();
    unsigned lit_any = 0;

    void add(const PointView& pv, double distance, const glm::vec3& ndc, glm::vec4& screen_box) {
        lit_any |= pv.lit;
        angle_lo = std::min(angle_lo, pv.angle_deg);
        angle_hi = std::max(angle_hi, pv.angle_deg);
        dist_lo = std::min(dist_lo, distance);
        dist_hi = std::max(dist_hi, distance);
        const double mip = std::log2(std::max(pv.rho, 1e-9));
        mip_lo = std::min(mip_lo, mip);
        mip_hi = std::max(mip_hi, mip);
        screen_box = glm::vec4(std::min(screen_box.x, ndc.x), std::min(screen_box.y, ndc.y),
                               std::max(screen_box.z, ndc.x), std::max(screen_box.w, ndc.y));
    }
    void finish(ObjectView& view) const {
        view.angle_min_deg = angle_lo;
        view.angle_max_deg = angle_hi;
        view.distance_min = dist_lo;
        view.distance_max = dist_hi;
        view.mip_min = mip_lo;
        view.mip_max = mip_hi;
        for (unsigned bits = lit_any; bits; bits &= bits - 1) ++view.lights_above_horizon;
    }
};

}  // namespace

ObjectView ScenePlanner::Impl::view_object(size_t oi, const PlanView& frame, std::vector<PointView>& points,
                                           glm::vec4& screen_box, std::pair<glm::vec3, glm::vec3>& world_box) const {
    ObjectView view;
    points.clear();
    const ObjectDesc& object = scene.objects[oi];
    const size_t mi = scene.material_index(object.material);
    ObjectFrame f;
    f.material = scene.find_material(object.material);
    f.model = frame.models.empty() ? object.transform.matrix() : frame.models[oi];
    f.model3 = glm::mat3(f.model);
    f.normal_matrix = glm::inverseTranspose(f.model3);
    f.view_matrix = frame.view;
    f.view_projection = frame.projection * frame.view;
    const glm::mat4 inverse_view = glm::inverse(frame.view);
    f.eye = glm::vec3(inverse_view[3]);
    f.orthographic = frame.projection[2][3] == 0.0f;
    f.back = glm::normalize(glm::vec3(inverse_view[2]));
    f.pixel_per_w = 2.0 / (std::fabs(static_cast<double>(frame.projection[1][1])) * frame.height);
    f.handed = glm::determinant(f.model3) < 0.0f ? -1.0 : 1.0;
    // Texels per world unit along the surface: the traced texture's texels
    // per tile over the world units a tile spans (renderer: units_per_tile).
    const double model_scale = std::cbrt(std::fabs(static_cast<double>(glm::determinant(f.model3))));
    const double tiles_per_unit = f.material ? f.material->uv.area_scale<double>() /
                                                   std::max(1e-12, static_cast<double>(units_per_uv[oi]) * model_scale)
                                             : 1.0;
    f.texels_per_unit = (mi < reliefs.size() ? std::max(1, reliefs[mi].traced_width) : 1) * tiles_per_unit;
    if (f.material && mi < reliefs.size()) {
        const glm::dmat2 texels(static_cast<double>(std::max(1, reliefs[mi].traced_width)), 0.0, 0.0,
                                static_cast<double>(std::max(1, reliefs[mi].traced_height)));
        f.uv_to_texels = texels * f.material->uv.matrix<double>();
    }

    const ObjectSurvey& survey = surveys[oi];
    world_box = transformed_box(survey.box_min, survey.box_max, f.model);
    screen_box = glm::vec4(2.0f, 2.0f, -2.0f, -2.0f);
    // Few big triangles: the visible part of each, this frame.
    std::vector<SurfacePoint> visible;
    if (!survey.triangles.empty())
        visible = clipped_points(survey, f.view_projection * f.model, frame.width, frame.height);
    const std::vector<SurfacePoint>& surface = survey.triangles.empty() ? survey.points : visible;
    points.reserve(surface.size());
    ViewRanges ranges;
    TriangleFrame tf;
    tf.density = f.texels_per_unit;
    for (const SurfacePoint& sp : surface) {
        const glm::vec3 p = glm::vec3(f.model * glm::vec4(sp.position, 1.0f));
        glm::vec3 n = f.normal_matrix * sp.normal;
        if (!(glm::length(n) > 0.0f)) continue;
        n = glm::normalize(n);
        const glm::vec3 to_eye =
            f.orthographic ? f.back * std::max(1e-3f, -(f.view_matrix * glm::vec4(p, 1.0f)).z) : f.eye - p;
        const double distance = glm::length(to_eye);
        if (!(distance > 0.0)) continue;
        const double cos_view = glm::dot(n, to_eye) / distance;
        if (!(cos_view > 1e-6)) continue;  // back-facing: culled
        const glm::vec4 clip = f.view_projection * glm::vec4(p, 1.0f);
        if (!(clip.w > 0.0f)) continue;
        const glm::vec3 ndc = glm::vec3(clip) / clip.w;
        if (std::fabs(ndc.x) > 1.0f || std::fabs(ndc.y) > 1.0f || std::fabs(ndc.z) > 1.0f) continue;
        const double depth = -(f.view_matrix * glm::vec4(p, 1.0f)).z;
        // A pixel's width across the ray at this point: the pixel's angle
        // shrinks off axis as cos(off-axis angle) (depth / distance).
        const double pixel_world = f.orthographic ? f.pixel_per_w * static_cast<double>(clip.w)
                                                  : f.pixel_per_w * static_cast<double>(clip.w) * (depth / distance);
        update_triangle(tf, sp, f);
        PointView pv;
        pv.angle_deg = glm::degrees(std::acos(std::min(1.0, cos_view)));
        pv.rho = tf.density * pixel_world / cos_view;
        pv.weight = sp.pixels >= 0.0 ? sp.pixels : tf.area_scale * sp.area * cos_view / (pixel_world * pixel_world);
        view_in_tangent_frame(pv, sp, n, to_eye, tf, f);
        light_point(pv, p, n, scene.lights);
        points.push_back(pv);
        view.pixels += pv.weight;
        ranges.add(pv, distance, ndc, screen_box);
    }
    view.visible = !points.empty();
    if (view.visible) ranges.finish(view);
    return view;
}

}  // namespace px
