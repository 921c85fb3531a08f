// What a pixel's surface is (from the GPU's debug output or the exact
// reference) and the error metrics between two such images.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "assets/image.h"
#include "core/result.h"
#include "core/surface_image.h"

namespace px::reference {

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

// Compares `measured` with `truth` over pixels covered in both. uv errors
// are measured modulo the tile (the shorter way round) and scaled by the
// texture size in texels. Errors: different image sizes.
Result<ErrorMetrics> compare_surfaces(const SurfaceImage& measured, const SurfaceImage& truth, int texture_width,
                                      int texture_height);
// PSNR of `measured` against `truth` colour over the pixels `mask` covers
// (both RGBA8, same size), in dB; identical images give 99.
double color_psnr(const Image& measured, const Image& truth, const SurfaceImage& mask);

}  // namespace px::reference
