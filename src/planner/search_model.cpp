#include "parallaxes/planner/search_model.h"

#include "parallaxes/core/limits.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "parallaxes/reference/tracer.h"

namespace px {

const SearchCurve* SearchModel::find(Technique technique, int samples) const {
    for (const SearchCurve& c : curves)
        if (c.technique == technique && c.samples == samples) return &c;
    return nullptr;
}

namespace {

// A deterministic sequence in [0, 1): the van der Corput radical inverse
// (base 2 and 3 give a Halton set, well spread for any count).
double radical_inverse(std::uint32_t i, std::uint32_t base) {
    double inv = 1.0 / base, f = inv, r = 0.0;
    while (i > 0) {
        r += f * (i % base);
        i /= base;
        f *= inv;
    }
    return r;
}

double quantile(std::vector<double>& v, double q) {
    if (v.empty()) return 0.0;
    const double at = std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size()));
    const size_t k = std::min(v.size() - 1, static_cast<size_t>(std::max(at, 1.0)) - 1);
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
}

}  // namespace

std::vector<SearchCurve> search_candidates(const std::vector<int>& samples) {
    // A fixed order: normal, parallax, offset_limited, maxmip, then steep,
    // pom and relief at each count.
    auto curve = [](Technique t, int n) {
        SearchCurve c;
        c.technique = t;
        c.samples = n;
        return c;
    };
    std::vector<SearchCurve> curves{curve(Technique::normal, 0), curve(Technique::parallax, 0),
                                    curve(Technique::offset_limited, 0), curve(Technique::maxmip, 0)};
    for (Technique t : {Technique::steep, Technique::pom, Technique::relief})
        for (int n : samples) curves.push_back(curve(t, n));
    return curves;
}

namespace {

std::vector<int> usable_counts(const std::vector<int>& samples) {
    std::vector<int> counts;
    for (int n : samples)
        if (n >= 1 && n <= kMaxExactSteps) counts.push_back(n);
    std::sort(counts.begin(), counts.end());
    counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
    return counts;
}

// A linear search's last two samples: the one above the surface and the
// one on or under it (or the bottom).
struct March {
    double ray_above, height_above, ray_below, height_below;
};

// One ray as the shaders walk it (march.glsl), in texels of the field: uv
// at ray height r is uv + (r - ph) P, P = height_scale view.xy /
// max(view.z, 1/64); and its error against the exact hit.
struct ShaderRay {
    const HeightField* field;
    double w, h, ph;
    glm::dvec2 at_polygon, parallax, truth;
    double per_level;  // 1 / texels per pixel: errors in texels of the level sampled

    glm::dvec2 position(double r) const { return at_polygon + (r - ph) * parallax; }
    double height_at(glm::dvec2 p) const { return field->sample_bilinear(p.x / w, p.y / h); }
    // As the bench measures it (reference/metrics.cpp): the difference
    // wrapped into one tile, so a miss costs at most half a tile.
    double error_at(double r) const {
        glm::dvec2 d = position(r) - truth;
        d -= glm::dvec2(w, h) * glm::round(d / glm::dvec2(w, h));
        return glm::length(d) * per_level;
    }
};

// The linear search of each count, from the top down in n equal steps,
// stopping at the first sample on or under the surface, or at the bottom.
// Where every count divides the finest, the heights come from one grid.
void march_counts(const ShaderRay& ray, const std::vector<int>& counts, int finest, bool nested,
                  std::vector<double>& grid_height, std::vector<March>& marches) {
    if (nested)
        for (int i = 0; i <= finest; ++i)
            grid_height[static_cast<size_t>(i)] = ray.height_at(ray.position(1.0 - static_cast<double>(i) / finest));
    for (size_t k = 0; k < counts.size(); ++k) {
        const int n = counts[k];
        auto sample = [&](int i) {
            return nested ? grid_height[static_cast<size_t>(i * (finest / n))]
                          : ray.height_at(ray.position(1.0 - static_cast<double>(i) / n));
        };
        March m{1.0, sample(0), 1.0, sample(0)};
        if (m.height_above < 1.0) {
            for (int i = 1; i <= n; ++i) {
                const double r = 1.0 - static_cast<double>(i) / n;
                const double s = sample(i);
                m.ray_below = r;
                m.height_below = s;
                if (s >= r || i >= n) break;
                m.ray_above = r;
                m.height_above = s;
            }
        }
        marches[k] = m;
    }
}

// The errors of steep (the sample), POM (the secant between the last two
// samples) and relief (binary refinement) after each march, from curve `c`.
void push_search_errors(const ShaderRay& ray, const std::vector<March>& marches, int refine,
                        std::vector<std::vector<double>>& errors, size_t c) {
    for (const March& m : marches) errors[c++].push_back(ray.error_at(m.ray_below));
    for (const March& m : marches) {
        const double gap_above = m.ray_above - m.height_above, gap_below = m.ray_below - m.height_below;
        const double d = gap_above - gap_below;
        const double t = d > 0.0 ? std::clamp(gap_above / d, 0.0, 1.0) : 1.0;
        errors[c++].push_back(ray.error_at(m.ray_above + t * (m.ray_below - m.ray_above)));
    }
    for (const March& m : marches) {
        double above = m.ray_above, below = m.ray_below;
        for (int i = 0; i < refine; ++i) {
            const double middle = 0.5 * (above + below);
            if (ray.height_at(ray.position(middle)) >= middle) below = middle;
            else above = middle;
        }
        errors[c++].push_back(ray.error_at(below));
    }
}

}  // namespace

std::vector<std::vector<double>> simulate_rays(const HeightField& field, double height_scale, double polygon_height,
                                               const std::vector<SearchRay>& rays, const std::vector<int>& samples,
                                               int refine_steps, const std::vector<double>& quantiles) {
    const std::vector<int> counts = usable_counts(samples);
    const size_t curve_count = search_candidates(counts).size();
    const bool usable = field.width > 0 && field.height > 0 &&
                        field.texels.size() == static_cast<size_t>(field.width) * static_cast<size_t>(field.height) &&
                        height_scale > 0.0 && std::isfinite(height_scale);
    if (!usable || rays.empty()) return std::vector<std::vector<double>>(quantiles.size(), std::vector<double>(curve_count, 0.0));

    const double w = field.width, h = field.height;
    const double ph = std::isfinite(polygon_height) ? polygon_height : 1.0;
    const int refine = std::clamp(refine_steps, 0, 32);
    // The finest grid every count is a subset of, when there is one.
    int finest = 1;
    for (int n : counts) finest = std::max(finest, n);
    bool nested = true;
    for (int n : counts) nested = nested && finest % n == 0;

    std::vector<std::vector<double>> errors(curve_count);
    for (auto& e : errors) e.reserve(rays.size());
    std::vector<double> grid_height(static_cast<size_t>(finest) + 1);
    std::vector<March> marches(counts.size());

    for (const SearchRay& start : rays) {
        glm::dvec3 view = start.view;
        if (!(glm::length(view) > 0.0) || !std::isfinite(view.x + view.y + view.z)) continue;
        view = glm::normalize(view);
        if (view.z <= 1e-6) continue;  // the polygon is seen edge-on or from behind: nothing to draw
        const reference::Ray exact_ray = reference::view_ray(field, start.uv, view, height_scale, ph);
        const reference::Hit exact = reference::first_hit(field, exact_ray, 0.0, 1.0);
        ShaderRay ray;
        ray.field = &field;
        ray.w = w;
        ray.h = h;
        ray.ph = ph;
        ray.truth = exact.hit ? glm::dvec2(exact.position) : glm::dvec2(exact_ray.origin + exact_ray.direction);
        ray.parallax = height_scale * glm::dvec2(view.x, view.y) / std::max(view.z, 1.0 / 64.0) * glm::dvec2(w, h);
        ray.at_polygon = start.uv * glm::dvec2(w, h);
        ray.per_level = 1.0 / std::max(1.0, std::isfinite(start.texels_per_pixel) ? start.texels_per_pixel : 1.0);

        size_t c = 0;
        errors[c++].push_back(ray.error_at(ph));  // normal mapping: the uv as drawn
        const double h0 = ray.height_at(ray.at_polygon);
        errors[c++].push_back(ray.error_at(h0));                       // parallax: one offset by h / V.z
        errors[c++].push_back(ray.error_at(ph + (h0 - ph) * view.z));  // offset limiting: by h alone
        errors[c++].push_back(0.0);                                    // maxmip: an exact walk of the same field
        march_counts(ray, counts, finest, nested, grid_height, marches);
        push_search_errors(ray, marches, refine, errors, c);
    }
    std::vector<std::vector<double>> out(quantiles.size(), std::vector<double>(curve_count, 0.0));
    for (size_t q = 0; q < quantiles.size(); ++q)
        for (size_t c = 0; c < curve_count; ++c) out[q][c] = quantile(errors[c], quantiles[q]);
    return out;
}

int search_sector(double view_x, double view_y) {
    if (!std::isfinite(view_x) || !std::isfinite(view_y) || (view_x == 0.0 && view_y == 0.0)) return 0;
    const double folded = std::atan2(std::fabs(view_y), std::fabs(view_x));  // [0, pi/2]
    const int sector = static_cast<int>(folded / (0.5 * M_PI) * kSearchSectors);
    return std::clamp(sector, 0, kSearchSectors - 1);
}

namespace {

// The error at `level` of the equal-weight mixture of distributions given
// by their kSearchLevels (each level's share of the rays at its upper end,
// as the planner pools them).
double mixture_level(const std::vector<std::vector<double>>& parts, double level) {
    std::vector<std::pair<double, double>> pooled;
    for (const std::vector<double>& part : parts) {
        double below = 0.0;
        for (int k = 0; k < kSearchLevelCount; ++k) {
            pooled.emplace_back(part[static_cast<size_t>(k)], kSearchLevels[k] - below);
            below = kSearchLevels[k];
        }
    }
    std::sort(pooled.begin(), pooled.end());
    double total = 0.0;
    for (const auto& e : pooled) total += e.second;
    double sum = 0.0;
    for (const auto& e : pooled) {
        sum += e.second;
        if (sum >= level * total * (1.0 - 1e-12)) return e.first;
    }
    return pooled.empty() ? 0.0 : pooled.back().first;
}

}  // namespace

SearchModel simulate_searches(const HeightField& field, double height_scale, double polygon_height,
                              const SearchModelOptions& options) {
    SearchModel model;
    model.angles = options.angles;
    std::sort(model.angles.begin(), model.angles.end());
    model.rays = std::clamp(options.rays, 1, 1 << 16);
    const std::vector<int> counts = usable_counts(options.samples);
    model.curves = search_candidates(counts);
    std::vector<SearchRay> rays(static_cast<size_t>(model.rays));
    const std::vector<double> levels(kSearchLevels, kSearchLevels + kSearchLevelCount);
    const double sector_width = 0.5 * M_PI / kSearchSectors;
    for (double angle : model.angles) {
        const double theta = glm::radians(std::clamp(angle, 0.0, 89.9));
        // Per curve, per sector, the error at each level.
        std::vector<std::vector<std::vector<double>>> by_sector(model.curves.size());
        for (int sector = 0; sector < kSearchSectors; ++sector) {
            for (int k = 0; k < model.rays; ++k) {
                // Spread over the tile and the sector's azimuths (Halton),
                // in all four of its mirror images in turn.
                const auto i = static_cast<std::uint32_t>(k) + 1;
                double phi = sector_width * (sector + radical_inverse(i, 5));
                if (k & 1) phi = M_PI - phi;
                if (k & 2) phi = -phi;
                rays[static_cast<size_t>(k)] = {glm::dvec2(radical_inverse(i, 2), radical_inverse(i, 3)),
                                                glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                                           std::cos(theta))};
            }
            const std::vector<std::vector<double>> p =
                simulate_rays(field, height_scale, polygon_height, rays, counts, options.refine_steps, levels);
            for (size_t c = 0; c < model.curves.size(); ++c) {
                std::vector<double> at(static_cast<size_t>(kSearchLevelCount));
                for (size_t k = 0; k < at.size(); ++k) at[k] = p[k][c];
                by_sector[c].push_back(std::move(at));
            }
        }
        for (size_t c = 0; c < model.curves.size(); ++c) {
            // Over every azimuth: the sectors' distributions pooled.
            std::vector<double> at(static_cast<size_t>(kSearchLevelCount));
            for (size_t k = 0; k < at.size(); ++k) at[k] = mixture_level(by_sector[c], kSearchLevels[k]);
            model.curves[c].error.push_back(at[5]);  // 0.95
            model.curves[c].upper.push_back(at[6]);  // 0.97
            model.curves[c].levels.push_back(std::move(at));
            model.curves[c].sector_levels.push_back(std::move(by_sector[c]));
        }
    }
    return model;
}

SearchMargin search_margin(Technique technique) {
    // Fitted on the 7 fit reliefs of examples/scenes/relief_family (1,050
    // cases) by `parallax bench --search-model examples/scenes/relief_family`
    // on llvmpipe, 2026-12-03 (docs/planner.md, "The search model"): the
    // scale the 95th percentile of (measured - floor) / simulated p95, the
    // floor the 90th percentile of what the GPU measures where the
    // simulation leaves nothing.
    switch (technique) {
        case Technique::normal: return {1.016, 0.0};
        case Technique::parallax: return {1.017, 0.0};
        case Technique::offset_limited: return {1.044, 0.0};
        case Technique::steep: return {1.023, 0.0478};
        case Technique::pom: return {1.078, 0.0506};
        case Technique::relief: return {1.058, 0.0518};
        case Technique::maxmip: return {1.0, 0.0};
        default: return {1.0, 0.0};
    }
}

}  // namespace px
