// The survey of an object's surface the planner predicts over: points
// fixed for a fine mesh, and each frame the visible part of a coarse one.
#include "planner_detail.h"

#include <algorithm>
#include <cmath>

namespace px {
namespace planning {

// Points on the visible part of every triangle of `survey` this frame, up
// to kMaxSurfacePoints in all, spread in proportion to pixels: each triangle
// is clipped in clip space against the six planes of the view volume (its
// barycentric coordinates carried along, linear there), the polygon left is
// fanned into triangles on the screen, and each gets a barycentric grid of
// points (perspective-correct back to the triangle), each standing for its
// share of the pixels.
namespace {

struct ClipVertex {
    glm::dvec4 clip;
    glm::dvec3 bary;
};

// A screen triangle of the visible part of survey triangle `triangle`.
struct Piece {
    ClipVertex v[3];
    double pixels;
    std::size_t triangle;
};

// Triangle `tri` clipped in clip space to the view volume: Sutherland-Hodgman
// against w +- x >= 0, w +- y >= 0, w +- z >= 0, a hair inside so that every
// point lands within the view. Empty where nothing of it is inside.
std::vector<ClipVertex> clip_to_view(const SurveyTriangle& tri, const glm::dmat4& mvp) {
    std::vector<ClipVertex> poly(3);
    for (int c = 0; c < 3; ++c) {
        poly[static_cast<size_t>(c)].clip = mvp * glm::dvec4(glm::dvec3(tri.position[c]), 1.0);
        poly[static_cast<size_t>(c)].bary = glm::dvec3(c == 0, c == 1, c == 2);
    }
    // Wholly outside one plane (most triangles of a big mesh): skipped.
    for (int plane = 0; plane < 6; ++plane) {
        const int axis = plane / 2;
        const double sign = (plane % 2) ? -1.0 : 1.0;
        bool outside = true;
        for (const ClipVertex& v : poly) outside = outside && v.clip.w - sign * v.clip[axis] < 0.0;
        if (outside) return {};
    }
    constexpr double kInside = 1.0 - 1e-6;
    for (int plane = 0; plane < 6 && !poly.empty(); ++plane) {
        const int axis = plane / 2;
        const double sign = (plane % 2) ? -1.0 : 1.0;
        auto distance = [&](const ClipVertex& v) { return kInside * v.clip.w - sign * v.clip[axis]; };
        std::vector<ClipVertex> out;
        for (size_t i = 0; i < poly.size(); ++i) {
            const ClipVertex& a = poly[i];
            const ClipVertex& b = poly[(i + 1) % poly.size()];
            const double da = distance(a), db = distance(b);
            if (da >= 0.0) out.push_back(a);
            if ((da >= 0.0) != (db >= 0.0)) {
                const double s = da / (da - db);
                out.push_back({a.clip + s * (b.clip - a.clip), a.bary + s * (b.bary - a.bary)});
            }
        }
        poly = std::move(out);
    }
    return poly;
}

// Points on `piece` by its share of the pixels (at least one): a
// barycentric grid, perspective-correct back to the survey triangle.
void spread_points(const Piece& piece, const SurveyTriangle& tri, double share, std::vector<SurfacePoint>& points) {
    int k = 1;
    while ((k + 1) * (k + 2) / 2 <= share && k < 24) ++k;
    const int count = k * (k + 1) / 2;
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k - i; ++j) {
            const double s1 = (i + 1.0 / 3.0) / k, s2 = (j + 1.0 / 3.0) / k, s0 = 1.0 - s1 - s2;
            const double w0 = s0 / piece.v[0].clip.w, w1 = s1 / piece.v[1].clip.w, w2 = s2 / piece.v[2].clip.w;
            const glm::dvec3 bary = (w0 * piece.v[0].bary + w1 * piece.v[1].bary + w2 * piece.v[2].bary) / (w0 + w1 + w2);
            SurfacePoint p;
            p.bary = glm::vec3(bary);
            for (int c = 0; c < 3; ++c) {
                p.corners[c] = tri.position[c];
                p.corner_uvs[c] = tri.uv[c];
            }
            p.position = p.bary.x * tri.position[0] + p.bary.y * tri.position[1] + p.bary.z * tri.position[2];
            const glm::vec3 n = p.bary.x * tri.normal[0] + p.bary.y * tri.normal[1] + p.bary.z * tri.normal[2];
            p.normal = glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f, 0.0f, 1.0f);
            p.tangent = tri.tangent;
            p.triangle = piece.triangle;
            p.pixels = piece.pixels / count;
            points.push_back(p);
        }
}

}  // namespace

std::vector<SurfacePoint> clipped_points(const ObjectSurvey& survey, const glm::mat4& model_view_projection,
                                         int width, int height) {
    std::vector<Piece> pieces;
    double total = 0.0;
    const glm::dmat4 mvp(model_view_projection);
    auto screen = [&](const ClipVertex& v) {
        return glm::dvec2((v.clip.x / v.clip.w + 1.0) * 0.5 * width, (v.clip.y / v.clip.w + 1.0) * 0.5 * height);
    };
    for (std::size_t t = 0; t < survey.triangles.size(); ++t) {
        const std::vector<ClipVertex> poly = clip_to_view(survey.triangles[t], mvp);
        if (poly.size() < 3) continue;
        // The polygon fanned into triangles on the screen.
        for (size_t i = 1; i + 1 < poly.size(); ++i) {
            const glm::dvec2 a = screen(poly[0]), b = screen(poly[i]), c = screen(poly[i + 1]);
            const double pixels = 0.5 * std::fabs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
            if (!(pixels > 0.0) || !std::isfinite(pixels)) continue;
            pieces.push_back({{poly[0], poly[i], poly[i + 1]}, pixels, t});
            total += pixels;
        }
    }
    std::vector<SurfacePoint> points;
    if (!(total > 0.0)) return points;
    for (const Piece& piece : pieces)
        spread_points(piece, survey.triangles[piece.triangle],
                      static_cast<double>(kMaxSurfacePoints) * piece.pixels / total, points);
    return points;
}

ObjectSurvey survey_mesh(const Mesh& mesh) {
    ObjectSurvey s;
    if (mesh.vertices.empty()) return s;
    s.box_min = s.box_max = mesh.vertices[0].position;
    for (const Vertex& v : mesh.vertices) {
        s.box_min = glm::min(s.box_min, v.position);
        s.box_max = glm::max(s.box_max, v.position);
    }
    const size_t triangles = mesh.indices.size() / 3;
    if (triangles == 0) return s;
    if (triangles <= kMaxClippedTriangles)
        for (size_t t = 0; t < triangles; ++t) {
            SurveyTriangle tri;
            bool ok = true;
            for (int c = 0; c < 3 && ok; ++c) {
                const std::uint32_t i = mesh.indices[3 * t + static_cast<size_t>(c)];
                if (i >= mesh.vertices.size()) {
                    ok = false;
                    break;
                }
                tri.position[c] = mesh.vertices[i].position;
                tri.normal[c] = mesh.vertices[i].normal;
                tri.uv[c] = mesh.vertices[i].uv;
                if (c == 0) tri.tangent = mesh.vertices[i].tangent;
            }
            if (ok) s.triangles.push_back(tri);
        }
    // Points per triangle on a barycentric grid (k(k+1)/2 of them), or every
    // stride-th triangle's centre when the mesh has more triangles than points.
    int k = 1;
    while ((k + 1) * (k + 2) / 2 * triangles <= static_cast<size_t>(kMaxSurfacePoints) && k < 24) ++k;
    const size_t stride = std::max<size_t>(1, triangles / kMaxSurfacePoints);
    for (size_t t = 0; t < triangles; t += stride) {
        const Vertex* v[3];
        bool ok = true;
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t i = mesh.indices[3 * t + static_cast<size_t>(c)];
            if (i >= mesh.vertices.size()) ok = false;
            v[c] = ok ? &mesh.vertices[i] : nullptr;
        }
        if (!ok) continue;
        const float area = 0.5f * glm::length(glm::cross(v[1]->position - v[0]->position, v[2]->position - v[0]->position));
        const int points = k * (k + 1) / 2;
        for (int i = 0; i < k; ++i)
            for (int j = 0; j < k - i; ++j) {
                SurfacePoint p;
                const float b1 = (static_cast<float>(i) + 1.0f / 3.0f) / static_cast<float>(k);
                const float b2 = (static_cast<float>(j) + 1.0f / 3.0f) / static_cast<float>(k);
                p.bary = glm::vec3(1.0f - b1 - b2, b1, b2);
                for (int c = 0; c < 3; ++c) {
                    p.corners[c] = v[c]->position;
                    p.corner_uvs[c] = v[c]->uv;
                }
                p.position = p.bary.x * v[0]->position + p.bary.y * v[1]->position + p.bary.z * v[2]->position;
                const glm::vec3 n = p.bary.x * v[0]->normal + p.bary.y * v[1]->normal + p.bary.z * v[2]->normal;
                p.normal = glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f, 0.0f, 1.0f);
                p.tangent = v[0]->tangent;
                p.area = area * static_cast<float>(stride) / static_cast<float>(points);
                p.triangle = t;
                s.points.push_back(p);
            }
    }
    return s;
}

}  // namespace planning
}  // namespace px
