// Limits that the scene description, the shaders and the exact reference
// share: one value each, seen from every layer.
#pragma once

namespace px {

// Lights drawn per object: a constant loop bound in GLSL ES 1.00 (Appendix
// A), and 4 light vectors + 4 other varyings fit the 8 varying vectors that
// ES 2.0 guarantees. The renderer and the reference both draw the first
// kMaxLights lights of a scene.
inline constexpr int kMaxLights = 4;

}  // namespace px
