// The per-pixel exact reference image of a scene: for every pixel centre, the
// camera ray against the scene's planes, then the exact relief trace
// (reference/tracer.h) from where it meets the polygon, exact light
// visibility, and the shading of shaders_es/chunks/surface_main.glsl.
// What the GPU's debug surface output and colour are measured against
// (reference/metrics.h).
#pragma once

#include "assets/image.h"
#include "core/result.h"
#include "effects/technique.h"
#include "reference/metrics.h"
#include "scene/scene.h"

namespace px::reference {

struct ReferenceOptions {
    ShadowMode shadow = ShadowMode::none;  // applied to every light and every material
    int soft_samples = 64;                 // light-disc samples per soft visibility
};

struct ReferenceImage {
    SurfaceImage surface;  // uv, height, first light's visibility per pixel
    Image color;           // RGBA8, row 0 = bottom
    // Size of the traced height field of the first plane drawn with a
    // height-reading material (0 when there is none): the texel unit of
    // compare_surfaces().
    int texture_width = 0;
    int texture_height = 0;
    // Per pixel (row 0 = bottom), where `surface` is covered: the unit vector
    // toward the eye in the material's texture frame (x along u, y along v, z
    // along the normal; not height-scaled) at the point the camera ray meets
    // the polygon, and the uv there. What a technique's offset bound and
    // error bound are computed from (profiling/stability.h).
    std::vector<glm::dvec3> view_ts;
    std::vector<glm::dvec2> entry_uv;
    // The traced material's relief depth (tile units) and polygon height
    // (0 bottom, 1 top) of the first height-reading plane.
    double height_scale = 0.0;
    double polygon_height = 1.0;
};

// Scope: objects whose mesh is a plane (the accuracy scenes); any other mesh
// is an error naming the object. The camera, uv transform, tangent frame and
// lighting follow the renderer and surface.vert exactly, in double precision;
// texture reads are base level (no mipmaps). Every plane is traced as the
// exact relief whatever its technique; SurfaceSample::covered is set only
// where the nearest plane's material reads height (what the GPU's surface
// output reports). Deterministic for any thread count.
Result<ReferenceImage> render_reference(const SceneDesc& scene, int width, int height,
                                        const ReferenceOptions& options = {});

}  // namespace px::reference
