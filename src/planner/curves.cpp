// The cost table as curves over the view angle, and the weighted
// percentiles a prediction over an object's points takes.
#include "planner_detail.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace px {
namespace planning {

std::string fmt(const char* format, double a) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, format, a);
    return buffer;
}

// Linear interpolation in a table sorted by x, clamped at the ends.
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
    if (xs.empty()) return 0.0;
    if (x <= xs.front()) return ys.front();
    if (x >= xs.back()) return ys.back();
    const size_t i = static_cast<size_t>(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin());
    const double t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
    return ys[i - 1] + t * (ys[i] - ys[i - 1]);
}

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

}  // namespace planning
}  // namespace px
