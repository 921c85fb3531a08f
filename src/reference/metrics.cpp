#include "parallaxes/reference/metrics.h"
#include "parallaxes/reference/reference_image.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace px::reference {

namespace {

// The shorter way round a tile: d - round(d), in [-0.5, 0.5). Hit uvs are
// unbounded (tiles repeat), so uv 0.999 and 1.001 are the same texel row.
double wrap_tile(double d) { return d - std::floor(d + 0.5); }

std::string size_text(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

// Nearest-rank percentile: the smallest error at least 95% of them reach
// (reorders `errors`, which must not be empty).
double p95(std::vector<double>& errors) {
    const size_t rank = static_cast<size_t>(std::ceil(0.95 * static_cast<double>(errors.size()))) - 1;
    std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(rank), errors.end());
    return errors[rank];
}

}  // namespace

double nearest_rank_p95(std::vector<double> values) { return values.empty() ? 0.0 : p95(values); }

Result<ContourError> compare_contours(const SurfaceImage& measured, const SurfaceImage& truth) {
    if (measured.width != truth.width || measured.height != truth.height ||
        measured.samples.size() != truth.samples.size() ||
        truth.samples.size() != static_cast<size_t>(truth.width) * static_cast<size_t>(truth.height))
        return make_error("compare_contours: images of different sizes (" + std::to_string(measured.width) + "x" +
                          std::to_string(measured.height) + " against " + std::to_string(truth.width) + "x" +
                          std::to_string(truth.height) + ")");
    ContourError e;
    for (int y = 0; y < truth.height; ++y)
        for (int x = 0; x < truth.width; ++x) {
            const bool t = truth.at(x, y).covered;
            const bool m = measured.at(x, y).covered;
            if (t != m) {
                ++e.mismatched;
                if (m) ++e.measured_only;
            }
            if (!t) continue;
            const bool edge = (x > 0 && !truth.at(x - 1, y).covered) || (x + 1 < truth.width && !truth.at(x + 1, y).covered) ||
                              (y > 0 && !truth.at(x, y - 1).covered) || (y + 1 < truth.height && !truth.at(x, y + 1).covered);
            if (edge) ++e.contour;
        }
    return e;
}

Result<ErrorMetrics> compare_surfaces(const SurfaceImage& measured, const SurfaceImage& truth, int texture_width,
                                      int texture_height) {
    if (measured.width != truth.width || measured.height != truth.height)
        return make_error("compare_surfaces: measured image is " + size_text(measured.width, measured.height) +
                          " but the reference is " + size_text(truth.width, truth.height));
    const size_t count = static_cast<size_t>(std::max(truth.width, 0)) * static_cast<size_t>(std::max(truth.height, 0));
    if (measured.samples.size() != count || truth.samples.size() != count)
        return make_error("compare_surfaces: sample count does not match the image size " +
                          size_text(truth.width, truth.height));
    if (texture_width < 1 || texture_height < 1)
        return make_error("compare_surfaces: texture size " + size_text(texture_width, texture_height) +
                          " is empty");

    ErrorMetrics m;
    std::vector<double> uv_errors;
    uv_errors.reserve(count);
    double depth_sum = 0.0;
    double shadow_sum = 0.0;
    long wrong = 0;
    for (size_t i = 0; i < count; ++i) {
        const SurfaceSample& a = measured.samples[i];
        const SurfaceSample& b = truth.samples[i];
        if (!a.covered || !b.covered) continue;
        const double du = wrap_tile(a.uv.x - b.uv.x) * texture_width;
        const double dv = wrap_tile(a.uv.y - b.uv.y) * texture_height;
        const double e = std::sqrt(du * du + dv * dv);
        uv_errors.push_back(e);
        if (e > 1.0) ++wrong;
        const double dh = std::fabs(a.height - b.height);
        depth_sum += dh;
        m.depth_error_max = std::max(m.depth_error_max, dh);
        shadow_sum += std::fabs(a.visibility - b.visibility);
    }
    m.pixels = static_cast<long>(uv_errors.size());
    if (m.pixels == 0) return m;  // nothing to compare: all errors stay 0

    const double n = static_cast<double>(m.pixels);
    double uv_sum = 0.0;
    for (double e : uv_errors) {
        uv_sum += e;
        m.uv_error_max = std::max(m.uv_error_max, e);
    }
    m.uv_error_mean = uv_sum / n;
    m.uv_error_p95 = p95(uv_errors);
    m.wrong_surface_share = static_cast<double>(wrong) / n;
    m.depth_error_mean = depth_sum / n;
    m.shadow_disagreement = shadow_sum / n;
    // color_psnr_db stays 0: surfaces carry no colour; callers fill it from color_psnr().
    return m;
}

Result<ObjectError> compare_object(const SurfaceImage& measured, const ReferenceImage& truth, int object) {
    const SurfaceImage& reference = truth.surface;
    if (measured.width != reference.width || measured.height != reference.height)
        return make_error("compare_object: measured image is " + size_text(measured.width, measured.height) +
                          " but the reference is " + size_text(reference.width, reference.height));
    const size_t count =
        static_cast<size_t>(std::max(reference.width, 0)) * static_cast<size_t>(std::max(reference.height, 0));
    if (measured.samples.size() != count || reference.samples.size() != count ||
        truth.object_index.size() != count || truth.texels_per_pixel.size() != count)
        return make_error("compare_object: the samples, object indices or footprints do not match the image size " +
                          size_text(reference.width, reference.height));
    if (object < 0 || static_cast<size_t>(object) >= truth.object_texture_size.size())
        return make_error("compare_object: object " + std::to_string(object) + " is out of range (the reference has " +
                          std::to_string(truth.object_texture_size.size()) + " objects)");
    const glm::ivec2 texture = truth.object_texture_size[static_cast<size_t>(object)];

    ObjectError e;
    std::vector<double> base, level;
    double visibility_sum = 0.0;
    for (size_t i = 0; i < count; ++i) {
        if (truth.object_index[i] != object) continue;
        ++e.reference_pixels;
        const SurfaceSample& a = measured.samples[i];
        const SurfaceSample& b = reference.samples[i];
        if (!b.covered) continue;  // nothing the GPU reports to compare with (a material reading no height)
        if (!a.covered) {
            ++e.pixels_missing;
            continue;
        }
        const double du = wrap_tile(a.uv.x - b.uv.x) * texture.x;
        const double dv = wrap_tile(a.uv.y - b.uv.y) * texture.y;
        const double error = std::sqrt(du * du + dv * dv);
        base.push_back(error);
        // Magnified (rho < 1) the base level is sampled: its texels are the unit.
        level.push_back(error / std::max(1.0, truth.texels_per_pixel[i]));
        visibility_sum += std::fabs(a.visibility - b.visibility);
    }
    e.pixels = static_cast<long>(base.size());
    if (e.pixels == 0) return e;  // nothing to compare: all errors stay 0
    const double n = static_cast<double>(e.pixels);
    double base_sum = 0.0, level_sum = 0.0;
    long wrong = 0;
    for (size_t k = 0; k < base.size(); ++k) {
        if (base[k] > 1.0) ++wrong;
        base_sum += base[k];
        level_sum += level[k];
        e.base_error_max = std::max(e.base_error_max, base[k]);
        e.level_error_max = std::max(e.level_error_max, level[k]);
    }
    e.base_error_mean = base_sum / n;
    e.level_error_mean = level_sum / n;
    e.wrong_surface_share = static_cast<double>(wrong) / n;
    e.base_error_p95 = p95(base);
    e.level_error_p95 = p95(level);
    e.visibility_error_mean = visibility_sum / n;
    return e;
}

double color_psnr(const Image& measured, const Image& truth, const SurfaceImage& mask) {
    // A broken precondition gives NaN: it fails every threshold comparison
    // instead of passing as a plausible number.
    const bool sizes_match = measured.width == truth.width && measured.height == truth.height &&
                             mask.width == truth.width && mask.height == truth.height;
    const size_t count = static_cast<size_t>(std::max(truth.width, 0)) * static_cast<size_t>(std::max(truth.height, 0));
    if (!sizes_match || measured.channels < 3 || truth.channels < 3 || mask.samples.size() != count ||
        measured.pixels.size() != count * static_cast<size_t>(measured.channels) ||
        truth.pixels.size() != count * static_cast<size_t>(truth.channels))
        return std::numeric_limits<double>::quiet_NaN();

    double squared_sum = 0.0;
    long values = 0;
    for (int y = 0; y < truth.height; ++y)
        for (int x = 0; x < truth.width; ++x) {
            if (!mask.at(x, y).covered) continue;
            const std::uint8_t* a = measured.texel(x, y);
            const std::uint8_t* b = truth.texel(x, y);
            for (int c = 0; c < 3; ++c) {
                const double d = static_cast<double>(a[c]) - static_cast<double>(b[c]);
                squared_sum += d * d;
            }
            values += 3;
        }
    if (values == 0 || squared_sum == 0.0) return 99.0;
    const double mse = squared_sum / static_cast<double>(values);
    // Capped so that "identical" (99) always ranks at least as high as any real score.
    return std::min(99.0, 10.0 * std::log10(255.0 * 255.0 / mse));
}

}  // namespace px::reference
