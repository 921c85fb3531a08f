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
#include "parallaxes/planner/planner.h"
#include "parallaxes/planner/object_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <map>
#include <tuple>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "parallaxes/core/counters.h"
#include "parallaxes/core/text.h"

namespace px {

namespace {

constexpr int kMaxSurfacePoints = 320;  // per object: enough for the percentiles, cheap per frame


std::string fmt(const char* format, double a) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, format, a);
    return buffer;
}

// A point of an object's surface, in object space, with its triangle.
struct SurfacePoint {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec4 tangent;
    glm::vec3 corners[3];
    glm::vec2 corner_uvs[3];  // mesh uv
    glm::vec3 bary;
    float area = 0.0f;  // object-space area this point stands for
    std::size_t triangle = 0;  // points of one triangle are consecutive
    // Pixels this point stands for, where the survey sampled the triangle's
    // visible part on the screen (clipped_points); < 0: from `area`.
    double pixels = -1.0;
};

// A triangle as drawn, for a survey of its visible part.
struct SurveyTriangle {
    glm::vec3 position[3];
    glm::vec3 normal[3];
    glm::vec2 uv[3];
    glm::vec4 tangent;
};

// Meshes of at most this many triangles (quads, cubes, coarse planes) are
// surveyed per frame on what the camera sees: each triangle clipped to the
// view volume and sampled in proportion to its pixels, so a single quad
// that fills the image (its precomputed points all outside the view) gets
// the decision a tessellated one gets. Finer meshes keep their
// precomputed points, dense enough on the surface.
constexpr std::size_t kMaxClippedTriangles = 4096;

struct ObjectSurvey {
    std::vector<SurfacePoint> points;
    std::vector<SurveyTriangle> triangles;  // when the mesh has at most kMaxClippedTriangles
    glm::vec3 box_min{0.0f}, box_max{0.0f};  // object space
};

// Points on the visible part of every triangle of `survey` this frame, up
// to kMaxSurfacePoints in all, spread in proportion to pixels: each triangle
// is clipped in clip space against the six planes of the view volume (its
// barycentric coordinates carried along, linear there), the polygon left is
// fanned into triangles on the screen, and each gets a barycentric grid of
// points (perspective-correct back to the triangle), each standing for its
// share of the pixels.
std::vector<SurfacePoint> clipped_points(const ObjectSurvey& survey, const glm::mat4& model_view_projection,
                                         int width, int height) {
    struct ClipVertex {
        glm::dvec4 clip;
        glm::dvec3 bary;
    };
    struct Piece {
        ClipVertex v[3];
        double pixels;
        std::size_t triangle;
    };
    std::vector<Piece> pieces;
    double total = 0.0;
    const glm::dmat4 mvp(model_view_projection);
    for (std::size_t t = 0; t < survey.triangles.size(); ++t) {
        const SurveyTriangle& tri = survey.triangles[t];
        std::vector<ClipVertex> poly(3);
        for (int c = 0; c < 3; ++c) {
            poly[static_cast<size_t>(c)].clip = mvp * glm::dvec4(glm::dvec3(tri.position[c]), 1.0);
            poly[static_cast<size_t>(c)].bary = glm::dvec3(c == 0, c == 1, c == 2);
        }
        // Wholly outside one plane (most triangles of a big mesh): skipped.
        bool outside = false;
        for (int plane = 0; plane < 6 && !outside; ++plane) {
            const int axis = plane / 2;
            const double sign = (plane % 2) ? -1.0 : 1.0;
            outside = true;
            for (const ClipVertex& v : poly) outside = outside && v.clip.w - sign * v.clip[axis] < 0.0;
        }
        if (outside) continue;
        // Sutherland-Hodgman against w +- x >= 0, w +- y >= 0, w +- z >= 0,
        // a hair inside so that every point lands within the view.
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
        if (poly.size() < 3) continue;
        auto screen = [&](const ClipVertex& v) {
            return glm::dvec2((v.clip.x / v.clip.w + 1.0) * 0.5 * width, (v.clip.y / v.clip.w + 1.0) * 0.5 * height);
        };
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
    for (const Piece& piece : pieces) {
        // Points for this piece by its share of the pixels (at least one).
        const double share = static_cast<double>(kMaxSurfacePoints) * piece.pixels / total;
        int k = 1;
        while ((k + 1) * (k + 2) / 2 <= share && k < 24) ++k;
        const int count = k * (k + 1) / 2;
        const SurveyTriangle& tri = survey.triangles[piece.triangle];
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

// One visible point, this frame.
struct PointView {
    double angle_deg;   // from the surface normal
    double rho;         // texels per pixel (major axis of the footprint)
    double weight;      // pixels on screen
    double pv_parallax; // per-vertex view: |delta (V.xy / V.z)| (unitless; times depth in texels)
    double pv_offset;   // per-vertex view: |delta V.xy| (offset limiting)
    unsigned lit;       // bit per light: the light is above this point's horizon
    double light_elevation_deg;  // the lowest light above the horizon: what shadows depend on
    int sector = 0;     // the view's azimuth sector in the field (search_sector)
};

// Linear interpolation in a table sorted by x, clamped at the ends.
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
    if (xs.empty()) return 0.0;
    if (x <= xs.front()) return ys.front();
    if (x >= xs.back()) return ys.back();
    const size_t i = static_cast<size_t>(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin());
    const double t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
    return ys[i - 1] + t * (ys[i] - ys[i - 1]);
}

struct Curve {
    std::vector<double> angles, error, visibility, cost;
    // A search model's curve: per angle, the raw simulated error at each of
    // kSearchLevels (base texels), pooled over an object's pixels.
    std::vector<std::vector<double>> levels;
    // The same per angle and azimuth sector (search_sector).
    std::vector<std::vector<std::vector<double>>> sector_levels;
};

// relief, technique, samples, shadow, shadow samples, light elevation (tenths of a degree; 0 unshadowed)
using CurveKey = std::tuple<int, Technique, int, ShadowMode, int, int>;

std::map<CurveKey, Curve> curves_of(const CostTable& table) {
    std::map<CurveKey, std::vector<const CostSample*>> grouped;
    for (const CostSample& s : table.rows)
        grouped[{s.relief, s.technique, s.samples, s.shadow, s.shadow_samples,
                 s.shadow == ShadowMode::none ? 0 : static_cast<int>(std::lround(s.light_elevation_deg * 10.0))}]
            .push_back(&s);
    std::map<CurveKey, Curve> out;
    for (auto& [key, rows] : grouped) {
        std::sort(rows.begin(), rows.end(), [](const CostSample* a, const CostSample* b) { return a->angle_deg < b->angle_deg; });
        Curve c;
        for (const CostSample* r : rows) {
            if (!c.angles.empty() && r->angle_deg == c.angles.back()) continue;
            c.angles.push_back(r->angle_deg);
            c.error.push_back(r->error_p95);
            c.visibility.push_back(r->visibility_error);
            c.cost.push_back(r->cost);
        }
        out.emplace(key, std::move(c));
    }
    // Timings are noisy (shared machines, few pixels at grazing angles):
    // where a technique was measured at several sample counts, a count
    // costs at least what any smaller one does at the same angle, so that
    // noise never makes more samples look cheaper than fewer.
    // One pass: the map orders keys by relief, technique, then samples, so
    // the curves of one (relief, technique, shadow, shadow samples,
    // elevation) and angle grid come in increasing sample counts, and each
    // takes the running maximum of the ones before it (a table of many
    // sample counts stays n log n, not quadratic).
    using Group = std::tuple<int, Technique, ShadowMode, int, int, std::vector<double>>;
    std::map<Group, std::vector<double>> running;
    for (auto& [key, curve] : out) {
        const auto& [relief, technique, samples, shadow, shadow_samples, elevation] = key;
        (void)samples;
        std::vector<double>& most = running[Group{relief, technique, shadow, shadow_samples, elevation, curve.angles}];
        if (most.size() == curve.cost.size())
            for (size_t k = 0; k < curve.cost.size(); ++k) curve.cost[k] = std::max(curve.cost[k], most[k]);
        most = curve.cost;
    }
    return out;
}

// The reliefs of a table nearest in character to `f`: thinnest feature and
// steepness, on log scales.
int nearest_relief(const CostTable& table, const ReliefFeatures& f, const std::vector<bool>& eligible) {
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < table.reliefs.size(); ++i) {
        if (!eligible[i]) continue;
        const ReliefFeatures& r = table.reliefs[i].features;
        const double d = std::fabs(std::log2((f.thinnest_texels + 0.5) / (r.thinnest_texels + 0.5))) +
                         2.0 * std::fabs(std::log2(std::max(f.steepness, 0.02) / std::max(r.steepness, 0.02)));
        if (d < best_d) {
            best_d = d;
            best = static_cast<int>(i);
        }
    }
    return best;
}

// A calibration that measured errors but not times ("costs": "table"):
// each curve priced from the generic table's curve of the same candidate on
// the generic relief nearest to the calibrated one, at the calibration's
// angles (a step-bounded technique at whatever bound the table measured). A
// shadowed curve gets its unshadowed twin's price plus the shadow's
// overhead the table measured on its nearest shadowed relief. Curves the
// table cannot price are dropped (no candidate without a cost).
void price_from_generic(const CostTable& calibration, std::map<CurveKey, Curve>& curves, const CostTable& generic,
                        const std::map<CurveKey, Curve>& generic_curves) {
    const auto find = [&](int relief, Technique t, int samples, ShadowMode shadow, int ss, int elevation) -> const Curve* {
        const bool steps = technique_info(t).options & kOptSteps;
        for (auto it = generic_curves.lower_bound(CurveKey{relief, t, 0, ShadowMode::none, 0, 0});
             it != generic_curves.end(); ++it) {
            const auto& [r, tt, n, sh, k, e] = it->first;
            if (r != relief || tt != t) break;
            if ((n == samples || steps) && sh == shadow && k == ss && e == elevation && !it->second.angles.empty())
                return &it->second;
        }
        return nullptr;
    };
    std::vector<bool> all(generic.reliefs.size(), true);
    std::map<CurveKey, Curve> priced;
    // Unshadowed curves first: a shadowed one is priced over its twin.
    for (const bool shadowed : {false, true})
        for (const auto& [key, c] : curves) {
            const auto& [relief, t, samples, shadow, ss, elevation] = key;
            if ((shadow != ShadowMode::none) != shadowed) continue;
            if (relief < 0 || static_cast<size_t>(relief) >= calibration.reliefs.size()) continue;
            const ReliefFeatures& f = calibration.reliefs[static_cast<size_t>(relief)].features;
            Curve out = c;
            if (!shadowed) {
                const Curve* g = find(nearest_relief(generic, f, all), t, samples, ShadowMode::none, 0, 0);
                if (!g) continue;
                for (size_t k = 0; k < out.angles.size(); ++k) out.cost[k] = interpolate(g->angles, g->cost, out.angles[k]);
            } else {
                std::vector<bool> eligible(generic.reliefs.size(), false);
                for (const CostSample& row : generic.rows)
                    if (row.shadow == shadow) eligible[static_cast<size_t>(row.relief)] = true;
                const int near = nearest_relief(generic, f, eligible);
                const Curve* g = find(near, t, samples, shadow, ss, elevation);
                const Curve* g_twin = find(near, t, samples, ShadowMode::none, 0, 0);
                auto twin = priced.find(CurveKey{relief, t, samples, ShadowMode::none, 0, 0});
                if (!g || !g_twin || twin == priced.end()) continue;
                for (size_t k = 0; k < out.angles.size(); ++k) {
                    const double a = out.angles[k];
                    out.cost[k] = interpolate(twin->second.angles, twin->second.cost, a) +
                                  std::max(0.0, interpolate(g->angles, g->cost, a) - interpolate(g_twin->angles, g_twin->cost, a));
                }
            }
            priced.emplace(key, std::move(out));
        }
    curves = std::move(priced);
}

// A candidate the planner weighs.
struct Candidate {
    Technique technique;
    int samples;
    bool exact_view;
    bool lod;
};

std::string candidate_name(const Candidate& c) {
    std::string s = technique_name(c.technique);
    if (c.samples > 0) s += (technique_info(c.technique).options & kOptSteps ? " steps<=" : " x") + std::to_string(c.samples);
    if (!c.exact_view && (technique_info(c.technique).options & kOptHeight) && !technique_info(c.technique).always_exact_view)
        s += " per-vertex-view";
    if (c.lod) s += " lod";
    return s;
}

// The p95 of (value, weight) pairs, by weight.
// The value at which the weights of the values up to it first reach
// `share` of `total` (values, weights), as a sort followed by a running sum
// would find it, in expected linear time: quickselect, keeping the weight
// of everything left of the part still searched. Reorders `v`.
double weighted_quantile(std::vector<std::pair<double, double>>& v, double share, double total) {
    if (v.empty()) return 0.0;
    const double target = share * total;
    auto lo = v.begin(), hi = v.end();
    double before = 0.0;  // the weight of [begin, lo): values no larger than those in [lo, hi)
    while (hi - lo > 1) {
        const auto middle = lo + (hi - lo) / 2;
        std::nth_element(lo, middle, hi, [](const auto& a, const auto& b) { return a.first < b.first; });
        double below = 0.0;  // [lo, middle): values up to the middle one
        for (auto it = lo; it < middle; ++it) below += it->second;
        if (before + below >= target) {
            hi = middle;
        } else if (before + below + middle->second >= target) {
            return middle->first;
        } else {
            before += below + middle->second;
            lo = middle + 1;
        }
    }
    // One left; or none, where rounding kept the sum under the target to the end.
    return lo != v.end() ? lo->first : std::max_element(v.begin(), v.end())->first;
}

double weighted_p95(std::vector<std::pair<double, double>>& v) {
    double total = 0.0;
    for (const auto& e : v) total += e.second;
    return weighted_quantile(v, 0.95, total);
}

}  // namespace

struct ScenePlanner::Impl {
    SceneDesc scene;
    Caps caps;
    std::vector<MaterialRelief> reliefs;
    CostTable generic;
    std::vector<CostTable> calibrations;
    std::map<CurveKey, Curve> generic_curves;
    std::vector<std::map<CurveKey, Curve>> calibration_curves;
    std::vector<std::string> calibration_notes;  // per material: why its calibration file was not used
    std::vector<ObjectSurvey> surveys;
    std::vector<float> units_per_uv;  // per object: world units per mesh uv unit
    // Per material that names its technique: plan_variant, run once here.
    std::vector<std::optional<VariantPlan>> named_plans;
    std::vector<OutlineRequest> outlines;  // per object
    // Per material with a search model: its curves as a one-relief table
    // (errors simulated with the margin, costs from the generic table).
    std::vector<std::optional<CostTable>> model_tables;
    std::vector<std::map<CurveKey, Curve>> model_curves;

    // Where a material's predictions come from.
    struct Source {
        const CostTable* table = nullptr;
        const std::map<CurveKey, Curve>* curves = nullptr;
        int relief = -1;
        double depth_scale = 1.0;  // material depth / table relief depth
        std::string label;
        bool simulated = false;    // the search model: step-overs already simulated
    };
    Source generic_source(const MaterialRelief& r) const;
    // The search model of material `mi`, if it has one.
    std::optional<Source> model_source(size_t mi) const;
    // The calibration of this very relief, if one can plan it; `skipped`
    // says why a matching one could not (it is then not used).
    // Only where it measured what this view needs: the view angles seen
    // (up to `angle_max_deg`), on this renderer.
    std::optional<Source> calibrated_source(const MaterialRelief& r, double angle_max_deg, std::string* skipped) const;

    Result<ObjectPlan> plan_object(size_t object_index, const std::vector<ObjectView>& views,
                                   const std::vector<std::vector<PointView>>& points,
                                   const std::vector<glm::vec4>& screen_boxes,
                                   const std::vector<std::pair<glm::vec3, glm::vec3>>& world_boxes,
                                   bool silhouette_on_screen) const;
    ObjectView view_object(size_t object_index, const PlanView& frame,
                           std::vector<PointView>& points, glm::vec4& screen_box,
                           std::pair<glm::vec3, glm::vec3>& world_box) const;
};

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
    // Each search model as a one-relief table: the simulated error with the
    // margin, the cost the generic table measured for the candidate on its
    // nearest relief (a candidate's time depends on its samples and the
    // view far more than on the relief), at the model's angles.
    m.model_tables.resize(m.reliefs.size());
    m.model_curves.resize(m.reliefs.size());
    for (size_t mi = 0; mi < m.reliefs.size(); ++mi) {
        const MaterialRelief& r = m.reliefs[mi];
        if (!r.search || r.search->angles.empty()) continue;
        const int nearest = m.generic_source(r).relief;
        if (nearest < 0) continue;
        std::map<CurveKey, Curve> curves;
        for (const SearchCurve& sc : r.search->curves) {
            if (sc.error.size() != r.search->angles.size() || sc.upper.size() != r.search->angles.size()) continue;
            // The generic curve of the candidate (maxmip: at whatever step
            // bound the table measured).
            const Curve* cost = nullptr;
            int samples = sc.samples;
            for (const auto& [key, c] : m.generic_curves) {
                const auto& [relief, technique, n, shadow, shadow_samples, elevation] = key;
                (void)shadow_samples;
                (void)elevation;
                if (relief != nearest || technique != sc.technique || shadow != ShadowMode::none) continue;
                const bool steps = technique_info(technique).options & kOptSteps;
                if (n != sc.samples && !steps) continue;
                cost = &c;
                samples = n;
                break;
            }
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
        t.date = m.generic.date;
        t.renderer = m.generic.renderer;
        t.version = m.generic.version;
        t.reliefs.push_back({"search model", r.features});
        m.model_tables[mi] = std::move(t);
        m.model_curves[mi] = std::move(curves);
    }
    if (options.calibrations) m.calibrations = *options.calibrations;
    m.calibration_notes.resize(m.reliefs.size());
    if (options.find_calibration) {
        // Once per relief: the field and its depth (two materials may share
        // a height map at different depths, and a calibration is of both).
        std::vector<std::pair<std::uint64_t, double>> asked;
        for (size_t mi = 0; mi < m.reliefs.size() && mi < scene.materials.size(); ++mi) {
            const ReliefFeatures& f = m.reliefs[mi].features;
            if (!(f.range > 0.0) || !scene.materials[mi].effects || !scene.materials[mi].effects->parallax) continue;
            const auto same = [&](const std::pair<std::uint64_t, double>& a) {
                return a.first == f.field_hash &&
                       std::fabs(a.second - f.depth_texels) <= 1e-3 * std::max(1.0, f.depth_texels);
            };
            if (std::find_if(asked.begin(), asked.end(), same) != asked.end()) continue;
            asked.emplace_back(f.field_hash, f.depth_texels);
            std::optional<CostTable> found = options.find_calibration(f, m.calibration_notes[mi]);
            if (found) m.calibrations.push_back(std::move(*found));
        }
    }
    for (const CostTable& c : m.calibrations) {
        m.calibration_curves.push_back(curves_of(c));
        if (!c.costs_measured) price_from_generic(c, m.calibration_curves.back(), m.generic, m.generic_curves);
    }
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        if (!meshes.empty()) {
            m.units_per_uv.push_back(meshes[i]->units_per_uv);
            m.surveys.push_back(survey_mesh(*meshes[i]));
            continue;
        }
        const Mesh mesh = build_object_mesh(scene.objects[i].mesh);
        m.units_per_uv.push_back(mesh.units_per_uv);
        m.surveys.push_back(survey_mesh(mesh));
    }
    for (size_t mi = 0; mi < scene.materials.size(); ++mi) {
        const MaterialDesc& material = scene.materials[mi];
        m.named_plans.emplace_back();
        if (material.effects) continue;
        Result<VariantPlan> named =
            plan_variant(material, caps, m.reliefs[mi].traced_width, m.reliefs[mi].traced_height);
        if (!named) return with_context("material '" + echo(material.name) + "'", named.error());
        m.named_plans.back() = std::move(*named);
    }
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        const size_t mi = scene.material_index(scene.objects[i].material);
        m.outlines.push_back(mi < scene.materials.size()
                                 ? outline_request(scene.objects[i], scene.materials[mi], m.units_per_uv[i])
                                 : OutlineRequest{});
    }
    return p;
}

}  // namespace

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
            if (!calibrations[c].costs_measured) {
                std::vector<bool> all(generic.reliefs.size(), true);
                const int near = nearest_relief(generic, f, all);
                s.label += "; errors measured, costs from table '" +
                           (near >= 0 ? generic.reliefs[static_cast<size_t>(near)].name : std::string("?")) + "'";
            }
            return s;
        }
    return std::nullopt;
}

ObjectView ScenePlanner::Impl::view_object(size_t oi, const PlanView& frame,
                                           std::vector<PointView>& points, glm::vec4& screen_box,
                                           std::pair<glm::vec3, glm::vec3>& world_box) const {
    ObjectView view;
    points.clear();
    const ObjectDesc& object = scene.objects[oi];
    const MaterialDesc* material = scene.find_material(object.material);
    const size_t mi = scene.material_index(object.material);
    const glm::mat4 model = frame.models.empty() ? object.transform.matrix() : frame.models[oi];
    const glm::mat3 model3(model);
    const glm::mat3 normal_matrix = glm::inverseTranspose(model3);
    const glm::mat4& view_matrix = frame.view;
    const glm::mat4& projection = frame.projection;
    const glm::mat4 view_projection = projection * view_matrix;
    // The eye, and for an orthographic projection (w' independent of z)
    // the direction back along the parallel rays.
    const glm::mat4 inverse_view = glm::inverse(view_matrix);
    const glm::vec3 eye(inverse_view[3]);
    const bool orthographic = projection[2][3] == 0.0f;
    const glm::vec3 back = glm::normalize(glm::vec3(inverse_view[2]));
    // A pixel's size across the screen at clip w: 2 w / (P[1][1] height)
    // (glm::perspective: w is the depth, and P[1][1] = 1 / tan(fov / 2)).
    const double pixel_per_w = 2.0 / (std::fabs(static_cast<double>(projection[1][1])) * frame.height);
    // Texels per world unit along the surface: the traced texture's texels
    // per tile over the world units a tile spans (renderer: units_per_tile).
    const double model_scale = std::cbrt(std::fabs(static_cast<double>(glm::determinant(model3))));
    const double tiles_per_unit = material ? material->uv.area_scale<double>() /
                                                 std::max(1e-12, static_cast<double>(units_per_uv[oi]) * model_scale)
                                           : 1.0;
    const double texels_per_unit = (mi < reliefs.size() ? std::max(1, reliefs[mi].traced_width) : 1) * tiles_per_unit;
    // Mesh uv to texels of the traced texture (the uv transform's linear part).
    glm::dmat2 uv_to_texels(1.0);
    if (material && mi < reliefs.size()) {
        const glm::dmat2 texels(static_cast<double>(std::max(1, reliefs[mi].traced_width)), 0.0, 0.0,
                                static_cast<double>(std::max(1, reliefs[mi].traced_height)));
        uv_to_texels = texels * material->uv.matrix<double>();
    }

    // World box and screen box.
    const ObjectSurvey& survey = surveys[oi];
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner((c & 1) ? survey.box_max.x : survey.box_min.x, (c & 2) ? survey.box_max.y : survey.box_min.y,
                               (c & 4) ? survey.box_max.z : survey.box_min.z);
        const glm::vec3 w = glm::vec3(model * glm::vec4(corner, 1.0f));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
    world_box = {lo, hi};
    screen_box = glm::vec4(2.0f, 2.0f, -2.0f, -2.0f);

    double angle_lo = 90.0, angle_hi = 0.0, dist_lo = std::numeric_limits<double>::max(), dist_hi = 0.0;
    double mip_lo = std::numeric_limits<double>::max(), mip_hi = -std::numeric_limits<double>::max();
    unsigned lit_any = 0;
    const size_t light_count = std::min<size_t>(scene.lights.size(), 32);
    std::size_t cached_triangle = static_cast<std::size_t>(-1);
    glm::dvec3 corner_to_eye[3];
    double density = texels_per_unit, area_scale = 1.0;
    // Few big triangles: the visible part of each, this frame.
    std::vector<SurfacePoint> visible;
    if (!survey.triangles.empty())
        visible = clipped_points(survey, view_projection * model, frame.width, frame.height);
    const std::vector<SurfacePoint>& surface = survey.triangles.empty() ? survey.points : visible;
    points.reserve(surface.size());
    for (const SurfacePoint& sp : surface) {
        const glm::vec3 p = glm::vec3(model * glm::vec4(sp.position, 1.0f));
        glm::vec3 n = normal_matrix * sp.normal;
        if (!(glm::length(n) > 0.0f)) continue;
        n = glm::normalize(n);
        const glm::vec3 to_eye =
            orthographic ? back * std::max(1e-3f, -(view_matrix * glm::vec4(p, 1.0f)).z) : eye - p;
        const double distance = glm::length(to_eye);
        if (!(distance > 0.0)) continue;
        const double cos_view = glm::dot(n, to_eye) / distance;
        if (!(cos_view > 1e-6)) continue;  // back-facing: culled
        const glm::vec4 clip = view_projection * glm::vec4(p, 1.0f);
        if (!(clip.w > 0.0f)) continue;
        const glm::vec3 ndc = glm::vec3(clip) / clip.w;
        if (std::fabs(ndc.x) > 1.0f || std::fabs(ndc.y) > 1.0f || std::fabs(ndc.z) > 1.0f) continue;
        const double depth = -(view_matrix * glm::vec4(p, 1.0f)).z;
        // A pixel's width across the ray at this point: the pixel's angle
        // shrinks off axis as cos(off-axis angle) (depth / distance).
        const double pixel_world = orthographic ? pixel_per_w * static_cast<double>(clip.w)
                                                : pixel_per_w * static_cast<double>(clip.w) * (depth / distance);
        // Texels per world unit on this triangle: from its area in the
        // texture (uv transform and texture size) over its area in the world.
        // Once per triangle (its points are consecutive): the corners in
        // the world, the unit vectors from them to the eye, the density.
        if (sp.triangle != cached_triangle) {
            cached_triangle = sp.triangle;
            glm::vec3 c[3];
            for (int k = 0; k < 3; ++k) {
                c[k] = glm::vec3(model * glm::vec4(sp.corners[k], 1.0f));
                const glm::dvec3 to = orthographic ? glm::dvec3(back) : glm::dvec3(eye - c[k]);
                const double len = glm::length(to);
                corner_to_eye[k] = len > 0.0 ? to / len : glm::dvec3(0.0);
            }
            const double world_triangle = 0.5 * glm::length(glm::cross(c[1] - c[0], c[2] - c[0]));
            const glm::dvec2 t1 = uv_to_texels * glm::dvec2(sp.corner_uvs[1] - sp.corner_uvs[0]);
            const glm::dvec2 t2 = uv_to_texels * glm::dvec2(sp.corner_uvs[2] - sp.corner_uvs[0]);
            const double texel_triangle = 0.5 * std::fabs(t1.x * t2.y - t1.y * t2.x);
            density = world_triangle > 0.0 && texel_triangle > 0.0 ? std::sqrt(texel_triangle / world_triangle)
                                                                   : texels_per_unit;
            const double object_triangle =
                0.5 * static_cast<double>(glm::length(glm::cross(sp.corners[1] - sp.corners[0], sp.corners[2] - sp.corners[0])));
            area_scale = world_triangle / std::max(1e-30, object_triangle);
        }
        const double rho = density * pixel_world / cos_view;
        const double world_area = area_scale * sp.area;
        PointView pv;
        pv.angle_deg = glm::degrees(std::acos(std::min(1.0, cos_view)));
        pv.rho = rho;
        pv.weight = sp.pixels >= 0.0 ? sp.pixels : world_area * cos_view / (pixel_world * pixel_world);
        // The tangent frame of the point.
        glm::vec3 t = glm::vec3(model3 * glm::vec3(sp.tangent));
        t = t - n * glm::dot(n, t);
        t = glm::length(t) > 0.0f ? glm::normalize(t) : glm::vec3(1.0f, 0.0f, 0.0f);
        const glm::vec3 b = glm::cross(n, t);
        auto in_frame = [&](const glm::vec3& v) { return glm::dvec3(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)); };
        const glm::dvec3 exact = glm::normalize(in_frame(to_eye));
        // The frame is orthonormal: interpolate the corners' unit vectors
        // in the world, then express the result in it.
        const glm::dvec3 mixed = static_cast<double>(sp.bary.x) * corner_to_eye[0] +
                                 static_cast<double>(sp.bary.y) * corner_to_eye[1] +
                                 static_cast<double>(sp.bary.z) * corner_to_eye[2];
        const glm::dvec3 interpolated(glm::dot(mixed, glm::dvec3(t)), glm::dot(mixed, glm::dvec3(b)),
                                      glm::dot(mixed, glm::dvec3(n)));
        // The view's azimuth in the field's uv (as the search model's rays
        // are given): the frame's x is +u, its y +v with the mesh's
        // handedness (surface.vert), then the material's uv transform.
        const double handed = (sp.tangent.w < 0.0f ? -1.0 : 1.0) * (glm::determinant(model3) < 0.0f ? -1.0 : 1.0);
        const glm::dvec2 mesh_uv(exact.x, exact.y * handed);
        const glm::dvec2 in_uv = material ? material->uv.matrix<double>() * mesh_uv : mesh_uv;
        pv.sector = search_sector(in_uv.x, in_uv.y);
        if (interpolated.z > 1e-9) {
            pv.pv_parallax = glm::length(glm::dvec2(interpolated) / interpolated.z - glm::dvec2(exact) / exact.z);
            pv.pv_offset = glm::length(glm::dvec2(interpolated) - glm::dvec2(exact));
        } else {
            pv.pv_parallax = pv.pv_offset = 1e9;
        }
        pv.lit = 0;
        pv.light_elevation_deg = 90.0;
        for (size_t l = 0; l < light_count; ++l) {
            const LightDesc& light = scene.lights[l];
            const glm::vec3 to_light = light.kind == LightKind::point ? light.position - p : -light.direction;
            const float length = glm::length(to_light);
            if (!(length > 0.0f)) continue;
            const float sine = glm::dot(n, to_light) / length;
            // A light's disc (soft shadows) reaches its angular radius below
            // its centre: part of it is above the horizon until the centre
            // is that far below (the renderer's soft visibility and the exact
            // reference both light that part).
            const double reach = std::sin(glm::radians(std::clamp(static_cast<double>(light.angular_radius_deg), 0.0, 90.0)));
            if (sine > -reach && (sine > 0.0f || reach > 0.0)) {
                pv.lit |= 1u << l;
                pv.light_elevation_deg = std::min(pv.light_elevation_deg,
                                                  glm::degrees(std::asin(std::clamp(static_cast<double>(sine), -1.0, 1.0))));
            }
        }
        lit_any |= pv.lit;
        points.push_back(pv);
        view.pixels += pv.weight;
        angle_lo = std::min(angle_lo, pv.angle_deg);
        angle_hi = std::max(angle_hi, pv.angle_deg);
        dist_lo = std::min(dist_lo, distance);
        dist_hi = std::max(dist_hi, distance);
        const double mip = std::log2(std::max(rho, 1e-9));
        mip_lo = std::min(mip_lo, mip);
        mip_hi = std::max(mip_hi, mip);
        screen_box = glm::vec4(std::min(screen_box.x, ndc.x), std::min(screen_box.y, ndc.y), std::max(screen_box.z, ndc.x),
                               std::max(screen_box.w, ndc.y));
    }
    view.visible = !points.empty();
    if (view.visible) {
        view.angle_min_deg = angle_lo;
        view.angle_max_deg = angle_hi;
        view.distance_min = dist_lo;
        view.distance_max = dist_hi;
        view.mip_min = mip_lo;
        view.mip_max = mip_hi;
        for (unsigned bits = lit_any; bits; bits &= bits - 1) ++view.lights_above_horizon;
    }
    return view;
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
    std::vector<ObjectView> views(n);
    std::vector<std::vector<PointView>> points(n);
    std::vector<glm::vec4> screen_boxes(n);
    std::vector<std::pair<glm::vec3, glm::vec3>> world_boxes(n);
    for (size_t i = 0; i < n; ++i) views[i] = m.view_object(i, frame, points[i], screen_boxes[i], world_boxes[i]);
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
        Result<ObjectPlan> p = m.plan_object(i, views, points, screen_boxes, world_boxes, silhouette);
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

namespace {

// What one candidate is predicted to leave and cost over an object's points.
struct Prediction {
    double error = 0.0;  // p95, texels of the level sampled
    double cost = 0.0;   // mean over pixels, relative to normal mapping
    bool known = false;  // the table has the candidate
};

}  // namespace

Result<ObjectPlan> ScenePlanner::Impl::plan_object(size_t oi, const std::vector<ObjectView>& views,
                                                   const std::vector<std::vector<PointView>>& all_points,
                                                   const std::vector<glm::vec4>& screen_boxes,
                                                   const std::vector<std::pair<glm::vec3, glm::vec3>>& world_boxes,
                                                   bool silhouette_on_screen) const {
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
    plan.view = views[oi];
    plan.options = material.technique;
    if (!material.effects) {  // its plan_variant, made with the planner
        if (mi >= named_plans.size() || !named_plans[mi]) return make_error(who + ": the material was not planned");
        plan.key = named_plans[mi]->key;
        plan.notes = named_plans[mi]->notes;
        return plan;
    }

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
    auto finish_normal = [&](std::string why) {
        key.technique = Technique::normal;
        options.technique = Technique::normal;
        plan.notes.push_back(std::move(why));
        if (request.shadow != ShadowMode::none)
            plan.notes.push_back(std::string("shadow=") + shadow_mode_name(request.shadow) +
                                 " dropped: normal mapping traces no relief to cast it");
        key = key.canonical();
        return plan;
    };

    if (!request.parallax) return finish_normal("normal mapping: the material asks for no parallax");
    if (!(material.height_scale > 0.0f))
        return finish_normal("normal mapping: height_scale is 0, so there is no relief to trace");
    if (!(relief.features.range > 0.0))
        return finish_normal("normal mapping: the height field is flat, so there is no relief to trace");
    const ObjectView& view = views[oi];
    if (!view.visible) return finish_normal("normal mapping: no part of the surface faces the camera inside the view");
    const std::vector<PointView>& points = all_points[oi];
    {
        std::vector<std::pair<double, double>> added;
        for (const PointView& p : points)
            added.emplace_back(relief.features.depth_texels * p.pv_parallax / std::max(1.0, p.rho), p.weight);
        plan.view.per_vertex_view_error = weighted_p95(added);
    }

    // Sources of prediction: the material's own calibration first.
    // The table's nearest relief holds the shadow rows; the search model
    // (where the material has one) predicts hits; a calibration of this very
    // relief comes first.
    const Source table_source = generic_source(relief);
    const std::optional<Source> modelled = model_source(mi);
    const Source& uncalibrated = modelled ? *modelled : table_source;
    std::string calibration_skipped;
    const std::optional<Source> calibrated =
        calibrated_source(relief, views[oi].visible ? views[oi].angle_max_deg : 0.0, &calibration_skipped);
    if (!calibrated && !calibration_skipped.empty()) plan.notes.push_back(calibration_skipped);
    if (!calibrated && mi < calibration_notes.size() && !calibration_notes[mi].empty())
        plan.notes.push_back(calibration_notes[mi]);
    const Source& source = calibrated ? *calibrated : uncalibrated;
    if (source.relief < 0) return make_error(who + ": the cost table has no relief to predict from");
    plan.prediction_source = source.label;

    // Effects the scene or context rule out.
    bool want_shadow = request.shadow != ShadowMode::none;
    if (want_shadow) {
        if (scene.lights.empty()) {
            want_shadow = false;
            plan.notes.push_back(std::string("shadow=") + shadow_mode_name(request.shadow) + " dropped: the scene has no light");
        } else if (view.lights_above_horizon == 0) {
            want_shadow = false;
            plan.notes.push_back(std::string("shadow=") + shadow_mode_name(request.shadow) +
                                 " dropped: every light is behind the surface or below its horizon wherever it is seen");
        } else {
            // A height field whose slopes are all below the light's
            // elevation cannot shadow itself: with |grad h| <= S everywhere,
            // h rises less than S t over a distance t, and the ray to the
            // light rises tan(elevation) t. S: the steepest rise between
            // neighbouring texels, in texels of height per texel, times
            // sqrt(2) for the diagonals of a bilinear surface. A soft
            // light's disc reaches its angular radius lower.
            const double slope_deg = glm::degrees(std::atan(std::sqrt(2.0) * relief.features.steepness *
                                                            relief.features.depth_texels));
            double lowest = 90.0;
            for (const PointView& p : points)
                if (p.lit) lowest = std::min(lowest, p.light_elevation_deg);
            double radius = 0.0;
            if (request.shadow == ShadowMode::soft)
                for (const LightDesc& l : scene.lights) radius = std::max(radius, static_cast<double>(l.angular_radius_deg));
            if (lowest - radius > slope_deg) {
                want_shadow = false;
                plan.notes.push_back(std::string("shadow=") + shadow_mode_name(request.shadow) + " dropped: the light is " +
                                     fmt("%.1f", lowest - radius) + " degrees or more above the surface wherever it is "
                                     "seen, steeper than the relief's steepest slope (" + fmt("%.1f", slope_deg) +
                                     " degrees): nothing on it can cast a shadow");
            }
        }
    }
    const bool lod_possible = request.lod_fade != EffectSwitch::off && caps.derivatives();
    if (request.lod_fade == EffectSwitch::on && !caps.derivatives())
        plan.notes.push_back("lod_fade dropped: this OpenGL ES 2.0 context lacks GL_OES_standard_derivatives");
    const double fade_start = request.lod_threshold - request.lod_band;

    // Normal mapping's error and whether LOD would turn it on everywhere.
    auto curve = [&](const Source& s, Technique t, int samples, ShadowMode shadow, int shadow_samples) -> const Curve* {
        auto it = s.curves->find({s.relief, t, samples, shadow, shadow_samples, 0});
        return it == s.curves->end() ? nullptr : &it->second;
    };
    const double depth_texels = relief.features.depth_texels;
    // Each point's place in a table's angle grid, once per grid: every
    // curve of a table shares one, so a prediction is a few multiply-adds
    // per point, and a mean cost is one per table angle.
    struct Basis {
        const std::vector<double>* angles = nullptr;
        std::vector<std::pair<size_t, double>> at;  // per point: lower index, fraction
        std::vector<double> weight;                 // per table angle: the points' weight on it
        double total = 0.0;
    };
    std::deque<Basis> bases;  // stable references as it grows
    auto basis_for = [&](const std::vector<double>& angles) -> const Basis& {
        for (const Basis& b : bases)
            if (*b.angles == angles) return b;
        Basis b;
        b.angles = &angles;
        b.weight.assign(angles.size(), 0.0);
        for (const PointView& p : points) {
            size_t i = 0;
            double t = 0.0;
            if (angles.size() > 1 && p.angle_deg > angles.front()) {
                if (p.angle_deg >= angles.back()) {
                    i = angles.size() - 1;
                } else {
                    i = static_cast<size_t>(std::upper_bound(angles.begin(), angles.end(), p.angle_deg) - angles.begin()) - 1;
                    t = (p.angle_deg - angles[i]) / (angles[i + 1] - angles[i]);
                }
            }
            b.at.emplace_back(i, t);
            b.weight[i] += (1.0 - t) * p.weight;
            if (t > 0.0) b.weight[i + 1] += t * p.weight;
            b.total += p.weight;
        }
        bases.push_back(std::move(b));
        return bases.back();
    };
    auto value = [](const Basis& b, const std::vector<double>& ys, size_t point) {
        const auto [i, t] = b.at[point];
        return t > 0.0 ? ys[i] + t * (ys[i + 1] - ys[i]) : ys[i];
    };
    auto mean = [](const Basis& b, const std::vector<double>& ys) {
        double sum = 0.0;
        for (size_t k = 0; k < ys.size(); ++k) sum += b.weight[k] * ys[k];
        return b.total > 0.0 ? sum / b.total : 0.0;
    };
    // Each point's LOD fade (0: the technique, 1: normal mapping), once.
    std::vector<double> blends(points.size());
    for (size_t i = 0; i < points.size(); ++i)
        blends[i] = std::clamp((std::log2(std::max(points[i].rho, 1e-9)) - fade_start) / request.lod_band, 0.0, 1.0);
    auto predict_cost = [&](const Source& s, const Candidate& c) {
        Prediction out;
        const Curve* tc = curve(s, c.technique, c.samples, ShadowMode::none, 0);
        const Curve* nc = curve(s, Technique::normal, 0, ShadowMode::none, 0);
        if (!tc || !nc) return out;
        out.known = true;
        const Basis& b = basis_for(tc->angles);
        if (!c.lod) {
            out.cost = mean(b, tc->cost);
            return out;
        }
        double sum = 0.0;
        for (size_t i = 0; i < points.size(); ++i)
            sum += (blends[i] >= 1.0 ? 1.0 : value(b, tc->cost, i)) * points[i].weight;
        out.cost = b.total > 0.0 ? sum / b.total : 0.0;
        return out;
    };
    auto predict_model_error = [&](const Source& s, const Candidate& c) {
        const Curve* tc = curve(s, c.technique, c.samples, ShadowMode::none, 0);
        const Curve* nc = curve(s, Technique::normal, 0, ShadowMode::none, 0);
        if (!tc || !nc) return std::numeric_limits<double>::infinity();
        const Basis& b = basis_for(tc->angles);
        const Basis& bn = basis_for(nc->angles);
        const bool per_vertex = !c.exact_view && !technique_info(c.technique).always_exact_view &&
                                (technique_info(c.technique).options & kOptHeight);
        // The step-over bound: a linear search of `samples` layers moves the
        // ray depth x tan(view angle) / samples texels per sample; where that
        // passes the relief's narrowest feature the search can step over it
        // and land up to a step away, whatever the table relief (whose
        // features may be wider) measured. Exact walks never step over.
        const bool linear_search = !s.simulated && (technique_info(c.technique).options & kOptSamples) && c.samples > 0;
        const double thinnest = std::max(relief.features.thinnest_texels, 0.5);
        if (s.simulated && tc->levels.size() == tc->angles.size() && nc->levels.size() == nc->angles.size() &&
            !tc->levels.empty()) {
            // The search model: every pixel's error is a draw from the
            // simulated distribution at its angle (its levels), in texels
            // of the level sampled; the object's p95 and p97 are of those
            // draws pooled over its pixels (what the GPU's p95 is of), with
            // the margin on top: max(p95 x scale, p97) + floor. Each
            // level's share of the rays is put at its upper end.
            const SearchMargin margin = search_margin(c.technique);
            const SearchMargin normal_margin = search_margin(Technique::normal);
            // Pixels 8 texels across or more sample mip levels 3 and coarser,
            // whose smoothing the simulation on the base level knows nothing
            // of: there the prediction is at least the generic table's for the
            // candidate on the nearest relief (measured on the GPU at such
            // levels). (Simulating the searches on mip level 2 against the
            // full field's exact hit was tried and over-predicted: 0.5+ texels
            // for POM x64 on the fine sine at 128x128, where the GPU measures
            // 0.022; docs/planner.md.)
            constexpr double kPastSimulated = 8.0;
            const Curve* table_curve = curve(table_source, c.technique, c.samples, ShadowMode::none, 0);
            const Basis* table_basis = table_curve ? &basis_for(table_curve->angles) : nullptr;
            std::vector<std::pair<double, double>> pooled;
            pooled.reserve(points.size() * static_cast<size_t>(kSearchLevelCount));
            for (size_t i = 0; i < points.size(); ++i) {
                const PointView& p = points[i];
                const auto [ti, tt] = b.at[i];
                const auto [ni, nt] = bn.at[i];
                const double added = per_vertex ? depth_texels * (c.technique == Technique::offset_limited ? p.pv_offset
                                                                                                           : p.pv_parallax)
                                                : 0.0;
                const double per_level = 1.0 / std::max(1.0, p.rho);
                double below = 0.0;
                const auto sector = static_cast<size_t>(p.sector);
                for (int k = 0; k < kSearchLevelCount; ++k) {
                    // The point's azimuth sector where the model has them.
                    const auto at = [k, sector](const Curve& cv, size_t idx, double t) {
                        const bool sectors = cv.sector_levels.size() == cv.levels.size() &&
                                             sector < cv.sector_levels[idx].size();
                        const auto& a = sectors ? cv.sector_levels[idx][sector] : cv.levels[idx];
                        const double lo = a[static_cast<size_t>(k)];
                        if (!(t > 0.0)) return lo;
                        const auto& next = sectors ? cv.sector_levels[idx + 1][sector] : cv.levels[idx + 1];
                        return lo + t * (next[static_cast<size_t>(k)] - lo);
                    };
                    double v = (at(*tc, ti, tt) + added) * per_level;
                    if (table_basis && p.rho >= kPastSimulated)
                        v = std::max(v, (value(*table_basis, table_curve->error, i) * table_source.depth_scale + added) *
                                            per_level - margin.floor);
                    if (c.lod)
                        v = (1.0 - blends[i]) * v +
                            blends[i] * (at(*nc, ni, nt) * per_level + normal_margin.floor - margin.floor);
                    pooled.emplace_back(v, p.weight * (kSearchLevels[k] - below));
                    below = kSearchLevels[k];
                }
            }
            double total = 0.0;
            for (const auto& e : pooled) total += e.second;
            const double p95 = weighted_quantile(pooled, 0.95, total);
            const double p97 = weighted_quantile(pooled, 0.97, total);
            return std::max(p95 * margin.scale, p97) + margin.floor;
        }
        std::vector<std::pair<double, double>> errors;
        errors.reserve(points.size());
        for (size_t i = 0; i < points.size(); ++i) {
            const PointView& p = points[i];
            double e = value(b, tc->error, i) * s.depth_scale;
            if (linear_search) {
                const double travel = depth_texels * std::tan(glm::radians(std::min(p.angle_deg, 89.5)));
                const double step = travel / c.samples;
                if (step > thinnest) e = std::max(e, step);
            }
            if (per_vertex) e += depth_texels * (c.technique == Technique::offset_limited ? p.pv_offset : p.pv_parallax);
            const double floor_technique = s.simulated ? search_margin(c.technique).floor : 0.0;
            const double floor_normal = s.simulated ? search_margin(Technique::normal).floor : 0.0;
            double level = e / std::max(1.0, p.rho) + floor_technique;
            if (c.lod)
                level = (1.0 - blends[i]) * level +
                        blends[i] * (value(bn, nc->error, i) * s.depth_scale / std::max(1.0, p.rho) + floor_normal);
            errors.emplace_back(level, p.weight);
        }
        return weighted_p95(errors);
    };
    // Without fragment highp (ES 2.0, Mali-400 class) the uv itself is fp16:
    // no technique places a hit closer than half its step on [0.5, 1), 2^-12
    // of a tile (docs/stability.md, nohighp: 0.04 to 0.06 texel of mean
    // error at 256 texels on every technique, maxmip included).
    const double uv_floor = caps.es_major < 3 && !caps.fragment_highp
                                ? std::ldexp(static_cast<double>(std::max(relief.traced_width, relief.traced_height)), -12)
                                : 0.0;
    auto predict_error = [&](const Source& s, const Candidate& c) {
        return std::max(predict_model_error(s, c), uv_floor);
    };
    auto predict = [&](const Source& s, const Candidate& c) {
        Prediction out = predict_cost(s, c);
        if (out.known) out.error = predict_error(s, c);
        return out;
    };

    // Candidates: every (technique, samples) the source measured that this
    // context runs, with the exact or the per-vertex view, with LOD or not.
    std::vector<Candidate> candidates;
    for (const auto& [k, c] : *source.curves) {
        const auto& [r, t, samples, shadow, shadow_samples, elevation] = k;
        (void)c;
        (void)elevation;
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
                candidates.push_back({t, samples, exact != 0, lod != 0});
            }
        }
    }
    // Every visible pixel past the threshold: normal mapping, where its
    // error holds (auto) or whenever asked (on).
    if (lod_possible && view.mip_min >= request.lod_threshold) {
        const Prediction normal = predict(source, {Technique::normal, 0, true, false});
        // Not where a shadow is wanted and could fall (its light reaches
        // the surface, over slopes steep enough): normal mapping casts none,
        // and the shadow's own target would be missed.
        if (request.lod_fade == EffectSwitch::on ||
            (normal.known && normal.error <= request.max_error_texels && !want_shadow)) {
            plan.predicted_error = normal.error;
            plan.predicted_cost = 1.0;
            return finish_normal("normal mapping: every visible pixel samples mip level " + fmt("%.1f", view.mip_min) +
                                 " or coarser, past the lod_fade threshold " + fmt("%g", request.lod_threshold) +
                                 " (predicted " + fmt("%.3g", normal.error) + " texels)");
        }
    }

    // Shadow: the cheapest sample count meeting its target.
    int shadow_samples = 0;
    double shadow_cost = 0.0, shadow_error = -1.0;
    if (want_shadow) {
        // The nearest table relief that has shadow rows of this mode (the
        // search model simulates no shadows: the generic table's).
        const Source& shadow_base = source.simulated ? table_source : source;
        const CostTable& table = *shadow_base.table;
        std::vector<bool> eligible(table.reliefs.size(), false);
        for (const CostSample& s : table.rows)
            if (s.shadow == request.shadow) eligible[static_cast<size_t>(s.relief)] = true;
        const int shadow_relief = nearest_relief(table, relief.features, eligible);
        if (shadow_relief < 0) {
            return make_error(who + ": " + field_path + ".shadow: the cost table has no " + shadow_mode_name(request.shadow) +
                              " shadow measurements to choose a sample count from");
        }
        Source shadow_source = shadow_base;
        shadow_source.relief = shadow_relief;
        double best_error = std::numeric_limits<double>::infinity();
        std::vector<std::tuple<double, int, double>> options_by_cost;  // cost, samples, error
        // Per shadow sample count, its curves at each light elevation.
        std::map<std::pair<std::pair<Technique, int>, int>, std::vector<std::pair<double, const Curve*>>> by_count;
        for (const auto& [k, c] : *shadow_base.curves) {
            const auto& [r, t, samples, shadow, ss, elevation] = k;
            if (r != shadow_relief || shadow != request.shadow) continue;
            by_count[{{t, samples}, ss}].emplace_back(elevation / 10.0, &c);
        }
        for (auto& [count, curves] : by_count) {
            std::sort(curves.begin(), curves.end(),
                      [](const auto& a, const auto& b) { return a.first < b.first; });
            const Curve* base = curve(shadow_source, count.first.first, count.first.second, ShadowMode::none, 0);
            double e_sum = 0.0, w_sum = 0.0, c_sum = 0.0;
            for (const PointView& p : points) {
                if (!p.lit) continue;
                // Between the measured elevations linearly; under the lowest,
                // its error grown with the shadow's length (1 / tan).
                const double e = p.light_elevation_deg;
                double visibility = 0.0, cost = 0.0;
                if (e <= curves.front().first || curves.size() == 1) {
                    const Curve& c = *curves.front().second;
                    const double grow = e < curves.front().first
                                            ? std::tan(glm::radians(curves.front().first)) / std::tan(glm::radians(std::max(e, 0.5)))
                                            : 1.0;
                    visibility = std::min(1.0, interpolate(c.angles, c.visibility, p.angle_deg) * grow);
                    cost = interpolate(c.angles, c.cost, p.angle_deg);
                } else if (e >= curves.back().first) {
                    const Curve& c = *curves.back().second;
                    visibility = interpolate(c.angles, c.visibility, p.angle_deg);
                    cost = interpolate(c.angles, c.cost, p.angle_deg);
                } else {
                    size_t i = 1;
                    while (curves[i].first < e) ++i;
                    const double t = (e - curves[i - 1].first) / (curves[i].first - curves[i - 1].first);
                    const Curve& a = *curves[i - 1].second;
                    const Curve& b = *curves[i].second;
                    visibility = (1.0 - t) * interpolate(a.angles, a.visibility, p.angle_deg) +
                                 t * interpolate(b.angles, b.visibility, p.angle_deg);
                    cost = (1.0 - t) * interpolate(a.angles, a.cost, p.angle_deg) + t * interpolate(b.angles, b.cost, p.angle_deg);
                }
                e_sum += visibility * p.weight;
                const double base_cost = base ? interpolate(base->angles, base->cost, p.angle_deg) : 1.0;
                c_sum += std::max(0.0, cost - base_cost) * p.weight;
                w_sum += p.weight;
            }
            const double e = w_sum > 0.0 ? e_sum / w_sum : 0.0;
            const double added = w_sum > 0.0 ? c_sum / w_sum : 0.0;
            best_error = std::min(best_error, e);
            if (e <= request.shadow_max_error) options_by_cost.emplace_back(added, count.second, e);
        }
        if (options_by_cost.empty())
            return make_error(who + ": " + field_path + ".shadow.max_error: " + fmt("%g", request.shadow_max_error) +
                              " is below what any shadow sample count reaches here (best " + fmt("%.3g", best_error) +
                              " mean visibility difference)");
        std::sort(options_by_cost.begin(), options_by_cost.end());
        std::tie(shadow_cost, shadow_samples, shadow_error) = options_by_cost.front();
    }

    // The cheapest candidate meeting the parallax target.
    // The shadow rows were measured over POM x32's hits: their prediction
    // holds for a primary search at least as accurate as that.
    double hit_target = request.max_error_texels;
    if (want_shadow) {
        const double pom32 = predict_error(source, {Technique::pom, 32, true, false});
        if (std::isfinite(pom32) && pom32 < hit_target) {
            hit_target = pom32;
            plan.notes.push_back("hit target tightened to " + fmt("%.3g", pom32) +
                                 " texels (POM x32's here): the shadow's prediction holds for hits as accurate as "
                                 "those its table rows were measured with");
        }
    }
    auto choose = [&](const Source& s, Prediction& chosen, double& best_error, std::string& best_name) -> std::optional<Candidate> {
        best_error = std::numeric_limits<double>::infinity();
        // Costs first (cheap), then errors in cost order until one meets
        // the target; every error only when none does (for the message).
        std::vector<std::pair<double, size_t>> order;
        std::vector<Prediction> predicted(candidates.size());
        for (size_t i = 0; i < candidates.size(); ++i) {
            predicted[i] = predict_cost(s, candidates[i]);
            if (!predicted[i].known) continue;
            // A per-vertex view saves a normalise per pixel (not in the
            // table's timings): preferred at equal cost, never at higher.
            order.emplace_back(predicted[i].cost - (candidates[i].exact_view ? 0.0 : 1e-6), i);
        }
        std::sort(order.begin(), order.end());
        for (const auto& [cost, i] : order) {
            predicted[i].error = predict_error(s, candidates[i]);
            if (predicted[i].error < best_error) {
                best_error = predicted[i].error;
                best_name = candidate_name(candidates[i]);
            }
            if (predicted[i].error <= hit_target) {
                chosen = predicted[i];
                return candidates[i];
            }
        }
        return std::nullopt;
    };
    Prediction chosen;
    double best_error = 0.0;
    std::string best_name;
    const std::optional<Candidate> pick = choose(source, chosen, best_error, best_name);
    if (!pick && best_name.empty())
        return make_error(who + ": the cost table (" + source.label + ") measured no candidate this context runs");
    if (!pick) {
        return make_error(who + ": " + field_path + ".parallax.max_error_texels: " + fmt("%g", request.max_error_texels) +
                          " texels is below what any technique reaches on this relief at view angles up to " +
                          fmt("%.1f", view.angle_max_deg) + " degrees on this OpenGL ES " + std::to_string(caps.es_major) +
                          " context (best: " + best_name + ", predicted " + fmt("%.3g", best_error) + " texels)" +
                          (uv_floor > 0.0 && best_error <= uv_floor
                               ? "; without fragment highp the uv is fp16, which places no hit closer than " +
                                     fmt("%.3g", uv_floor) + " texels on this " + std::to_string(relief.traced_width) +
                                     "x" + std::to_string(relief.traced_height) + " height map"
                               : std::string()));
    }
    if (calibrated) {
        Prediction generic_chosen;
        double generic_best = 0.0;
        std::string generic_best_name;
        const std::optional<Candidate> generic_pick = choose(uncalibrated, generic_chosen, generic_best, generic_best_name);
        if (!generic_pick || generic_pick->technique != pick->technique || generic_pick->samples != pick->samples ||
            generic_pick->exact_view != pick->exact_view || generic_pick->lod != pick->lod) {
            VariantKey g = key;
            if (generic_pick) {
                g.technique = generic_pick->technique;
                g.max_samples = static_cast<std::uint16_t>(generic_pick->samples);
                g.exact_view = generic_pick->exact_view;
                g.lod = generic_pick->lod;
                // As the chosen key is completed below: the refinements the
                // draw uses (a relief search refines options.refine_steps times).
                if (technique_info(g.technique).options & kOptRefine)
                    g.refine_steps = static_cast<std::uint8_t>(options.refine_steps);
                plan.generic_error = generic_chosen.error;
                plan.generic_cost = generic_chosen.cost;
            }
            plan.generic_key = g.canonical();
            plan.notes.push_back(std::string("the calibration changed the choice: ") +
                                 (modelled ? "the search model alone picks " : "the generic table alone picks ") +
                                 (generic_pick ? candidate_name(*generic_pick) : std::string("nothing that meets the target")));
        }
    }

    const TechniqueInfo& info = technique_info(pick->technique);
    key.technique = pick->technique;
    options.technique = pick->technique;
    if (info.options & kOptSamples) {
        key.max_samples = static_cast<std::uint16_t>(pick->samples);
        options.min_samples = options.max_samples = pick->samples;  // the table measured min = max
    }
    if (info.options & kOptSteps) {
        key.max_samples = static_cast<std::uint16_t>(pick->samples);
        options.max_steps = pick->samples;
    }
    if (info.options & kOptRefine) key.refine_steps = static_cast<std::uint8_t>(options.refine_steps);
    key.exact_view = pick->exact_view;
    options.exact_view = pick->exact_view;
    key.lod = pick->lod;
    options.lod = pick->lod;
    plan.predicted_error = chosen.error;
    plan.predicted_cost = chosen.cost + shadow_cost;
    const std::string target_text =
        hit_target < request.max_error_texels
            ? fmt("%.3g", hit_target) + " texels (the hit target tightened for the shadow; asked " +
                  fmt("%g", request.max_error_texels) + ")"
            : fmt("%g", request.max_error_texels) + " texels";
    plan.notes.push_back(candidate_name(*pick) + ": the cheapest candidate predicted within " + target_text + " (" +
                         fmt("%.3g", chosen.error) + ", x" +
                         fmt("%.2f", chosen.cost) + " normal mapping per pixel; " + source.label + ")");
    if (info.options & kOptHeight && !info.always_exact_view)
        plan.notes.push_back(pick->exact_view
                                 ? "view vector exact per pixel: the per-vertex normalisation would add up to " +
                                       fmt("%.3g", plan.view.per_vertex_view_error) + " texels on these triangles"
                                 : "view vector normalised per vertex (the PowerVR whitepaper's saving): it adds " +
                                       fmt("%.3g", plan.view.per_vertex_view_error) + " texels here, within the target");
    if (pick->lod)
        plan.notes.push_back("lod_fade on: the surface reaches mip level " + fmt("%.1f", view.mip_max) +
                             ", past the fade's start at " + fmt("%g", fade_start));
    else if (request.lod_fade != EffectSwitch::off && lod_possible && (info.options & kOptLod))
        plan.notes.push_back(view.mip_max <= fade_start
                                 ? "lod_fade not needed: the finest pixels sample mip level " + fmt("%.1f", view.mip_max) +
                                       ", before the fade starts at " + fmt("%g", fade_start)
                                 : "lod_fade off: fading would not lower the cost within the target");

    if (want_shadow) {
        key.shadow = request.shadow;
        key.shadow_samples = static_cast<std::uint8_t>(shadow_samples);
        options.shadow = request.shadow;
        options.shadow_samples = shadow_samples;
        plan.predicted_shadow_error = shadow_error;
        plan.notes.push_back(std::string("shadow=") + shadow_mode_name(request.shadow) + " x" + std::to_string(shadow_samples) +
                             ": the fewest shadow samples predicted within " + fmt("%g", request.shadow_max_error) +
                             " (" + fmt("%.3g", shadow_error) + ")");
    }

    // Depth correction: where other geometry meets or overlaps the relief.
    if (info.options & kOptDepth) {
        bool want_depth = request.depth_correction == EffectSwitch::on;
        if (request.depth_correction == EffectSwitch::automatic) {
            // The relief's volume: a plane's between bias and bias + scale
            // along its normal (object space), any other mesh's box grown
            // by the depth; then in world space.
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
            const glm::mat4 model = object.transform.matrix();
            glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
            for (int c = 0; c < 8; ++c) {
                const glm::vec3 corner((c & 1) ? box_hi.x : box_lo.x, (c & 2) ? box_hi.y : box_lo.y, (c & 4) ? box_hi.z : box_lo.z);
                const glm::vec3 w = glm::vec3(model * glm::vec4(corner, 1.0f));
                lo = glm::min(lo, w);
                hi = glm::max(hi, w);
            }
            const glm::vec4& sb = screen_boxes[oi];
            std::string other;
            for (size_t j = 0; j < scene.objects.size() && other.empty(); ++j) {
                if (j == oi || !views[j].visible) continue;
                const auto& [olo, ohi] = world_boxes[j];
                const bool meets = olo.x <= hi.x && ohi.x >= lo.x && olo.y <= hi.y && ohi.y >= lo.y && olo.z <= hi.z &&
                                   ohi.z >= lo.z;
                const glm::vec4& ob = screen_boxes[j];
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
        key.depth_write = want_depth;
        options.depth_write = want_depth;
    } else if (request.depth_correction == EffectSwitch::on) {
        plan.notes.push_back(std::string("depth correction dropped: ") + info.name + " finds no hit depth");
    }
    key = key.canonical();
    if (std::string note = no_derivatives_note(key); !note.empty()) plan.notes.push_back(note);
    return plan;
}

}  // namespace px
