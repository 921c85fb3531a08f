// The CPU mirror of shaders_es/techniques/maxmip.frag: the quadtree descent
// through a maximum mip-map (Tevs, Ihrke & Seidel 2008; Drobot 2010) over the
// bilinearly filtered surface (see assets/max_mipmap.h), ending in a
// closed-form ray / bilinear-patch solve in one cell. Same algorithm, same
// steps, same iteration count, in float as the shader's highp, so the tests
// can check the shader's traversal against the exact double-precision
// reference (reference/tracer.h) and measure the iteration budget it needs.
//
// Space as in reference/tracer.h: x = u * width, y = v * height texels,
// z = normalised height; the field repeats.
#pragma once

#include <glm/glm.hpp>

#include "assets/heightfield.h"
#include "assets/max_mipmap.h"
#include "reference/tracer.h"

namespace px::reference {

struct MaxmipHit {
    bool hit = false;            // false: the ray does not descend, the sizes differ, or the budget ran out
    double t = 0.0;              // ray parameter (units of the input direction)
    glm::dvec3 position{0.0};    // texel space: origin + t * direction
    glm::dvec2 uv{0.0};          // unbounded uv of the hit
    double height = 1.0;         // normalised height of the hit
    int iterations = 0;          // loop iterations used (one node visit or one cell solve each)
    bool budget_exhausted = false;  // the budget ran out: position is the last point known above the surface
};

// The first point where a descending ray is on or under the bilinear surface
// of `field` quantised to 8 bits (`pyramid` must be built from it). A ray
// starting above the relief's top is first moved down to z = 1 (where
// reference::view_ray starts); it ends at z = 0, where it always hits.
// `budget`: the most loop iterations, the shader's PX_MAX_SAMPLES. No hit
// (hit = false, iterations 0) if the pyramid's size is not the field's.
MaxmipHit maxmip_first_hit(const MaxMipmap& pyramid, const HeightField& field, const Ray& ray, int budget);

// The view ray in the shader's conventions (reference::trace_view): the hit
// uv is uv + (height - polygon_height) * parallax, as maxmip.frag returns it,
// with parallax = height_scale * view_ts.xy / max(view_ts.z, z_min), z_min
// the divisor below which the ray would cross more than 2^24 texels over the
// relief's depth (no grazing clamp: the exact ray past 89.1 degrees too).
MaxmipHit maxmip_trace_view(const MaxMipmap& pyramid, const HeightField& field, glm::dvec2 uv, glm::dvec3 view_ts,
                            double height_scale, double polygon_height, int budget);

// The texel-space ray maxmip_trace_view (and the shader) actually traces:
// its float entry point and direction, exactly, as a reference::Ray (t in
// [0, 1], height 1 down to 0). first_hit on it is the exact answer for the
// same rounded input, which separates the traversal's own error from the
// rounding of uv and view vector to float that happens before it.
Ray maxmip_view_ray(const MaxMipmap& pyramid, glm::dvec2 uv, glm::dvec3 view_ts, double height_scale,
                    double polygon_height);

}  // namespace px::reference
