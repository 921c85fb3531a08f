// normal: normal mapping (Blinn 1978; Peercy et al. 1997). Shades the
// polygon's own uv with the normal map: no parallax.
#include "chunks/surface_common.glsl"
#include "chunks/surface_main.glsl"
