// The per-pixel exact reference image of a scene: for every pixel centre, the
// camera ray against the scene's planes, then the exact relief trace
// (reference/tracer.h) from where it meets the polygon, exact light
// visibility, and the shading of shaders_es/chunks/surface_main.glsl.
// What the GPU's debug surface output and colour are measured against
// (reference/metrics.h).
#pragma once

#include "parallaxes/scene/material_images.h"
#include "parallaxes/scene/prepared_scene.h"

#include <vector>

#include <glm/glm.hpp>

#include "parallaxes/assets/image.h"
#include "parallaxes/core/result.h"
#include "parallaxes/effects/technique.h"
#include "parallaxes/reference/metrics.h"
#include "parallaxes/scene/scene.h"

namespace px::reference {

struct ReferenceOptions {
    ShadowMode shadow = ShadowMode::none;  // applied to every light and every material
    int soft_samples = 64;                 // light-disc samples per soft visibility
    // Which plane a pixel shows. false (the default): the nearest polygon,
    // what the GPU's depth test keeps without depth correction. true: the
    // nearest surface point, every relief at its traced hit (the image depth
    // correction aims at; see render_reference for the rules). With one
    // plane in view both give the same image bit for bit (unless a relief
    // hit falls past the far or before the near plane). Off, only the nearest
    // polygon is traced, as before the option.
    bool depth_composite = false;
    // Build each material's images as the renderer drawing the comparison
    // did (Renderer::material_image_options): the same resampled textures.
    MaterialImageOptions images;
    // Colour as the renderer's default frame writes it: linear light encoded
    // for an sRGB display (HostFrame::TargetColor::srgb_encoded); false:
    // linear. An sRGB albedo (MaterialImages::albedo_srgb) is decoded either way.
    bool srgb_output = true;
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
    // error bound are computed from (include/parallaxes/profiling/measurement/stability.h).
    std::vector<glm::dvec3> view_ts;
    std::vector<glm::dvec2> entry_uv;
    // The traced material's relief depth (tile units) and polygon height
    // (0 bottom, 1 top) of the first height-reading plane.
    double height_scale = 0.0;
    double polygon_height = 1.0;
    // Per pixel (row 0 = bottom): the index into scene.objects of the plane
    // the pixel shows, -1 where none (background). Filled whatever
    // `covered` says: a plane whose material reads no height has an index too.
    std::vector<int> object_index;
    // Per pixel: GL's mip-selection scale rho of the shown plane, in texels
    // of its material's traced height field (object_texture_size) per pixel:
    // max(|d(uv * size)/dx|, |d(uv * size)/dy|), uv the polygon point's
    // texture uv (uv transform applied), the derivatives central differences
    // over one pixel (the rays through x +- 0.5 and y +- 0.5 against the same
    // plane, unbounded), as px_mip_level computes from dFdx/dFdy. Its mip
    // level is log2(rho). +inf where a neighbouring ray misses the plane's
    // front (the horizon), 0 where no plane is shown. A material that reads
    // no height still gets the footprint of its (unused) height field.
    std::vector<double> texels_per_pixel;
    // Per scene object: the size of its material's traced height field, the
    // texel unit of its errors (compare_object); 0 x 0 where the material
    // reads no height.
    std::vector<glm::ivec2> object_texture_size;
};

// Scope: objects whose mesh is a plane (the accuracy scenes); any other mesh
// is an error naming the object. The camera, uv transform, tangent frame and
// lighting follow the renderer and surface.vert exactly, in double precision;
// texture reads are base level (no mipmaps). Every plane is traced as the
// exact relief whatever its technique; SurfaceSample::covered is set only
// where the shown plane's material reads height (where the GPU's surface
// output reports a traced hit; it reports every other object drawn too, at
// its polygon: see compare_object). Deterministic for any thread count.
//
// With options.depth_composite, every plane whose front the pixel's ray meets
// within its extent and the near/far range is a candidate. A plane whose
// material reads height (height_scale > 0, eye above its plane) competes at
// its traced relief hit: the polygon point moved along the ray by the hit's
// depth under (or height over) the polygon over the view cosine, the depth in
// world units from the renderer's u_units_per_tile (mesh size times the
// model's mean scale over the uv area scale), as px_write_depth does but
// without its 1/64 cosine floor. Any other plane competes at its polygon
// point. The smallest ray parameter in [0, 1] wins (a relief hit past the far
// plane or before the near one drops out); ties go to the first object (GL_LESS).
// This is the physically right image: the GPU matches it only where the
// reliefs involved are drawn with depth_write (others are at their polygon
// in its depth test). Only candidates that can still win are traced: a
// relief's hit is never nearer than where the ray meets its highest texel.
// The pixel is shaded as without the option, from the winner's polygon point.
Result<ReferenceImage> render_reference(const SceneDesc& scene, int width, int height,
                                        const ReferenceOptions& options = {});
// The same from a prepared scene (scene/prepared_scene.h): nothing is
// validated or built again, the images are the ones the renderer uploaded
// (options.images is then the preparation's, and must not ask otherwise).
Result<ReferenceImage> render_reference(const PreparedScene& scene, int width, int height,
                                        const ReferenceOptions& options = {});

}  // namespace px::reference
