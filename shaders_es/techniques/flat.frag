// flat: albedo lit with the geometric normal; no normal map, no height.
#include "chunks/surface_common.glsl"
#include "chunks/surface_main.glsl"
