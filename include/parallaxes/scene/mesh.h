// Triangle meshes with per-vertex tangent frames (tangent + handedness sign),
// the frame the parallax shaders trace in.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "parallaxes/assets/heightfield.h"
#include "parallaxes/core/result.h"

namespace px {

struct Vertex {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    // xyz: unit tangent along +u, orthogonal to normal. w: handedness, +1 or -1,
    // so that bitangent (along +v) = w * cross(normal, tangent.xyz).
    glm::vec4 tangent{1.0f, 0.0f, 0.0f, 1.0f};
    glm::vec2 uv{0.0f};
    // The surface's bend away from its tangent plane, to second order (the
    // curved-relief silhouettes' quadric, PX_CURVED): at a tangent-plane
    // offset x along the tangent and y along the bitangent (w * cross(normal,
    // tangent)), mesh units, the surface lies c.x x^2 + c.y x y + c.z y^2
    // below the plane (positive where it bends away from the normal: 1 / (2
    // r) each way on a sphere of radius r). Zero on planes and cubes;
    // fit_curvature fits it from the mesh.
    glm::vec3 curvature{0.0f};
    // How many times more mesh uv a step along the tangent (x) and the
    // bitangent (y) crosses here than the mesh's mean (Mesh::units_per_uv
    // over |dP/du| and |dP/dv|): a uv sphere's u runs around twice the
    // length its v does, and its u crowds toward the poles. The searches'
    // uv step is stretched by it (surface.vert), so that the relief keeps
    // its shape in space wherever the mesh's uv does not. 1 on planes and
    // cubes; generate_tangents sets it, within [1/64, 64].
    glm::vec2 uv_stretch{1.0f};
    // How the mesh's uv bends away from linear across the tangent plane: at
    // a tangent-plane offset (x, y) (mesh units, as `curvature`), mesh u
    // moves by its linear part plus uv_bend_u . (x^2, x y, y^2), v by its
    // part plus uv_bend_v . (x^2, x y, y^2) (a uv sphere's rows curve
    // toward its poles: a straight step east at latitude L drifts toward the
    // equator by tan(L) x^2 / 2 r^2 radians). The curved search follows it
    // along its long grazing paths (surface.vert v_uv_bend). Zero on planes
    // and cubes; fit_curvature fits it.
    glm::vec3 uv_bend_u{0.0f};
    glm::vec3 uv_bend_v{0.0f};
};

struct Mesh {
    std::vector<Vertex> vertices;
    std::vector<std::uint32_t> indices;  // triangle list
    // World units per uv unit, averaged over the mesh: converts a relief depth
    // given in texture-tile units into object-space depth.
    float units_per_uv = 1.0f;
    // How far the flat triangles lie inside the smooth surface that the
    // vertex normals describe, at most (mesh units; chord_sag). 0 on planes
    // and cubes; fit_curvature sets it.
    float chord_sag = 0.0f;
};

enum class MeshKind { plane, cube, sphere, torus, cylinder };
const char* mesh_kind_name(MeshKind kind);
// A sphere, torus or cylinder: a mesh whose surface bends (Vertex::curvature
// is fitted), where a material's silhouette follows the curved relief.
bool mesh_kind_is_curved(MeshKind kind);
Result<MeshKind> parse_mesh_kind(const std::string& name);

// Plane in the xy plane facing +z, centred on the origin, `size` wide,
// uv 0..1 across it, `segments` quads per side. An authored tangent or
// normal replaces every vertex's (+x, +z) as given, unnormalised and
// unchecked (tangent w stays +1): surface.vert makes a frame of anything.
Mesh make_plane(float size = 2.0f, int segments = 1, const std::optional<glm::vec3>& tangent = std::nullopt,
                const std::optional<glm::vec3>& normal = std::nullopt);
// make_plane widened by `margin` (mesh uv) on each side: uv from -margin to
// 1 + margin over (1 + 2 margin) * size, the same uv per mesh unit (a
// bounded relief's plane: bounded_margin in scene.h).
Mesh make_widened_plane(float size, int segments, float margin, const std::optional<glm::vec3>& tangent = std::nullopt,
                        const std::optional<glm::vec3>& normal = std::nullopt);
// Axis-aligned cube, `size` wide, each face uv 0..1.
Mesh make_cube(float size = 2.0f);
// UV sphere: u around the equator, v from south to north pole.
Mesh make_uv_sphere(float radius = 1.0f, int slices = 48, int stacks = 24);
// Torus around the z axis: u around the ring, v around the tube.
Mesh make_torus(float ring_radius = 1.0f, float tube_radius = 0.35f, int ring_segments = 64,
                int tube_segments = 32);

// The grid of a displaced plane: about `per_texel` vertices per texel of the
// material's uv' = uv_matrix * uv + offset along each side, i.e. quads
// along u = per_texel * ceil(|diag(width, height) * uv_matrix * (1, 0)|), at
// least 1 (per_texel * width * |scale.x| without rotation), and likewise
// along v. Computed from sizes alone, so the vertex budget is checked before
// anything is allocated. `per_texel` is clamped to 1..8.
struct DisplacedGrid {
    std::int64_t columns = 1;  // quads along u
    std::int64_t rows = 1;     // quads along v
    std::int64_t vertex_count() const { return (columns + 1) * (rows + 1); }
};
DisplacedGrid displaced_plane_grid(int field_width, int field_height, const glm::dmat2& uv_matrix, int per_texel = 1);

// Open tube around the z axis, centred on the origin, `height` tall: u
// around it (the u = 0 / 1 seam at +y, so u = 0.5 faces a camera on -y, as
// the sphere's), v from the bottom (z = -height / 2) to the top; `rows`
// rings of quads along it.
Mesh make_cylinder(float radius = 0.6f, float height = 2.0f, int segments = 48, int rows = 1);
// make_cylinder longer by `margin` (mesh uv) at each end: v from -margin to
// 1 + margin over (1 + 2 margin) * height, the same uv per mesh unit (a
// bounded relief's open ends: bounded_margin in scene.h).
Mesh make_widened_cylinder(float radius, float height, float margin, int segments = 48, int rows = 1);

// The rim caps of a bounded tube drawn by the exact shape search
// (march.glsl, PX_SHAPE_TUBE): at each end of `tube` (a cylinder as
// make_cylinder builds it, radius `radius`), an annulus in the end's plane
// from radius `inner` to `outer`, where rays come onto the tube's length
// inside its relief. Facing into the tube (the renderer draws their back
// faces, which the shader tells from the tube's by gl_FrontFacing); every
// vertex is a copy of the tube's rim vertex at its angle, frame, uv and
// fits, so that a hit near the rim is shaded in the wall's frame.
// Empty when `tube` has no rim rows or the radii are not 0 <= inner < outer.
Mesh make_tube_rim_caps(const Mesh& tube, float radius, float inner, float outer);

// The side walls of a bounded tile (surface_main.glsl, v_wall_height): along
// each edge of `plane` (a plane as make_plane builds it, in z = 0), a strip
// from z = -below to z = +above, where rays come into the tile's relief
// through its side. Facing out of the tile; every vertex a copy of the
// plane's edge vertex (frame and uv), but for its z. Empty when the plane
// has no edge vertices or the span is not -below < above.
Mesh make_tile_walls(const Mesh& plane, float below, float above);

// A sphere, torus or cylinder (`kind`, with the MeshDesc sizes given) as
// real geometry: built at about `per_texel` vertices per texel of the material's uv'
// = uv_matrix * uv + uv_offset along u and v (displaced_plane_grid's
// counts), every vertex moved along its normal by (h - polygon_height) *
// height_scale * units_per_tile, h sampled bilinearly with repeat at its
// uv', units_per_tile = `units_per_uv` / sqrt(|det uv_matrix|) (the
// parallax-drawn mesh's, as the renderer's units_per_tile uniform). The
// frame stays the base mesh's: the normal map shades it. Where uv seams
// meet (the sphere's poles) vertices of one point may move apart by the
// field's differences there. Errors: a plane or cube kind (planes:
// make_displaced_plane), an empty field, a grid over kMaxSceneVertices
// (checked before allocating).
struct CurvedMeshSize {
    float radius = 1.0f;       // sphere, cylinder; torus ring
    float tube_radius = 0.35f; // torus
    float height = 2.0f;       // cylinder
};
// The grid make_displaced_curved builds (quads around and along), from
// sizes alone, and an upper bound on its vertices.
DisplacedGrid displaced_curved_grid(MeshKind kind, int field_width, int field_height, const glm::dmat2& uv_matrix,
                                    int per_texel = 1);
Result<Mesh> make_displaced_curved(MeshKind kind, const CurvedMeshSize& size, const HeightField& field,
                                   const glm::dmat2& uv_matrix, const glm::dvec2& uv_offset, float height_scale,
                                   float polygon_height, float units_per_uv, int per_texel = 1);



// A plane like make_plane(size) whose vertices (the grid above, `per_texel`
// vertices per texel along each side, at mesh uv
// i/columns, j/rows) move along the normal to where the relief is: heights
// sampled bilinearly with repeat at the material's uv' = uv_matrix * uv +
// uv_offset (as the GPU samples the texture the shading reads), z = (h -
// polygon_height) * height_scale * units_per_tile, with height_scale in tile
// units and a tile size / sqrt(|det uv_matrix|) mesh units (the renderer's
// units per tile). The tangent frame stays the plane's: the normal map shades
// it, as with parallax. Errors: an empty field, a grid over kMaxSceneVertices
// (checked before allocating).
Result<Mesh> make_displaced_plane(float size, const HeightField& field, const glm::dmat2& uv_matrix,
                                  const glm::dvec2& uv_offset, float height_scale, float polygon_height,
                                  int per_texel = 1);

// Fits each vertex's `curvature` (Vertex) from the mesh itself, over the
// vertex's neighbours (those it shares a triangle with, over every vertex at
// its position, so that seams and poles see both sides): Goldfeather and
// Interrante's cubic through the neighbours' drops below the tangent plane
// and their normals, in the vertex's (tangent, bitangent) frame, keeping its
// second-order part. Where the neighbours do not determine the cubic, the
// quadric alone; where they do not determine that (all along one line), the
// mean drop over squared distance, the same each way. Run after
// generate_tangents (it reads the final frame).
void fit_curvature(Mesh& mesh);

// The deepest point of the mesh's triangles below the smooth surface their
// vertices and normals describe (mesh units, at least 0): per triangle, at
// its edges' middles and its centroid, by the second-order estimate
// 1/2 sum_i b_i (p_i - p) . n_i (Phong tessellation with shape factor 1/2,
// exact to second order on a sphere: R (1 - cos phi) for a chord of half
// angle phi). A saddle's triangles, partly outside, count their inside
// part only.
float chord_sag(const Mesh& mesh);
// How much farther out than its chord sag (the second-order estimate) a
// curved relief's polygon is drawn (surface.vert's shell, set by the
// renderer), and a bounded tube's rim caps made room for: a margin for the
// sag's higher orders.
inline constexpr float kShellOverSag = 1.5f;

// Recomputes every vertex tangent from positions, normals and uvs of an
// indexed triangle list (per-triangle uv derivatives, accumulated and
// Gram-Schmidt orthogonalised). Where triangles sharing a vertex disagree on
// handedness (mirrored uvs), the vertex is split so that each side keeps its
// own frame. Also sets units_per_uv. Errors on indices out of range or an
// index count that is not a multiple of 3.
Status generate_tangents(Mesh& mesh);

}  // namespace px
