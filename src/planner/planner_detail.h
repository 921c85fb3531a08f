// The effect planner's parts, private to planner/: the survey of an
// object's surface (survey.cpp), the cost table read as curves and a
// candidate's prediction over an object's points (prediction.cpp), and the
// planner's state (ScenePlanner::Impl: made in scene_planner.cpp, each
// frame's view of an object in view_object.cpp, its plan in plan_object.cpp).
#pragma once

#include <cstddef>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "parallaxes/planner/object_plan.h"
#include "parallaxes/planner/planner.h"

namespace px {
namespace planning {

constexpr int kMaxSurfacePoints = 320;  // per object: enough for the percentiles, cheap per frame

// printf of one number, for notes.
std::string fmt(const char* format, double a);

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
                                         int width, int height);

ObjectSurvey survey_mesh(const Mesh& mesh);

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
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x);

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

std::map<CurveKey, Curve> curves_of(const CostTable& table);

// The reliefs of a table nearest in character to `f`: thinnest feature and
// steepness, on log scales.
int nearest_relief(const CostTable& table, const ReliefFeatures& f, const std::vector<bool>& eligible);

// A calibration that measured errors but not times ("costs": "table"):
// each curve priced from the generic table's curve of the same candidate on
// the generic relief nearest to the calibrated one, at the calibration's
// angles (a step-bounded technique at whatever bound the table measured). A
// shadowed curve gets its unshadowed twin's price plus the shadow's
// overhead the table measured on its nearest shadowed relief. Curves the
// table cannot price are dropped (no candidate without a cost).
void price_from_generic(const CostTable& calibration, std::map<CurveKey, Curve>& curves, const CostTable& generic,
                        const std::map<CurveKey, Curve>& generic_curves);

// A candidate the planner weighs.
struct Candidate {
    Technique technique;
    int samples;
    bool exact_view;
    bool lod;
};

std::string candidate_name(const Candidate& c);

// The p95 of (value, weight) pairs, by weight.
// The value at which the weights of the values up to it first reach
// `share` of `total` (values, weights), as a sort followed by a running sum
// would find it, in expected linear time: quickselect, keeping the weight
// of everything left of the part still searched. Reorders `v`.
double weighted_quantile(std::vector<std::pair<double, double>>& v, double share, double total);
double weighted_p95(std::vector<std::pair<double, double>>& v);

// Where a material's predictions come from.
struct Source {
    const CostTable* table = nullptr;
    const std::map<CurveKey, Curve>* curves = nullptr;
    int relief = -1;
    double depth_scale = 1.0;  // material depth / table relief depth
    std::string label;
    bool simulated = false;    // the search model: step-overs already simulated
};

// The curve of one candidate in `s` (unshadowed: ShadowMode::none, 0), or null.
const Curve* find_curve(const Source& s, Technique t, int samples, ShadowMode shadow, int shadow_samples);

// What one candidate is predicted to leave and cost over an object's points.
struct Prediction {
    double error = 0.0;  // p95, texels of the level sampled
    double cost = 0.0;   // mean over pixels, relative to normal mapping
    bool known = false;  // the table has the candidate
};

// The cheapest candidate meeting a target, or why none does.
struct Choice {
    std::optional<Candidate> pick;
    Prediction chosen;
    double best_error = 0.0;  // the lowest error predicted (for the message where none meets the target)
    std::string best_name;    // the candidate that has it; empty: no candidate the source measured
};

// Predictions for one object this frame. Each point's place in a table's
// angle grid is found once per grid: every curve of a table shares one, so
// a prediction is a few multiply-adds per point, and a mean cost is one per
// table angle.
class ObjectPredictor {
public:
    // `table_source`: the generic table's nearest relief, which bounds a
    // search model's prediction where pixels sample coarse mip levels.
    ObjectPredictor(const MaterialRelief& relief, const std::vector<PointView>& points, const EffectRequest& request,
                    const Caps& caps, const Source& table_source);

    Prediction predict_cost(const Source& s, const Candidate& c);
    // The p95 error, at least the uv's own floor (uv_floor).
    double predict_error(const Source& s, const Candidate& c);
    Prediction predict(const Source& s, const Candidate& c);
    // Costs first (cheap), then errors in cost order until one meets
    // `target`; every error only when none does (for the message).
    Choice choose(const Source& s, const std::vector<Candidate>& candidates, double target);
    // Without fragment highp the uv is fp16: no hit is placed closer than
    // this (texels); 0 with highp.
    double uv_floor() const { return uv_floor_; }

private:
    struct Basis {
        const std::vector<double>* angles = nullptr;
        std::vector<std::pair<size_t, double>> at;  // per point: lower index, fraction
        std::vector<double> weight;                 // per table angle: the points' weight on it
        double total = 0.0;
    };
    const Basis& basis_for(const std::vector<double>& angles);
    double model_error(const Source& s, const Candidate& c);
    double simulated_error(const Candidate& c, const Curve& tc, const Curve& nc, bool per_vertex);
    double measured_error(const Source& s, const Candidate& c, const Curve& tc, const Curve& nc, bool per_vertex);

    const MaterialRelief& relief_;
    const std::vector<PointView>& points_;
    const EffectRequest& request_;
    const Source& table_source_;
    double uv_floor_ = 0.0;
    std::vector<double> blends_;  // per point: its LOD fade (0: the technique, 1: normal mapping)
    std::deque<Basis> bases_;     // stable references as it grows
};

// The shadow sample count chosen: the fewest meeting the shadow's target.
struct ShadowChoice {
    int samples = 0;
    double cost = 0.0;    // added over the unshadowed search, relative to normal mapping
    double error = -1.0;  // mean visibility difference
};
// `who` and `field_path` name the object and the material's effects in errors.
Result<ShadowChoice> choose_shadow_samples(const Source& source, const Source& table_source, const ReliefFeatures& relief,
                                           const EffectRequest& request, const std::vector<PointView>& points,
                                           const std::string& who, const std::string& field_path);

// The world-space box around the eight corners of [lo, hi] under `model`.
std::pair<glm::vec3, glm::vec3> transformed_box(const glm::vec3& lo, const glm::vec3& hi, const glm::mat4& model);

}  // namespace planning

struct ScenePlanner::Impl {
    using Curves = std::map<planning::CurveKey, planning::Curve>;
    using Source = planning::Source;

    SceneDesc scene;
    Caps caps;
    std::vector<MaterialRelief> reliefs;
    CostTable generic;
    std::vector<CostTable> calibrations;
    Curves generic_curves;
    std::vector<Curves> calibration_curves;
    std::vector<std::string> calibration_notes;  // per material: why its calibration file was not used
    std::vector<planning::ObjectSurvey> surveys;
    std::vector<float> units_per_uv;  // per object: world units per mesh uv unit
    // Per material that names its technique: plan_variant, run once here.
    std::vector<std::optional<VariantPlan>> named_plans;
    std::vector<OutlineRequest> outlines;  // per object
    // Per material with a search model: its curves as a one-relief table
    // (errors simulated with the margin, costs from the generic table).
    std::vector<std::optional<CostTable>> model_tables;
    std::vector<Curves> model_curves;

    // What every object's plan this frame is made from.
    struct FrameViews {
        std::vector<ObjectView> views;
        std::vector<std::vector<planning::PointView>> points;
        std::vector<glm::vec4> screen_boxes;
        std::vector<std::pair<glm::vec3, glm::vec3>> world_boxes;
    };

    // scene_planner.cpp: the sources of prediction.
    Source generic_source(const MaterialRelief& r) const;
    // The search model of material `mi`, if it has one.
    std::optional<Source> model_source(size_t mi) const;
    // The calibration of this very relief, if one can plan it; `skipped`
    // says why a matching one could not (it is then not used).
    // Only where it measured what this view needs: the view angles seen
    // (up to `angle_max_deg`), on this renderer.
    std::optional<Source> calibrated_source(const MaterialRelief& r, double angle_max_deg, std::string* skipped) const;
    // scene_planner.cpp: made once, with the planner.
    void model_search_curves();
    void find_calibrations(const PlannerOptions& options);
    void survey_objects(const std::vector<const Mesh*>& meshes);
    Status plan_named_materials();

    // view_object.cpp
    ObjectView view_object(size_t object_index, const PlanView& frame,
                           std::vector<planning::PointView>& points, glm::vec4& screen_box,
                           std::pair<glm::vec3, glm::vec3>& world_box) const;

    // plan_object.cpp
    Result<ObjectPlan> plan_object(size_t object_index, const FrameViews& frame, bool silhouette_on_screen) const;
    // The plan's prediction sources for material `mi`, with the notes on a
    // calibration not used.
    struct Sources {
        Source table;                    // the generic table's nearest relief
        std::optional<Source> modelled;  // the material's search model
        std::optional<Source> calibrated;
        const Source& uncalibrated() const { return modelled ? *modelled : table; }
        const Source& chosen() const { return calibrated ? *calibrated : uncalibrated(); }
    };
    Sources prediction_sources(size_t mi, const ObjectView& view, std::vector<std::string>& notes) const;
    // Whether the requested shadow can show (a light reaches the surface
    // over slopes steep enough to cast one); notes say why not.
    bool shadow_wanted(const EffectRequest& request, const ObjectView& view, const MaterialRelief& relief,
                       const std::vector<planning::PointView>& points, std::vector<std::string>& notes) const;
    // Every (technique, samples) the source measured that this context runs,
    // with the exact or the per-vertex view, with LOD or not.
    std::vector<planning::Candidate> candidates(const Source& source, const MaterialRelief& relief, bool want_shadow,
                                                bool silhouette_on_screen, bool lod_possible, const ObjectView& view,
                                                double fade_start) const;
    // Where a calibration picks another candidate than the uncalibrated
    // source would: that pick as the plan's generic key, with a note.
    void note_calibration_change(ObjectPlan& plan, planning::ObjectPredictor& predictor, const Sources& sources,
                                 const std::vector<planning::Candidate>& candidates, double hit_target,
                                 const planning::Candidate& pick) const;
    // Depth correction: where other geometry meets or overlaps the relief.
    void plan_depth(ObjectPlan& plan, size_t object_index, const FrameViews& frame) const;
    // The relief's volume in world space: a plane's between bias and bias +
    // scale along its normal (object space), any other mesh's box grown by
    // the depth.
    std::pair<glm::vec3, glm::vec3> relief_world_box(size_t object_index) const;
};

}  // namespace px
