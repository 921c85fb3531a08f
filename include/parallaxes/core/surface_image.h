// What a pixel's surface is: the hit that a shader computed (read back from
// the GPU's debug outputs by render/surface_capture) or that the exact
// reference traced (reference/). Both sides see this type; neither owns it.
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace px {

struct SurfaceSample {
    bool covered = false;     // a relief surface was drawn here
    glm::dvec2 uv{0.0};       // hit uv (unbounded: tiles repeat)
    double height = 0.0;      // normalised relief height at the hit (0 bottom, 1 top)
    double visibility = 1.0;  // of the first light, 0..1
};

struct SurfaceImage {
    int width = 0;
    int height = 0;
    std::vector<SurfaceSample> samples;  // row 0 = bottom, as GL reads
    // How the GPU's debug outputs came back: 0 as floats (ES 3.0), 24 when
    // packed in 24 bits per uv and 16 per height and visibility (ES 2.0),
    // 11 when packed in 11 bits each (ES 2.0 without fragment highp). The
    // reference leaves it 0.
    int packing_bits = 0;
    const SurfaceSample& at(int x, int y) const { return samples[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)]; }
};

}  // namespace px
