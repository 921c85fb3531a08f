// Triangle meshes with per-vertex tangent frames (tangent + handedness sign),
// the frame the parallax shaders trace in.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "assets/heightfield.h"
#include "core/result.h"

namespace px {

struct Vertex {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    // xyz: unit tangent along +u, orthogonal to normal. w: handedness, +1 or -1,
    // so that bitangent (along +v) = w * cross(normal, tangent.xyz).
    glm::vec4 tangent{1.0f, 0.0f, 0.0f, 1.0f};
    glm::vec2 uv{0.0f};
};

struct Mesh {
    std::vector<Vertex> vertices;
    std::vector<std::uint32_t> indices;  // triangle list
    // World units per uv unit, averaged over the mesh: converts a relief depth
    // given in texture-tile units into object-space depth.
    float units_per_uv = 1.0f;
};

enum class MeshKind { plane, cube, sphere, torus };
const char* mesh_kind_name(MeshKind kind);
Result<MeshKind> parse_mesh_kind(const std::string& name);

// Plane in the xy plane facing +z, centred on the origin, `size` wide,
// uv 0..1 across it, `segments` quads per side.
Mesh make_plane(float size = 2.0f, int segments = 1);
// Axis-aligned cube, `size` wide, each face uv 0..1.
Mesh make_cube(float size = 2.0f);
// UV sphere: u around the equator, v from south to north pole.
Mesh make_uv_sphere(float radius = 1.0f, int slices = 48, int stacks = 24);
// Torus around the z axis: u around the ring, v around the tube.
Mesh make_torus(float ring_radius = 1.0f, float tube_radius = 0.35f, int ring_segments = 64,
                int tube_segments = 32);

// A plane like make_plane(size) whose vertices, one per texel of `field`
// (at uv i/width, j/height, heights sampled bilinearly with wrap), move
// along the normal to where the relief is: z = (h - polygon_height) *
// height_scale * units_per_tile, with height_scale in tile units. The
// tangent frame stays the plane's: the normal map shades it, as with
// parallax. Errors: an empty field.
Result<Mesh> make_displaced_plane(float size, const HeightField& field, float height_scale, float polygon_height,
                                  float units_per_tile);

// Recomputes every vertex tangent from positions, normals and uvs of an
// indexed triangle list (per-triangle uv derivatives, accumulated and
// Gram-Schmidt orthogonalised). Where triangles sharing a vertex disagree on
// handedness (mirrored uvs), the vertex is split so that each side keeps its
// own frame. Also sets units_per_uv. Errors on indices out of range or an
// index count that is not a multiple of 3.
Status generate_tangents(Mesh& mesh);

}  // namespace px
