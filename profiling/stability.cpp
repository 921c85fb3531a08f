#include "profiling/stability.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/limits.h"
#include "core/text.h"
#include "gl/gl.h"
#include "reference/reference_image.h"
#include "render/surface_capture.h"

namespace px::profiling {

namespace {

using nlohmann::json;

// --- Reading the catalogue --------------------------------------------------

// Reads one JSON object, naming the JSON path in every error and refusing
// keys it does not know (a misspelt key must not be silently ignored).
class Reader {
public:
    Reader(const json& j, std::string path, std::string origin, std::string* error)
        : j_(j), path_(std::move(path)), origin_(std::move(origin)), error_(error) {
        if (!j_.is_object()) fail("must be an object");
    }
    bool ok() const { return error_->empty(); }
    const std::string& path() const { return path_; }
    void fail(const std::string& what, const std::string& key = "") {
        if (!error_->empty()) return;
        *error_ = origin_ + ": " + path_ + (key.empty() ? "" : "." + key) + ": " + what;
    }
    const json* get(const char* key) {
        seen_.insert(key);
        if (!j_.is_object()) return nullptr;
        auto it = j_.find(key);
        return it == j_.end() ? nullptr : &*it;
    }
    template <typename T>
    void number(const char* key, T& out, double lo, double hi) {
        const json* v = get(key);
        if (!v) return;
        if (!v->is_number()) return fail("must be a number", key);
        const double d = v->get<double>();
        if (!(d >= lo && d <= hi)) return fail("must be within " + num(lo) + ".." + num(hi) + ", got " + num(d), key);
        if constexpr (std::is_integral_v<T>) {
            if (d != std::floor(d)) return fail("must be a whole number, got " + num(d), key);
        }
        out = static_cast<T>(d);
    }
    void text(const char* key, std::string& out) {
        const json* v = get(key);
        if (!v) return;
        if (!v->is_string()) return fail("must be a string", key);
        out = v->get<std::string>();
    }
    void boolean(const char* key, bool& out) {
        const json* v = get(key);
        if (!v) return;
        if (!v->is_boolean()) return fail("must be true or false", key);
        out = v->get<bool>();
    }
    template <int N>
    void vec(const char* key, glm::vec<N, float>& out, double bound) {
        const json* v = get(key);
        if (!v) return;
        if (!v->is_array() || v->size() != N) return fail("must be an array of " + std::to_string(N) + " numbers", key);
        for (int i = 0; i < N; ++i) {
            const json& e = (*v)[static_cast<size_t>(i)];
            if (!e.is_number() || !(std::fabs(e.get<double>()) <= bound))
                return fail("components must be numbers within ±" + num(bound), key);
            out[i] = e.get<float>();
        }
    }
    void finish() {
        if (!ok() || !j_.is_object()) return;
        for (auto it = j_.begin(); it != j_.end(); ++it)
            if (!seen_.count(it.key())) return fail("unknown key '" + echo(it.key()) + "'");
    }
    Reader child(const char* key) {
        const json* v = get(key);
        static const json empty = json::object();
        return Reader(v ? *v : empty, path_ + "." + key, origin_, error_);
    }
    bool has(const char* key) const { return j_.is_object() && j_.contains(key); }

    static std::string num(double d) {
        char b[32];
        std::snprintf(b, sizeof b, "%g", d);
        return b;
    }

private:
    const json& j_;
    std::string path_, origin_;
    std::string* error_;
    std::set<std::string> seen_;
};

Result<BoundKind> parse_bound_kind(const std::string& s) {
    static const std::map<std::string, BoundKind> kinds = {
        {"zero", BoundKind::zero},     {"limited", BoundKind::limited},           {"parallax", BoundKind::parallax},
        {"step", BoundKind::step},     {"refined_step", BoundKind::refined_step}, {"exact", BoundKind::exact}};
    auto it = kinds.find(s);
    if (it == kinds.end())
        return make_error("unknown bound '" + echo(s) + "' (known: zero, limited, parallax, step, refined_step, exact)");
    return it->second;
}

void read_field(Reader r, FieldSpec& f) {
    std::string kind;
    r.text("kind", kind);
    if (!kind.empty()) {
        Result<FieldKind> k = parse_field_kind(kind);
        if (!k) return r.fail(k.error().message, "kind");
        f.kind = *k;
    }
    r.number("size", f.size, 1, kMaxTextureSize);
    r.number("level", f.level, 0, 1);
    r.number("count", f.count, 1, 256);
    r.number("frequency", f.frequency, 0, 256);
    r.number("mortar", f.mortar, 0, 0.5);
    r.number("line_width", f.line_width, 1, 256);
    r.number("radius", f.radius, 0, 0.5);
    r.text("text", f.text);
    r.finish();
}

void read_case(Reader r, StabilityCase& c, bool defaults) {
    if (!defaults) {
        r.text("name", c.name);
        if (c.name.empty()) r.fail("every case needs a name", "name");
        r.text("why", c.why);
    }
    if (r.has("field")) read_field(r.child("field"), c.field);
    if (r.has("image")) {
        Reader im = r.child("image");
        int w = 0, h = 0;
        im.number("width", w, 1, kMaxTextureSize);
        im.number("height", h, 1, kMaxTextureSize);
        im.finish();
        if (w < 1 || h < 1) im.fail("needs width and height");
        c.image_width = w;
        c.image_height = h;
    }
    r.number("height_scale", c.height_scale, 0, kMaxHeightScale);
    if (r.has("height_bias")) {
        float b = 0;
        r.number("height_bias", b, -kMaxHeightScale, kMaxHeightScale);
        c.height_bias = b;
    }
    if (r.has("angle")) {
        double a = 0;
        r.number("angle", a, 0, 90);
        c.angles = {a};
    }
    if (const json* a = r.get("angles")) {
        if (!a->is_array() || a->empty() || a->size() > 64) return r.fail("must be an array of 1 to 64 angles", "angles");
        c.angles.clear();
        for (const json& e : *a) {
            if (!e.is_number() || !(e.get<double>() >= 0 && e.get<double>() <= 90))
                return r.fail("angles are degrees within 0..90", "angles");
            c.angles.push_back(e.get<double>());
        }
    }
    r.boolean("sweep", c.sweep);
    if (const json* d = r.get("distances")) {
        if (!d->is_array() || d->size() < 2 || d->size() > 64)
            return r.fail("must be an array of 2 to 64 distances", "distances");
        c.distances.clear();
        for (const json& e : *d) {
            if (!e.is_number() || !(e.get<double>() > 0 && e.get<double>() <= 1000))
                return r.fail("distances must be within (0, 1000]", "distances");
            c.distances.push_back(e.get<double>());
        }
    }
    r.number("distance", c.distance, 1e-4, 1000);
    if (r.has("camera")) {
        Reader cam = r.child("camera");
        glm::vec3 p(0.0f), t(0.0f);
        cam.vec<3>("position", p, 1000);
        cam.vec<3>("target", t, 1000);
        cam.finish();
        c.camera_position = p;
        c.camera_target = t;
    }
    r.number("fov", c.fov_deg, 1, 170);
    r.number("plane_size", c.plane_size, kMinExtent, kMaxExtent);
    r.number("segments", c.segments, 1, 256);
    r.number("samples", c.samples, 1, 256);
    r.number("refine_steps", c.refine_steps, 0, 16);
    if (r.has("light")) {
        Reader l = r.child("light");
        l.number("elevation", c.light_elevation_deg, -90, 90);
        l.number("azimuth", c.light_azimuth_deg, -360, 360);
        l.finish();
    }
    std::string shadow;
    r.text("shadow", shadow);
    if (!shadow.empty()) {
        Result<ShadowMode> m = parse_shadow_mode(shadow);
        if (!m) return r.fail(m.error().message, "shadow");
        c.shadow = *m;
    }
    if (r.has("uv")) {
        Reader uv = r.child("uv");
        uv.vec<2>("scale", c.uv.scale, 1e5);
        uv.vec<2>("offset", c.uv.offset, 1e5);
        uv.number("rotation", c.uv.rotation_deg, -3600, 3600);
        uv.finish();
    }
    r.vec<3>("model_scale", c.model_scale, 1e4);
    if (r.has("lod")) {
        Reader l = r.child("lod");
        c.lod = true;
        l.number("threshold", c.lod_threshold, 0, 16);
        l.number("band", c.lod_band, 0.01, 16);
        l.finish();
    }
    if (r.has("exact_view")) {
        bool e = false;
        r.boolean("exact_view", e);
        c.exact_view = e;
    }
    if (const json* t = r.get("techniques")) {
        if (!t->is_array()) return r.fail("must be an array of technique names", "techniques");
        for (const json& e : *t) {
            if (!e.is_string() || !parse_technique(e.get<std::string>()))
                return r.fail("unknown technique (known: " + technique_names_joined() + ")", "techniques");
            c.techniques.push_back(e.get<std::string>());
        }
    }
    if (r.has("limits")) {
        const json* l = r.get("limits");
        if (!l->is_object()) return r.fail("must map technique names to the limit each shows", "limits");
        for (auto it = l->begin(); it != l->end(); ++it) {
            if (!parse_technique(it.key()))
                return r.fail("unknown technique '" + echo(it.key()) + "'", "limits");
            if (!it->is_string() || it->get<std::string>().empty())
                return r.fail("each limit is a sentence saying what the technique cannot do", "limits." + it.key());
            c.limits[it.key()] = it->get<std::string>();
        }
    }
    r.boolean("expect_dark", c.expect_dark);
    r.boolean("full_only", c.full_only);
    r.number("quick_stride", c.quick_stride, 1, 64);
    r.finish();
    if (!defaults && c.sweep && c.angles.size() < 2) r.fail("a sweep needs at least two angles", "angles");
}

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

}  // namespace

// The catalogue's text, embedded by CMake (generated/stability_catalogue.cpp).
extern const char* const kEmbeddedCatalogue;

const std::string& embedded_catalogue_text() {
    static const std::string text = kEmbeddedCatalogue;
    return text;
}

Result<Catalogue> parse_catalogue(const std::string& text, const std::string& origin) {
    json root;
    try {
        root = json::parse(text, nullptr, true, /*ignore_comments=*/true);
    } catch (const json::parse_error& e) {
        return make_error(origin + ": not valid JSON: " + echo(e.what(), 200));
    }
    std::string error;
    Catalogue cat;
    Reader top(root, "catalogue", origin, &error);
    {
        Reader b = top.child("bounds");
        b.number("slack_texels", cat.bounds.slack_texels, 0, 100);
        b.number("offset_relative_slack", cat.bounds.offset_relative_slack, 0, 1);
        b.number("violation_share", cat.bounds.violation_share, 0, 1);
        b.number("crest_flip_height", cat.bounds.crest_flip_height, 0, 1);
        Reader t = b.child("techniques");
        for (const TechniqueInfo& info : technique_table()) {
            if (!t.has(info.name)) {
                t.fail(std::string("no bounds for technique '") + info.name + "'");
                break;
            }
            Reader one = t.child(info.name);
            TechniqueBounds tb;
            for (auto [key, slot] : {std::pair{"error", &tb.error}, std::pair{"offset", &tb.offset},
                                     std::pair{"continuity", &tb.continuity}}) {
                std::string kind;
                one.text(key, kind);
                Result<BoundKind> k = parse_bound_kind(kind);
                if (!k) {
                    one.fail(k.error().message, key);
                    break;
                }
                *slot = *k;
            }
            one.finish();
            cat.bounds.techniques[info.name] = tb;
        }
        t.finish();
        b.finish();
    }
    StabilityCase defaults;
    if (top.has("defaults")) read_case(top.child("defaults"), defaults, true);
    const json* cases = top.get("cases");
    if (error.empty() && (!cases || !cases->is_array() || cases->empty()))
        top.fail("needs a non-empty array of cases", "cases");
    std::set<std::string> names;
    if (error.empty()) {
        for (size_t i = 0; i < cases->size() && error.empty(); ++i) {
            StabilityCase c = defaults;
            read_case(Reader((*cases)[i], "catalogue.cases[" + std::to_string(i) + "]", origin, &error), c, false);
            if (!error.empty()) break;
            if (!names.insert(c.name).second) {
                error = origin + ": catalogue.cases[" + std::to_string(i) + "].name: '" + echo(c.name) +
                        "' names another case too";
                break;
            }
            cat.cases.push_back(std::move(c));
        }
    }
    top.finish();
    if (!error.empty()) return make_error(error);
    return cat;
}

Result<SceneDesc> stability_scene(const StabilityCase& c, const std::string& technique, double angle,
                                  double distance, const std::string& scratch_dir) {
    SceneDesc s;
    s.name = c.name;
    const double a = angle * M_PI / 180.0;
    if (c.camera_position) {
        s.camera.position = *c.camera_position;
        s.camera.target = *c.camera_target;
    } else {
        s.camera.position = glm::vec3(0.0f, static_cast<float>(-distance * std::sin(a)),
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
    LightDesc light;
    const double az = c.light_azimuth_deg * M_PI / 180.0, el = c.light_elevation_deg * M_PI / 180.0;
    light.direction = -glm::vec3(static_cast<float>(std::cos(el) * std::cos(az)),
                                 static_cast<float>(std::cos(el) * std::sin(az)), static_cast<float>(std::sin(el)));
    light.angular_radius_deg = 2.0f;
    s.lights = {light};

    MaterialDesc m;
    m.name = "surface";
    m.albedo.kind = TextureSource::Kind::color;
    m.albedo.color = glm::vec3(0.75f, 0.7f, 0.65f);
    if (c.image_width) {
        Result<std::string> path = write_height_image(c, scratch_dir);
        if (!path) return path.error();
        m.height.kind = TextureSource::Kind::file;
        m.height.path = *path;
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
    o.material = "surface";
    s.objects = {o};
    Status valid = validate_scene(s);
    if (!valid) return with_context("case '" + c.name + "'", valid.error());
    return s;
}

void judge(StabilityRow& row, const CatalogueBounds& bounds, const StabilityCase& c) {
    std::vector<std::string> failed;
    std::vector<std::string> limit;
    if (row.non_finite > 0) failed.push_back(std::to_string(row.non_finite) + " pixels NaN or Inf");
    if (row.offset_violations > 0)
        failed.push_back(std::to_string(row.offset_violations) + " pixels past the offset bound (max ratio " +
                         Reader::num(row.offset_ratio_max) + ")");
    if (row.dark_max > 0.0) failed.push_back("lit by a light below the horizon (visibility " + Reader::num(row.dark_max) + ")");
    // Accuracy is judged at fp32 (the native run and the fp32 emulation);
    // at fp16 and lowp the growth of the error is the finding, reported.
    const bool judged = row.precision == "native" || row.precision == "fp32";
    std::vector<std::string> accuracy;
    if (judged && row.pixels > 0) {
        if (row.error_mean > row.error_bound_mean + bounds.slack_texels)
            accuracy.push_back("mean error " + Reader::num(row.error_mean) + " past its bound " +
                               Reader::num(row.error_bound_mean + bounds.slack_texels));
        if (row.error_violations > bounds.violation_share)
            accuracy.push_back(Reader::num(100.0 * row.error_violations) + " % of pixels past their error bound");
        if (row.continuity_max >= 0.0 && row.continuity_violations > bounds.violation_share)
            accuracy.push_back(Reader::num(100.0 * row.continuity_violations) +
                               " % of pixels jump past their continuity bound (max " + Reader::num(row.continuity_max) +
                               " texels)");
    }
    auto it = c.limits.find(row.technique);
    const bool documented = it != c.limits.end();
    if (!accuracy.empty()) {
        if (documented) {
            limit.push_back(it->second);
        } else {
            failed.insert(failed.end(), accuracy.begin(), accuracy.end());
        }
    }
    std::string reasons;
    if (!failed.empty()) {
        row.verdict = "fail";
        for (const std::string& f : failed) reasons += (reasons.empty() ? "" : "; ") + f;
        if (!limit.empty()) reasons += "; (limit: " + limit.front() + ")";
    } else if (!limit.empty()) {
        row.verdict = "limit";
        reasons = limit.front();
    } else {
        row.verdict = row.pixels > 0 || row.non_finite > 0 ? "pass" : "n/a";
        if (row.verdict == "n/a") reasons = "nothing covered (no NaN, nothing to measure)";
    }
    row.reasons = reasons;
}

namespace {

struct Measurement {
    SurfaceImage gpu;
};

// Accumulates one technique's rows over the frames of a case.
struct Accumulator {
    long pixels = 0;
    long non_finite = 0;
    double error_sum = 0.0, error_max = 0.0, bound_sum = 0.0;
    long error_violations = 0;
    double offset_ratio_max = 0.0;
    long offset_violations = 0;
    double dark_max = -1.0;
};

void measure_frame(const SurfaceImage& gpu, const SurfaceImage* entry, const reference::ReferenceImage& ref,
                   const TechniqueBounds& tb, const StabilityCase& c, const CatalogueBounds& bounds, Accumulator& acc,
                   bool lod) {
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
        const double bound = bound_value(error_kind, terms, p, false, c.samples, c.refine_steps);
        acc.error_sum += error;
        acc.error_max = std::max(acc.error_max, error);
        acc.bound_sum += bound;
        if (error > bound + bounds.slack_texels) ++acc.error_violations;
        if (entry && entry->samples[i].covered && finite(entry->samples[i])) {
            const double offset = glm::length(wrapped_texels(g.uv - entry->samples[i].uv, tw, th));
            const double ob = bound_value(tb.offset, terms, p, true, c.samples, c.refine_steps);
            const double allowed = ob * (1.0 + bounds.offset_relative_slack) + bounds.slack_texels;
            acc.offset_ratio_max = std::max(acc.offset_ratio_max, offset / std::max(allowed, 1e-12));
            // Wrapping folds offsets past half a tile: judge only those below it.
            const double half_tile = 0.5 * std::min(tw, th);
            if (offset > allowed && allowed < half_tile) ++acc.offset_violations;
        }
    }
}

}  // namespace

Result<std::vector<StabilityRow>> run_stability(const Catalogue& catalogue, const StabilityOptions& options,
                                                const StabilityProgress& progress) {
    if (options.image_size < 16 || options.image_size > 1024)
        return make_error("stability: image size must be within 16..1024, got " + std::to_string(options.image_size));
    const GLubyte* version = glGetString(GL_VERSION);
    if (!version) return make_error("stability: no current OpenGL ES context");
    const int context_es = std::string(reinterpret_cast<const char*>(version)).find("OpenGL ES 2") != std::string::npos ? 2 : 3;

    // What runs here: (precision, variant ES) pairs.
    struct Run {
        std::string precision;
        int variant_es;
    };
    std::vector<Run> runs;
    for (const std::string& precision : options.precisions) {
        if (precision == "native") {
            runs.push_back({precision, context_es});
        } else {
            if (context_es < 3)
                return make_error("stability: emulated precision '" + precision +
                                  "' runs on an OpenGL ES 3.0 context (it emulates ES 2.0 variants there); this one is ES 2.0");
            if (precision != "nohighp") runs.push_back({precision, 3});
            runs.push_back({precision, 2});
        }
    }

    struct Work {
        const StabilityCase* c;
        std::vector<Frame> frames;                        // evaluated together (a sweep) or one
        std::vector<std::pair<size_t, size_t>> pairs;     // continuity neighbours
        std::string label;
    };
    std::vector<Work> work;
    for (const StabilityCase& c : catalogue.cases) {
        if (c.full_only && !options.full) continue;
        if (!options.cases_pattern.empty() && !glob_match(options.cases_pattern, c.name)) continue;
        Work w{&c, {}, {}, c.name};
        w.frames = frames_of(c, options.full, w.pairs);
        if (!w.frames.empty()) {
            work.push_back(w);
            continue;
        }
        for (double a : c.angles) {
            Work one{&c, {{a, c.distance}}, {}, c.angles.size() > 1 ? c.name + "@" + angle_label(a) : c.name};
            work.push_back(one);
        }
    }
    if (work.empty()) return make_error("stability: no case matches '" + echo(options.cases_pattern) + "'");

    int total = 0;
    for (const Work& w : work)
        for (const Run& run : runs)
            for (const TechniqueInfo* t : techniques_of(*w.c))
                if (t->min_es_major <= run.variant_es) total += static_cast<int>(w.frames.size());
    int done = 0;

    std::map<std::string, std::unique_ptr<Renderer>> renderers;  // per run: programs stay cached
    auto renderer_for = [&](const Run& run) -> Result<Renderer*> {
        const std::string key = run.precision + "/" + std::to_string(run.variant_es);
        auto it = renderers.find(key);
        if (it != renderers.end()) return it->second.get();
        RendererOptions ro;
        if (options.renderer_options) {
            Result<RendererOptions> made = options.renderer_options(run.precision, run.variant_es);
            if (!made) return made.error();
            ro = *made;
        } else if (run.precision != "native") {
            return make_error("stability: no shader transform for precision '" + run.precision + "'");
        }
        Result<std::unique_ptr<Renderer>> r = Renderer::create(ro);
        if (!r) return r.error();
        Renderer* raw = r->get();
        renderers.emplace(key, std::move(*r));
        return raw;
    };

    std::vector<StabilityRow> rows;
    const int size = options.image_size;
    for (const Work& w : work) {
        const StabilityCase& c = *w.c;
        // The reference of each frame, shared by every technique and run.
        std::vector<reference::ReferenceImage> refs;
        for (const Frame& f : w.frames) {
            Result<SceneDesc> scene = stability_scene(c, "pom", f.angle, f.distance, options.scratch_dir);
            if (!scene) return scene.error();
            reference::ReferenceOptions ro;
            ro.shadow = c.shadow;
            Result<reference::ReferenceImage> ref = reference::render_reference(*scene, size, size, ro);
            if (!ref) return with_context("case '" + c.name + "' reference", ref.error());
            refs.push_back(std::move(*ref));
        }
        for (const Run& run : runs) {
            Result<Renderer*> renderer = renderer_for(run);
            if (!renderer) return renderer.error();
            std::vector<SurfaceImage> entries(w.frames.size());  // the normal-mapping pass: each pixel's own uv
            for (const TechniqueInfo* t : techniques_of(c)) {
                if (t->min_es_major > run.variant_es) continue;
                StabilityRow row;
                row.case_name = w.label;
                row.technique = t->name;
                row.context = "es" + std::to_string(run.variant_es);
                row.precision = run.precision;
                Accumulator acc;
                std::vector<SurfaceImage> gpu_frames;
                for (size_t fi = 0; fi < w.frames.size(); ++fi) {
                    const Frame& f = w.frames[fi];
                    auto capture = [&](const std::string& technique) -> Result<SurfaceImage> {
                        Result<SceneDesc> scene = stability_scene(c, technique, f.angle, f.distance, options.scratch_dir);
                        if (!scene) return scene.error();
                        Status loaded = (*renderer)->load(*scene);
                        if (!loaded) return with_context("case '" + w.label + "' " + technique + " " + row.context + " " + run.precision,
                                                         loaded.error());
                        Result<SurfaceImage> image = capture_surfaces(**renderer, size, size);
                        if (!image) return with_context("case '" + w.label + "' " + technique, image.error());
                        return image;
                    };
                    if (entries[fi].samples.empty()) {
                        Result<SurfaceImage> e = capture("normal");
                        if (!e) return e.error();
                        entries[fi] = std::move(*e);
                    }
                    Result<SurfaceImage> gpu = capture(t->name);
                    if (!gpu) return gpu.error();
                    measure_frame(*gpu, &entries[fi], refs[fi], catalogue.bounds.techniques.at(t->name), c,
                                  catalogue.bounds, acc, c.lod);
                    gpu_frames.push_back(std::move(*gpu));
                    if (progress) progress(++done, total, w.label + " " + t->name + " " + row.context + " " + run.precision);
                }
                row.pixels = acc.pixels;
                row.non_finite = acc.non_finite;
                row.error_mean = acc.pixels ? acc.error_sum / static_cast<double>(acc.pixels) : 0.0;
                row.error_max = acc.error_max;
                row.error_bound_mean = acc.pixels ? acc.bound_sum / static_cast<double>(acc.pixels) : 0.0;
                row.error_violations = acc.pixels ? static_cast<double>(acc.error_violations) / static_cast<double>(acc.pixels) : 0.0;
                row.offset_ratio_max = acc.offset_ratio_max;
                row.offset_violations = acc.offset_violations;
                row.dark_max = acc.dark_max;
                // Continuity: per pixel, the change of the error between
                // neighbouring frames, against the sum of the technique's
                // continuity bound and, in the LOD band, what the blend may
                // move: |log2(d2 / d1)| / band of the way to the polygon's uv.
                if (!w.pairs.empty()) {
                    const TechniqueBounds& tb = catalogue.bounds.techniques.at(t->name);
                    long compared = 0, violations = 0, flips = 0;
                    double jump_max = 0.0;
                    for (auto [a, b] : w.pairs) {
                        const reference::ReferenceImage& ra = refs[a];
                        const reference::ReferenceImage& rb = refs[b];
                        const int tw = ra.texture_width, th = ra.texture_height;
                        const double blend_step =
                            c.lod ? std::fabs(std::log2(w.frames[b].distance / w.frames[a].distance)) / c.lod_band : 0.0;
                        for (size_t i = 0; i < gpu_frames[a].samples.size(); ++i) {
                            const SurfaceSample& ga = gpu_frames[a].samples[i];
                            const SurfaceSample& gb = gpu_frames[b].samples[i];
                            const SurfaceSample& sa = ra.surface.samples[i];
                            const SurfaceSample& sb = rb.surface.samples[i];
                            if (!ga.covered || !gb.covered || !sa.covered || !sb.covered || !finite(ga) || !finite(gb))
                                continue;
                            if (std::fabs(sa.height - sb.height) > catalogue.bounds.crest_flip_height) {
                                ++flips;
                                continue;
                            }
                            const glm::dvec2 ea = wrapped_texels(ga.uv - sa.uv, tw, th);
                            const glm::dvec2 eb = wrapped_texels(gb.uv - sb.uv, tw, th);
                            const double jump = glm::length(eb - ea);
                            const PixelTerms ta = pixel_terms(ra.view_ts[i], ra.height_scale, tw, th);
                            const PixelTerms tbt = pixel_terms(rb.view_ts[i], rb.height_scale, tw, th);
                            const PixelTerms big{std::max(ta.parallax, tbt.parallax), std::max(ta.limited, tbt.limited)};
                            const double bound = bound_value(tb.continuity, big, ra.polygon_height, false, c.samples,
                                                             c.refine_steps) +
                                                 blend_step * big.parallax + catalogue.bounds.slack_texels;
                            ++compared;
                            jump_max = std::max(jump_max, jump);
                            if (jump > bound) ++violations;
                        }
                    }
                    row.continuity_max = jump_max;
                    row.continuity_violations = compared ? static_cast<double>(violations) / static_cast<double>(compared) : 0.0;
                    row.crest_flips = flips;
                }
                judge(row, catalogue.bounds, c);
                rows.push_back(std::move(row));
            }
        }
    }
    return rows;
}

bool glob_match(const std::string& pattern, const std::string& text) {
    const bool wild = pattern.find_first_of("*?") != std::string::npos;
    if (!wild) return text.find(pattern) != std::string::npos;
    // Iterative glob with backtracking to the last star.
    size_t p = 0, t = 0, star = std::string::npos, mark = 0;
    while (t < text.size()) {
        if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == text[t])) {
            ++p;
            ++t;
        } else if (p < pattern.size() && pattern[p] == '*') {
            star = p++;
            mark = t;
        } else if (star != std::string::npos) {
            p = star + 1;
            t = ++mark;
        } else {
            return false;
        }
    }
    while (p < pattern.size() && pattern[p] == '*') ++p;
    return p == pattern.size();
}

namespace {

std::string fixed(double v, int digits = 3) {
    if (!std::isfinite(v)) return "-";
    char b[48];
    if (v != 0.0 && std::fabs(v) < 1e-3)
        std::snprintf(b, sizeof b, "%.1e", v);
    else
        std::snprintf(b, sizeof b, "%.*f", digits, v);
    return b;
}

std::string continuity_text(const StabilityRow& r) {
    if (r.continuity_max < 0.0) return "-";
    return fixed(r.continuity_max) + " (" + fixed(100.0 * r.continuity_violations, 1) + "%)";
}

}  // namespace

std::string format_table(const std::vector<StabilityRow>& rows) {
    std::ostringstream o;
    char line[512];
    std::snprintf(line, sizeof line, "%-26s %-14s %-4s %-8s %9s %9s %9s %6s %8s %17s %-6s %s\n", "case", "technique", "ctx",
                  "precision", "max err", "mean err", "bound", "NaN", "offset", "continuity", "verdict", "why");
    o << line;
    for (const StabilityRow& r : rows) {
        std::snprintf(line, sizeof line, "%-26s %-14s %-4s %-8s %9s %9s %9s %6ld %8s %17s %-6s %s\n",
                      r.case_name.c_str(), r.technique.c_str(), r.context.c_str(), r.precision.c_str(),
                      fixed(r.error_max).c_str(), fixed(r.error_mean).c_str(), fixed(r.error_bound_mean).c_str(),
                      r.non_finite, fixed(r.offset_ratio_max, 2).c_str(), continuity_text(r).c_str(),
                      r.verdict.c_str(), echo(r.reasons, 160).c_str());
        o << line;
    }
    return o.str();
}

std::string format_markdown(const std::vector<StabilityRow>& rows, const std::string& command) {
    std::ostringstream o;
    o << "Command: `" << command << "`\n\n";
    o << "| case | technique | ctx | precision | max err | mean err | bound (mean) | NaN | offset/bound | continuity (max, share past) | verdict | why |\n";
    o << "| --- | --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | --- | --- |\n";
    for (const StabilityRow& r : rows) {
        o << "| " << r.case_name << " | " << r.technique << " | " << r.context << " | " << r.precision << " | "
          << fixed(r.error_max) << " | " << fixed(r.error_mean) << " | " << fixed(r.error_bound_mean) << " | "
          << r.non_finite << " | " << fixed(r.offset_ratio_max, 2) << " | " << continuity_text(r) << " | "
          << r.verdict << " | " << r.reasons << " |\n";
    }
    return o.str();
}

std::string format_json(const std::vector<StabilityRow>& rows) {
    json out = json::array();
    for (const StabilityRow& r : rows) {
        json j;
        j["case"] = r.case_name;
        j["technique"] = r.technique;
        j["context"] = r.context;
        j["precision"] = r.precision;
        j["pixels"] = r.pixels;
        j["non_finite"] = r.non_finite;
        j["error_max_texels"] = r.error_max;
        j["error_mean_texels"] = r.error_mean;
        j["error_bound_mean_texels"] = r.error_bound_mean;
        j["error_violation_share"] = r.error_violations;
        j["offset_ratio_max"] = r.offset_ratio_max;
        j["offset_violations"] = r.offset_violations;
        if (r.continuity_max >= 0.0) {
            j["continuity_max_texels"] = r.continuity_max;
            j["continuity_violation_share"] = r.continuity_violations;
            j["crest_flips"] = r.crest_flips;
        }
        if (r.dark_max >= 0.0) j["dark_max_visibility"] = r.dark_max;
        j["verdict"] = r.verdict;
        j["reasons"] = r.reasons;
        out.push_back(j);
    }
    return out.dump(1) + "\n";
}

}  // namespace px::profiling
