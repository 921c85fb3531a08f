// What a relief's parallax error depends on, measured from its height field:
// the keys of the planner's cost table (planner/cost_table.h).
#pragma once

#include <cstdint>
#include <string>

#include "parallaxes/assets/heightfield.h"

namespace px {

struct ReliefFeatures {
    int width = 0, height = 0;  // texels of the traced field
    // The relief's depth in texels: height_scale (tile units) times the
    // field's width. Every technique's error grows with it.
    double depth_texels = 0.0;
    // The largest rise between two neighbouring texels, as a share of the
    // relief's depth: 1 for walls and steps (bricks, text), small for smooth
    // reliefs (a sine). Where a search's samples step over an edge.
    double steepness = 0.0;
    // The narrowest feature: the shortest run of texels above (or below) the
    // relief's mid level along a row or column, in texels. A linear search
    // whose step passes it misses the feature: 1-texel lines need far more
    // samples than their depth alone says.
    double thinnest_texels = 0.0;
    // Share of the field's height range used (0: flat, no relief).
    double range = 0.0;
    // FNV-1a 64 of the 8-bit field and its size: the calibration cache's key.
    std::uint64_t field_hash = 0;
};

// `field` as the GPU samples it (quantized_8bit); `height_scale` in tile units.
ReliefFeatures measure_relief(const HeightField& field, double height_scale);

// "depth 15.4 texels, steepness 1.00, thinnest 1 texel"
std::string describe(const ReliefFeatures& f);
std::string hash_hex(std::uint64_t hash);

}  // namespace px
