// flat: albedo lit with the geometric normal; no normal map, no height.
#define PX_TECH_FLAT
#include "chunks/surface_common.glsl"
#include "chunks/surface_main.glsl"
