#include "parallaxes/reference/reference_image.h"
#include "parallaxes/assets/color.h"
#include "parallaxes/core/text.h"
#include "parallaxes/scene/material_images.h"

#include <algorithm>
#include <optional>
#include <cmath>
#include <limits>
#include <system_error>
#include <thread>
#include <vector>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "parallaxes/core/limits.h"
#include "parallaxes/core/numeric.h"
#include "parallaxes/reference/tracer.h"
#include "parallaxes/scene/material_images.h"

namespace px::reference {

namespace {

// One material's data as the GPU samples it.
struct MaterialData {
    MaterialImages images;
    HeightField traced;        // 8-bit quantised: what the shader reads
    bool reads_height = false; // the GPU's surface output covers it
    glm::dmat2 uv_matrix{1.0};
    glm::dvec2 uv_offset{0.0};
    glm::dmat2 uv_frame{1.0};
    double height_scale = 0.0;
    double polygon_height = 1.0;
    // The traced field's highest texel, at most 1: no view ray meets the
    // relief above it, which bounds how near a relief hit can be.
    double top_height = 1.0;
    // MaterialDesc::bounded: the relief exists over mesh uv [0, 1]^2 only;
    // mesh uv = uv_inverse * (uv - uv_offset).
    bool bounded = false;
    glm::dmat2 uv_inverse{1.0};
    double specular = 0.0;   // MaterialDesc::specular
    double shininess = 1.0;  // MaterialDesc::shininess
};

// One plane object, with its world tangent frame built as surface.vert does.
struct PlaneData {
    const MaterialData* material = nullptr;
    double half_size = 1.0;
    // The polygon as drawn: wider by bounded_margin for a bounded relief.
    double drawn_half_size = 1.0;
    // A bounded relief's slab in mesh z (from -relief_below to
    // +relief_above, 0 when not bounded): a ray that crosses it over the
    // tile comes into the relief through the tile's side (the GPU's side
    // walls, make_tile_walls) and is traced from where it crosses the
    // polygon's plane, however far out that is.
    double relief_below = 0.0;
    double relief_above = 0.0;
    glm::dmat4 model{1.0};
    glm::dmat4 inverse_model{1.0};
    double winding_sign = 1.0;  // sign of det(model3): mirroring flips the bitangent
    // World units per texture tile, as the renderer's u_units_per_tile (mesh
    // units per uv times the model's mean scale, over the uv area scale):
    // what turns the relief depth (tile units) into distance. 0 when unusable.
    double units_per_tile = 0.0;
    int object = 0;  // index into scene.objects
    // For the footprint (texels_per_pixel): where the line from the eye
    // through the near-plane point at ndc (x, y) meets the plane, as a
    // homography: texel uv = h.xy / h.z with h = ndc_to_texel * (x, y, 1),
    // ahead of the eye where h.z * dot(ndc_to_w, (x, y, 1)) > 0 (that point's
    // homogeneous w). Linear in ndc, so a neighbouring pixel is one add away.
    glm::dmat3 ndc_to_texel{1.0};
    glm::dvec3 ndc_to_w{0.0};
    glm::dvec3 t{1.0, 0.0, 0.0}, b{0.0, 1.0, 0.0}, n{0.0, 0.0, 1.0};
};

struct LightData {
    bool point = false;
    glm::dvec3 vector{0.0};  // toward the light (directional) or its position (point)
    glm::dvec3 color{1.0};
    double angular_radius = 0.0;  // radians
};


// GL_LINEAR with GL_REPEAT at the base level, as HeightField::sample_bilinear
// does; channels past the image's last repeat it (grey images), alpha 1 when absent.
// srgb: colour texels decoded to linear light before filtering, as a
// texture unit decodes an sRGB texture.
glm::dvec4 sample_bilinear(const Image& image, glm::dvec2 uv, bool srgb = false) {
    const int w = image.width;
    const int h = image.height;
    const BilinearTaps b = bilinear_taps(uv.x, uv.y, w, h);
    auto texel = [&](int x, int y) {
        const std::uint8_t* p = image.texel(x, y);
        glm::dvec4 v(1.0);
        for (int c = 0; c < 3; ++c) {
            v[c] = p[std::min(c, image.channels - 1)] / 255.0;
            if (srgb) v[c] = srgb_to_linear(v[c]);
        }
        if (image.channels == 4) v.w = p[3] / 255.0;
        return v;
    };
    return glm::mix(glm::mix(texel(b.x0, b.y0), texel(b.x1, b.y0), b.ax), glm::mix(texel(b.x0, b.y1), texel(b.x1, b.y1), b.ax),
                    b.ay);
}

// Into the material's texture frame: tangent-space components, then the uv
// frame on xy (surface.vert), normalised. Zero when v is zero.
glm::dvec3 to_texture_frame(const PlaneData& plane, glm::dvec3 v) {
    glm::dvec3 ts(glm::dot(v, plane.t), glm::dot(v, plane.b), glm::dot(v, plane.n));
    const glm::dvec2 xy = plane.material->uv_frame * glm::dvec2(ts.x, ts.y);
    ts = glm::dvec3(xy, ts.z);
    const double len = glm::length(ts);
    return len > 0.0 ? ts / len : glm::dvec3(0.0);
}


struct Frame {
    glm::dvec3 eye{0.0};
    glm::dmat4 inverse_view_projection{1.0};
    glm::dvec3 ambient{0.0};
    glm::dvec3 background{0.0};
    std::vector<PlaneData> planes;
    std::vector<LightData> lights;
    ReferenceOptions options;
    int width = 0, height = 0;
};

double light_visibility(const Frame& f, const MaterialData& m, const ReliefHit& hit, glm::dvec3 light_ts,
                        double angular_radius) {
    switch (f.options.shadow) {
        // No shadow ray: the polygon's horizon alone (px_light_term).
        case ShadowMode::none: return light_ts.z > 0.0 ? 1.0 : 0.0;
        case ShadowMode::hard:
        case ShadowMode::soft:
            // No relief to trace: only the geometric horizon can hide the light.
            if (!(m.height_scale > 0.0)) return light_ts.z > 0.0 ? 1.0 : 0.0;
            if (f.options.shadow == ShadowMode::hard)
                return hard_visibility(m.traced, hit.uv, hit.height, light_ts, m.height_scale);
            return soft_visibility(m.traced, hit.uv, hit.height, light_ts, m.height_scale, angular_radius,
                                   f.options.soft_samples);
    }
    return 1.0;
}

// One pixel's outputs.
struct PixelOut {
    SurfaceSample& sample;
    std::uint8_t* rgba;
    glm::dvec3& view_ts;
    glm::dvec2& entry_uv;
    int& object;
    double& texels_per_pixel;
};

// A ray from the near to the far plane through window point (cx, cy) (pixel
// units, pixel centres at +0.5): s in [0, 1] is exactly the depth range the
// GPU keeps (near/far clipping).
struct PixelRay {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0};
};

PixelRay pixel_ray(const Frame& f, double cx, double cy) {
    const glm::dvec2 ndc(cx / f.width * 2.0 - 1.0, cy / f.height * 2.0 - 1.0);
    const glm::dvec4 near_h = f.inverse_view_projection * glm::dvec4(ndc, -1.0, 1.0);
    const glm::dvec4 far_h = f.inverse_view_projection * glm::dvec4(ndc, 1.0, 1.0);
    PixelRay r;
    r.origin = glm::dvec3(near_h) / near_h.w;
    r.direction = glm::dvec3(far_h) / far_h.w - r.origin;
    return r;
}

// Whether a ray (mesh space o + s d, d.z < 0) that crosses plane p's
// plane at q is drawn there: q within the polygon as drawn, or for a
// bounded relief the ray inside the relief's slab over the tile (through
// its side), the exact form of the GPU's side walls.
bool drawn_at(const PlaneData& p, const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& q) {
    if (std::fabs(q.x) <= p.drawn_half_size && std::fabs(q.y) <= p.drawn_half_size) return true;
    if (!(p.relief_below + p.relief_above > 0.0)) return false;
    // The ray's s range in the slab, then in the square's x and y slabs.
    double lo = (p.relief_above - o.z) / d.z, hi = (-p.relief_below - o.z) / d.z;
    for (int axis = 0; axis < 2; ++axis) {
        if (d[axis] == 0.0) {
            if (std::fabs(o[axis]) > p.half_size) return false;
            continue;
        }
        const double a = (-p.half_size - o[axis]) / d[axis], b = (p.half_size - o[axis]) / d[axis];
        lo = std::max(lo, std::min(a, b));
        hi = std::min(hi, std::max(a, b));
    }
    return lo <= hi && hi >= 0.0;
}

// Where the ray meets the front of plane p within its extent, s in [0, 1].
bool meet_plane(const PlaneData& p, const PixelRay& r, double& s, glm::dvec2& mesh_uv) {
    const glm::dvec3 o = glm::dvec3(p.inverse_model * glm::dvec4(r.origin, 1.0));
    const glm::dvec3 d = glm::dvec3(p.inverse_model * glm::dvec4(r.direction, 0.0));
    // Back faces are culled: the front is the object's +z side, also
    // under a mirroring model matrix (the renderer flips glFrontFace).
    if (!(d.z < 0.0)) return false;
    s = -o.z / d.z;
    if (s < 0.0 || s > 1.0) return false;
    const glm::dvec3 q = o + s * d;
    if (!drawn_at(p, o, d, q)) return false;
    mesh_uv = glm::dvec2(q.x, q.y) / (2.0 * p.half_size) + 0.5;
    return true;
}

// The polygon point a pixel shows and what its shading starts from.
struct Entry {
    glm::dvec3 world{0.0};    // on the polygon
    glm::dvec2 uv{0.0};       // texture uv there
    glm::dvec3 view_ts{0.0};  // toward the eye, texture frame
};

Entry entry_at(const Frame& f, const PlaneData& p, const PixelRay& r, double s, glm::dvec2 mesh_uv) {
    const MaterialData& m = *p.material;
    Entry e;
    e.world = r.origin + s * r.direction;
    e.uv = m.uv_matrix * mesh_uv + m.uv_offset;
    e.view_ts = to_texture_frame(p, f.eye - e.world);
    return e;
}

// A bounded relief's trace (MaterialDesc::bounded): the view ray over the t
// range where it is inside the tile (mesh uv [0, 1]^2), so that what lies
// outside (the next tile of a repeating texture) is not there to be hit,
// whether the ray came in through the relief's top or through its side (the
// renderer draws the plane wider by bounded_margin, and maxmip starts its
// walk there: shaders_es/chunks/surface_main.glsl). Empty where the ray meets
// no relief inside the tile: it passes by.
std::optional<ReliefHit> trace_bounded(const MaterialData& m, glm::dvec2 uv, glm::dvec3 view_ts) {
    const HeightField& field = m.traced;
    if (!(view_ts.z > 1e-9) || field.width <= 0 || field.height <= 0) return std::nullopt;
    const Ray r = view_ray(field, uv, view_ts, m.height_scale, m.polygon_height);
    const glm::dvec2 size(field.width, field.height);
    const glm::dvec2 top = m.uv_inverse * (glm::dvec2(r.origin) / size - m.uv_offset);
    const glm::dvec2 step = m.uv_inverse * (glm::dvec2(r.direction) / size);
    double t_in = 0.0, t_out = 1.0;
    for (int a = 0; a < 2; ++a) {
        if (step[a] == 0.0) {
            if (top[a] < 0.0 || top[a] > 1.0) return std::nullopt;
            continue;
        }
        const double t0 = -top[a] / step[a], t1 = (1.0 - top[a]) / step[a];
        t_in = std::max(t_in, std::min(t0, t1));
        t_out = std::min(t_out, std::max(t0, t1));
    }
    if (!(t_in <= t_out)) return std::nullopt;
    const Hit h = first_hit(field, r, t_in, t_out);
    if (!h.hit) return std::nullopt;
    ReliefHit out;
    out.uv = glm::dvec2(h.position) / size;
    out.height = h.position.z;
    return out;
}

// A plane the ray meets: what depth compositing chooses among.
struct Candidate {
    size_t plane = 0;  // index into Frame::planes (= scene object order)
    double s = 0.0;    // ray parameter of the polygon point
    // Ray parameter per unit of normalised height below the polygon; 0 for
    // a plane that competes at its polygon point (then `entry` is unset).
    double s_per_height = 0.0;
    double bound = 0.0;  // the candidate is at no smaller ray parameter
    glm::dvec2 mesh_uv{0.0};
    Entry entry;
};

// The winner of depth compositing: the smallest ray parameter in [0, 1],
// ties to the first object. `traced` says whether `entry` and `hit` hold
// its entry_at and trace (computed once, reused for shading).
struct Composited {
    const PlaneData* plane = nullptr;
    double s = 0.0;  // of the polygon point (the shading's entry)
    glm::dvec2 mesh_uv{0.0};
    bool traced = false;
    Entry entry;
    ReliefHit hit;
};

Composited composite(const Frame& f, const PixelRay& r, std::vector<Candidate>& candidates) {
    candidates.clear();
    const double ray_length = glm::length(r.direction);
    for (size_t i = 0; i < f.planes.size(); ++i) {
        const PlaneData& p = f.planes[i];
        Candidate c;
        if (!meet_plane(p, r, c.s, c.mesh_uv)) continue;
        c.plane = i;
        c.bound = c.s;
        const MaterialData& m = *p.material;
        if (m.reads_height && m.height_scale > 0.0 && p.units_per_tile > 0.0) {
            c.entry = entry_at(f, p, r, c.s, c.mesh_uv);
            if (c.entry.view_ts.z > 0.0) {
                // A point h (normalised) under the polygon is h * scale tiles
                // deep, that over the view cosine along the ray.
                c.s_per_height = m.height_scale * p.units_per_tile / (c.entry.view_ts.z * ray_length);
                // No hit above the highest texel (the slack covers the
                // rounding of the hit's height).
                c.bound = c.s + (m.polygon_height - (m.top_height + 1e-9)) * c.s_per_height;
            }
        }
        // Ordered by bound, then object: few planes per pixel, so insertion.
        candidates.push_back(c);
        for (size_t k = candidates.size() - 1; k > 0; --k) {
            const Candidate& a = candidates[k - 1];
            if (a.bound < c.bound || (a.bound == c.bound && a.plane < c.plane)) break;
            std::swap(candidates[k - 1], candidates[k]);
        }
    }
    Composited best;
    double best_s = 2.0;
    size_t best_plane = 0;
    for (const Candidate& c : candidates) {
        // Bounds ascend: none from here on can come nearer than the best.
        if (c.bound > best_s) break;
        const PlaneData& p = f.planes[c.plane];
        double s = c.s;
        ReliefHit hit;
        if (c.s_per_height > 0.0) {
            const MaterialData& m = *p.material;
            if (m.bounded) {
                const std::optional<ReliefHit> bounded = trace_bounded(m, c.entry.uv, c.entry.view_ts);
                if (!bounded) continue;  // passes by the tile
                hit = *bounded;
            } else {
                hit = trace_view(m.traced, c.entry.uv, c.entry.view_ts, m.height_scale, m.polygon_height);
            }
            s = c.s + (m.polygon_height - hit.height) * c.s_per_height;
            // Before the near or past the far plane: clipped away.
            if (!(s >= 0.0 && s <= 1.0)) continue;
        }
        if (best.plane && !(s < best_s || (s == best_s && c.plane < best_plane))) continue;
        best.plane = &p;
        best.s = c.s;
        best.mesh_uv = c.mesh_uv;
        best.traced = c.s_per_height > 0.0;
        best.entry = c.entry;
        best.hit = hit;
        best_s = s;
        best_plane = c.plane;
    }
    return best;
}

// GL's mip-selection scale at pixel (x, y) for plane p (ReferenceImage::
// texels_per_pixel): the texel uv where the lines from the eye through the
// midpoints of the pixel's edges meet p's unbounded plane, differenced
// across the pixel. A few dozen operations: this runs for every shown pixel,
// depth compositing or not.
double texels_per_pixel(const Frame& f, const PlaneData& p, int x, int y) {
    const glm::dvec3 ndc((x + 0.5) / f.width * 2.0 - 1.0, (y + 0.5) / f.height * 2.0 - 1.0, 1.0);
    const glm::dvec3 centre = p.ndc_to_texel * ndc;
    const double centre_w = glm::dot(p.ndc_to_w, ndc);
    // Half a pixel is 1 / width in ndc x, 1 / height in ndc y.
    const glm::dvec3 half_x = p.ndc_to_texel[0] * (1.0 / f.width);
    const glm::dvec3 half_y = p.ndc_to_texel[1] * (1.0 / f.height);
    const double half_x_w = p.ndc_to_w.x / f.width;
    const double half_y_w = p.ndc_to_w.y / f.height;
    bool reached = true;
    const auto texel = [&](const glm::dvec3& h, double w) {
        if (!(h.z * w > 0.0)) reached = false;  // past the horizon: behind the eye, or never
        const double inverse = 1.0 / h.z;  // one division, not two
        return glm::dvec2(h.x * inverse, h.y * inverse);
    };
    const glm::dvec2 dx = texel(centre + half_x, centre_w + half_x_w) - texel(centre - half_x, centre_w - half_x_w);
    const glm::dvec2 dy = texel(centre + half_y, centre_w + half_y_w) - texel(centre - half_y, centre_w - half_y_w);
    if (!reached) return std::numeric_limits<double>::infinity();
    return std::sqrt(std::max(glm::dot(dx, dx), glm::dot(dy, dy)));
}

// Shades pixel (x, y) as plane p seen at `entry`; `traced` is p's trace
// from there when the caller has it already (depth compositing).
void shade_pixel(const Frame& f, int x, int y, const PixelOut& out, const PlaneData& p, const Entry& entry,
                 const ReliefHit* traced) {
    const MaterialData& m = *p.material;
    const glm::dvec3& world = entry.world;
    const glm::dvec3& view_ts = entry.view_ts;

    ReliefHit hit;
    hit.uv = entry.uv;
    hit.height = m.polygon_height;
    // Scale 0 is a flat polygon; z <= 0 only under a mirroring transform that
    // the shaders do not handle either: shade the polygon itself.
    if (traced)
        hit = *traced;
    else if (m.height_scale > 0.0 && view_ts.z > 0.0)
        hit = trace_view(m.traced, entry.uv, view_ts, m.height_scale, m.polygon_height);

    // px_shade: ambient * albedo + per light visibility * colour * (albedo N.L + specular).
    // Lit in linear light: an sRGB albedo decoded first (PX_SRGB_DECODE decodes
    // after filtering instead: the difference is the shader path's to show).
    const glm::dvec3 albedo = glm::dvec3(sample_bilinear(m.images.albedo, hit.uv, m.images.albedo_srgb));
    glm::dvec3 normal = glm::dvec3(sample_bilinear(m.images.normal, hit.uv)) * 2.0 - 1.0;
    if (m.images.layout.normal_rg)  // two-channel normal maps: z follows from x and y, as the shader does
        normal.z = std::sqrt(std::max(1.0 - normal.x * normal.x - normal.y * normal.y, 0.0));
    normal = glm::length(normal) > 0.0 ? glm::normalize(normal) : glm::dvec3(0.0, 0.0, 1.0);
    glm::dvec3 color = f.ambient * albedo;
    double first_visibility = 1.0;
    for (size_t i = 0; i < f.lights.size(); ++i) {
        const LightData& l = f.lights[i];
        const glm::dvec3 to_light = l.point ? l.vector - world : l.vector;
        const glm::dvec3 light_ts = to_texture_frame(p, to_light);
        const double visibility = light_visibility(f, m, hit, light_ts, l.angular_radius);
        if (i == 0) first_visibility = visibility;
        // px_light_term: a light on or below the polygon's plane lights nothing.
        if (!(light_ts.z > 0.0)) continue;
        const double n_dot_l = std::max(glm::dot(normal, light_ts), 0.0);
        const glm::dvec3 half_sum = light_ts + view_ts;
        const double half_len = glm::length(half_sum);
        const double n_dot_h = half_len > 0.0 ? std::max(glm::dot(normal, half_sum / half_len), 0.0) : 0.0;
        const double specular = n_dot_l > 0.0 ? m.specular * std::pow(n_dot_h, m.shininess) : 0.0;
        color += visibility * l.color * (albedo * n_dot_l + glm::dvec3(specular));
    }
    for (int c = 0; c < 3; ++c) out.rgba[c] = f.options.srgb_output ? linear_to_srgb8(color[c]) : to_unorm8(color[c]);
    out.rgba[3] = 255;

    out.sample.covered = m.reads_height;
    out.view_ts = view_ts;
    out.entry_uv = entry.uv;
    out.sample.uv = hit.uv;
    out.sample.height = hit.height;
    out.sample.visibility = first_visibility;
    out.object = p.object;
    out.texels_per_pixel = texels_per_pixel(f, p, x, y);
}

void render_pixel(const Frame& f, int x, int y, const PixelOut& out, std::vector<Candidate>& candidates) {
    const PixelRay ray = pixel_ray(f, x + 0.5, y + 0.5);
    const PlaneData* shown = nullptr;
    Entry entry;
    ReliefHit traced;
    bool has_trace = false;
    if (f.options.depth_composite) {
        const Composited c = composite(f, ray, candidates);
        shown = c.plane;
        // A traced winner keeps its entry and trace (the same inputs, the same bits).
        has_trace = c.traced;
        if (has_trace) {
            entry = c.entry;
            traced = c.hit;
        } else if (shown) {
            entry = entry_at(f, *shown, ray, c.s, c.mesh_uv);
        }
    } else {
        // The nearest polygon, the loop written out rather than through
        // meet_plane: it runs per plane per pixel of every default
        // reference, and so it costs what it did before compositing.
        // A bounded relief whose ray leaves it before meeting it lets the
        // ray through to the next polygon (the GPU discards the fragment).
        std::vector<const PlaneData*> passed;
        for (;;) {
            double nearest_s = 2.0;
            glm::dvec2 mesh_uv(0.0);
            for (const PlaneData& p : f.planes) {
                if (std::find(passed.begin(), passed.end(), &p) != passed.end()) continue;
                const glm::dvec3 o = glm::dvec3(p.inverse_model * glm::dvec4(ray.origin, 1.0));
                const glm::dvec3 d = glm::dvec3(p.inverse_model * glm::dvec4(ray.direction, 0.0));
                if (!(d.z < 0.0)) continue;  // back face (meet_plane says why)
                const double s = -o.z / d.z;
                if (s < 0.0 || s > 1.0 || !(s < nearest_s)) continue;  // strict: the first drawn wins ties (GL_LESS)
                const glm::dvec3 q = o + s * d;
                if (!drawn_at(p, o, d, q)) continue;
                shown = &p;
                nearest_s = s;
                mesh_uv = glm::dvec2(q.x, q.y) / (2.0 * p.half_size) + 0.5;
            }
            if (!shown) break;
            entry = entry_at(f, *shown, ray, nearest_s, mesh_uv);
            const MaterialData& m = *shown->material;
            if (!m.bounded || !(m.height_scale > 0.0)) break;
            if (const std::optional<ReliefHit> bounded = trace_bounded(m, entry.uv, entry.view_ts)) {
                traced = *bounded;
                has_trace = true;
                break;
            }
            passed.push_back(shown);
            shown = nullptr;
            has_trace = false;
        }
    }
    if (!shown) {
        for (int c = 0; c < 3; ++c) out.rgba[c] = to_unorm8(f.background[c]);
        out.rgba[3] = 255;
        return;
    }
    shade_pixel(f, x, y, out, *shown, entry, has_trace ? &traced : nullptr);
}

}  // namespace

namespace {
Result<ReferenceImage> render_reference_checked(const SceneDesc& scene, int width, int height,
                                                const ReferenceOptions& options, const PreparedScene* prepared);
}  // namespace

Result<ReferenceImage> render_reference(const SceneDesc& scene, int width, int height,
                                        const ReferenceOptions& options) {
    return out_of_memory_is_an_error("reference of scene '" + echo(scene.name) + "'",
                                     [&] { return render_reference_checked(scene, width, height, options, nullptr); });
}

Result<ReferenceImage> render_reference(const PreparedScene& scene, int width, int height,
                                        const ReferenceOptions& options) {
    if (options.images.power_of_two_textures != scene.options.images.power_of_two_textures)
        return make_error("reference: scene '" + echo(scene.desc.name) +
                          "' was prepared with other texture sizes than ReferenceOptions::images asks for");
    return out_of_memory_is_an_error("reference of scene '" + echo(scene.desc.name) + "'", [&] {
        return render_reference_checked(scene.desc, width, height, options, &scene);
    });
}

namespace {

// What the reference refuses before it builds anything: an empty image, no
// soft samples, a scene that is not valid, an object that is not a plane.
Status check_request(const SceneDesc& scene, int width, int height, const ReferenceOptions& options,
                     const PreparedScene* prepared) {
    if (width < 1 || height < 1)
        return make_error("reference: image size " + std::to_string(width) + "x" + std::to_string(height) +
                          " is empty");
    if (options.shadow == ShadowMode::soft && options.soft_samples < 1)
        return make_error("reference: soft_samples must be at least 1, got " + std::to_string(options.soft_samples));
    if (!prepared) {  // a prepared scene was validated when it was prepared
        Status valid = validate_scene(scene);
        if (!valid) return valid.error();
        Status resources = check_scene_resources(scene, true);
        if (!resources) return resources.error();
    }
    for (const ObjectDesc& o : scene.objects)
        if (o.mesh.kind != MeshKind::plane)
            return make_error("reference: object '" + o.name + "' is a " + mesh_kind_name(o.mesh.kind) +
                              "; the exact reference handles planes only");
    return {};
}

// Material mi's data: its images (the prepared scene's, or built here) and
// what the trace and the shading read of its description.
Status build_material(MaterialData& m, const SceneDesc& scene, size_t mi, const ReferenceOptions& options,
                      const PreparedScene* prepared) {
    const MaterialDesc& desc = scene.materials[mi];
    if (prepared) {
        m.images = prepared->materials[mi]->images;
    } else {
        Result<MaterialImages> images = build_material_images(desc, scene.base_dir, options.images);
        if (!images) return images.error();
        m.images = std::move(*images);
    }
    m.traced = m.images.traced;
    m.reads_height = (technique_info(desc.technique.technique).options & kOptHeight) != 0;
    m.uv_matrix = desc.uv.matrix<double>();
    m.uv_offset = glm::dvec2(desc.uv.offset);
    m.bounded = desc.bounded;
    if (glm::determinant(m.uv_matrix) != 0.0) m.uv_inverse = glm::inverse(m.uv_matrix);
    m.uv_frame = desc.uv.frame<double>();
    m.height_scale = desc.height_scale;
    m.polygon_height = desc.polygon_height();
    if (!m.traced.texels.empty())
        m.top_height = std::min(1.0, static_cast<double>(*std::max_element(m.traced.texels.begin(),
                                                                            m.traced.texels.end())));
    m.specular = desc.specular;
    m.shininess = desc.shininess;
    return {};
}

// surface.vert's frame, with its fallbacks, from the vertices'
// tangent and normal (the mesh's, or the authored ones as make_plane
// gives them to every vertex, in float): n from the normal matrix (a
// normal under 1e-6 long: the model's +z); t Gram-Schmidt against it
// (under 1e-3 of it left, or a tangent under 1e-6 long: the model's
// +x, then +y); b = handedness * cross(n, t) (mesh tangent w = +1).
void set_tangent_frame(PlaneData& p, const ObjectDesc& o, const glm::dmat3& model3) {
    const glm::dvec3 authored_n(o.mesh.normal.value_or(glm::vec3(0.0f, 0.0f, 1.0f)));
    const glm::dvec3 authored_t(o.mesh.tangent.value_or(glm::vec3(1.0f, 0.0f, 0.0f)));
    p.n = glm::normalize(glm::inverseTranspose(model3) *
                         (glm::dot(authored_n, authored_n) < 1e-12 ? glm::dvec3(0.0, 0.0, 1.0) : authored_n));
    const auto perp = [&](const glm::dvec3& t) { return t - p.n * glm::dot(p.n, t); };
    const auto degenerate = [](const glm::dvec3& t, const glm::dvec3& t_perp) {
        return glm::dot(t_perp, t_perp) <= 1e-6 * glm::dot(t, t);
    };
    glm::dvec3 t = model3 * authored_t;
    glm::dvec3 t_perp = perp(t);
    if (glm::dot(authored_t, authored_t) < 1e-12 || degenerate(t, t_perp)) {
        t = model3[0];
        t_perp = perp(t);
        if (degenerate(t, t_perp)) {
            t = model3[1];
            t_perp = perp(t);
        }
    }
    p.t = glm::normalize(t_perp);
    p.b = p.winding_sign * glm::cross(p.n, p.t);
}

// One plane object: its size, its bounded relief's slab, its transform and
// tangent frame; an error where the transform is singular.
Result<PlaneData> plane_data(const ObjectDesc& o, const MaterialDesc& desc, const MaterialData& m, int object) {
    PlaneData p;
    p.material = &m;
    p.object = object;
    p.half_size = 0.5 * static_cast<double>(o.mesh.size);
    p.drawn_half_size = p.half_size * drawn_length_scale(o.mesh, desc);  // as build_widened_mesh
    if (desc.bounded && desc.height_scale > 0.0f) {
        // The relief's depth in mesh units, as the walls' (relief_depth in the renderer).
        const double depth = static_cast<double>(desc.height_scale) *
                             static_cast<double>(o.mesh.size) / desc.uv.area_scale<double>();
        const double polygon = desc.polygon_height();
        if (std::isfinite(depth) && std::isfinite(polygon)) {
            p.relief_below = std::max(polygon, 0.0) * depth;
            p.relief_above = std::max(1.0 - polygon, 0.0) * depth;
        }
    }
    p.model = glm::dmat4(o.transform.matrix());  // the float matrix the GPU gets, widened
    p.inverse_model = glm::inverse(p.model);
    const glm::dmat3 model3(p.model);
    const double det3 = glm::determinant(model3);
    if (!(std::fabs(det3) > 0.0))
        return make_error("reference: object '" + o.name + "' has a singular transform");
    p.winding_sign = det3 < 0.0 ? -1.0 : 1.0;
    const double area_scale = desc.uv.area_scale<double>();
    p.units_per_tile = static_cast<double>(o.mesh.size) * std::cbrt(std::fabs(det3)) / area_scale;
    if (!std::isfinite(p.units_per_tile) || !(p.units_per_tile > 0.0)) p.units_per_tile = 0.0;
    set_tangent_frame(p, o, model3);
    return p;
}

// The camera's inverse view-projection, and each plane's footprint
// homography from it (PlaneData::ndc_to_texel).
void set_view(Frame& f, const CameraDesc& cam, int width, int height) {
    const double aspect = static_cast<double>(width) / static_cast<double>(height);
    const glm::dmat4 view = glm::lookAt(glm::dvec3(cam.position), glm::dvec3(cam.target), glm::dvec3(cam.up));
    const glm::dmat4 projection = glm::perspective(glm::radians(static_cast<double>(cam.fov_y_deg)), aspect,
                                                   static_cast<double>(cam.near_plane),
                                                   static_cast<double>(cam.far_plane));
    f.inverse_view_projection = glm::inverse(projection * view);
    f.eye = glm::dvec3(cam.position);
    for (PlaneData& p : f.planes) {
        // The object-space near-plane point at ndc (x, y), homogeneous: n =
        // A * (x, y, 1), A's columns the x, y and constant parts.
        const glm::dmat4 m = p.inverse_model * f.inverse_view_projection;
        const glm::dmat4x3 a_t = glm::transpose(glm::dmat3x4(m[0], m[1], m[3] - m[2]));  // row i: n_i's coefficients
        const glm::dvec3 e = glm::dvec3(p.inverse_model * glm::dvec4(f.eye, 1.0));
        // The line from the eye e through n meets z = 0 at
        // (e.z n.xy - n.z e.xy) / (e.z n.w - n.z): each part linear in n.
        const glm::dvec3 row_x = e.z * a_t[0] - e.x * a_t[2];
        const glm::dvec3 row_y = e.z * a_t[1] - e.y * a_t[2];
        const glm::dvec3 row_w = e.z * a_t[3] - a_t[2];
        // Object xy to texel uv: mesh uv = xy / size + 0.5, the uv transform,
        // the field's size (the constants cancel in differences).
        const glm::dvec2 size(p.material->traced.width, p.material->traced.height);
        const glm::dmat2 to_texel = glm::dmat2(size.x, 0.0, 0.0, size.y) * p.material->uv_matrix / (2.0 * p.half_size);
        const glm::dvec3 row_u = to_texel[0][0] * row_x + to_texel[1][0] * row_y;
        const glm::dvec3 row_v = to_texel[0][1] * row_x + to_texel[1][1] * row_y;
        p.ndc_to_texel = glm::transpose(glm::dmat3(row_u, row_v, row_w));
        p.ndc_to_w = a_t[3];
    }
}

// As the renderer: the first kMaxLights lights, colour times intensity.
void add_lights(Frame& f, const SceneDesc& scene) {
    const size_t light_count = std::min<size_t>(scene.lights.size(), static_cast<size_t>(kMaxLights));
    for (size_t i = 0; i < light_count; ++i) {
        const LightDesc& l = scene.lights[i];
        LightData d;
        d.point = l.kind == LightKind::point;
        d.vector = d.point ? glm::dvec3(l.position) : -glm::normalize(glm::dvec3(l.direction));
        d.color = glm::dvec3(l.color) * static_cast<double>(l.intensity);
        d.angular_radius = glm::radians(static_cast<double>(l.angular_radius_deg));
        f.lights.push_back(d);
    }
}

// The image's buffers at their size, every pixel cleared.
void size_output(ReferenceImage& out, int width, int height) {
    out.surface.width = width;
    out.surface.height = height;
    out.surface.samples.assign(static_cast<size_t>(width) * height, SurfaceSample{});
    out.color.width = width;
    out.color.height = height;
    out.color.channels = 4;
    out.color.pixels.assign(static_cast<size_t>(width) * height * 4, 0);
    out.view_ts.assign(static_cast<size_t>(width) * height, glm::dvec3(0.0));
    out.entry_uv.assign(static_cast<size_t>(width) * height, glm::dvec2(0.0));
    out.object_index.assign(static_cast<size_t>(width) * height, -1);
    out.texels_per_pixel.assign(static_cast<size_t>(width) * height, 0.0);
}

// Every pixel of the frame into out. Rows interleaved over threads; each
// pixel depends on nothing but the frame, so the image is the same for any
// thread count.
void render_pixels(const Frame& f, ReferenceImage& out, int width, int height) {
    const int threads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
    auto work = [&](int first) {
        std::vector<Candidate> candidates;  // this thread's scratch, reused for every pixel
        candidates.reserve(f.planes.size());
        for (int y = first; y < height; y += threads)
            for (int x = 0; x < width; ++x) {
                const size_t i = static_cast<size_t>(y) * width + x;
                const PixelOut pixel{out.surface.samples[i], out.color.texel(x, y), out.view_ts[i],
                                     out.entry_uv[i],        out.object_index[i], out.texels_per_pixel[i]};
                render_pixel(f, x, y, pixel, candidates);
            }
    };
    std::vector<std::thread> pool;
    pool.reserve(static_cast<size_t>(threads));
    int started = 1;
    try {
        for (; started < threads; ++started) pool.emplace_back(work, started);
    } catch (const std::system_error&) {
        // No more threads to be had: this thread takes the rows of the ones
        // that did not start (the image does not depend on the split).
    }
    work(0);
    for (int i = started; i < threads; ++i) work(i);
    for (std::thread& t : pool) t.join();
}

Result<ReferenceImage> render_reference_checked(const SceneDesc& scene, int width, int height,
                                                const ReferenceOptions& options, const PreparedScene* prepared) {
    if (Status request = check_request(scene, width, height, options, prepared); !request) return request.error();

    // Materials: only those a plane uses, built once each.
    std::vector<MaterialData> materials(scene.materials.size());
    std::vector<bool> built(scene.materials.size(), false);
    Frame f;
    f.width = width;
    f.height = height;
    f.options = options;
    ReferenceImage out;
    for (const ObjectDesc& o : scene.objects) {
        size_t mi = scene.materials.size();
        for (size_t i = 0; i < scene.materials.size(); ++i)
            if (scene.materials[i].name == o.material) mi = i;
        if (mi == scene.materials.size())
            return make_error("reference: object '" + o.name + "' names unknown material '" + o.material + "'");
        MaterialData& m = materials[mi];
        if (!built[mi]) {
            if (Status material = build_material(m, scene, mi, options, prepared); !material) return material.error();
            built[mi] = true;
        }
        if (m.reads_height && out.texture_width == 0) {
            out.texture_width = m.traced.width;
            out.texture_height = m.traced.height;
            out.height_scale = m.height_scale;
            out.polygon_height = m.polygon_height;
        }

        out.object_texture_size.push_back(m.reads_height ? glm::ivec2(m.traced.width, m.traced.height)
                                                         : glm::ivec2(0));

        Result<PlaneData> plane = plane_data(o, scene.materials[mi], m, static_cast<int>(f.planes.size()));
        if (!plane) return plane.error();
        f.planes.push_back(*plane);
    }

    set_view(f, scene.camera, width, height);
    f.ambient = glm::dvec3(scene.ambient);
    f.background = glm::dvec3(scene.background);
    add_lights(f, scene);
    size_output(out, width, height);
    render_pixels(f, out, width, height);
    return out;
}

}  // namespace

}  // namespace px::reference
