// Mesh generators and tangent frames: the frame the parallax shaders trace in
// must be unit, orthogonal, and follow +u / +v, or the relief shifts the
// wrong way.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>

#include "parallaxes/core/limits.h"
#include "parallaxes/core/numeric.h"
#include "parallaxes/scene/mesh.h"

namespace px {
namespace {

bool finite3(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

glm::vec3 bitangent(const Vertex& v) {
    return v.tangent.w * glm::cross(v.normal, glm::vec3(v.tangent));
}

// Per-vertex invariants: everything finite, normal and tangent unit,
// tangent orthogonal to the normal, w exactly +-1.
void expect_valid_frames(const Mesh& mesh) {
    ASSERT_FALSE(mesh.vertices.empty());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
        SCOPED_TRACE("vertex " + std::to_string(i));
        const Vertex& v = mesh.vertices[i];
        const glm::vec3 t(v.tangent);
        ASSERT_TRUE(finite3(v.position));
        ASSERT_TRUE(finite3(v.normal));
        ASSERT_TRUE(finite3(t));
        ASSERT_TRUE(std::isfinite(v.uv.x) && std::isfinite(v.uv.y));
        EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-4f);
        EXPECT_NEAR(glm::length(t), 1.0f, 1e-4f);
        EXPECT_LT(std::abs(glm::dot(t, v.normal)), 1e-4f);
        EXPECT_TRUE(v.tangent.w == 1.0f || v.tangent.w == -1.0f) << v.tangent.w;
    }
    EXPECT_TRUE(std::isfinite(mesh.units_per_uv));
    EXPECT_GT(mesh.units_per_uv, 0.0f);
}

// Per-triangle checks: the geometric face normal agrees with the vertex
// normals (counter-clockwise from outside), and each corner's tangent and
// bitangent point along the triangle's dP/du and dP/dv.
void expect_triangles_follow_uv(const Mesh& mesh) {
    ASSERT_EQ(mesh.indices.size() % 3, 0u);
    std::size_t with_uv_area = 0;
    for (std::size_t f = 0; f < mesh.indices.size(); f += 3) {
        SCOPED_TRACE("triangle " + std::to_string(f / 3));
        const Vertex* v[3];
        for (int c = 0; c < 3; ++c) {
            ASSERT_LT(mesh.indices[f + c], mesh.vertices.size());
            v[c] = &mesh.vertices[mesh.indices[f + c]];
        }
        const glm::vec3 e1 = v[1]->position - v[0]->position;
        const glm::vec3 e2 = v[2]->position - v[0]->position;
        const glm::vec3 face = glm::cross(e1, e2);
        if (glm::length(face) < 1e-9f) continue;
        for (int c = 0; c < 3; ++c) EXPECT_GT(glm::dot(face, v[c]->normal), 0.0f) << "corner " << c;

        const glm::vec2 d1 = v[1]->uv - v[0]->uv;
        const glm::vec2 d2 = v[2]->uv - v[0]->uv;
        const float det = d1.x * d2.y - d2.x * d1.y;
        if (std::abs(det) < 1e-9f) continue;
        ++with_uv_area;
        const glm::vec3 dpdu = (e1 * d2.y - e2 * d1.y) / det;
        const glm::vec3 dpdv = (e2 * d1.x - e1 * d2.x) / det;
        for (int c = 0; c < 3; ++c) {
            EXPECT_GT(glm::dot(dpdu, glm::vec3(v[c]->tangent)), 0.0f) << "corner " << c;
            EXPECT_GT(glm::dot(dpdv, bitangent(*v[c])), 0.0f) << "corner " << c;
        }
    }
    EXPECT_GT(with_uv_area, 0u);
}

void expect_good_mesh(const Mesh& mesh) {
    expect_valid_frames(mesh);
    expect_triangles_follow_uv(mesh);
}

void expect_outward(const Mesh& mesh, const std::function<glm::vec3(const glm::vec3&)>& centre_of) {
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
        const Vertex& v = mesh.vertices[i];
        EXPECT_GT(glm::dot(v.normal, v.position - centre_of(v.position)), 0.0f) << "vertex " << i;
    }
}

TEST(MeshKind, NamesRoundTrip) {
    for (MeshKind k : {MeshKind::plane, MeshKind::cube, MeshKind::sphere, MeshKind::torus}) {
        Result<MeshKind> parsed = parse_mesh_kind(mesh_kind_name(k));
        ASSERT_TRUE(parsed.ok()) << mesh_kind_name(k);
        EXPECT_EQ(*parsed, k);
    }
    EXPECT_STREQ(mesh_kind_name(MeshKind::sphere), "sphere");
}

TEST(MeshKind, UnknownNameListsKnownOnes) {
    Result<MeshKind> r = parse_mesh_kind("teapot");
    ASSERT_FALSE(r.ok());
    const std::string& m = r.error().message;
    for (const char* name : {"teapot", "plane", "cube", "sphere", "torus"})
        EXPECT_NE(m.find(name), std::string::npos) << m;
    EXPECT_FALSE(parse_mesh_kind("Plane").ok());
}

TEST(MeshPlane, FrameIsExactlyXYZ) {
    for (int segments : {1, 3}) {
        const Mesh mesh = make_plane(2.0f, segments);
        EXPECT_EQ(mesh.vertices.size(), static_cast<std::size_t>((segments + 1) * (segments + 1)));
        EXPECT_EQ(mesh.indices.size(), static_cast<std::size_t>(6 * segments * segments));
        for (const Vertex& v : mesh.vertices) {
            EXPECT_EQ(v.normal, glm::vec3(0, 0, 1));
            EXPECT_NEAR(v.tangent.x, 1.0f, 1e-6f);
            EXPECT_NEAR(v.tangent.y, 0.0f, 1e-6f);
            EXPECT_NEAR(v.tangent.z, 0.0f, 1e-6f);
            EXPECT_EQ(v.tangent.w, 1.0f);
            // uv (0,0) at (-1,-1), (1,1) at (+1,+1).
            EXPECT_NEAR(v.position.x, 2.0f * v.uv.x - 1.0f, 1e-6f);
            EXPECT_NEAR(v.position.y, 2.0f * v.uv.y - 1.0f, 1e-6f);
            EXPECT_EQ(v.position.z, 0.0f);
        }
        expect_good_mesh(mesh);
    }
}

TEST(MeshPlane, UnitsPerUvIsSize) {
    EXPECT_FLOAT_EQ(make_plane(2.0f).units_per_uv, 2.0f);
    EXPECT_FLOAT_EQ(make_plane(2.0f, 5).units_per_uv, 2.0f);
    EXPECT_NEAR(make_plane(7.5f, 2).units_per_uv, 7.5f, 1e-5f);
}

TEST(MeshCube, FramesWindingAndOutwardNormals) {
    const Mesh mesh = make_cube(2.0f);
    EXPECT_EQ(mesh.vertices.size(), 24u);
    EXPECT_EQ(mesh.indices.size(), 36u);
    expect_good_mesh(mesh);
    expect_outward(mesh, [](const glm::vec3&) { return glm::vec3(0.0f); });
    for (const Vertex& v : mesh.vertices) {
        // Axis-aligned faces: position on the face's plane, uv 0..1.
        EXPECT_NEAR(glm::dot(v.position, v.normal), 1.0f, 1e-6f);
        EXPECT_TRUE(v.uv.x == 0.0f || v.uv.x == 1.0f);
        EXPECT_TRUE(v.uv.y == 0.0f || v.uv.y == 1.0f);
    }
    EXPECT_NEAR(mesh.units_per_uv, 2.0f, 1e-5f);
}

TEST(MeshSphere, FramesWindingAndOutwardNormals) {
    const Mesh mesh = make_uv_sphere(1.5f, 24, 12);
    expect_good_mesh(mesh);
    expect_outward(mesh, [](const glm::vec3&) { return glm::vec3(0.0f); });
    for (const Vertex& v : mesh.vertices) EXPECT_NEAR(glm::length(v.position), 1.5f, 1e-5f);
}

TEST(MeshSphere, UvLayout) {
    const Mesh mesh = make_uv_sphere(1.0f, 16, 8);
    float min_v = 1.0f, max_v = 0.0f;
    for (const Vertex& v : mesh.vertices) {
        EXPECT_GE(v.uv.x, 0.0f);
        EXPECT_LE(v.uv.x, 1.0f);
        min_v = std::min(min_v, v.uv.y);
        max_v = std::max(max_v, v.uv.y);
        // v runs south (0) to north (1): the higher the vertex, the larger v.
        if (v.uv.y == 0.0f) {
            EXPECT_NEAR(v.normal.z, -1.0f, 1e-6f);
        }
        if (v.uv.y == 1.0f) {
            EXPECT_NEAR(v.normal.z, 1.0f, 1e-6f);
        }
        EXPECT_NEAR(v.normal.z, std::sin(3.14159265f * (v.uv.y - 0.5f)), 1e-5f);
    }
    EXPECT_EQ(min_v, 0.0f);
    EXPECT_EQ(max_v, 1.0f);
}

TEST(MeshSphere, PolesHaveFiniteOrthogonalTangents) {
    for (auto [slices, stacks] :
         {std::pair{3, 2}, std::pair{4, 3}, std::pair{48, 24}, std::pair{7, 64}}) {
        SCOPED_TRACE(std::to_string(slices) + "x" + std::to_string(stacks));
        const Mesh mesh = make_uv_sphere(1.0f, slices, stacks);
        expect_good_mesh(mesh);
        int pole_vertices = 0;
        for (const Vertex& v : mesh.vertices) {
            if (std::abs(v.normal.z) < 1.0f - 1e-6f) continue;
            ++pole_vertices;
            EXPECT_NEAR(glm::length(glm::vec3(v.tangent)), 1.0f, 1e-5f);
            EXPECT_NEAR(v.tangent.z, 0.0f, 1e-5f);
        }
        EXPECT_GE(pole_vertices, 2);
    }
}

TEST(MeshTorus, FramesWindingAndOutwardNormals) {
    const float ring = 1.0f;
    const Mesh mesh = make_torus(ring, 0.35f, 32, 16);
    expect_good_mesh(mesh);
    // Outward from the tube's centre line: the circle of radius `ring` in z = 0.
    expect_outward(mesh, [ring](const glm::vec3& p) {
        const glm::vec2 xy(p.x, p.y);
        return glm::vec3(ring * glm::normalize(xy), 0.0f);
    });
    for (const Vertex& v : mesh.vertices) {
        const glm::vec3 centre(ring * glm::normalize(glm::vec2(v.position)), 0.0f);
        EXPECT_NEAR(glm::length(v.position - centre), 0.35f, 1e-5f);
    }
}

TEST(MeshCylinder, FramesWindingAndOutwardNormals) {
    const Mesh mesh = make_cylinder(0.6f, 2.0f, 24, 3);
    expect_good_mesh(mesh);
    expect_outward(mesh, [](const glm::vec3& p) { return glm::vec3(0.0f, 0.0f, p.z); });
    for (const Vertex& v : mesh.vertices) {
        EXPECT_NEAR(glm::length(glm::vec2(v.position)), 0.6f, 1e-5f);
        EXPECT_NEAR(v.position.z, (v.uv.y - 0.5f) * 2.0f, 1e-5f);  // v runs up the axis
    }
}

TEST(MeshGenerators, NoSplitsAndStableUnderRegeneration) {
    for (const Mesh& generated : {make_plane(2.0f, 4), make_cube(1.0f), make_uv_sphere(1.0f, 12, 6),
                                  make_torus(1.0f, 0.3f, 12, 8)}) {
        Mesh again = generated;
        ASSERT_TRUE(generate_tangents(again).ok());
        ASSERT_EQ(again.vertices.size(), generated.vertices.size());
        EXPECT_EQ(again.indices, generated.indices);
        EXPECT_FLOAT_EQ(again.units_per_uv, generated.units_per_uv);
        for (std::size_t i = 0; i < again.vertices.size(); ++i)
            EXPECT_LT(glm::length(again.vertices[i].tangent - generated.vertices[i].tangent),
                      1e-6f);
    }
}

// Two unit quads sharing the edge x = 1; the right one has u mirrored
// (u = 2 - x), as when a texture is mirrored across a symmetry seam.
Mesh mirrored_quads() {
    Mesh mesh;
    const glm::vec2 xy[6] = {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}};
    for (const glm::vec2& p : xy) {
        Vertex v;
        v.position = glm::vec3(p, 0.0f);
        v.normal = glm::vec3(0, 0, 1);
        v.uv = glm::vec2(p.x <= 1.0f ? p.x : 2.0f - p.x, p.y);
        v.tangent = glm::vec4(0.0f);  // must be overwritten
        mesh.vertices.push_back(v);
    }
    mesh.indices = {0, 1, 4, 0, 4, 3,   // left: u along +x
                    1, 2, 5, 1, 5, 4};  // right: u along -x
    return mesh;
}

TEST(MeshTangents, MirroredUvsSplitSharedVertices) {
    Mesh mesh = mirrored_quads();
    ASSERT_TRUE(generate_tangents(mesh).ok());
    // The two shared vertices (1 and 4) are duplicated, nothing else.
    ASSERT_EQ(mesh.vertices.size(), 8u);
    expect_good_mesh(mesh);

    for (std::size_t f = 0; f < 4; ++f) {
        const bool right = f >= 2;
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t i = mesh.indices[3 * f + c];
            const Vertex& v = mesh.vertices[i];
            SCOPED_TRACE("triangle " + std::to_string(f) + " vertex " + std::to_string(i));
            EXPECT_EQ(v.tangent.w, right ? -1.0f : 1.0f);
            EXPECT_NEAR(v.tangent.x, right ? -1.0f : 1.0f, 1e-6f);
            // Both sides: bitangent along +v = +y.
            EXPECT_NEAR(bitangent(v).y, 1.0f, 1e-6f);
        }
    }
    // No vertex is shared across the mirror seam any more.
    for (std::size_t l = 0; l < 6; ++l)
        for (std::size_t r = 6; r < 12; ++r) EXPECT_NE(mesh.indices[l], mesh.indices[r]);
    // The copies sit where the originals were.
    int at_seam = 0;
    for (const Vertex& v : mesh.vertices) at_seam += v.position.x == 1.0f;
    EXPECT_EQ(at_seam, 4);
    EXPECT_FLOAT_EQ(mesh.units_per_uv, 1.0f);
}

TEST(MeshTangents, IndexCountNotMultipleOfThree) {
    Mesh mesh = make_plane();
    mesh.indices.push_back(0);
    const Mesh before = mesh;
    const Status s = generate_tangents(mesh);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("multiple of 3"), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find("7"), std::string::npos) << s.error().message;
    EXPECT_EQ(mesh.vertices.size(), before.vertices.size());
}

TEST(MeshTangents, IndexOutOfRange) {
    Mesh mesh = make_plane();  // 4 vertices, 6 indices
    mesh.indices[4] = 17;
    const Status s = generate_tangents(mesh);
    ASSERT_FALSE(s.ok());
    const std::string& m = s.error().message;
    EXPECT_NE(m.find("index 4"), std::string::npos) << m;
    EXPECT_NE(m.find("17"), std::string::npos) << m;
    EXPECT_NE(m.find("4 vertices"), std::string::npos) << m;

    mesh.indices[4] = 4;  // one past the end
    EXPECT_FALSE(generate_tangents(mesh).ok());
}

TEST(MeshTangents, NonFinitePositionIsAnError) {
    Mesh mesh = make_plane();
    mesh.vertices[2].position.y = std::nanf("");
    const Status s = generate_tangents(mesh);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("vertex 2"), std::string::npos) << s.error().message;
}

TEST(MeshTangents, DegenerateTrianglesAndUnusedVerticesStayFinite) {
    Mesh mesh;
    auto add = [&](glm::vec3 p, glm::vec2 uv, glm::vec3 n) {
        Vertex v;
        v.position = p;
        v.uv = uv;
        v.normal = n;
        mesh.vertices.push_back(v);
    };
    const glm::vec3 up(0, 0, 1);
    add({0, 0, 0}, {0, 0}, up);                  // 0
    add({1, 0, 0}, {0, 0}, up);                  // 1: same uv as 0
    add({0, 1, 0}, {0, 0}, up);                  // 2: same uv as 0
    add({5, 5, 5}, {1, 1}, glm::vec3(1, 0, 0));  // 3: unused, normal along the default tangent
    add({0, 0, 0}, {0, 0}, up);                  // 4..6: collinear, but a proper uv triangle
    add({1, 0, 0}, {1, 0}, up);
    add({2, 0, 0}, {0, 1}, up);
    mesh.indices = {0, 1, 2,   // zero uv area
                    4, 5, 6,   // zero world area
                    0, 0, 0};  // fully degenerate
    ASSERT_TRUE(generate_tangents(mesh).ok());
    EXPECT_EQ(mesh.vertices.size(), 7u);
    expect_valid_frames(mesh);
    EXPECT_EQ(mesh.units_per_uv, 1.0f);  // no usable triangle: left neutral
    EXPECT_EQ(mesh.vertices[3].tangent.w, 1.0f);

    // Same again with zero normals: the frame still comes out finite.
    for (Vertex& v : mesh.vertices) v.normal = glm::vec3(0.0f);
    ASSERT_TRUE(generate_tangents(mesh).ok());
    for (const Vertex& v : mesh.vertices) {
        ASSERT_TRUE(finite3(glm::vec3(v.tangent)));
        EXPECT_NEAR(glm::length(glm::vec3(v.tangent)), 1.0f, 1e-5f);
    }
}

TEST(MeshTangents, ZeroNormalFallsBackToFaceNormal) {
    Mesh mesh = make_plane(2.0f);
    for (Vertex& v : mesh.vertices) v.normal = glm::vec3(0.0f);
    ASSERT_TRUE(generate_tangents(mesh).ok());
    for (const Vertex& v : mesh.vertices) {
        EXPECT_NEAR(v.tangent.x, 1.0f, 1e-6f);
        EXPECT_EQ(v.tangent.w, 1.0f);
    }
}

TEST(MeshTangents, FrameDoesNotDependOnWinding) {
    // Clockwise triangles with the same normals and uvs: the uv map, hence
    // the frame, is unchanged; only the uv-area sign flips.
    // Flipping every other triangle also checks that inconsistent winding
    // alone is not taken for mirrored uvs (no vertex gets split).
    for (std::size_t step : {3, 6}) {
        Mesh mesh = make_plane(2.0f, 2);
        for (std::size_t f = 0; f < mesh.indices.size(); f += step)
            std::swap(mesh.indices[f + 1], mesh.indices[f + 2]);
        ASSERT_TRUE(generate_tangents(mesh).ok());
        EXPECT_EQ(mesh.vertices.size(), 9u);
        for (const Vertex& v : mesh.vertices)
            EXPECT_LT(glm::length(v.tangent - glm::vec4(1, 0, 0, 1)), 1e-6f);
    }
}

TEST(MeshTangents, RotatedUvsGiveRotatedTangent) {
    // uv rotated 90 degrees: +u runs along +y, +v along -x.
    Mesh mesh = make_plane(2.0f);
    for (Vertex& v : mesh.vertices) v.uv = glm::vec2(v.uv.y, 1.0f - v.uv.x);
    ASSERT_TRUE(generate_tangents(mesh).ok());
    expect_good_mesh(mesh);
    for (const Vertex& v : mesh.vertices) {
        EXPECT_NEAR(v.tangent.y, 1.0f, 1e-6f);
        EXPECT_EQ(v.tangent.w, 1.0f);
        EXPECT_NEAR(bitangent(v).x, -1.0f, 1e-6f);
    }
}

}  // namespace
}  // namespace px

namespace px {
namespace {

// A height field whose texel (x, y) holds a distinct value: where each vertex
// samples it can be read back from its height.
HeightField ramp_field(int w, int h) {
    HeightField f;
    f.width = w;
    f.height = h;
    f.texels.resize(static_cast<std::size_t>(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            f.texels[static_cast<std::size_t>(y) * w + x] = static_cast<float>(x + 3 * y) / (4.0f * (w + h));
    return f;
}

glm::dmat2 uv_scale(double su, double sv) { return glm::dmat2(su, 0.0, 0.0, sv); }

// The real-geometry baseline displaces along the material's transformed uv,
// as the shading samples: about one vertex per texel of uv' along each side
// (width * |scale|), heights sampled at uv' = M uv + offset with repeat, and
// a relief height_scale tiles deep, a tile size / area_scale mesh units.
TEST(MeshDisplacedPlane, GridAndDisplacementFollowTheUvTransform) {
    const HeightField field = ramp_field(16, 8);
    for (double s : {1.0, 2.0, 3.0, 0.5}) {
        SCOPED_TRACE("uv scale " + std::to_string(s));
        const glm::dmat2 m = uv_scale(s, s);
        const glm::dvec2 offset(0.25, -1.5);
        const DisplacedGrid grid = displaced_plane_grid(16, 8, m);
        EXPECT_EQ(grid.columns, static_cast<std::int64_t>(16 * s));
        EXPECT_EQ(grid.rows, static_cast<std::int64_t>(8 * s));
        const float size = 2.0f, scale = 0.1f, polygon = 1.0f;
        Result<Mesh> mesh = make_displaced_plane(size, field, m, offset, scale, polygon);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        ASSERT_EQ(static_cast<std::int64_t>(mesh->vertices.size()), grid.vertex_count());
        EXPECT_EQ(mesh->indices.size(), static_cast<std::size_t>(6 * grid.columns * grid.rows));
        const double units_per_tile = size / s;
        for (const Vertex& v : mesh->vertices) {
            const glm::dvec2 tiled = m * glm::dvec2(v.uv) + offset;
            const double expected = (field.sample_bilinear(tiled.x, tiled.y) - polygon) * scale * units_per_tile;
            ASSERT_NEAR(v.position.z, expected, 1e-6) << "at mesh uv " << v.uv.x << ", " << v.uv.y;
        }
    }
    // Anisotropic and rotated: texels along each transformed mesh edge.
    EXPECT_EQ(displaced_plane_grid(16, 8, uv_scale(2.0, -3.0)).columns, 32);
    EXPECT_EQ(displaced_plane_grid(16, 8, uv_scale(2.0, -3.0)).rows, 24);
    const glm::dmat2 quarter_turn(0.0, 1.0, -1.0, 0.0);  // +u to +v: the u edge crosses the 8 texels of v
    EXPECT_EQ(displaced_plane_grid(16, 8, quarter_turn).columns, 8);
    EXPECT_EQ(displaced_plane_grid(16, 8, quarter_turn).rows, 16);
}

// vertices_per_texel: k quads per texel along each side, so an even k puts a
// vertex on every texel centre (uv (i + 0.5) / 16 is vertex 2i + 1 at k = 2),
// where the displaced height is the texel's own.
TEST(MeshDisplacedPlane, VerticesPerTexelPutVerticesOnTexelCentres) {
    HeightField field = ramp_field(16, 8);
    for (std::size_t i = 0; i < field.texels.size(); ++i) field.texels[i] = static_cast<float>((i * 7919) % 13) / 13.0f;
    const DisplacedGrid grid = displaced_plane_grid(16, 8, uv_scale(1.0, 1.0), 2);
    EXPECT_EQ(grid.columns, 32);
    EXPECT_EQ(grid.rows, 16);
    EXPECT_EQ(displaced_plane_grid(16, 8, uv_scale(2.0, -3.0), 4).columns, 128);
    EXPECT_EQ(displaced_plane_grid(16, 8, uv_scale(1.0, 1.0), 0).columns, 16);   // clamped to 1
    EXPECT_EQ(displaced_plane_grid(16, 8, uv_scale(1.0, 1.0), 99).columns, 128);  // clamped to 8
    Result<Mesh> mesh = make_displaced_plane(2.0f, field, uv_scale(1.0, 1.0), glm::dvec2(0.0), 0.1f, 0.0f, 2);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    ASSERT_EQ(static_cast<std::int64_t>(mesh->vertices.size()), grid.vertex_count());
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            const Vertex& v = mesh->vertices[static_cast<std::size_t>((2 * y + 1) * 33 + 2 * x + 1)];
            ASSERT_NEAR(v.uv.x, (x + 0.5) / 16.0, 1e-6);
            ASSERT_NEAR(v.uv.y, (y + 0.5) / 8.0, 1e-6);
            // The relief 0.1 tiles deep, a tile 2 units: z = h * 0.2.
            ASSERT_NEAR(v.position.z, field.texels[static_cast<std::size_t>(y) * 16 + x] * 0.2f, 1e-6)
                << "texel " << x << ", " << y;
        }
    // The budget counts the denser grid: 1024^2 texels at 2 per texel is over it.
    HeightField sized_only;
    sized_only.width = sized_only.height = 1024;
    Result<Mesh> over = make_displaced_plane(2.0f, sized_only, uv_scale(1.0, 1.0), glm::dvec2(0.0), 0.1f, 1.0f, 2);
    ASSERT_FALSE(over.ok());
    EXPECT_NE(over.error().message.find("2048x2048 grid (2 vertices per texel"), std::string::npos)
        << over.error().message;
}

// The grid grows with the uv scale, so the budget is checked on the grid,
// from sizes, before any vertex exists (the field below has no texels).
TEST(MeshDisplacedPlane, OverTheVertexLimitIsRefusedBeforeAllocating) {
    HeightField sized_only;
    sized_only.width = sized_only.height = 1024;  // 1025^2 vertices at scale 1: under 2^22
    EXPECT_LE(displaced_plane_grid(1024, 1024, uv_scale(1.0, 1.0)).vertex_count(), kMaxSceneVertices);
    Result<Mesh> mesh = make_displaced_plane(2.0f, sized_only, uv_scale(4.0, 4.0), glm::dvec2(0.0), 0.1f, 1.0f);
    ASSERT_FALSE(mesh.ok());
    const std::string& message = mesh.error().message;
    EXPECT_NE(message.find("4096x4096 grid"), std::string::npos) << message;
    EXPECT_NE(message.find("16785409 vertices, over the limit of 4194304"), std::string::npos) << message;
    // The largest uv scale on the largest field: counted without overflow.
    const DisplacedGrid huge = displaced_plane_grid(4096, 4096, uv_scale(16384.0, 16384.0));
    EXPECT_GT(huge.vertex_count(), kMaxSceneVertices);
}

// Curved meshes as real geometry: every vertex moved along its normal by
// (h - polygon) * height_scale * units_per_uv / area_scale, h the field at
// its transformed uv; the grid at least one vertex per texel of uv', and
// no coarser than the parallax mesh; a cube and an over-budget grid refused.
TEST(MeshDisplacedCurved, VerticesMoveAlongTheirNormalsByTheRelief) {
    const HeightField field = ramp_field(16, 8);
    const glm::dmat2 m = uv_scale(4.0, 8.0);
    const glm::dvec2 offset(0.5, 0.25);
    const float scale = 0.05f, polygon = 1.0f, units_per_uv = 3.0f;
    for (MeshKind kind : {MeshKind::sphere, MeshKind::cylinder, MeshKind::torus}) {
        SCOPED_TRACE(mesh_kind_name(kind));
        const DisplacedGrid grid = displaced_curved_grid(kind, 16, 8, m);
        EXPECT_EQ(grid.columns, 64);  // 16 texels x 4 tiles
        EXPECT_EQ(grid.rows, 64);     // 8 texels x 8 tiles
        const CurvedMeshSize size{0.8f, 0.3f, 2.0f};
        Result<Mesh> mesh = make_displaced_curved(kind, size, field, m, offset, scale, polygon, units_per_uv);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        const Mesh base = kind == MeshKind::sphere  ? make_uv_sphere(0.8f, 64, 64)
                          : kind == MeshKind::torus ? make_torus(0.8f, 0.3f, 64, 64)
                                                    : make_cylinder(0.8f, 2.0f, 64, 64);
        ASSERT_EQ(mesh->vertices.size(), base.vertices.size());
        const double depth = scale * units_per_uv / std::sqrt(4.0 * 8.0);
        for (std::size_t i = 0; i < base.vertices.size(); ++i) {
            const Vertex& b = base.vertices[i];
            const glm::dvec2 tiled = m * glm::dvec2(b.uv) + offset;
            const double h = field.sample_bilinear(tiled.x, tiled.y);
            const glm::vec3 expected = b.position + b.normal * static_cast<float>((h - polygon) * depth);
            ASSERT_NEAR(glm::length(mesh->vertices[i].position - expected), 0.0f, 1e-5f) << i;
            EXPECT_EQ(mesh->vertices[i].normal, b.normal);  // the frame stays the smooth mesh's
        }
    }
    // Never coarser than the parallax mesh (48 x 24 for a sphere).
    EXPECT_EQ(displaced_curved_grid(MeshKind::sphere, 4, 4, uv_scale(1.0, 1.0)).columns, 48);
    EXPECT_EQ(displaced_curved_grid(MeshKind::sphere, 4, 4, uv_scale(1.0, 1.0)).rows, 24);
    EXPECT_FALSE(make_displaced_curved(MeshKind::cube, {}, field, m, offset, scale, polygon, 1.0f).ok());
    HeightField sized_only;
    sized_only.width = sized_only.height = 4096;
    Result<Mesh> huge = make_displaced_curved(MeshKind::sphere, {}, sized_only, uv_scale(4.0, 4.0), offset, scale,
                                              polygon, 1.0f);
    ASSERT_FALSE(huge.ok());
    EXPECT_NE(huge.error().message.find("over the limit of 4194304"), std::string::npos) << huge.error().message;
}

// The curved-relief quadric (Vertex::curvature) fitted from each mesh,
// against the surfaces' own principal curvatures (their frames run along
// the principal directions, so the cross term is 0).
TEST(MeshCurvature, FitMatchesThePrincipalCurvatures) {
    const float r = 0.8f;
    const Mesh sphere = make_uv_sphere(r);
    for (const Vertex& v : sphere.vertices) {  // poles included: they see their whole fan
        EXPECT_NEAR(v.curvature.x, 0.5f / r, 0.01f / r) << v.position.x << " " << v.position.y << " " << v.position.z;
        EXPECT_NEAR(v.curvature.y, 0.0f, 0.01f / r);
        EXPECT_NEAR(v.curvature.z, 0.5f / r, 0.01f / r);
    }
    const Mesh tube = make_cylinder(r, 2.0f);
    for (const Vertex& v : tube.vertices) {  // bent around (u), straight along (v)
        EXPECT_NEAR(v.curvature.x, 0.5f / r, 0.01f / r);
        EXPECT_NEAR(v.curvature.y, 0.0f, 0.01f / r);
        EXPECT_NEAR(v.curvature.z, 0.0f, 0.01f / r);
    }
    const float ring = 1.0f, radius = 0.35f;
    const Mesh torus = make_torus(ring, radius);
    for (const Vertex& v : torus.vertices) {
        // Around the tube 1 / r; around the ring cos(tube) / (R + r cos(tube)),
        // negative (saddle) on the inner half: the quadric in the vertex's own
        // frame (the one the shader uses), which generate_tangents may turn
        // off the ring's direction by a few degrees.
        const glm::dvec3 n = glm::normalize(glm::dvec3(v.normal));
        const glm::dvec3 radial = glm::normalize(glm::dvec3(v.position.x, v.position.y, 0.0));
        const double cos_tube = glm::dot(n, radial);
        const double k_ring = cos_tube / (ring + radius * cos_tube), k_tube = 1.0 / radius;
        const glm::dvec3 e_ring = glm::normalize(glm::cross(glm::dvec3(0.0, 0.0, 1.0), radial));
        const glm::dvec3 e_tube = glm::cross(n, e_ring);
        glm::dvec3 t = glm::dvec3(v.tangent);
        t = glm::normalize(t - n * glm::dot(n, t));
        const glm::dvec3 b = (v.tangent.w < 0.0f ? -1.0 : 1.0) * glm::cross(n, t);
        const glm::dvec3 expected(0.5 * (k_ring * glm::dot(t, e_ring) * glm::dot(t, e_ring) + k_tube * glm::dot(t, e_tube) * glm::dot(t, e_tube)),
                                  k_ring * glm::dot(t, e_ring) * glm::dot(b, e_ring) + k_tube * glm::dot(t, e_tube) * glm::dot(b, e_tube),
                                  0.5 * (k_ring * glm::dot(b, e_ring) * glm::dot(b, e_ring) + k_tube * glm::dot(b, e_tube) * glm::dot(b, e_tube)));
        EXPECT_NEAR(v.curvature.x, expected.x, 0.02 / radius) << v.uv.x << " " << v.uv.y;
        EXPECT_NEAR(v.curvature.y, expected.y, 0.02 / radius) << v.uv.x << " " << v.uv.y;
        EXPECT_NEAR(v.curvature.z, expected.z, 0.02 / radius) << v.uv.x << " " << v.uv.y;
    }
    for (const Vertex& v : make_plane(2.0f, 4).vertices) EXPECT_EQ(v.curvature, glm::vec3(0.0f));
    for (const Vertex& v : make_cube(2.0f).vertices) EXPECT_EQ(v.curvature, glm::vec3(0.0f));
    // Scaling the mesh scales the curvature inversely.
    const Mesh big = make_uv_sphere(4.0f * r);
    EXPECT_NEAR(big.vertices[100].curvature.x, sphere.vertices[100].curvature.x / 4.0f, 1e-4f);
}

// The chord sag (chord_sag, Mesh::chord_sag): how deep a curved mesh's flat
// triangles lie inside the smooth surface. On a uv sphere each triangle's
// deepest point is R minus the centre's distance to its plane (its vertices
// lie on the sphere); the second-order estimate finds the deepest of them
// within 5 %, and falls as the square of the tessellation.
TEST(MeshChordSag, MatchesTheSpheresTrianglesAndFallsWithTheTessellation) {
    const float r = 0.9f;
    const Mesh sphere = make_uv_sphere(r, 48, 24);
    double deepest = 0.0;
    for (std::size_t t = 0; t + 2 < sphere.indices.size(); t += 3) {
        const glm::dvec3 a(sphere.vertices[sphere.indices[t]].position), b(sphere.vertices[sphere.indices[t + 1]].position),
            c(sphere.vertices[sphere.indices[t + 2]].position);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        if (!(glm::length(n) > 1e-12)) continue;  // a pole's sliver
        deepest = std::max(deepest, static_cast<double>(r) - std::fabs(glm::dot(glm::normalize(n), a)));
    }
    EXPECT_NEAR(sphere.chord_sag, deepest, 0.05 * deepest);
    EXPECT_EQ(sphere.chord_sag, chord_sag(sphere));
    const Mesh finer = make_uv_sphere(r, 96, 48);
    EXPECT_NEAR(sphere.chord_sag / finer.chord_sag, 4.0, 0.4);
    // A torus's inner half is a saddle (its chords partly outside): finite,
    // and about its tube's chords (32 around a tube of 0.35).
    const Mesh torus = make_torus(1.0f, 0.35f);
    EXPECT_GT(torus.chord_sag, 0.35f * (1.0f - std::cos(kPi<float> / 32.0f)));
    EXPECT_LT(torus.chord_sag, 4.0f * 0.35f * (1.0f - std::cos(kPi<float> / 32.0f)) + 1.0f * (1.0f - std::cos(kPi<float> / 64.0f)) * 2.0f);
    EXPECT_EQ(make_plane(2.0f, 4).chord_sag, 0.0f);
    EXPECT_EQ(chord_sag(make_plane(2.0f, 4)), 0.0f);
    EXPECT_EQ(chord_sag(make_cube(2.0f)), 0.0f);
    // Indices out of range and zero normals are passed over, not read.
    Mesh broken = sphere;
    broken.indices.push_back(static_cast<std::uint32_t>(broken.vertices.size()) + 5u);
    broken.indices.push_back(0u);
    broken.indices.push_back(1u);
    for (Vertex& v : broken.vertices) v.normal = glm::vec3(0.0f);
    EXPECT_TRUE(std::isfinite(chord_sag(broken)));
}

// The uv stretch (Vertex::uv_stretch): mesh uv per unit step along the
// tangent and bitangent over the mesh's mean. A uv sphere's u runs 2 pi r
// around the equator and its v pi r pole to pole; u crowds toward the poles.
TEST(MeshUvStretch, FollowsTheLocalUvDensity) {
    const float r = 0.8f;
    const Mesh sphere = make_uv_sphere(r);
    for (const Vertex& v : sphere.vertices) {
        const double lat = std::asin(std::clamp(static_cast<double>(v.position.z) / r, -1.0, 1.0));
        if (std::fabs(lat) > 0.8) continue;  // toward the poles the chords lag the latitude (tan(lat) times its step)
        EXPECT_NEAR(v.uv_stretch.x, sphere.units_per_uv / (2.0 * kPi<double> * r * std::cos(lat)),
                    0.03 * v.uv_stretch.x) << lat;
        EXPECT_NEAR(v.uv_stretch.y, sphere.units_per_uv / (kPi<double> * r), 0.02 * v.uv_stretch.y) << lat;
    }
    for (const Vertex& v : make_plane(2.0f, 4).vertices) EXPECT_EQ(v.uv_stretch, glm::vec2(1.0f));
    for (const Vertex& v : make_cube(2.0f).vertices) EXPECT_EQ(v.uv_stretch, glm::vec2(1.0f));
    const Mesh tube = make_cylinder(r, 2.0f);
    for (const Vertex& v : tube.vertices) {
        EXPECT_NEAR(v.uv_stretch.x, tube.units_per_uv / (2.0 * kPi<double> * r), 0.02 * v.uv_stretch.x);
        EXPECT_NEAR(v.uv_stretch.y, tube.units_per_uv / 2.0, 0.02 * v.uv_stretch.y);
    }
}

// A vertex's position and frame as the mesh's fits read it.
struct VertexFrame {
    glm::dvec3 p, n, t, b;
};
VertexFrame frame_of(const Vertex& v) {
    VertexFrame f;
    f.p = glm::dvec3(v.position);
    f.n = glm::normalize(glm::dvec3(v.normal));
    f.t = glm::dvec3(v.tangent);
    f.t = glm::normalize(f.t - f.n * glm::dot(f.n, f.t));
    f.b = (v.tangent.w < 0.0f ? -1.0 : 1.0) * glm::cross(f.n, f.t);
    return f;
}

// The second-order part of uv at a tangent-plane offset, by central
// differences at 0: u's and v's (x^2, x y, y^2) coefficients.
std::pair<glm::dvec3, glm::dvec3> bend_by_differences(const std::function<glm::dvec2(double, double)>& uv_off) {
    const double h = 1e-3;
    const glm::dvec2 f0 = uv_off(0.0, 0.0);
    const glm::dvec2 fxx = (uv_off(h, 0.0) - 2.0 * f0 + uv_off(-h, 0.0)) / (h * h);
    const glm::dvec2 fyy = (uv_off(0.0, h) - 2.0 * f0 + uv_off(0.0, -h)) / (h * h);
    const glm::dvec2 fxy = (uv_off(h, h) - uv_off(h, -h) - uv_off(-h, h) + uv_off(-h, -h)) / (4.0 * h * h);
    return {glm::dvec3(0.5 * fxx.x, fxy.x, 0.5 * fyy.x), glm::dvec3(0.5 * fxx.y, fxy.y, 0.5 * fyy.y)};
}

// The uv bend (fit_uv_bend, Vertex::uv_bend_u/v): mesh uv's second-order
// part across the tangent plane, against the sphere's own uv written out.
// A point at tangent-plane offset (x, y) from a vertex is the sphere's point
// under it (along the vertex's normal); its u and v are the generator's
// longitude and latitude over 2 pi and pi. Central differences of that
// give the bend; the fit from the vertex's two rings of neighbours (a
// quartic, 15 degrees of arc each way on the 48 x 24 sphere) must match it
// within 4 % of the largest term up to 45 degrees of latitude (measured
// 2026-12-05: the u xy term, the worst, 3.3 % low at 45 degrees, 0.6 % at
// 7.5; the v xx term, the latitude's drift, within 0.6 %). Toward the poles
// 1 / cos(lat) changes faster across the rings than a quartic follows: the
// u xy term is 5.7 % low at 52.5 degrees and 11 % at 60, where the test
// stops. Planes and the cylinder's uv are linear: no bend.
TEST(MeshUvBend, MatchesTheSpheresOwnUvToSecondOrder) {
    const double r = 0.8;
    const Mesh sphere = make_uv_sphere(static_cast<float>(r));
    const auto uv_at = [&](const glm::dvec3& p) {
        const double lon = std::atan2(-p.x, p.y);
        double u = lon / (2.0 * kPi<double>);
        if (u < 0.0) u += 1.0;
        return glm::dvec2(u, std::asin(std::clamp(p.z / glm::length(p), -1.0, 1.0)) / kPi<double> + 0.5);
    };
    long checked = 0;
    for (const Vertex& v : sphere.vertices) {
        const double lat = std::asin(std::clamp(static_cast<double>(v.position.z) / r, -1.0, 1.0));
        if (std::fabs(lat) > 45.0 * kPi<double> / 180.0 + 1e-6) continue;
        if (v.uv.x < 0.1f || v.uv.x > 0.9f) continue;  // away from the seam, where u wraps
        const VertexFrame f = frame_of(v);
        const auto [want_u, want_v] = bend_by_differences([&](double x, double y) {
            const glm::dvec3 q = f.p + x * f.t + y * f.b;
            return uv_at(q - (r - std::sqrt(r * r - x * x - y * y)) * f.n);
        });
        // The largest second-order term at this latitude, with a floor where
        // the bend vanishes at the equator: 1 / (2 pi r^2), the v xx term's
        // at 45 degrees.
        const double scale = std::max({std::fabs(want_u.y), std::fabs(want_v.x), 1.0 / (2.0 * kPi<double> * r * r)});
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(v.uv_bend_u[k], want_u[k], 0.04 * scale) << "u term " << k << " at latitude " << lat;
            EXPECT_NEAR(v.uv_bend_v[k], want_v[k], 0.04 * scale) << "v term " << k << " at latitude " << lat;
        }
        ++checked;
    }
    EXPECT_GT(checked, 400);
    for (const Vertex& v : make_plane(2.0f, 4).vertices) {
        EXPECT_EQ(v.uv_bend_u, glm::vec3(0.0f));
        EXPECT_EQ(v.uv_bend_v, glm::vec3(0.0f));
    }
    for (const Vertex& v : make_cylinder(0.8f, 2.0f).vertices) {
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(v.uv_bend_u[k], 0.0, 1e-3);
            EXPECT_NEAR(v.uv_bend_v[k], 0.0, 1e-3);
        }
    }
}

// The same on the torus (ring radius 1, tube 0.4), whose uv bends both
// ways: u's xy term follows the ring's circumference as the tube turns,
// v's xx term the tube's rows as they curve around the ring. The point
// under a tangent-plane offset is found along the vertex's normal by
// Newton's method on the torus's implicit equation. The fit matches within
// 4 % of the largest term everywhere away from the seams (measured
// 2026-12-05: within 1.5 %, the v xy term's fold-in of 0.003 the largest).
TEST(MeshUvBend, MatchesTheTorussOwnUvToSecondOrder) {
    const double R = 1.0, r = 0.4;
    const Mesh torus = make_torus(static_cast<float>(R), static_cast<float>(r));
    const auto implicit = [&](const glm::dvec3& p) {
        const double a = std::sqrt(p.x * p.x + p.y * p.y) - R;
        return a * a + p.z * p.z - r * r;
    };
    const auto uv_at = [&](const glm::dvec3& p) {
        double u = std::atan2(p.y, p.x) / (2.0 * kPi<double>);
        double v = std::atan2(p.z, std::sqrt(p.x * p.x + p.y * p.y) - R) / (2.0 * kPi<double>);
        return glm::dvec2(u < 0.0 ? u + 1.0 : u, v < 0.0 ? v + 1.0 : v);
    };
    long checked = 0;
    for (const Vertex& v : torus.vertices) {
        if (v.uv.x < 0.1f || v.uv.x > 0.9f || v.uv.y < 0.1f || v.uv.y > 0.9f) continue;  // the seams
        const VertexFrame f = frame_of(v);
        const auto [want_u, want_v] = bend_by_differences([&](double x, double y) {
            const glm::dvec3 q = f.p + x * f.t + y * f.b;
            double s = 0.0;
            for (int i = 0; i < 20; ++i) {
                const double e = 1e-6;
                const double slope = (implicit(q + (s + e) * f.n) - implicit(q + (s - e) * f.n)) / (2.0 * e);
                s -= implicit(q + s * f.n) / slope;
            }
            return uv_at(q + s * f.n);
        });
        double scale = 0.0;
        for (int k = 0; k < 3; ++k) scale = std::max({scale, std::fabs(want_u[k]), std::fabs(want_v[k])});
        if (!(scale > 0.05)) continue;  // the outer and inner equators' flat rows: nothing to compare against
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(v.uv_bend_u[k], want_u[k], 0.04 * scale) << "u term " << k << " at v " << v.uv.y;
            EXPECT_NEAR(v.uv_bend_v[k], want_v[k], 0.04 * scale) << "v term " << k << " at v " << v.uv.y;
        }
        ++checked;
    }
    EXPECT_GT(checked, 500);
}

// A bounded cylinder drawn longer (make_widened_cylinder): v runs past
// [0, 1] by the margin at each end, at the same uv per mesh unit, with the
// same frame, stretch and bend as the tube it extends.
TEST(MeshWidenedCylinder, ExtendsTheTubeAtTheSameUvDensity) {
    const float r = 0.7f, height = 2.0f, margin = 0.1f;
    const Mesh tube = make_cylinder(r, height);
    const Mesh longer = make_widened_cylinder(r, height, margin);
    EXPECT_NEAR(longer.units_per_uv, tube.units_per_uv, 1e-4 * tube.units_per_uv);
    float v_lo = 1.0f, v_hi = 0.0f;
    for (const Vertex& v : longer.vertices) {
        v_lo = std::min(v_lo, v.uv.y);
        v_hi = std::max(v_hi, v.uv.y);
        // z = (v - 0.5) height: the tube's own uv per unit, continued.
        EXPECT_NEAR(v.position.z, (v.uv.y - 0.5f) * height, 1e-5f);
        EXPECT_NEAR(v.uv_stretch.x, tube.vertices[0].uv_stretch.x, 1e-4f);
        EXPECT_NEAR(v.uv_stretch.y, tube.vertices[0].uv_stretch.y, 1e-4f);
        EXPECT_NEAR(v.curvature.x, tube.vertices[0].curvature.x, 1e-3f * std::fabs(tube.vertices[0].curvature.x) + 1e-6f);
        EXPECT_NEAR(v.curvature.z, tube.vertices[0].curvature.z, 1e-4f);
    }
    EXPECT_FLOAT_EQ(v_lo, -margin);
    EXPECT_FLOAT_EQ(v_hi, 1.0f + margin);
}

// A bounded tube's rim caps (make_tube_rim_caps): an annulus in each end's
// plane from the inner to the outer radius, every triangle facing into the
// tube (the renderer draws their back faces, seen from beyond each end),
// every vertex the tube's rim vertex at its angle, but for its radius.
TEST(MeshTubeRimCaps, AnnuliInTheEndPlanesFacingIntoTheTube) {
    const float r = 0.7f, height = 2.0f, inner = 0.6f, outer = 0.75f;
    const Mesh tube = make_cylinder(r, height);
    const Mesh caps = make_tube_rim_caps(tube, r, inner, outer);
    ASSERT_FALSE(caps.indices.empty());
    ASSERT_EQ(caps.indices.size() % 3, 0u);
    float covered = 0.0f;  // the annuli's area, top and bottom
    for (size_t i = 0; i < caps.indices.size(); i += 3) {
        const glm::vec3 a = caps.vertices[caps.indices[i]].position;
        const glm::vec3 b = caps.vertices[caps.indices[i + 1]].position;
        const glm::vec3 c = caps.vertices[caps.indices[i + 2]].position;
        EXPECT_FLOAT_EQ(a.z, b.z);
        EXPECT_FLOAT_EQ(a.z, c.z);
        ASSERT_NEAR(std::fabs(a.z), 0.5f * height, 1e-6f);
        // Counter-clockwise seen from the inside: its normal points along
        // the axis towards the other end.
        const glm::vec3 n = glm::cross(b - a, c - a);
        EXPECT_LT(n.z * a.z, 0.0f) << "triangle " << i / 3 << " faces out of the tube";
        covered += 0.5f * glm::length(n);
    }
    // Two 48-gon annuli: their area, inside the circles' by the chords.
    const float ring = 48.0f * 0.5f * std::sin(2.0f * kPi<float> / 48.0f) * (outer * outer - inner * inner);
    EXPECT_NEAR(covered, 2.0f * ring, 1e-4f * ring);
    for (const Vertex& v : caps.vertices) {
        const float radius = glm::length(glm::vec2(v.position));
        EXPECT_TRUE(std::fabs(radius - inner) < 1e-5f || std::fabs(radius - outer) < 1e-5f) << radius;
        // The wall's rim vertex: its frame, uv and fits.
        const Vertex* rim = nullptr;
        for (const Vertex& t : tube.vertices)
            if (t.uv == v.uv) rim = &t;
        ASSERT_NE(rim, nullptr);
        EXPECT_EQ(rim->normal, v.normal);
        EXPECT_EQ(rim->tangent, v.tangent);
        EXPECT_EQ(rim->curvature, v.curvature);
        EXPECT_EQ(rim->uv_stretch, v.uv_stretch);
        EXPECT_NEAR(glm::length(glm::vec2(rim->position) / r - glm::vec2(v.position) / radius), 0.0f, 1e-5f);
    }
    // Radii that make no annulus, no caps.
    EXPECT_TRUE(make_tube_rim_caps(tube, r, 0.8f, 0.75f).indices.empty());
    EXPECT_TRUE(make_tube_rim_caps(tube, r, -0.1f, 0.75f).indices.empty());
}

// A bounded tile's side walls (make_tile_walls): a strip along each of the
// plane's four edges from z = -below to +above, facing out of the tile,
// every vertex the plane's edge vertex but for its z.
TEST(MeshTileWalls, StripsAlongTheEdgesFacingOut) {
    const float size = 2.0f, below = 0.3f, above = 0.05f;
    const Mesh plane = make_plane(size, 4);
    const Mesh walls = make_tile_walls(plane, below, above);
    ASSERT_EQ(walls.indices.size(), 4u * 4u * 6u);  // 4 edges of 4 quads
    float area = 0.0f;
    for (size_t i = 0; i < walls.indices.size(); i += 3) {
        const glm::vec3 a = walls.vertices[walls.indices[i]].position;
        const glm::vec3 b = walls.vertices[walls.indices[i + 1]].position;
        const glm::vec3 c = walls.vertices[walls.indices[i + 2]].position;
        const glm::vec3 n = glm::cross(b - a, c - a);
        EXPECT_NEAR(n.z, 0.0f, 1e-6f) << "vertical";
        // Out of the tile: along the edge's outward axis.
        const glm::vec3 mid = (a + b + c) / 3.0f;
        EXPECT_GT(glm::dot(glm::vec2(n), glm::vec2(mid)), 0.0f) << "triangle " << i / 3 << " faces into the tile";
        area += 0.5f * glm::length(n);
    }
    EXPECT_NEAR(area, 4.0f * size * (below + above), 1e-4f);
    for (const Vertex& w : walls.vertices) {
        EXPECT_TRUE(std::fabs(w.position.z + below) < 1e-6f || std::fabs(w.position.z - above) < 1e-6f);
        const Vertex* edge = nullptr;
        for (const Vertex& v : plane.vertices)
            if (v.uv == w.uv) edge = &v;
        ASSERT_NE(edge, nullptr);
        EXPECT_TRUE(edge->uv.x == 0.0f || edge->uv.x == 1.0f || edge->uv.y == 0.0f || edge->uv.y == 1.0f);
        EXPECT_EQ(glm::vec2(edge->position), glm::vec2(w.position));
        EXPECT_EQ(edge->normal, w.normal);
        EXPECT_EQ(edge->tangent, w.tangent);
    }
    EXPECT_TRUE(make_tile_walls(plane, -0.1f, 0.05f).indices.empty());
}

}  // namespace
}  // namespace px
