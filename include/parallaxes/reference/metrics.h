// What a pixel's surface is (from the GPU's debug output or the exact
// reference) and the error metrics between two such images.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "parallaxes/assets/image.h"
#include "parallaxes/core/result.h"
#include "parallaxes/core/surface_image.h"

namespace px::reference {

struct ReferenceImage;  // reference/reference_image.h

struct ErrorMetrics {
    long pixels = 0;                // pixels covered in both images
    double uv_error_mean = 0.0;     // hit-uv error in texels of the base level
    double uv_error_p95 = 0.0;
    double uv_error_max = 0.0;
    double wrong_surface_share = 0.0;  // share of pixels more than one texel off
    double depth_error_mean = 0.0;  // |height difference| in units of the relief depth
    double depth_error_max = 0.0;
    double shadow_disagreement = 0.0;  // mean |visibility difference|
    double color_psnr_db = 0.0;     // over covered pixels; +inf shown as 99
};

// The nearest-rank 95th percentile of `values` (the smallest value at least
// 95 % of them reach), as every p95 here; 0 when there are none.
double nearest_rank_p95(std::vector<double> values);

// Compares `measured` with `truth` over pixels covered in both. uv errors
// are measured modulo the tile (the shorter way round) and scaled by the
// texture size in texels. Errors: different image sizes.
Result<ErrorMetrics> compare_surfaces(const SurfaceImage& measured, const SurfaceImage& truth, int texture_width,
                                      int texture_height);
// One scene object's error: compare_object().
struct ObjectError {
    long reference_pixels = 0;  // pixels where the reference shows the object
    long pixels = 0;            // of those, covered in both images: what the errors below are over
    long pixels_missing = 0;    // of those, covered in the reference only (the GPU drew nothing there)
    // Hit-uv error in texels of the object's base level (modulo the tile,
    // scaled by ReferenceImage::object_texture_size), as compare_surfaces.
    double base_error_mean = 0.0;
    double base_error_p95 = 0.0;
    double base_error_max = 0.0;
    double wrong_surface_share = 0.0;  // share of `pixels` more than one base texel off
    // The same per pixel over max(1, texels_per_pixel): in texels of the
    // mip level the GPU samples there (a minified surface forgives more).
    double level_error_mean = 0.0;
    double level_error_p95 = 0.0;
    double level_error_max = 0.0;
    double visibility_error_mean = 0.0;  // mean |first light's visibility difference|
};

// `measured` against `truth` over the pixels where the reference shows scene
// object `object` (ReferenceImage::object_index) and covers it. The GPU's
// capture does not say which object drew a pixel: where it drew another
// object there (an occluder the depth test let through, or a relief that
// should have hidden this one but lost at its polygon), its uv is the other
// object's and counts as error, typically past a texel (wrong_surface_share).
// That is intended: it is the error depth correction removes.
//
// The capture covers every object drawn, whatever its technique; the
// reference covers only objects whose material reads height, so an object
// drawn with normal mapping or flat has no compared pixels. To measure one,
// give the reference's copy of the scene a height-reading technique for it
// (as the bench does for normal mapping): the reference then traces its
// relief, and the error is the parallax the technique leaves out.
// Errors: sizes that differ, an object out of range, a reference missing its
// per-pixel object and footprint data.
Result<ObjectError> compare_object(const SurfaceImage& measured, const ReferenceImage& truth, int object);

// Silhouettes: where one image shows a surface and the other does not
// (SurfaceSample::covered), over the length of the truth's contour, in
// pixels: covered pixels with an uncovered 4-neighbour inside the image
// (the image's border is not a contour). The truth is typically the relief
// drawn as real geometry (a displaced mesh); docs/silhouettes.md.
struct ContourError {
    long mismatched = 0;        // covered in exactly one of the two
    long measured_only = 0;     // of those, covered in `measured` only
    long contour = 0;           // the truth's contour length
    double share() const { return contour > 0 ? static_cast<double>(mismatched) / static_cast<double>(contour) : 0.0; }
};
// Errors: sizes that differ.
Result<ContourError> compare_contours(const SurfaceImage& measured, const SurfaceImage& truth);

// PSNR of `measured` against `truth` colour over the pixels `mask` covers
// (both RGBA8, same size), in dB; identical images give 99.
double color_psnr(const Image& measured, const Image& truth, const SurfaceImage& mask);

}  // namespace px::reference
