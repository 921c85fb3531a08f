// The exact CPU reference: rays against the bilinearly filtered height field
// that the GPU samples (GL_LINEAR, GL_REPEAT, texel centres at +0.5), in
// double precision, walking every texel cell the ray crosses and solving ray
// against bilinear patch in closed form, so it never steps over a feature.
//
// Space: x = u * width and y = v * height in texels (unbounded: the field
// repeats), z = normalised relief height (0 bottom, 1 top). The surface is
// z = S(x, y), the bilinear interpolation of the texel values at
// ((i + 0.5), (j + 0.5)). Between four neighbouring texel centres S is one
// bilinear patch: a "cell".
#pragma once

#include <glm/glm.hpp>

#include "parallaxes/assets/heightfield.h"

namespace px::reference {

struct Ray {
    glm::dvec3 origin;     // texels, texels, normalised height
    glm::dvec3 direction;  // any length; t runs in units of it
};

struct Hit {
    bool hit = false;
    double t = 0.0;              // ray parameter of the first hit
    glm::dvec3 position{0.0};    // origin + t * direction
    long cells_visited = 0;      // cells the walk entered (for tests and curiosity)
};

// The first point with t in [t_min, t_max] where the ray is on or below the
// surface: z(t) <= S(x(t), y(t)). A ray starting below the surface hits at
// t_min. Exact up to floating-point rounding of the per-cell quadratic.
Hit first_hit(const HeightField& field, const Ray& ray, double t_min, double t_max);

// Whether any point with t in (t_min, t_max] is strictly below the surface
// by more than `epsilon` (normalised height): the shadow-ray test.
bool occluded(const HeightField& field, const Ray& ray, double t_min, double t_max, double epsilon = 1e-9);

// assets/heightfield.h: the field as the GPU samples it, 8-bit quantised;
// the reference must trace what the shader traces.
using px::quantized_8bit;

// The view ray of the parallax techniques, in the conventions of
// shaders_es/chunks/march.glsl: `uv` where the pixel meets the polygon,
// `view_ts` the unit vector toward the eye in the texture frame (z along the
// normal, z > 0), relief `height_scale` deep in tile units, polygon at
// normalised height `polygon_height`. The ray starts where it enters the
// relief's top (z = 1) and descends; first_hit over t in [0, 1] ends at z = 0.
Ray view_ray(const HeightField& field, glm::dvec2 uv, glm::dvec3 view_ts, double height_scale,
             double polygon_height);

struct ReliefHit {
    glm::dvec2 uv{0.0};   // where the view ray meets the relief (unbounded uv)
    double height = 1.0;  // normalised height there
};
ReliefHit trace_view(const HeightField& field, glm::dvec2 uv, glm::dvec3 view_ts, double height_scale,
                     double polygon_height);

// How far, in texels, the exact hit of this view ray moves when its inputs
// move by one unit in the last place of 32-bit floats: the uv by one float
// ulp along u and along v, the view vector by 2^-24 (relative) along its
// two tangent components, each both ways; the largest of the eight. A
// tracer running in fp32 reads a uv and a view vector at least that far off
// (rasterised varyings, a per-vertex view), so its hit error cannot be
// expected below this floor: at grazing angles, where the ray runs along a
// ridge, the exact hit moves hundreds of texels per texel of sideways
// shift (docs/exact_tracing.md).
double fp32_input_floor(const HeightField& field, glm::dvec2 uv, glm::dvec3 view_ts, double height_scale,
                        double polygon_height);

// Light visibility at a point on the relief (uv, normalised height) for a
// light in unit texture-frame direction `light_ts` (toward the light):
// hard: 1 if the ray toward the light leaves the relief's top unblocked, else
// 0 (0 also when light_ts.z <= 0). Soft: the unblocked share of a light disc
// of the given angular radius (radians) around light_ts, integrated with
// `samples` stratified directions over the disc (deterministic).
double hard_visibility(const HeightField& field, glm::dvec2 uv, double height, glm::dvec3 light_ts,
                       double height_scale);
double soft_visibility(const HeightField& field, glm::dvec2 uv, double height, glm::dvec3 light_ts,
                       double height_scale, double angular_radius, int samples = 64);

}  // namespace px::reference
