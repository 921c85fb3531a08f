// A candidate's predicted error and cost over one object's points this
// frame, and the shadow sample count (docs/planner.md).
#include "planner_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "parallaxes/core/text.h"

namespace px {
namespace planning {

const Curve* find_curve(const Source& s, Technique t, int samples, ShadowMode shadow, int shadow_samples) {
    auto it = s.curves->find({s.relief, t, samples, shadow, shadow_samples, 0});
    return it == s.curves->end() ? nullptr : &it->second;
}

namespace {

// The error-to-texel floor of the uv: without fragment highp (ES 2.0,
// Mali-400 class) the uv itself is fp16: no technique places a hit closer
// than half its step on [0.5, 1), 2^-12 of a tile (docs/stability.md,
// nohighp: 0.04 to 0.06 texel of mean error at 256 texels on every
// technique, maxmip included).
double fp16_uv_floor(const Caps& caps, const MaterialRelief& relief) {
    return caps.es_major < 3 && !caps.fragment_highp
               ? std::ldexp(static_cast<double>(std::max(relief.traced_width, relief.traced_height)), -12)
               : 0.0;
}

}  // namespace

ObjectPredictor::ObjectPredictor(const MaterialRelief& relief, const std::vector<PointView>& points,
                                 const EffectRequest& request, const Caps& caps, const Source& table_source)
    : relief_(relief), points_(points), request_(request), table_source_(table_source),
      uv_floor_(fp16_uv_floor(caps, relief)), blends_(points.size()) {
    // Each point's LOD fade (0: the technique, 1: normal mapping), once.
    const double fade_start = request.lod_threshold - request.lod_band;
    for (size_t i = 0; i < points.size(); ++i)
        blends_[i] = std::clamp((std::log2(std::max(points[i].rho, 1e-9)) - fade_start) / request.lod_band, 0.0, 1.0);
}

const ObjectPredictor::Basis& ObjectPredictor::basis_for(const std::vector<double>& angles) {
    for (const Basis& b : bases_)
        if (*b.angles == angles) return b;
    Basis b;
    b.angles = &angles;
    b.weight.assign(angles.size(), 0.0);
    for (const PointView& p : points_) {
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
    bases_.push_back(std::move(b));
    return bases_.back();
}

namespace {

// A curve's value at point `point` of the basis it was placed in.
template <class Basis>
double value_at(const Basis& b, const std::vector<double>& ys, size_t point) {
    const auto [i, t] = b.at[point];
    return t > 0.0 ? ys[i] + t * (ys[i + 1] - ys[i]) : ys[i];
}

// The pixel-weighted mean of a curve over the basis's points.
template <class Basis>
double mean_over(const Basis& b, const std::vector<double>& ys) {
    double sum = 0.0;
    for (size_t k = 0; k < ys.size(); ++k) sum += b.weight[k] * ys[k];
    return b.total > 0.0 ? sum / b.total : 0.0;
}

// A search model's raw error at level `k` of the point's angle (between
// table angles `idx` and idx + 1 at fraction `t`), in the point's azimuth
// sector where the model has them.
double level_at(const Curve& cv, size_t idx, double t, int k, size_t sector) {
    const bool sectors = cv.sector_levels.size() == cv.levels.size() && sector < cv.sector_levels[idx].size();
    const auto& a = sectors ? cv.sector_levels[idx][sector] : cv.levels[idx];
    const double lo = a[static_cast<size_t>(k)];
    if (!(t > 0.0)) return lo;
    const auto& next = sectors ? cv.sector_levels[idx + 1][sector] : cv.levels[idx + 1];
    return lo + t * (next[static_cast<size_t>(k)] - lo);
}

// What the per-vertex view vector adds at a point, in texels.
double per_vertex_added(const PointView& p, Technique t, double depth_texels) {
    return depth_texels * (t == Technique::offset_limited ? p.pv_offset : p.pv_parallax);
}

}  // namespace

Prediction ObjectPredictor::predict_cost(const Source& s, const Candidate& c) {
    Prediction out;
    const Curve* tc = find_curve(s, c.technique, c.samples, ShadowMode::none, 0);
    const Curve* nc = find_curve(s, Technique::normal, 0, ShadowMode::none, 0);
    if (!tc || !nc) return out;
    out.known = true;
    const Basis& b = basis_for(tc->angles);
    if (!c.lod) {
        out.cost = mean_over(b, tc->cost);
        return out;
    }
    double sum = 0.0;
    for (size_t i = 0; i < points_.size(); ++i)
        sum += (blends_[i] >= 1.0 ? 1.0 : value_at(b, tc->cost, i)) * points_[i].weight;
    out.cost = b.total > 0.0 ? sum / b.total : 0.0;
    return out;
}

double ObjectPredictor::model_error(const Source& s, const Candidate& c) {
    const Curve* tc = find_curve(s, c.technique, c.samples, ShadowMode::none, 0);
    const Curve* nc = find_curve(s, Technique::normal, 0, ShadowMode::none, 0);
    if (!tc || !nc) return std::numeric_limits<double>::infinity();
    const TechniqueInfo& info = technique_info(c.technique);
    const bool per_vertex = !c.exact_view && !info.always_exact_view && (info.options & kOptHeight);
    if (s.simulated && tc->levels.size() == tc->angles.size() && nc->levels.size() == nc->angles.size() &&
        !tc->levels.empty())
        return simulated_error(c, *tc, *nc, per_vertex);
    return measured_error(s, c, *tc, *nc, per_vertex);
}

// The search model: every pixel's error is a draw from the simulated
// distribution at its angle (its levels), in texels of the level sampled;
// the object's p95 and p97 are of those draws pooled over its pixels (what
// the GPU's p95 is of), with the margin on top: max(p95 x scale, p97) +
// floor. Each level's share of the rays is put at its upper end.
double ObjectPredictor::simulated_error(const Candidate& c, const Curve& tc, const Curve& nc, bool per_vertex) {
    const Basis& b = basis_for(tc.angles);
    const Basis& bn = basis_for(nc.angles);
    const double depth_texels = relief_.features.depth_texels;
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
    const Curve* table_curve = find_curve(table_source_, c.technique, c.samples, ShadowMode::none, 0);
    const Basis* table_basis = table_curve ? &basis_for(table_curve->angles) : nullptr;
    std::vector<std::pair<double, double>> pooled;
    pooled.reserve(points_.size() * static_cast<size_t>(kSearchLevelCount));
    for (size_t i = 0; i < points_.size(); ++i) {
        const PointView& p = points_[i];
        const auto [ti, tt] = b.at[i];
        const auto [ni, nt] = bn.at[i];
        const double added = per_vertex ? per_vertex_added(p, c.technique, depth_texels) : 0.0;
        const double per_level = 1.0 / std::max(1.0, p.rho);
        double below = 0.0;
        const auto sector = static_cast<size_t>(p.sector);
        for (int k = 0; k < kSearchLevelCount; ++k) {
            double v = (level_at(tc, ti, tt, k, sector) + added) * per_level;
            if (table_basis && p.rho >= kPastSimulated)
                v = std::max(v, (value_at(*table_basis, table_curve->error, i) * table_source_.depth_scale + added) *
                                    per_level - margin.floor);
            if (c.lod)
                v = (1.0 - blends_[i]) * v +
                    blends_[i] * (level_at(nc, ni, nt, k, sector) * per_level + normal_margin.floor - margin.floor);
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

// A table's curve: each point's error at its angle, scaled by the relief
// depths, with the step-over bound: a linear search of `samples` layers
// moves the ray depth x tan(view angle) / samples texels per sample; where
// that passes the relief's narrowest feature the search can step over it
// and land up to a step away, whatever the table relief (whose features
// may be wider) measured. Exact walks never step over.
double ObjectPredictor::measured_error(const Source& s, const Candidate& c, const Curve& tc, const Curve& nc,
                                       bool per_vertex) {
    const Basis& b = basis_for(tc.angles);
    const Basis& bn = basis_for(nc.angles);
    const double depth_texels = relief_.features.depth_texels;
    const bool linear_search = !s.simulated && (technique_info(c.technique).options & kOptSamples) && c.samples > 0;
    const double thinnest = std::max(relief_.features.thinnest_texels, 0.5);
    std::vector<std::pair<double, double>> errors;
    errors.reserve(points_.size());
    for (size_t i = 0; i < points_.size(); ++i) {
        const PointView& p = points_[i];
        double e = value_at(b, tc.error, i) * s.depth_scale;
        if (linear_search) {
            const double travel = depth_texels * std::tan(glm::radians(std::min(p.angle_deg, 89.5)));
            const double step = travel / c.samples;
            if (step > thinnest) e = std::max(e, step);
        }
        if (per_vertex) e += per_vertex_added(p, c.technique, depth_texels);
        const double floor_technique = s.simulated ? search_margin(c.technique).floor : 0.0;
        const double floor_normal = s.simulated ? search_margin(Technique::normal).floor : 0.0;
        double level = e / std::max(1.0, p.rho) + floor_technique;
        if (c.lod)
            level = (1.0 - blends_[i]) * level +
                    blends_[i] * (value_at(bn, nc.error, i) * s.depth_scale / std::max(1.0, p.rho) + floor_normal);
        errors.emplace_back(level, p.weight);
    }
    return weighted_p95(errors);
}

double ObjectPredictor::predict_error(const Source& s, const Candidate& c) {
    return std::max(model_error(s, c), uv_floor_);
}

Prediction ObjectPredictor::predict(const Source& s, const Candidate& c) {
    Prediction out = predict_cost(s, c);
    if (out.known) out.error = predict_error(s, c);
    return out;
}

Choice ObjectPredictor::choose(const Source& s, const std::vector<Candidate>& candidates, double target) {
    Choice out;
    out.best_error = std::numeric_limits<double>::infinity();
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
        if (predicted[i].error < out.best_error) {
            out.best_error = predicted[i].error;
            out.best_name = candidate_name(candidates[i]);
        }
        if (predicted[i].error <= target) {
            out.chosen = predicted[i];
            out.pick = candidates[i];
            return out;
        }
    }
    return out;
}

namespace {

// One shadow sample count's curves at each light elevation (sorted), seen
// over the object's lit points: the mean visibility difference and the
// mean cost added over the unshadowed search (`base`).
std::pair<double, double> shadow_estimate(const std::vector<std::pair<double, const Curve*>>& curves, const Curve* base,
                                          const std::vector<PointView>& points) {
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
    return {w_sum > 0.0 ? e_sum / w_sum : 0.0, w_sum > 0.0 ? c_sum / w_sum : 0.0};
}

}  // namespace

Result<ShadowChoice> choose_shadow_samples(const Source& source, const Source& table_source, const ReliefFeatures& relief,
                                           const EffectRequest& request, const std::vector<PointView>& points,
                                           const std::string& who, const std::string& field_path) {
    // The nearest table relief that has shadow rows of this mode (the
    // search model simulates no shadows: the generic table's).
    const Source& shadow_base = source.simulated ? table_source : source;
    const CostTable& table = *shadow_base.table;
    std::vector<bool> eligible(table.reliefs.size(), false);
    for (const CostSample& s : table.rows)
        if (s.shadow == request.shadow) eligible[static_cast<size_t>(s.relief)] = true;
    const int shadow_relief = nearest_relief(table, relief, eligible);
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
        std::sort(curves.begin(), curves.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        const Curve* base = find_curve(shadow_source, count.first.first, count.first.second, ShadowMode::none, 0);
        const auto [e, added] = shadow_estimate(curves, base, points);
        best_error = std::min(best_error, e);
        if (e <= request.shadow_max_error) options_by_cost.emplace_back(added, count.second, e);
    }
    if (options_by_cost.empty())
        return make_error(who + ": " + field_path + ".shadow.max_error: " + fmt("%g", request.shadow_max_error) +
                          " is below what any shadow sample count reaches here (best " + fmt("%.3g", best_error) +
                          " mean visibility difference)");
    std::sort(options_by_cost.begin(), options_by_cost.end());
    ShadowChoice out;
    std::tie(out.cost, out.samples, out.error) = options_by_cost.front();
    return out;
}

std::pair<glm::vec3, glm::vec3> transformed_box(const glm::vec3& box_lo, const glm::vec3& box_hi, const glm::mat4& model) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner((c & 1) ? box_hi.x : box_lo.x, (c & 2) ? box_hi.y : box_lo.y, (c & 4) ? box_hi.z : box_lo.z);
        const glm::vec3 w = glm::vec3(model * glm::vec4(corner, 1.0f));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
    return {lo, hi};
}

}  // namespace planning
}  // namespace px
