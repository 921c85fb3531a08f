#include "parallaxes/profiling/measurement/stability.h"

#include "parallaxes/profiling/measurement/bench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <functional>
#include <set>
#include <sstream>

#include "parallaxes/core/limits.h"
#include "parallaxes/core/text.h"
#include "parallaxes/gl/gl.h"
#include "parallaxes/reference/reference_image.h"
#include "parallaxes/reference/tracer.h"
#include "parallaxes/render/surface_capture.h"
#include "parallaxes/scene/material_images.h"

namespace px::profiling {

namespace {

// --- Per-pixel bounds -------------------------------------------------------

struct PixelTerms {
    double parallax = 0.0;  // P, texels
    double limited = 0.0;   // s |V.xy|, texels
};

// P and s|V.xy| in texels of a w x h map, from the exact unit view vector.
PixelTerms pixel_terms(const glm::dvec3& v, double s, int w, int h) {
    const glm::dvec2 texels(v.x * w, v.y * h);
    PixelTerms t;
    t.limited = s * glm::length(texels);
    t.parallax = t.limited / std::max(v.z, 1.0 / 64.0);
    return t;
}

double bound_value(BoundKind k, const PixelTerms& t, double polygon_height, bool for_offset, int samples,
                   int refine) {
    const double reach = std::max(polygon_height, 1.0 - polygon_height);
    switch (k) {
        case BoundKind::zero:
        case BoundKind::exact: return 0.0;
        case BoundKind::limited: return t.limited * (for_offset ? reach : 1.0);
        case BoundKind::parallax: return t.parallax * (for_offset ? reach : 1.0);
        case BoundKind::step: return t.parallax / std::max(samples, 1);
        case BoundKind::refined_step: return t.parallax / (std::max(samples, 1) * std::ldexp(1.0, refine));
    }
    return 0.0;
}

bool finite(const SurfaceSample& s) {
    return std::isfinite(s.uv.x) && std::isfinite(s.uv.y) && std::isfinite(s.height) && std::isfinite(s.visibility);
}

// The shorter way round the tile, in texels.
glm::dvec2 wrapped_texels(glm::dvec2 d, int w, int h) {
    d -= glm::round(d);
    return glm::dvec2(d.x * w, d.y * h);
}

// What the linear search would find along the exact ray, computed from its
// definition (not from the shader): samples at heights 1 - i/N, the first one
// on or under the exact surface (the 8-bit bilinear field the GPU samples)
// and the one before it. A technique that searches can do no better than its
// samples: where the ray crosses a feature between two samples (a chord
// shorter than a step) the search misses it, and its bound says so instead of
// a fitted allowance.
struct SearchBound {
    double steep = 0.0;    // |true hit - first sample under|, texels
    double bracket = 0.0;  // max distance from the true hit to either end of the bracket
    bool true_hit_in_bracket = false;
    double filtered = 0.0; // how far the hit moves on the surface raised or lowered by kFilteredHeight
    double entry = 0.0;    // how far it moves with the entry uv's fp32 rounding
};

// The surface a technique's filtered fetches see is not the exact bilinear
// one: Mesa returns a mediump sampler's texels as fp16 (half an ulp below 1
// is 2^-12), and GL leaves the filter's sub-texel precision to the
// implementation: D3D10-class hardware keeps 8 bits of it, so a weight is
// off by up to 2^-9 and the filtered height by 2^-9 of the corners' range
// (at most 1). The hit a technique can promise lies between the exact hits
// on the surface lowered and raised by the sum; where the ray meets the
// surface at a shallow angle that window is wide, and the bound says so.
constexpr double kFilteredHeight = 1.0 / 4096.0 + 1.0 / 512.0;

std::vector<SearchBound> search_bounds(const reference::ReferenceImage& ref, const HeightField& field, int samples) {
    std::vector<SearchBound> out(ref.surface.samples.size());
    const int tw = ref.texture_width, th = ref.texture_height;
    if (tw == 0 || field.width == 0) return out;
    const double s = ref.height_scale, p = ref.polygon_height;
    const int n = std::max(samples, 1);
    for (size_t i = 0; i < out.size(); ++i) {
        const SurfaceSample& r = ref.surface.samples[i];
        if (!r.covered) continue;
        const glm::dvec3 v = ref.view_ts[i];
        if (!(v.z > 0.0)) continue;
        // The ray the search is defined on: the shaders clamp V.z at 1/64
        // (chunks/march.glsl), so past 89.1 degrees it is steeper than the
        // view ray; the gap to the exact hit shows as the technique's limit.
        const glm::dvec2 parallax = s * glm::dvec2(v.x, v.y) / std::max(v.z, 1.0 / 64.0);
        const glm::dvec2 uv0 = ref.entry_uv[i];
        auto at = [&](int k) { return uv0 + ((1.0 - double(k) / n) - p) * parallax; };
        int k = 0;
        for (; k < n; ++k) {
            const glm::dvec2 uv = at(k);
            if (field.sample_bilinear(uv.x, uv.y) >= 1.0 - double(k) / n) break;
        }
        const glm::dvec2 below = at(k), above = at(std::max(k - 1, 0));
        // Unwrapped: the reference's hit and the samples share one uv frame,
        // and a bound on the straight distance bounds the error measured the
        // shorter way round the tile too (a deep relief spans tiles).
        const glm::dvec2 texels(tw, th);
        const double d_below = glm::length((r.uv - below) * texels);
        const double d_above = glm::length((r.uv - above) * texels);
        out[i].steep = d_below;
        out[i].bracket = std::max(d_below, d_above);
        const double h_above = 1.0 - double(std::max(k - 1, 0)) / n, h_below = 1.0 - double(k) / n;
        out[i].true_hit_in_bracket = r.height <= h_above + 1e-9 && r.height >= h_below - 1e-9;
    }
    return out;
}

// SearchBound::filtered for every covered pixel: the exact trace on the field
// shifted down and up by kFilteredHeight.
// Also: the GPU's entry uv is known only to its fp32 rounding, 4 ulp of its
// magnitude m (a few roundings in the interpolation); where that is past a
// tenth of a texel (tiled uvs of 10^3 and more) the exact hits from the
// entry moved that far along the view ray's direction, either way, widen
// the window the same way (a ray that skims a crest flips with its entry).
void filtered_bounds(const reference::ReferenceImage& ref, const HeightField& field, std::vector<SearchBound>& out) {
    const int tw = ref.texture_width, th = ref.texture_height;
    if (tw == 0 || field.width == 0) return;
    HeightField lower = field, upper = field;
    for (float& t : lower.texels) t -= static_cast<float>(kFilteredHeight);
    for (float& t : upper.texels) t += static_cast<float>(kFilteredHeight);
    const glm::dvec2 texels(tw, th);
    for (size_t i = 0; i < out.size(); ++i) {
        const SurfaceSample& r = ref.surface.samples[i];
        const glm::dvec3 v = ref.view_ts[i];
        if (!r.covered || !(v.z > 0.0)) continue;
        const glm::dvec2 uv0 = ref.entry_uv[i];
        double window = 0.0, entry = 0.0;
        for (const HeightField* f : {&lower, &upper}) {
            const reference::ReliefHit h = reference::trace_view(*f, uv0, v, ref.height_scale, ref.polygon_height);
            window = std::max(window, glm::length((r.uv - h.uv) * texels));
        }
        const double magnitude = std::max(std::fabs(uv0.x), std::fabs(uv0.y));
        const double entry_rounding = 4.0 * magnitude * std::ldexp(1.0, -23);  // tiles
        if (entry_rounding * std::max(tw, th) > 0.1 && glm::length(glm::dvec2(v)) > 0.0) {
            const glm::dvec2 along = glm::normalize(glm::dvec2(v.x, v.y)) * entry_rounding;
            for (double sign : {-1.0, 1.0}) {
                const reference::ReliefHit h =
                    reference::trace_view(field, uv0 + sign * along, v, ref.height_scale, ref.polygon_height);
                entry = std::max(entry, glm::length((r.uv - h.uv) * texels));
            }
        }
        out[i].filtered = window;
        out[i].entry = entry;
    }
}

// --- Scenes -------------------------------------------------------------------

struct Frame {
    double angle = 60.0;
    double distance = 2.2;
};

std::vector<Frame> frames_of(const StabilityCase& c, bool full, std::vector<std::pair<size_t, size_t>>& pairs) {
    std::vector<Frame> frames;
    pairs.clear();
    if (!c.distances.empty()) {
        for (double d : c.distances) frames.push_back({c.angles.front(), d});
    } else if (c.sweep) {
        for (double a : c.angles) frames.push_back({a, c.distance});
    } else {
        return frames;  // one frame per angle: separate rows
    }
    // Neighbours compared for continuity: every pair, or without --full the
    // pairs that start every quick_stride-th frame (still neighbours).
    std::vector<Frame> kept;
    for (size_t i = 0; i + 1 < frames.size(); ++i) {
        if (!full && i % static_cast<size_t>(c.quick_stride) != 0) continue;
        kept.push_back(frames[i]);
        kept.push_back(frames[i + 1]);
        pairs.emplace_back(kept.size() - 2, kept.size() - 1);
    }
    return kept;
}

std::string angle_label(double a) {
    std::ostringstream s;
    s << a;
    return s.str();
}

std::vector<const TechniqueInfo*> techniques_of(const StabilityCase& c) {
    std::vector<const TechniqueInfo*> out;
    for (const TechniqueInfo& info : technique_table()) {
        if (!c.techniques.empty() && std::find(c.techniques.begin(), c.techniques.end(), info.name) == c.techniques.end())
            continue;
        out.push_back(&info);
    }
    return out;
}


}  // namespace

Result<std::string> write_height_image(const StabilityCase& c, const std::string& scratch_dir) {
    FieldSpec spec = c.field;
    spec.size = std::max(*c.image_width, *c.image_height);
    Result<HeightField> field = make_height_field(spec);
    if (!field) return field.error();
    Image image;
    image.width = *c.image_width;
    image.height = *c.image_height;
    image.channels = 1;
    image.pixels.resize(static_cast<size_t>(image.width) * image.height);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            // The field resampled (nearest) onto the image's grid: a repeating tile of any size.
            const int fx = x * field->width / image.width;
            const int fy = y * field->height / image.height;
            image.texel(x, y)[0] = static_cast<std::uint8_t>(std::lround(std::clamp(field->at(fx, fy), 0.0f, 1.0f) * 255.0f));
        }
    std::error_code ec;
    std::filesystem::create_directories(scratch_dir, ec);
    if (ec) return make_error("stability: cannot create '" + scratch_dir + "': " + ec.message());
    const std::string path = scratch_dir + "/" + c.name + "_height.png";
    Status written = write_png(path, image);
    if (!written) return written.error();
    return path;
}

namespace {

// The case's scene, not yet validated (prepare_scene and replace_material
// validate what they are handed).
Result<SceneDesc> unchecked_scene(const StabilityCase& c, const std::string& technique, double angle, double distance,
                                  const std::string& height_image) {
    SceneDesc s;
    s.name = c.name;
    const double a = angle * M_PI / 180.0;
    if (c.camera_position) {
        s.camera.position = *c.camera_position;
        s.camera.target = *c.camera_target;
    } else {
        const double az = c.azimuth_deg * M_PI / 180.0;
        s.camera.position = glm::vec3(static_cast<float>(distance * std::sin(a) * std::sin(az)),
                                      static_cast<float>(-distance * std::sin(a) * std::cos(az)),
                                      static_cast<float>(distance * std::cos(a)));
        s.camera.target = glm::vec3(0.0f);
    }
    s.camera.up = angle < 1.0 && !c.camera_position ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f);
    s.camera.fov_y_deg = c.fov_deg;
    // Near plane: a tenth of the eye's distance to the plane's centre, so
    // that close-up cases keep their depth precision, within the limits.
    const float eye_distance = glm::length(s.camera.position - s.camera.target);
    s.camera.near_plane = std::clamp(0.1f * eye_distance, 1e-4f, 0.05f);
    s.camera.far_plane = std::max(50.0f, 4.0f * eye_distance);
    s.lights = {sun_light(c.light_elevation_deg, c.light_azimuth_deg)};

    MaterialDesc m;
    m.name = "surface";
    m.albedo.kind = TextureSource::Kind::color;
    m.albedo.color = glm::vec3(0.75f, 0.7f, 0.65f);
    if (c.image_width) {
        if (height_image.empty())
            return make_error("case '" + c.name + "': its height image has not been written (write_height_image)");
        m.height.kind = TextureSource::Kind::file;
        m.height.path = height_image;
    } else {
        m.height.kind = TextureSource::Kind::procedural;
        m.height.field = c.field;
    }
    m.height_scale = c.height_scale;
    m.height_bias = c.height_bias;
    m.uv = c.uv;
    Result<Technique> t = parse_technique(technique);
    if (!t) return t.error();
    m.technique.technique = *t;
    m.technique.min_samples = m.technique.max_samples = c.samples;
    m.technique.refine_steps = c.refine_steps;
    m.technique.shadow = c.shadow;
    m.technique.lod = c.lod;
    m.technique.lod_threshold = c.lod_threshold;
    m.technique.lod_band = c.lod_band;
    if (c.exact_view) m.technique.exact_view = *c.exact_view;
    s.materials = {m};
    ObjectDesc o;
    o.name = "plane";
    o.mesh.kind = MeshKind::plane;
    o.mesh.size = c.plane_size;
    o.mesh.segments = c.segments;
    o.transform.scale = c.model_scale;
    o.mesh.tangent = c.tangent;
    o.mesh.normal = c.normal;
    o.material = "surface";
    s.objects = {o};
    return s;
}

}  // namespace

Result<SceneDesc> stability_scene(const StabilityCase& c, const std::string& technique, double angle,
                                  double distance, const std::string& height_image) {
    Result<SceneDesc> s = unchecked_scene(c, technique, angle, distance, height_image);
    if (!s) return s;
    Status valid = validate_scene(*s);
    if (!valid) return with_context("case '" + c.name + "'", valid.error());
    return s;
}

namespace {

struct Measurement {
    SurfaceImage gpu;
};

// Accumulates one technique's rows over the frames of a case.
struct Accumulator {
    long pixels = 0;
    long non_finite = 0;
    double error_sum = 0.0, error_max = 0.0, bound_sum = 0.0, nominal_sum = 0.0;
    long error_violations = 0, nominal_violations = 0;
    // On the rays the pixels were handed (measure_frame's `own`), where read back.
    long own_pixels = 0;
    double own_sum = 0.0, own_max = 0.0;
    long own_violations = 0, own_nominal_violations = 0;
    double offset_ratio_max = 0.0;
    long offset_violations = 0;
    double dark_max = -1.0;
};

// The per-pixel error bound of a technique: the catalogue's kind, with the
// linear search's own limit where the kind is a search step, plus fp32's
// rounding of the ray: the interpolated view vector's components carry a
// relative error of about 2^-20 (a handful of fp32 roundings), and P divides
// by V.z, so P's error is P 2^-20 / V.z; and a uv of magnitude m is held to
// m 2^-23 (its ulp), a few roundings deep: 4 m 2^-23 tiles.
// `with_search`: the derived bound, with what the search's own samples
// allow where a feature lies between two of them; without it the nominal
// bound, which a technique misses exactly where it has a limit.
double error_bound(BoundKind kind, const PixelTerms& t, double polygon_height, int samples, int refine,
                   const SearchBound& search, bool with_search, const glm::dvec3& v, const glm::dvec2& uv, int tw,
                   int th, double slack) {
    double b = bound_value(kind, t, polygon_height, false, samples, refine);
    if (with_search) {
        if (kind == BoundKind::step) b = std::max(b, search.bracket);
        if (kind == BoundKind::refined_step && !search.true_hit_in_bracket) b = std::max(b, search.bracket);
    }
    // Techniques that read the hardware-filtered surface (all but the exact
    // one, which filters 8-bit texels itself in highp).
    if (kind != BoundKind::exact && kind != BoundKind::zero) b += search.filtered;
    if (kind != BoundKind::zero) b += search.entry;
    const double rounding_ray = t.parallax * std::ldexp(1.0, -20) / std::max(v.z, 1.0 / 64.0);
    const double magnitude = std::max(std::fabs(uv.x), std::fabs(uv.y));
    const double rounding_uv = 4.0 * magnitude * std::ldexp(1.0, -23) * std::max(tw, th);
    return b + rounding_ray + rounding_uv + slack;
}

// The rays a frame's pixels were handed (RendererOptions::capture_ray) and
// the field the technique traced: for the exact tracer, judged on them.
struct OwnRays {
    const SurfaceImage* rays = nullptr;
    const HeightField* field = nullptr;
};

void measure_frame(const SurfaceImage& gpu, const SurfaceImage* entry, const reference::ReferenceImage& ref,
                   const std::vector<SearchBound>& search, const TechniqueBounds& tb, const StabilityCase& c,
                   const CatalogueBounds& bounds, Accumulator& acc, bool lod, std::vector<double>* per_pixel_bound,
                   const std::string& precision, const OwnRays& own) {
    const int tw = ref.texture_width, th = ref.texture_height;
    const double s = ref.height_scale, p = ref.polygon_height;
    const BoundKind error_kind = lod ? BoundKind::parallax : tb.error;  // past the LOD threshold: normal mapping
    for (size_t i = 0; i < gpu.samples.size(); ++i) {
        const SurfaceSample& g = gpu.samples[i];
        if (!g.covered) continue;
        if (!finite(g)) {
            ++acc.non_finite;
            continue;
        }
        if (c.expect_dark) acc.dark_max = std::max(acc.dark_max, g.visibility);
        const SurfaceSample& r = ref.surface.samples[i];
        if (!r.covered || tw == 0) continue;
        const PixelTerms terms = pixel_terms(ref.view_ts[i], s, tw, th);
        ++acc.pixels;
        const double error = glm::length(wrapped_texels(g.uv - r.uv, tw, th));
        const double bound = error_bound(error_kind, terms, p, c.samples, c.refine_steps, search[i], true,
                                         ref.view_ts[i], r.uv, tw, th, bounds.slack_texels);
        const double nominal = error_bound(error_kind, terms, p, c.samples, c.refine_steps, search[i], false,
                                           ref.view_ts[i], r.uv, tw, th, bounds.slack_texels);
        if (per_pixel_bound) (*per_pixel_bound)[i] = bound;
        acc.error_sum += error;
        acc.error_max = std::max(acc.error_max, error);
        acc.bound_sum += bound;
        acc.nominal_sum += nominal;
        if (error > bound) ++acc.error_violations;
        if (error > nominal) ++acc.nominal_violations;
        if (own.rays) {
            // The exact trace of this pixel's own fp32 ray, against the same
            // bound (its terms are the camera ray's: the two differ by far
            // less than they change). A pixel the capture misses counts as
            // its camera-ray error.
            const SurfaceSample& ray = own.rays->samples[i];
            const bool traceable = ray.covered && std::isfinite(ray.uv.x) && std::isfinite(ray.uv.y) &&
                                   std::isfinite(ray.height) && std::isfinite(ray.visibility);
            const double own_error = traceable ? own_ray_error(*own.field, g.uv, ray, ref.polygon_height) : error;
            ++acc.own_pixels;
            acc.own_sum += own_error;
            acc.own_max = std::max(acc.own_max, own_error);
            if (own_error > bound) ++acc.own_violations;
            if (own_error > nominal) ++acc.own_nominal_violations;
        }
        if (entry && entry->samples[i].covered && finite(entry->samples[i])) {
            const double offset = glm::length(wrapped_texels(g.uv - entry->samples[i].uv, tw, th));
            const double ob = bound_value(tb.offset, terms, p, true, c.samples, c.refine_steps);
            // The offset is a difference of two uvs, each held to what the
            // fragment stage can represent at its magnitude m: fp32 keeps m
            // to 2^-23 relative (4 ulp with the interpolation), a stage
            // without highp to fp16's ulp (2^-10 relative, 2^-24 at least),
            // the whitepaper's all-lowp stage to 2^-8 of a tile.
            const glm::dvec2 at = entry->samples[i].uv;
            const double m = std::max({std::fabs(at.x), std::fabs(at.y), std::fabs(g.uv.x), std::fabs(g.uv.y)});
            double quantum = 4.0 * m * std::ldexp(1.0, -23);
            if (precision == "nohighp") quantum = 2.0 * std::max(m * std::ldexp(1.0, -10), std::ldexp(1.0, -24));
            if (precision == "lowp_all") quantum = 2.0 * std::ldexp(1.0, -8);
            const double allowed = ob * (1.0 + bounds.offset_relative_slack) + bounds.slack_texels +
                                   2.0 * quantum * std::max(tw, th);
            acc.offset_ratio_max = std::max(acc.offset_ratio_max, offset / std::max(allowed, 1e-12));
            // Wrapping folds offsets past half a tile: judge only those below it.
            const double half_tile = 0.5 * std::min(tw, th);
            if (offset > allowed && allowed < half_tile) ++acc.offset_violations;
        }
    }
}

// Error over bound per pixel as a picture (see StabilityOptions::image_dir).
Status write_error_image(const std::string& path, const SurfaceImage& gpu, const reference::ReferenceImage& ref,
                         const std::vector<double>& bounds) {
    Image image;
    image.width = gpu.width;
    image.height = gpu.height;
    image.channels = 3;
    image.pixels.assign(static_cast<size_t>(image.width) * image.height * 3, 0);
    for (size_t i = 0; i < gpu.samples.size(); ++i) {
        std::uint8_t* px = &image.pixels[3 * i];
        const SurfaceSample& g = gpu.samples[i];
        if (!g.covered) continue;
        if (!finite(g)) {
            px[0] = 255, px[2] = 255;
            continue;
        }
        const SurfaceSample& r = ref.surface.samples[i];
        if (!r.covered || ref.texture_width == 0) {
            px[2] = 128;
            continue;
        }
        const double e = glm::length(wrapped_texels(g.uv - r.uv, ref.texture_width, ref.texture_height));
        const double q = bounds[i] > 0.0 ? e / bounds[i] : 0.0;
        if (q <= 1.0) {
            px[0] = static_cast<std::uint8_t>(255.0 * q);
            px[1] = 200;
        } else {
            px[0] = 255;
            px[1] = static_cast<std::uint8_t>(std::clamp(120.0 / q, 0.0, 120.0));
        }
    }
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
    return write_png(path, image);
}

}  // namespace

namespace {

// What runs here: (precision, variant ES) pairs.
struct Run {
    std::string precision;
    int variant_es;
};

Result<std::vector<Run>> stability_runs(const StabilityOptions& options, int context_es) {
    std::vector<Run> runs;
    for (const std::string& precision : options.precisions) {
        if (precision == "native") {
            runs.push_back({precision, context_es});
            continue;
        }
        if (context_es < 3)
            return make_error("stability: emulated precision '" + precision +
                              "' runs on an OpenGL ES 3.0 context (it emulates ES 2.0 variants there); this one is ES 2.0");
        if (precision != "nohighp") runs.push_back({precision, 3});
        runs.push_back({precision, 2});
    }
    return runs;
}

struct Work {
    const StabilityCase* c;
    std::vector<Frame> frames;                     // evaluated together (a sweep) or one
    std::vector<std::pair<size_t, size_t>> pairs;  // continuity neighbours
    std::string label;
};

std::vector<Work> stability_work(const Catalogue& catalogue, const StabilityOptions& options) {
    std::vector<Work> work;
    for (const StabilityCase& c : catalogue.cases) {
        if (c.full_only && !options.full) continue;
        if (!options.cases_pattern.empty() && !glob_match(options.cases_pattern, c.name)) continue;
        Work w{&c, {}, {}, c.name};
        w.frames = frames_of(c, options.full, w.pairs);
        if (options.sweep_pairs > 0 && w.pairs.size() > static_cast<size_t>(options.sweep_pairs)) {
            w.pairs.resize(static_cast<size_t>(options.sweep_pairs));
            w.frames.resize(2 * w.pairs.size());  // pairs are stored as consecutive frames
        }
        if (!w.frames.empty()) {
            work.push_back(w);
            continue;
        }
        for (double a : c.angles)
            work.push_back(Work{&c, {{a, c.distance}}, {}, c.angles.size() > 1 ? c.name + "@" + angle_label(a) : c.name});
    }
    return work;
}

// One case's frames: the reference of each (shared by every technique and
// run) and, for a technique whose load resamples the height (maxmip on a map
// that is not a power of two), its own reference of that surface, made once
// per frame when first needed.
struct CaseReferences {
    const Work* w = nullptr;
    std::string height_image;
    int size = 0;
    std::vector<reference::ReferenceImage> refs;
    std::vector<std::vector<SearchBound>> searches;
    std::vector<std::optional<reference::ReferenceImage>> resampled_refs;
    std::vector<std::vector<SearchBound>> resampled_searches;
    std::string resampled_note;
    // The fields the references trace (the same for every frame).
    HeightField field, resampled_field;

    Result<reference::ReferenceImage> trace(const std::string& technique, size_t fi, std::vector<SearchBound>& search,
                                            std::string* note) {
        const StabilityCase& c = *w->c;
        const Frame& f = w->frames[fi];
        Result<SceneDesc> scene = stability_scene(c, technique, f.angle, f.distance, height_image);
        if (!scene) return scene.error();
        Result<MaterialImages> images = build_material_images(scene->materials[0], scene->base_dir);
        if (!images) return images.error();
        if (note) {
            if (images->notes.empty()) return make_error("");  // not resampled: the shared reference holds
            *note = images->notes.front();
        }
        reference::ReferenceOptions ro;
        ro.shadow = c.shadow;
        Result<reference::ReferenceImage> ref = reference::render_reference(*scene, size, size, ro);
        if (!ref)
            return with_context("case '" + c.name + "' reference" + (note ? " of the resampled height" : ""), ref.error());
        search = search_bounds(*ref, images->traced, c.samples);
        filtered_bounds(*ref, images->traced, search);
        (note ? resampled_field : field) = images->traced;
        return ref;
    }

    Status make(const Work& work, const StabilityOptions& options) {
        w = &work;
        size = options.image_size;
        if (work.c->image_width) {
            Result<std::string> path = write_height_image(*work.c, options.scratch_dir);
            if (!path) return path.error();
            height_image = *path;
        }
        for (size_t fi = 0; fi < work.frames.size(); ++fi) {
            searches.emplace_back();
            Result<reference::ReferenceImage> ref = trace("pom", fi, searches.back(), nullptr);
            if (!ref) return ref.error();
            refs.push_back(std::move(*ref));
        }
        resampled_refs.resize(work.frames.size());
        resampled_searches.resize(work.frames.size());
        return {};
    }

    // `field`: the height field `ref` traces.
    Status reference_for(const TechniqueInfo& t, size_t fi, const reference::ReferenceImage*& ref,
                         const std::vector<SearchBound>*& search, const HeightField*& traced) {
        ref = &refs[fi];
        search = &searches[fi];
        traced = &field;
        if (t.id != Technique::maxmip || !w->c->image_width) return {};
        if (!resampled_refs[fi]) {
            std::string note;
            Result<reference::ReferenceImage> r = trace(t.name, fi, resampled_searches[fi], &note);
            if (!r) return r.error().message.empty() ? Status{} : Status(r.error());
            resampled_note = note;
            resampled_refs[fi] = std::move(*r);
        }
        ref = &*resampled_refs[fi];
        search = &resampled_searches[fi];
        traced = &resampled_field;
        return {};
    }
};

// Continuity: per pixel, the change of the error between neighbouring
// frames. Each error is within its own bound, so the change is within their
// sum; in the LOD band the blend may also move the hit |log2(d2 / d1)| /
// band of the way to the polygon's uv (at most P). More than that is a pop.
void judge_continuity(StabilityRow& row, const Work& w, const TechniqueInfo& t, const CaseReferences& cr,
                      const std::vector<SurfaceImage>& gpu_frames, const std::vector<std::vector<double>>& frame_bounds,
                      const CatalogueBounds& bounds) {
    const StabilityCase& c = *w.c;
    long compared = 0, violations = 0, flips = 0;
    double jump_max = 0.0;
    for (auto [a, b] : w.pairs) {
        const bool own = t.id == Technique::maxmip && cr.resampled_refs[a] && cr.resampled_refs[b];
        const reference::ReferenceImage& ra = own ? *cr.resampled_refs[a] : cr.refs[a];
        const reference::ReferenceImage& rb = own ? *cr.resampled_refs[b] : cr.refs[b];
        const int tw = ra.texture_width, th = ra.texture_height;
        const double blend_step = c.lod ? std::fabs(std::log2(w.frames[b].distance / w.frames[a].distance)) / c.lod_band : 0.0;
        for (size_t i = 0; i < gpu_frames[a].samples.size(); ++i) {
            const SurfaceSample& ga = gpu_frames[a].samples[i];
            const SurfaceSample& gb = gpu_frames[b].samples[i];
            const SurfaceSample& sa = ra.surface.samples[i];
            const SurfaceSample& sb = rb.surface.samples[i];
            if (!ga.covered || !gb.covered || !sa.covered || !sb.covered || !finite(ga) || !finite(gb)) continue;
            if (std::fabs(sa.height - sb.height) > bounds.crest_flip_height) {
                ++flips;
                continue;
            }
            const glm::dvec2 ea = wrapped_texels(ga.uv - sa.uv, tw, th);
            const glm::dvec2 eb = wrapped_texels(gb.uv - sb.uv, tw, th);
            const double jump = glm::length(eb - ea);
            const double p_max = std::max(pixel_terms(ra.view_ts[i], ra.height_scale, tw, th).parallax,
                                          pixel_terms(rb.view_ts[i], rb.height_scale, tw, th).parallax);
            const double bound = frame_bounds[a][i] + frame_bounds[b][i] + blend_step * p_max;
            ++compared;
            jump_max = std::max(jump_max, jump);
            if (jump > bound) ++violations;
        }
    }
    row.continuity_max = jump_max;
    row.continuity_violations = compared ? static_cast<double>(violations) / static_cast<double>(compared) : 0.0;
    row.crest_flips = flips;
}

void fill_row(StabilityRow& row, const Accumulator& acc) {
    const auto share = [&](long n) { return acc.pixels ? static_cast<double>(n) / static_cast<double>(acc.pixels) : 0.0; };
    const auto mean = [&](double sum) { return acc.pixels ? sum / static_cast<double>(acc.pixels) : 0.0; };
    row.pixels = acc.pixels;
    row.non_finite = acc.non_finite;
    row.error_mean = mean(acc.error_sum);
    row.error_max = acc.error_max;
    row.error_bound_mean = mean(acc.bound_sum);
    row.error_violations = share(acc.error_violations);
    row.nominal_bound_mean = mean(acc.nominal_sum);
    row.nominal_violations = share(acc.nominal_violations);
    row.offset_ratio_max = acc.offset_ratio_max;
    row.offset_violations = acc.offset_violations;
    row.dark_max = acc.dark_max;
    if (acc.own_pixels > 0 && acc.own_pixels == acc.pixels) {
        row.own_error_mean = mean(acc.own_sum);
        row.own_error_max = acc.own_max;
        row.own_violations = share(acc.own_violations);
        row.own_nominal_violations = share(acc.own_nominal_violations);
    }
}

// Everything one technique's row needs besides the case.
struct RowJob {
    const Catalogue& catalogue;
    const StabilityOptions& options;
    const Work& w;
    CaseReferences& cr;
    Renderer& renderer;
    const Run& run;
    std::vector<SurfaceImage>& entries;  // the normal-mapping pass per frame: each pixel's own uv
    Renderer* ray_renderer;              // capture_ray, where the context reads floats back; else null
    const std::function<void(const std::string&)>& tick;
    // Per frame: the case's scene prepared once (validation, images, mesh);
    // each technique is handed to the draw by replacing the material, its
    // images shared.
    std::vector<std::shared_ptr<const PreparedScene>> prepared;
};

// The case's scene at frame `fi` with `technique`, on the frame's one preparation.
Result<std::shared_ptr<const PreparedScene>> prepared_frame(RowJob& job, size_t fi, const std::string& technique) {
    const Frame& f = job.w.frames[fi];
    Result<SceneDesc> scene = unchecked_scene(*job.w.c, technique, f.angle, f.distance, job.cr.height_image);
    if (!scene) return scene.error();
    if (job.prepared.size() != job.w.frames.size()) job.prepared.resize(job.w.frames.size());
    std::shared_ptr<const PreparedScene>& kept = job.prepared[fi];
    if (!kept) {
        Result<std::shared_ptr<const PreparedScene>> made = prepare_scene(*scene, job.renderer.prepare_options());
        if (!made) return with_context("case '" + job.w.c->name + "'", made.error());
        kept = *made;
        return kept;
    }
    std::shared_ptr<const PreparedScene> out = kept;
    for (const MaterialDesc& m : scene->materials) {
        Result<std::shared_ptr<const PreparedScene>> next = replace_material(*out, m);
        if (!next) return with_context("case '" + job.w.c->name + "'", next.error());
        out = std::move(*next);
    }
    return out;
}

Result<StabilityRow> stability_row(RowJob& job, const TechniqueInfo& t) {
    const StabilityCase& c = *job.w.c;
    const int size = job.options.image_size;
    StabilityRow row;
    row.case_name = job.w.label;
    row.technique = t.name;
    row.context = "es" + std::to_string(job.run.variant_es);
    row.precision = job.run.precision;
    Accumulator acc;
    std::vector<SurfaceImage> gpu_frames;
    std::vector<std::vector<double>> frame_bounds;
    std::string drawn_note, drawn_name = t.name;
    for (size_t fi = 0; fi < job.w.frames.size(); ++fi) {
        auto capture = [&](const std::string& technique) -> Result<SurfaceImage> {
            Result<std::shared_ptr<const PreparedScene>> scene = prepared_frame(job, fi, technique);
            if (!scene) return scene.error();
            Status loaded = job.renderer.load(*scene);
            if (!loaded)
                return with_context("case '" + job.w.label + "' " + technique + " " + row.context + " " + job.run.precision,
                                    loaded.error());
            Result<SurfaceImage> image = capture_surfaces(job.renderer, size, size);
            if (!image) return with_context("case '" + job.w.label + "' " + technique, image.error());
            return image;
        };
        if (job.entries[fi].samples.empty()) {
            Result<SurfaceImage> e = capture("normal");
            if (!e) return e.error();
            job.entries[fi] = std::move(*e);
        }
        Result<SurfaceImage> gpu = capture(t.name);
        if (!gpu) return gpu.error();
        // Judged as what was drawn: the planner may substitute (maxmip on a
        // height map that is not a power of two).
        const auto& reports = job.renderer.reports();
        const char* drawn = reports.empty() ? t.name : technique_name(reports.front().variant.technique);
        if (drawn != std::string(t.name) && drawn_note.empty()) {
            drawn_note = std::string("drawn as ") + drawn;
            if (!reports.front().notes.empty()) drawn_note += " (" + reports.front().notes.front() + ")";
            drawn_name = drawn;
        }
        const reference::ReferenceImage* ref = nullptr;
        const std::vector<SearchBound>* search = nullptr;
        const HeightField* traced = nullptr;
        Status own = job.cr.reference_for(t, fi, ref, search, traced);
        if (!own) return own.error();
        if (ref != &job.cr.refs[fi] && drawn_note.empty())
            drawn_note = "against the reference of its own resampled height: " + job.cr.resampled_note;
        // The exact tracer is judged on the rays it was handed (StabilityRow::own_error_mean).
        const TechniqueBounds& tb = job.catalogue.bounds.techniques.at(drawn_name);
        std::optional<SurfaceImage> rays;
        if (job.ray_renderer && tb.error == BoundKind::exact && !c.lod) {
            Result<std::shared_ptr<const PreparedScene>> scene = prepared_frame(job, fi, drawn_name);
            if (!scene) return scene.error();
            Status loaded = job.ray_renderer->load(*scene);
            if (!loaded) return with_context("case '" + job.w.label + "' " + drawn_name + " (capturing rays)", loaded.error());
            Result<SurfaceImage> captured = capture_surfaces(*job.ray_renderer, size, size);
            if (!captured) return with_context("case '" + job.w.label + "' " + drawn_name + " (capturing rays)", captured.error());
            if (captured->samples.size() != gpu->samples.size())
                return make_error("case '" + job.w.label + "': the captured rays and the hits differ in size");
            rays = std::move(*captured);
        }
        const OwnRays own_rays{rays ? &*rays : nullptr, traced};
        frame_bounds.emplace_back(gpu->samples.size(), 0.0);
        measure_frame(*gpu, &job.entries[fi], *ref, *search, tb, c, job.catalogue.bounds, acc, c.lod,
                      &frame_bounds.back(), job.run.precision, own_rays);
        if (!job.options.image_dir.empty()) {
            Status written = write_error_image(job.options.image_dir + "/" + job.w.label + "_" + t.name + "_" +
                                                   row.context + "_" + job.run.precision + "_" + std::to_string(fi) + ".png",
                                               *gpu, *ref, frame_bounds.back());
            if (!written) return written.error();
        }
        gpu_frames.push_back(std::move(*gpu));
        job.tick(job.w.label + " " + t.name + " " + row.context + " " + job.run.precision);
    }
    fill_row(row, acc);
    if (!job.w.pairs.empty()) judge_continuity(row, job.w, t, job.cr, gpu_frames, frame_bounds, job.catalogue.bounds);
    judge(row, job.catalogue.bounds, c);
    if (!drawn_note.empty()) row.reasons = drawn_note + (row.reasons.empty() ? "" : "; " + row.reasons);
    return row;
}

}  // namespace

Result<std::vector<StabilityRow>> run_stability(const Catalogue& catalogue, const StabilityOptions& options,
                                                const StabilityProgress& progress) {
    if (options.image_size < 16 || options.image_size > 1024)
        return make_error("stability: image size must be within 16..1024, got " + std::to_string(options.image_size));
    const GLubyte* version = glGetString(GL_VERSION);
    if (!version) return make_error("stability: no current OpenGL ES context");
    const int context_es = std::string(reinterpret_cast<const char*>(version)).find("OpenGL ES 2") != std::string::npos ? 2 : 3;
    Result<std::vector<Run>> runs = stability_runs(options, context_es);
    if (!runs) return runs.error();
    const std::vector<Work> work = stability_work(catalogue, options);
    if (work.empty()) return make_error("stability: no case matches '" + echo(options.cases_pattern) + "'");

    int total = 0, done = 0;
    for (const Work& w : work)
        for (const Run& run : *runs)
            for (const TechniqueInfo* t : techniques_of(*w.c))
                if (t->min_es_major <= run.variant_es) total += static_cast<int>(w.frames.size());
    const std::function<void(const std::string&)> tick = [&](const std::string& what) {
        if (progress) progress(++done, total, what);
    };

    std::map<std::string, std::unique_ptr<Renderer>> renderers;  // per run: programs stay cached
    auto renderer_for = [&](const Run& run, bool capture_ray) -> Result<Renderer*> {
        const std::string key = run.precision + "/" + std::to_string(run.variant_es) + (capture_ray ? "/rays" : "");
        auto it = renderers.find(key);
        if (it != renderers.end()) return it->second.get();
        RendererOptions ro;
        ro.effect_planner = effect_planner;
        ro.texture_files = texture_files();
        if (options.renderer_options) {
            Result<RendererOptions> made = options.renderer_options(run.precision, run.variant_es);
            if (!made) return made.error();
            ro = *made;
        } else if (run.precision != "native") {
            return make_error("stability: no shader transform for precision '" + run.precision + "'");
        }
        ro.capture_ray = capture_ray;
        Result<std::unique_ptr<Renderer>> r = Renderer::create(ro);
        if (!r) return r.error();
        Renderer* raw = r->get();
        renderers.emplace(key, std::move(*r));
        return raw;
    };

    std::vector<StabilityRow> rows;
    for (const Work& w : work) {
        CaseReferences cr;
        Status made = cr.make(w, options);
        if (!made) return made.error();
        for (const Run& run : *runs) {
            Result<Renderer*> renderer = renderer_for(run, false);
            if (!renderer) return renderer.error();
            // Rays read back only as the shaders ship (an emulated profile's
            // rewritten variant has no capture) and where floats come back.
            Renderer* rays = nullptr;
            if (run.precision == "native" && run.variant_es >= 3 && captures_floats((*renderer)->caps())) {
                Result<Renderer*> r = renderer_for(run, true);
                if (!r) return r.error();
                rays = *r;
            }
            std::vector<SurfaceImage> entries(w.frames.size());
            RowJob job{catalogue, options, w, cr, **renderer, run, entries, rays, tick, {}};
            for (const TechniqueInfo* t : techniques_of(*w.c)) {
                if (t->min_es_major > run.variant_es) continue;
                Result<StabilityRow> row = stability_row(job, *t);
                if (!row) return row.error();
                rows.push_back(std::move(*row));
            }
        }
    }
    return rows;
}

}  // namespace px::profiling
