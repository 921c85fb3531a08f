// Limits that the scene description, the loaders, the shaders and the exact
// reference share: one value each, seen from every layer. Each is checked
// from parameters or file headers before anything is allocated or
// generated; docs/scene-format.md ("Limits") states them for users.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace px {

// Loop bounds must be constants in GLSL ES 1.00 (Appendix A), so each is a
// shader variant. A linear search's max_samples up to 256 keeps its worst
// case bounded; an exact walk's max_steps up to 4096 (the technique table's
// max_samples_limit, the planner's and search model's ranges).
inline constexpr int kMaxMarchSamples = 256;
inline constexpr int kMaxExactSteps = 4096;

// The sample counts every sweep measures by default (the benchmark, the
// planner's cost table, its search model, `plan --verify --candidates`):
// powers of two from 4 to the linear searches' limit.
inline constexpr std::array<int, 7> kSampleGrid = {4, 8, 16, 32, 64, 128, kMaxMarchSamples};
inline std::vector<int> sample_grid() { return std::vector<int>(kSampleGrid.begin(), kSampleGrid.end()); }
// "4,8,16,32,64,128,256", for help strings.
inline std::string sample_grid_text() {
    std::string out;
    for (int n : kSampleGrid) out += (out.empty() ? "" : ",") + std::to_string(n);
    return out;
}

// Lights drawn per object: a constant loop bound in GLSL ES 1.00 (Appendix
// A), and 4 light vectors + 4 other varyings fit the 8 varying vectors that
// ES 2.0 guarantees. A scene with more lights is refused.
inline constexpr int kMaxLights = 4;

// Texels per side of any texture: image files and procedural fields. 4096 is
// what most OpenGL ES 3.0 mobile GPUs support (ES 3.0 guarantees 2048).
inline constexpr int kMaxTextureSize = 4096;

// Texels a scene's materials may hold in all: the sum over every material of
// its albedo, height and normal sources. The load keeps about 24 bytes per
// texel at its peak (the float field, its 8-bit copy, RGBA images, the
// upload's expansion, the max pyramid), so this bounds it near 1.5 GB: one
// material of three 4096 x 4096 textures fits, or sixteen of 1024 x 1024.
inline constexpr std::int64_t kMaxSceneTexels = std::int64_t{1} << 26;

// Vertices of all a scene's meshes together (a displaced plane has one per
// texel corner): 4M vertices of 48 bytes plus indices stay under 300 MB.
inline constexpr std::int64_t kMaxSceneVertices = std::int64_t{1} << 22;
// A displaced mesh's vertices per texel along each side (MeshDesc).
inline constexpr int kMaxDisplacedVerticesPerTexel = 8;

// Counts in one scene.
inline constexpr int kMaxMaterials = 64;
inline constexpr int kMaxObjects = 1024;

// Bytes of one file read whole: a scene file, an image file.
inline constexpr std::size_t kMaxSceneFileBytes = std::size_t{16} << 20;
inline constexpr std::size_t kMaxImageFileBytes = std::size_t{64} << 20;

// Characters of the text a 'text' field raises (each glyph is 6 columns).
inline constexpr int kMaxFieldTextLength = 64;

// Magnitudes the renderer honours: every position, extent and scale stays
// well inside fp32 (and the shading's mediump: fp16 overflows at 65504)
// after the model, view and projection products.
inline constexpr float kMaxCoordinate = 1e5f;   // positions, translations
inline constexpr float kMaxExtent = 1e4f;       // mesh sizes and radii, object scales
inline constexpr float kMinExtent = 1e-4f;
// Tiles per mesh uv unit: uvs then reach 2^14, where fp32 keeps 2^-9 of a
// tile (half a texel of a 256-texel map); the stability catalogue measures
// what that costs (docs/stability.md).
inline constexpr float kMaxUvScale = 16384.0f;
inline constexpr float kMinUvScale = 1.0f / 16384.0f;
// The renderer uploads only the offset's fraction (textures repeat, so a
// whole-tile shift changes nothing), so large offsets cost no precision on
// the GPU; the bound keeps the value itself meaningful in fp32 (1/128 tile).
inline constexpr float kMaxUvOffset = 1e5f;
inline constexpr float kMaxAngleDeg = 3600.0f;  // rotations: ten turns either way
inline constexpr float kMaxRadiance = 1000.0f;  // light colour * intensity, ambient
inline constexpr float kMaxHeightScale = 4.0f;  // relief depth in tiles

// Bytes of any value a message echoes (a key, a string, a path).
inline constexpr std::size_t kMaxEchoBytes = 64;
inline constexpr std::size_t kMaxEchoPathBytes = 512;

}  // namespace px
