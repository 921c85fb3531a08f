#include "parallaxes/core/counters.h"
#include "parallaxes/scene/mesh.h"
#include "parallaxes/core/text.h"
#include "parallaxes/core/limits.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <numeric>
#include <optional>
#include <vector>
#include <string>

#include "parallaxes/core/numeric.h"

namespace px {

namespace {


struct MeshKindName {
    MeshKind kind;
    const char* name;
};

constexpr std::array<MeshKindName, 5> kMeshKinds = {{
    {MeshKind::plane, "plane"},
    {MeshKind::cube, "cube"},
    {MeshKind::sphere, "sphere"},
    {MeshKind::torus, "torus"},
    {MeshKind::cylinder, "cylinder"},
}};

bool is_finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
bool is_finite(const glm::vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }

// Appends the two triangles of quad a-b-c-d (counter-clockwise seen from the
// side it faces).
void push_quad(Mesh& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
}

// The quads of a (columns + 1) x (rows + 1) vertex grid stored row by row.
void push_grid_quads(Mesh& mesh, std::uint32_t columns, std::uint32_t rows) {
    const std::uint32_t row = columns + 1;
    for (std::uint32_t k = 0; k < rows; ++k)
        for (std::uint32_t j = 0; j < columns; ++j) {
            const std::uint32_t a = k * row + j;
            push_quad(mesh, a, a + 1, a + row + 1, a + row);
        }
}

// Any unit vector orthogonal to unit `n`: project the axis least aligned with it.
glm::vec3 any_orthogonal(const glm::vec3& n) {
    const glm::vec3 a = std::abs(n.x) <= std::abs(n.y) && std::abs(n.x) <= std::abs(n.z)
                            ? glm::vec3(1.0f, 0.0f, 0.0f)
                            : (std::abs(n.y) <= std::abs(n.z) ? glm::vec3(0.0f, 1.0f, 0.0f)
                                                              : glm::vec3(0.0f, 0.0f, 1.0f));
    return glm::normalize(a - n * glm::dot(n, a));
}

// Angle of the triangle's corner between edges `a` and `b` (both non-zero).
float corner_angle(const glm::vec3& a, const glm::vec3& b) {
    const float c = glm::dot(a, b) / std::sqrt(glm::dot(a, a) * glm::dot(b, b));
    return std::acos(std::clamp(c, -1.0f, 1.0f));
}

// What one triangle tells its three corners.
struct TriangleFrame {
    bool has_area = false;        // non-degenerate in space: face normal and angles valid
    bool usable = false;          // also non-degenerate in uv: t and b valid
    glm::vec3 face_normal{0.0f};  // unit
    glm::vec3 t{0.0f};            // unit dP/du
    glm::vec3 b{0.0f};            // unit dP/dv
    float t_len = 0.0f;           // |dP/du|
    float b_len = 0.0f;           // |dP/dv|
    std::array<float, 3> angle{};
    float world_area = 0.0f;
    float uv_area = 0.0f;
};

TriangleFrame triangle_frame(const Vertex& v0, const Vertex& v1, const Vertex& v2) {
    TriangleFrame f;
    const glm::vec3 e1 = v1.position - v0.position;
    const glm::vec3 e2 = v2.position - v0.position;
    const glm::vec3 cr = glm::cross(e1, e2);
    const float cr_len = glm::length(cr);
    // Relative thresholds: a sliver is degenerate whatever the mesh's scale.
    if (!(cr_len > 1e-7f * (glm::dot(e1, e1) + glm::dot(e2, e2)))) return f;
    f.has_area = true;
    f.face_normal = cr / cr_len;
    f.world_area = 0.5f * cr_len;
    const glm::vec3 e3 = v2.position - v1.position;
    f.angle = {corner_angle(e1, e2), corner_angle(-e1, e3), corner_angle(-e2, -e3)};

    const glm::vec2 d1 = v1.uv - v0.uv;
    const glm::vec2 d2 = v2.uv - v0.uv;
    const float det = d1.x * d2.y - d2.x * d1.y;  // twice the signed uv area
    if (!(std::abs(det) > 1e-7f * (glm::dot(d1, d1) + glm::dot(d2, d2)))) return f;
    // Solve e1 = d1.x T + d1.y B, e2 = d2.x T + d2.y B for T = dP/du, B = dP/dv.
    // Both are non-zero: the uv -> position map is affine and injective here.
    const glm::vec3 t = (e1 * d2.y - e2 * d1.y) / det;
    const glm::vec3 b = (e2 * d1.x - e1 * d2.x) / det;
    const float t_len = glm::length(t);
    const float b_len = glm::length(b);
    if (!(t_len > 0.0f && b_len > 0.0f && std::isfinite(t_len) && std::isfinite(b_len))) return f;
    f.usable = true;
    f.t = t / t_len;
    f.b = b / b_len;
    f.t_len = t_len;
    f.b_len = b_len;
    f.uv_area = 0.5f * std::abs(det);
    return f;
}

Status validate_for_tangents(const Mesh& mesh) {
    const std::size_t n_idx = mesh.indices.size();
    if (n_idx % 3 != 0)
        return make_error("mesh: index count " + std::to_string(n_idx) +
                          " is not a multiple of 3 (triangle list expected)");
    const std::size_t n_vert = mesh.vertices.size();
    for (std::size_t i = 0; i < n_idx; ++i) {
        if (mesh.indices[i] >= n_vert)
            return make_error("mesh: index " + std::to_string(i) + " (triangle " +
                              std::to_string(i / 3) + ") is " + std::to_string(mesh.indices[i]) +
                              ", out of range for " + std::to_string(n_vert) + " vertices");
    }
    for (std::size_t i = 0; i < n_vert; ++i) {
        const Vertex& v = mesh.vertices[i];
        const char* what = !is_finite(v.position) ? "position"
                           : !is_finite(v.normal) ? "normal"
                           : !is_finite(v.uv)     ? "uv"
                                                  : nullptr;
        if (what)
            return make_error("mesh: vertex " + std::to_string(i) + " has a non-finite " + what);
    }
    return {};
}

}  // namespace

const char* mesh_kind_name(MeshKind kind) {
    for (const MeshKindName& k : kMeshKinds)
        if (k.kind == kind) return k.name;
    return "unknown";
}

bool mesh_kind_is_curved(MeshKind kind) {
    return kind == MeshKind::sphere || kind == MeshKind::torus || kind == MeshKind::cylinder;
}

Result<MeshKind> parse_mesh_kind(const std::string& name) {
    std::string known;
    for (const MeshKindName& k : kMeshKinds) {
        if (name == k.name) return k.kind;
        known += known.empty() ? "" : ", ";
        known += k.name;
    }
    return make_error("unknown mesh kind '" + echo(name) + "' (known: " + known + ")");
}

namespace {

// Each triangle's frame, in index order.
std::vector<TriangleFrame> triangle_frames(const Mesh& mesh) {
    const std::size_t tri_count = mesh.indices.size() / 3;
    std::vector<TriangleFrame> tris(tri_count);
    for (std::size_t f = 0; f < tri_count; ++f) {
        const std::uint32_t* idx = &mesh.indices[3 * f];
        tris[f] =
            triangle_frame(mesh.vertices[idx[0]], mesh.vertices[idx[1]], mesh.vertices[idx[2]]);
    }
    return tris;
}

// Effective unit normal per vertex; a zero normal falls back to the
// angle-weighted face normal so the frame is still defined.
std::vector<glm::vec3> effective_normals(const Mesh& mesh, const std::vector<TriangleFrame>& tris) {
    const std::size_t tri_count = tris.size();
    std::vector<glm::vec3> face_sum(mesh.vertices.size(), glm::vec3(0.0f));
    for (std::size_t f = 0; f < tri_count; ++f)
        if (tris[f].has_area)
            for (int c = 0; c < 3; ++c)
                face_sum[mesh.indices[3 * f + c]] += tris[f].face_normal * tris[f].angle[c];
    std::vector<glm::vec3> normal(mesh.vertices.size());
    for (std::size_t v = 0; v < normal.size(); ++v) {
        const glm::vec3 n = mesh.vertices[v].normal;
        const glm::vec3 fs = face_sum[v];
        normal[v] = glm::length(n) > 1e-12f    ? glm::normalize(n)
                    : glm::length(fs) > 1e-12f ? glm::normalize(fs)
                                               : glm::vec3(0.0f, 0.0f, 1.0f);
    }
    return normal;
}

// The handedness a triangle asks of a corner: whether (dP/du, dP/dv, n) is
// right-handed. It equals the sign of the uv area for counter-clockwise
// triangles, but does not depend on winding.
int corner_sign(const std::vector<TriangleFrame>& tris, const std::vector<glm::vec3>& normal, std::size_t f,
                std::uint32_t v) {
    return glm::dot(normal[v], glm::cross(tris[f].t, tris[f].b)) >= 0.0f ? 1 : -1;
}

// Mirrored uvs: where a vertex's triangles disagree on handedness, the
// minority side moves to a copy of the vertex (on a tie, the w = -1 side).
void split_mirrored_vertices(Mesh& mesh, const std::vector<TriangleFrame>& tris, std::vector<glm::vec3>& normal) {
    const std::size_t tri_count = tris.size();
    const std::size_t original_count = mesh.vertices.size();
    std::vector<int> votes(original_count, 0);   // sum of corner signs
    std::vector<int> voters(original_count, 0);  // number of signed corners
    for (std::size_t f = 0; f < tri_count; ++f) {
        if (!tris[f].usable) continue;
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = mesh.indices[3 * f + c];
            votes[v] += corner_sign(tris, normal, f, v);
            ++voters[v];
        }
    }
    std::vector<std::uint32_t> copy_of(original_count, 0);  // 0: not split (index 0 never a copy)
    for (std::size_t v = 0; v < original_count; ++v) {
        if (std::abs(votes[v]) == voters[v]) continue;  // unanimous (or no votes)
        copy_of[v] = static_cast<std::uint32_t>(mesh.vertices.size());
        mesh.vertices.push_back(mesh.vertices[v]);
        normal.push_back(normal[v]);
    }
    for (std::size_t f = 0; f < tri_count; ++f) {
        if (!tris[f].usable) continue;
        for (int c = 0; c < 3; ++c) {
            std::uint32_t& v = mesh.indices[3 * f + c];
            if (v >= original_count || copy_of[v] == 0) continue;
            const int majority = votes[v] >= 0 ? 1 : -1;
            if (corner_sign(tris, normal, f, v) != majority) v = copy_of[v];
        }
    }
}

// Per vertex, over its usable corners: the angle-weighted unit dP/du and
// dP/dv (the weight makes the result independent of how the surface
// around the vertex is split into triangles), the handedness, and the
// angle-weighted |dP/du|, |dP/dv| with the weight itself.
struct FrameSums {
    std::vector<glm::vec3> t_sum, b_sum;
    std::vector<int> sign;
    std::vector<glm::dvec3> lengths;
};

FrameSums frame_sums(const Mesh& mesh, const std::vector<TriangleFrame>& tris, const std::vector<glm::vec3>& normal) {
    const std::size_t tri_count = tris.size();
    const std::size_t vert_count = mesh.vertices.size();
    FrameSums sums;
    sums.t_sum.assign(vert_count, glm::vec3(0.0f));
    sums.b_sum.assign(vert_count, glm::vec3(0.0f));
    sums.sign.assign(vert_count, 0);
    sums.lengths.assign(vert_count, glm::dvec3(0.0));
    for (std::size_t f = 0; f < tri_count; ++f) {
        if (!tris[f].usable) continue;
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = mesh.indices[3 * f + c];
            sums.t_sum[v] += tris[f].t * tris[f].angle[c];
            sums.b_sum[v] += tris[f].b * tris[f].angle[c];
            sums.lengths[v] += glm::dvec3(tris[f].t_len, tris[f].b_len, 1.0) * static_cast<double>(tris[f].angle[c]);
            sums.sign[v] = corner_sign(tris, normal, f, v);  // unanimous after the split
        }
    }
    return sums;
}

// Each vertex's tangent and handedness from its sums.
void set_tangents(Mesh& mesh, const std::vector<glm::vec3>& normal, const FrameSums& sums) {
    const std::vector<glm::vec3>& t_sum = sums.t_sum;
    const std::vector<glm::vec3>& b_sum = sums.b_sum;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        const glm::vec3 n = normal[v];
        // Gram-Schmidt; fall back to t = w * cross(b, n) when the accumulated
        // tangent is (nearly) along the normal, then to any orthogonal vector.
        const glm::vec3 t_proj = t_sum[v] - n * glm::dot(n, t_sum[v]);
        const glm::vec3 b_proj = b_sum[v] - n * glm::dot(n, b_sum[v]);
        const float group_w = sums.sign[v] < 0 ? -1.0f : 1.0f;
        glm::vec3 t;
        if (glm::length(t_proj) > 1e-4f * glm::length(t_sum[v]) && glm::length(t_proj) > 1e-20f)
            t = glm::normalize(t_proj);
        else if (glm::length(b_proj) > 1e-4f * glm::length(b_sum[v]) &&
                 glm::length(b_proj) > 1e-20f)
            t = glm::normalize(group_w * glm::cross(b_proj, n));
        else
            t = any_orthogonal(n);
        const float handed = glm::dot(glm::cross(n, t), b_sum[v]);
        const float w = handed > 0.0f ? 1.0f : handed < 0.0f ? -1.0f : group_w;
        mesh.vertices[v].tangent = glm::vec4(t, w);
    }
}

// World length per uv unit: each triangle's linear scale
// sqrt(world area / uv area), weighted by sqrt(uv area), which reduces to
// sum sqrt(world area) / sum sqrt(uv area). Lengths, not areas, so that
// large triangles do not dominate quadratically. Then the uv stretch
// (Vertex::uv_stretch): the mean over the local lengths, snapped to 1
// within float rounding (a plane's is 1 exactly).
void set_uv_scale(Mesh& mesh, const std::vector<TriangleFrame>& tris, const std::vector<glm::dvec3>& lengths) {
    double world = 0.0, uv = 0.0;
    for (const TriangleFrame& f : tris) {
        if (!f.usable) continue;
        world += std::sqrt(static_cast<double>(f.world_area));
        uv += std::sqrt(static_cast<double>(f.uv_area));
    }
    mesh.units_per_uv = uv > 0.0 ? static_cast<float>(world / uv) : 1.0f;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        const glm::dvec3 l = lengths[v];
        if (!(l.z > 0.0) || !(l.x > 0.0) || !(l.y > 0.0)) continue;
        auto stretch = [&](double len) {
            const double s = static_cast<double>(mesh.units_per_uv) * l.z / len;
            if (!std::isfinite(s)) return 1.0f;
            if (std::fabs(s - 1.0) < 1e-5) return 1.0f;
            return static_cast<float>(std::clamp(s, 1.0 / 64.0, 64.0));
        };
        mesh.vertices[v].uv_stretch = glm::vec2(stretch(l.x), stretch(l.y));
    }
}

}  // namespace

Status generate_tangents(Mesh& mesh) {
    if (Status s = validate_for_tangents(mesh); !s) return s;
    const std::vector<TriangleFrame> tris = triangle_frames(mesh);
    std::vector<glm::vec3> normal = effective_normals(mesh, tris);
    split_mirrored_vertices(mesh, tris, normal);
    const FrameSums sums = frame_sums(mesh, tris, normal);
    set_tangents(mesh, normal, sums);
    set_uv_scale(mesh, tris, sums.lengths);
    return {};
}

Mesh make_plane(float size, int segments, const std::optional<glm::vec3>& tangent,
                const std::optional<glm::vec3>& normal) {
    const int n = std::max(segments, 1);
    const auto row = static_cast<std::uint32_t>(n + 1);
    Mesh mesh;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            const glm::vec2 uv(static_cast<float>(i) / static_cast<float>(n),
                               static_cast<float>(j) / static_cast<float>(n));
            Vertex v;
            v.position = glm::vec3((uv - 0.5f) * size, 0.0f);
            v.normal = glm::vec3(0.0f, 0.0f, 1.0f);
            v.uv = uv;
            mesh.vertices.push_back(v);
        }
    }
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(n); ++j)
        for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) {
            const std::uint32_t a = j * row + i;
            push_quad(mesh, a, a + 1, a + row + 1, a + row);
        }
    (void)generate_tangents(mesh);  // cannot fail: indices are in range by construction
    // The authored frame as given: generate_tangents would repair it, and the
    // point of authoring one is to reach the shader's own fallbacks.
    for (Vertex& v : mesh.vertices) {
        if (tangent) v.tangent = glm::vec4(*tangent, 1.0f);
        if (normal) v.normal = *normal;
    }
    return mesh;
}

Mesh make_widened_plane(float size, int segments, float margin, const std::optional<glm::vec3>& tangent,
                        const std::optional<glm::vec3>& normal) {
    const float grow = 1.0f + 2.0f * margin;
    Mesh mesh = make_plane(size * grow, segments, tangent, normal);
    for (Vertex& v : mesh.vertices) v.uv = v.uv * grow - margin;
    mesh.units_per_uv = size;
    return mesh;
}

Mesh make_cube(float size) {
    // Per face: normal, +u and +v directions with cross(u, v) = normal, so
    // every face is counter-clockwise from outside with w = +1. Side faces
    // have +v up (+z, the scene's up axis).
    struct Face {
        glm::vec3 n, u, v;
    };
    const std::array<Face, 6> faces = {{
        {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
        {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}},
        {{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}},
        {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},
        {{0, 0, -1}, {1, 0, 0}, {0, -1, 0}},
    }};
    const float h = 0.5f * size;
    Mesh mesh;
    for (const Face& face : faces) {
        const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
        for (const glm::vec2 uv :
             {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)}) {
            Vertex v;
            v.position =
                h * (face.n + (2.0f * uv.x - 1.0f) * face.u + (2.0f * uv.y - 1.0f) * face.v);
            v.normal = face.n;
            v.uv = uv;
            mesh.vertices.push_back(v);
        }
        push_quad(mesh, base, base + 1, base + 2, base + 3);
    }
    (void)generate_tangents(mesh);
    return mesh;
}

namespace {

// A small linear least-squares problem by its normal equations, solved by
// Gaussian elimination with partial pivoting after scaling each unknown to a
// unit diagonal; nullopt where the columns are (nearly) dependent.
class LeastSquares {
public:
    explicit LeastSquares(std::size_t unknowns) : k_(unknowns), m_(unknowns * unknowns, 0.0), r_(unknowns, 0.0) {}
    void add(std::initializer_list<double> row, double value) {
        const double* a = row.begin();
        for (std::size_t i = 0; i < k_; ++i) {
            for (std::size_t j = 0; j < k_; ++j) m_[i * k_ + j] += a[i] * a[j];
            r_[i] += a[i] * value;
        }
    }
    std::optional<std::vector<double>> solve() const {
        std::vector<double> scale(k_), m = m_, r = r_;
        for (std::size_t i = 0; i < k_; ++i) {
            if (!(m_[i * k_ + i] > 0.0) || !std::isfinite(m_[i * k_ + i])) return std::nullopt;
            scale[i] = 1.0 / std::sqrt(m_[i * k_ + i]);
        }
        for (std::size_t i = 0; i < k_; ++i) {
            r[i] *= scale[i];
            for (std::size_t j = 0; j < k_; ++j) m[i * k_ + j] *= scale[i] * scale[j];
        }
        for (std::size_t col = 0; col < k_; ++col) {
            std::size_t pivot = col;
            for (std::size_t i = col + 1; i < k_; ++i)
                if (std::fabs(m[i * k_ + col]) > std::fabs(m[pivot * k_ + col])) pivot = i;
            if (!(std::fabs(m[pivot * k_ + col]) > 1e-9)) return std::nullopt;
            if (pivot != col) {
                for (std::size_t j = 0; j < k_; ++j) std::swap(m[col * k_ + j], m[pivot * k_ + j]);
                std::swap(r[col], r[pivot]);
            }
            for (std::size_t i = col + 1; i < k_; ++i) {
                const double f = m[i * k_ + col] / m[col * k_ + col];
                for (std::size_t j = col; j < k_; ++j) m[i * k_ + j] -= f * m[col * k_ + j];
                r[i] -= f * r[col];
            }
        }
        std::vector<double> x(k_);
        for (std::size_t i = k_; i-- > 0;) {
            double sum = r[i];
            for (std::size_t j = i + 1; j < k_; ++j) sum -= m[i * k_ + j] * x[j];
            x[i] = sum / m[i * k_ + i];
        }
        for (std::size_t i = 0; i < k_; ++i) {
            x[i] *= scale[i];
            if (!std::isfinite(x[i])) return std::nullopt;
        }
        return x;
    }

private:
    std::size_t k_;
    std::vector<double> m_, r_;
};

}  // namespace

float chord_sag(const Mesh& mesh) {
    const std::size_t n = mesh.vertices.size();
    double deepest = 0.0;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t v[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        if (v[0] >= n || v[1] >= n || v[2] >= n) continue;
        glm::dvec3 p[3], nrm[3];
        for (int a = 0; a < 3; ++a) {
            p[a] = glm::dvec3(mesh.vertices[v[a]].position);
            const glm::dvec3 raw(mesh.vertices[v[a]].normal);
            const double length = glm::length(raw);
            nrm[a] = length > 1e-12 && std::isfinite(length) ? raw / length : glm::dvec3(0.0);
        }
        // sag(b) = 1/2 sum_i b_i (p_i - x(b)) . n_i at x(b) = sum_j b_j p_j.
        const auto sag = [&](const glm::dvec3& b) {
            const glm::dvec3 x = b.x * p[0] + b.y * p[1] + b.z * p[2];
            return 0.5 * (b.x * glm::dot(p[0] - x, nrm[0]) + b.y * glm::dot(p[1] - x, nrm[1]) +
                          b.z * glm::dot(p[2] - x, nrm[2]));
        };
        for (const glm::dvec3& b : {glm::dvec3(0.5, 0.5, 0.0), glm::dvec3(0.0, 0.5, 0.5), glm::dvec3(0.5, 0.0, 0.5),
                                    glm::dvec3(1.0 / 3.0)}) {
            const double s = sag(b);
            if (std::isfinite(s)) deepest = std::max(deepest, s);
        }
    }
    return static_cast<float>(deepest);
}

namespace {

// A vertex's frame as the fits read it: its unit normal, its tangent made
// orthogonal to that, and the bitangent by its handedness (the frame the
// shaders rebuild); none where degenerate or not finite.
struct FitFrame {
    glm::dvec3 normal, tangent, bitangent;
};
std::optional<FitFrame> fit_frame(const Vertex& v) {
    const glm::dvec3 normal = glm::normalize(glm::dvec3(v.normal));
    glm::dvec3 tangent(v.tangent);
    tangent = tangent - normal * glm::dot(normal, tangent);
    const double tl = glm::length(tangent);
    if (!(tl > 1e-12) || !std::isfinite(tl) || !std::isfinite(normal.x + normal.y + normal.z)) return std::nullopt;
    tangent /= tl;
    return FitFrame{normal, tangent, (v.tangent.w < 0.0f ? -1.0 : 1.0) * glm::cross(normal, tangent)};
}

// The uv bend's basis, ordered by degree: x, y, the quadric's three, the
// cubic's four, the quartic's five.
constexpr std::size_t kBendTerms = 14;

// One set of normal equations for the quartic in (x, y), u and v its
// two right-hand sides; the cubic's and the quadric's are its leading
// 9 x 9 and 5 x 5 blocks (the basis is ordered by degree).
struct BendEquations {
    std::vector<double> equations, rhs_u, rhs_v;
};

// Vertex i's own two rings of neighbours, sorted and without repeats
// (neighbours: each vertex's ring, sorted and without repeats).
void two_rings(const std::vector<std::vector<std::uint32_t>>& neighbours, std::size_t i,
               std::vector<std::uint32_t>& rings) {
    rings.clear();
    for (std::uint32_t j : neighbours[i]) {
        rings.push_back(j);
        rings.insert(rings.end(), neighbours[j].begin(), neighbours[j].end());
    }
    std::sort(rings.begin(), rings.end());
    rings.erase(std::unique(rings.begin(), rings.end()), rings.end());
}

// The equations over the rings, in vertex i's tangent-plane offsets.
BendEquations bend_equations(const Mesh& mesh, std::size_t i, const std::vector<std::uint32_t>& rings,
                             const FitFrame& frame) {
    constexpr std::size_t kTerms = kBendTerms;
    const Vertex& v = mesh.vertices[i];
    const glm::dvec3 p(v.position);
    const glm::dvec3 &tangent = frame.tangent, &bitangent = frame.bitangent;
    BendEquations eq{std::vector<double>(kTerms * kTerms, 0.0), std::vector<double>(kTerms, 0.0),
                     std::vector<double>(kTerms, 0.0)};
    std::vector<double>& equations = eq.equations, &rhs_u = eq.rhs_u, &rhs_v = eq.rhs_v;
    for (std::uint32_t j : rings) {
        if (j == i) continue;
        const glm::dvec3 e = glm::dvec3(mesh.vertices[j].position) - p;
        const double x = glm::dot(e, tangent), y = glm::dot(e, bitangent);
        if (!(x * x + y * y > 0.0)) continue;
        const double du = static_cast<double>(mesh.vertices[j].uv.x) - v.uv.x;
        const double dv = static_cast<double>(mesh.vertices[j].uv.y) - v.uv.y;
        const double x2 = x * x, y2 = y * y;
        const double row[kTerms] = {x,      y,          x2,      x * y,       y2,     x2 * x, x2 * y,
                                    x * y2, y2 * y,     x2 * x2, x2 * x * y,  x2 * y2, x * y2 * y, y2 * y2};
        for (std::size_t a = 0; a < kTerms; ++a) {
            for (std::size_t c = a; c < kTerms; ++c) equations[a * kTerms + c] += row[a] * row[c];
            rhs_u[a] += row[a] * du;
            rhs_v[a] += row[a] * dv;
        }
    }
    for (std::size_t a = 0; a < kTerms; ++a)
        for (std::size_t c = 0; c < a; ++c) equations[a * kTerms + c] = equations[c * kTerms + a];
    return eq;
}

// The second-order parts of u and v from the leading k terms of the
// equations; u and v share them: one elimination for both. None where
// those terms do not determine them.
std::optional<std::pair<glm::dvec3, glm::dvec3>> solve_bend(const BendEquations& eq, std::size_t k) {
    constexpr std::size_t kTerms = kBendTerms;
    const std::vector<double>& equations = eq.equations, &rhs_u = eq.rhs_u, &rhs_v = eq.rhs_v;
    double m[kTerms * kTerms], r[2][kTerms], scale[kTerms];
    for (std::size_t a = 0; a < k; ++a) {
        const double d = equations[a * kTerms + a];
        if (!(d > 0.0) || !std::isfinite(d)) return std::nullopt;
        scale[a] = 1.0 / std::sqrt(d);
    }
    for (std::size_t a = 0; a < k; ++a) {
        for (std::size_t c = 0; c < k; ++c) m[a * k + c] = equations[a * kTerms + c] * scale[a] * scale[c];
        r[0][a] = rhs_u[a] * scale[a];
        r[1][a] = rhs_v[a] * scale[a];
    }
    for (std::size_t col = 0; col < k; ++col) {
        std::size_t pivot = col;
        for (std::size_t a = col + 1; a < k; ++a)
            if (std::fabs(m[a * k + col]) > std::fabs(m[pivot * k + col])) pivot = a;
        if (!(std::fabs(m[pivot * k + col]) > 1e-9)) return std::nullopt;
        if (pivot != col) {
            for (std::size_t c = 0; c < k; ++c) std::swap(m[col * k + c], m[pivot * k + c]);
            std::swap(r[0][col], r[0][pivot]);
            std::swap(r[1][col], r[1][pivot]);
        }
        for (std::size_t a = col + 1; a < k; ++a) {
            const double f = m[a * k + col] / m[col * k + col];
            for (std::size_t c = col; c < k; ++c) m[a * k + c] -= f * m[col * k + c];
            r[0][a] -= f * r[0][col];
            r[1][a] -= f * r[1][col];
        }
    }
    double x[2][kTerms];
    for (std::size_t a = k; a-- > 0;) {
        for (int w = 0; w < 2; ++w) {
            double sum = r[w][a];
            for (std::size_t c = a + 1; c < k; ++c) sum -= m[a * k + c] * x[w][c];
            x[w][a] = sum / m[a * k + a];
        }
    }
    const glm::dvec3 qu(x[0][2] * scale[2], x[0][3] * scale[3], x[0][4] * scale[4]);
    const glm::dvec3 qv(x[1][2] * scale[2], x[1][3] * scale[3], x[1][4] * scale[4]);
    if (!std::isfinite(qu.x + qu.y + qu.z + qv.x + qv.y + qv.z)) return std::nullopt;
    return std::make_pair(qu, qv);
}

// Vertex::uv_bend_u/v: over each vertex's own two rings of neighbours (by
// index, so that a seam's copies keep their own side's uv), mesh u and v
// fitted as cubics in the tangent-plane offset (x, y), their second-order
// parts kept (the cubic terms take up how the bend changes across the
// rings, as in fit_curvature); the quadratic alone where the rings do not
// determine the cubic, none where they do not determine that.
void fit_uv_bend(Mesh& mesh, std::vector<std::vector<std::uint32_t>>& neighbours) {
    const std::size_t n = mesh.vertices.size();
    for (std::vector<std::uint32_t>& ring : neighbours) {
        std::sort(ring.begin(), ring.end());
        ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    }
    std::vector<std::uint32_t> rings;
    for (std::size_t i = 0; i < n; ++i) {
        two_rings(neighbours, i, rings);
        Vertex& v = mesh.vertices[i];
        const std::optional<FitFrame> frame = fit_frame(v);
        if (!frame) continue;
        const BendEquations eq = bend_equations(mesh, i, rings, *frame);
        std::optional<std::pair<glm::dvec3, glm::dvec3>> fit = solve_bend(eq, kBendTerms);
        if (!fit) fit = solve_bend(eq, 9);
        if (!fit) fit = solve_bend(eq, 5);
        const std::optional<glm::dvec3> bu = fit ? std::optional<glm::dvec3>(fit->first) : std::nullopt;
        const std::optional<glm::dvec3> bv = fit ? std::optional<glm::dvec3>(fit->second) : std::nullopt;
        if (bu && bv) {
            v.uv_bend_u = glm::vec3(*bu);
            v.uv_bend_v = glm::vec3(*bv);
        }
    }
}

// Each vertex's neighbours over the triangles, with repeats (a triangle
// past the vertices is skipped).
std::vector<std::vector<std::uint32_t>> mesh_neighbours(const Mesh& mesh) {
    const std::size_t n = mesh.vertices.size();
    std::vector<std::vector<std::uint32_t>> neighbours(n);
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t v[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        if (v[0] >= n || v[1] >= n || v[2] >= n) continue;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                if (a != b) neighbours[v[a]].push_back(v[b]);
    }
    return neighbours;
}

// Vertex::curvature of one vertex from the neighbours of its position
// (group); left as it is where they do not determine it.
void fit_vertex_curvature(Mesh& mesh, Vertex& v, const std::vector<std::uint32_t>& group) {
    const glm::dvec3 p(v.position);
    const std::optional<FitFrame> frame = fit_frame(v);
    if (!frame) return;
    const glm::dvec3 &normal = frame->normal, &tangent = frame->tangent, &bitangent = frame->bitangent;
    // Goldfeather and Interrante's adjacent-normal cubic fit: the
    // surface near the vertex as z = A x^2 + B x y + C y^2 + D x^3 +
    // E x^2 y + F x y^2 + G y^3 below its tangent plane, through each
    // neighbour's drop and normal (the normal (zx, zy, 1) gives the
    // gradient). The cubic terms take up how the bend changes across
    // the neighbourhood, which a one-sided ring (a grid's single
    // diagonal) would otherwise fold into B (0.13 on the torus's tube).
    LeastSquares cubic(7), quadric(3);
    double rho4 = 0.0, rho2_drop = 0.0;
    for (std::uint32_t j : group) {
        const glm::dvec3 e = glm::dvec3(mesh.vertices[j].position) - p;
        const double x = glm::dot(e, tangent), y = glm::dot(e, bitangent);
        if (!(x * x + y * y > 0.0)) continue;  // at this vertex's position
        const double drop = -glm::dot(e, normal);
        const glm::dvec3 nj = glm::dvec3(mesh.vertices[j].normal);
        const double up = glm::dot(nj, normal);
        const double rho2 = x * x + y * y;
        rho4 += rho2 * rho2;
        rho2_drop += rho2 * drop;
        cubic.add({x * x, x * y, y * y, x * x * x, x * x * y, x * y * y, y * y * y}, drop);
        quadric.add({x * x, x * y, y * y}, drop);
        if (!(up > 1e-3) || !std::isfinite(up)) continue;  // a normal turned past the tangent plane
        const double zx = glm::dot(nj, tangent) / up, zy = glm::dot(nj, bitangent) / up;
        cubic.add({2.0 * x, y, 0.0, 3.0 * x * x, 2.0 * x * y, y * y, 0.0}, zx);
        cubic.add({0.0, x, 2.0 * y, 0.0, x * x, 2.0 * x * y, 3.0 * y * y}, zy);
        quadric.add({2.0 * x, y, 0.0}, zx);
        quadric.add({0.0, x, 2.0 * y}, zy);
    }
    if (!(rho4 > 0.0)) return;
    glm::dvec3 c;
    if (std::optional<std::vector<double>> fit = cubic.solve()) {
        c = glm::dvec3((*fit)[0], (*fit)[1], (*fit)[2]);
    } else if (std::optional<std::vector<double>> q = quadric.solve()) {
        c = glm::dvec3((*q)[0], (*q)[1], (*q)[2]);
    } else {  // too few directions: the same bend each way
        const double k0 = rho2_drop / rho4;
        c = glm::dvec3(k0, 0.0, k0);
    }
    if (std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) v.curvature = glm::vec3(c);
}

}  // namespace

void fit_curvature(Mesh& mesh) {
    mesh.chord_sag = chord_sag(mesh);
    const std::size_t n = mesh.vertices.size();
    std::vector<std::vector<std::uint32_t>> neighbours = mesh_neighbours(mesh);
    // Vertices at one position (seams, poles) share their neighbours. One
    // position: equal after rounding to a millionth of the mesh's extent
    // (a seam's two copies differ by sin(2 pi) in float).
    float extent = 0.0f;
    for (const Vertex& v : mesh.vertices)
        extent = std::max({extent, std::fabs(v.position.x), std::fabs(v.position.y), std::fabs(v.position.z)});
    const double cell = extent > 0.0f && std::isfinite(extent) ? 1e-6 * extent : 1.0;
    std::vector<std::array<double, 3>> key(n);
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) key[i][static_cast<std::size_t>(a)] = std::round(mesh.vertices[i].position[a] / cell);
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
    std::vector<std::uint32_t> group;
    for (std::size_t start = 0; start < n;) {
        std::size_t end = start + 1;
        while (end < n && key[order[end]] == key[order[start]]) ++end;
        group.clear();
        for (std::size_t k = start; k < end; ++k)
            group.insert(group.end(), neighbours[order[k]].begin(), neighbours[order[k]].end());
        std::sort(group.begin(), group.end());
        group.erase(std::unique(group.begin(), group.end()), group.end());
        for (std::size_t k = start; k < end; ++k) fit_vertex_curvature(mesh, mesh.vertices[order[k]], group);
        start = end;
    }
    fit_uv_bend(mesh, neighbours);
}

namespace {

Mesh uv_sphere_unfitted(float radius, int slices, int stacks) {
    // Poles on the z axis (the scene's up); u = 0 / 1 seam at +y, so u = 0.5
    // faces a camera on -y and +u runs towards +x there.
    const int ns = std::max(slices, 3);
    const int nt = std::max(stacks, 2);
    const auto fs = static_cast<float>(ns);
    const auto ft = static_cast<float>(nt);
    Mesh mesh;
    auto push = [&](const glm::vec3& n, const glm::vec2& uv) {
        Vertex v;
        v.position = radius * n;
        v.normal = n;
        v.uv = uv;
        mesh.vertices.push_back(v);
    };
    // Each pole is a row of `ns` vertices, one per pole triangle, at the
    // triangle's middle u: no triangle collapses in uv, so every pole vertex
    // gets a well-defined tangent (along its slice's latitude direction).
    for (int j = 0; j < ns; ++j)
        push({0.0f, 0.0f, -1.0f}, {(static_cast<float>(j) + 0.5f) / fs, 0.0f});
    for (int k = 1; k < nt; ++k) {
        const float v = static_cast<float>(k) / ft;
        const float lat = kPi<float> * (v - 0.5f);
        for (int j = 0; j <= ns; ++j) {  // j = ns duplicates j = 0 with u = 1
            const float u = static_cast<float>(j) / fs;
            const float lon = 2.0f * kPi<float> * u;
            push({-std::sin(lon) * std::cos(lat), std::cos(lon) * std::cos(lat), std::sin(lat)},
                 {u, v});
        }
    }
    for (int j = 0; j < ns; ++j)
        push({0.0f, 0.0f, 1.0f}, {(static_cast<float>(j) + 0.5f) / fs, 1.0f});

    const auto s = static_cast<std::uint32_t>(ns);
    const std::uint32_t row = s + 1;
    const std::uint32_t rings = static_cast<std::uint32_t>(nt) - 1;
    // Vertex j of interior ring k, k in 1..rings.
    auto ring = [&](std::uint32_t k, std::uint32_t j) { return s + (k - 1) * row + j; };
    const std::uint32_t north = s + rings * row;
    for (std::uint32_t j = 0; j < s; ++j)
        mesh.indices.insert(mesh.indices.end(), {j, ring(1, j + 1), ring(1, j)});
    for (std::uint32_t k = 1; k < rings; ++k)
        for (std::uint32_t j = 0; j < s; ++j)
            push_quad(mesh, ring(k, j), ring(k, j + 1), ring(k + 1, j + 1), ring(k + 1, j));
    for (std::uint32_t j = 0; j < s; ++j)
        mesh.indices.insert(mesh.indices.end(), {ring(rings, j), ring(rings, j + 1), north + j});
    (void)generate_tangents(mesh);
    return mesh;
}

Mesh torus_unfitted(float ring_radius, float tube_radius, int ring_segments, int tube_segments) {
    const int nr = std::max(ring_segments, 3);
    const int nt = std::max(tube_segments, 3);
    Mesh mesh;
    // u = 0 / 1 and v = 0 / 1 seams are duplicated so uvs stay continuous per
    // triangle. v = 0 is the outer equator, v = 0.25 the top.
    for (int j = 0; j <= nt; ++j) {
        const float v = static_cast<float>(j) / static_cast<float>(nt);
        const float tube = 2.0f * kPi<float> * v;
        for (int i = 0; i <= nr; ++i) {
            const float u = static_cast<float>(i) / static_cast<float>(nr);
            const float around = 2.0f * kPi<float> * u;
            const glm::vec3 radial(std::cos(around), std::sin(around), 0.0f);
            const glm::vec3 n = std::cos(tube) * radial + glm::vec3(0.0f, 0.0f, std::sin(tube));
            Vertex vert;
            vert.position = ring_radius * radial + tube_radius * n;
            vert.normal = n;
            vert.uv = {u, v};
            mesh.vertices.push_back(vert);
        }
    }
    push_grid_quads(mesh, static_cast<std::uint32_t>(nr), static_cast<std::uint32_t>(nt));
    (void)generate_tangents(mesh);
    return mesh;
}

Mesh cylinder_unfitted(float radius, float height, int segments, int rows) {
    const int ns = std::max(segments, 3);
    const int nr = std::max(rows, 1);
    Mesh mesh;
    for (int k = 0; k <= nr; ++k) {
        const float v = static_cast<float>(k) / static_cast<float>(nr);
        for (int j = 0; j <= ns; ++j) {  // j = ns duplicates j = 0 with u = 1
            const float u = static_cast<float>(j) / static_cast<float>(ns);
            const float lon = 2.0f * kPi<float> * u;
            const glm::vec3 n(-std::sin(lon), std::cos(lon), 0.0f);
            Vertex vert;
            vert.position = radius * n + glm::vec3(0.0f, 0.0f, (v - 0.5f) * height);
            vert.normal = n;
            vert.uv = {u, v};
            mesh.vertices.push_back(vert);
        }
    }
    push_grid_quads(mesh, static_cast<std::uint32_t>(ns), static_cast<std::uint32_t>(nr));
    (void)generate_tangents(mesh);
    return mesh;
}

}  // namespace

Mesh make_uv_sphere(float radius, int slices, int stacks) {
    Mesh mesh = uv_sphere_unfitted(radius, slices, stacks);
    fit_curvature(mesh);
    return mesh;
}

Mesh make_torus(float ring_radius, float tube_radius, int ring_segments, int tube_segments) {
    Mesh mesh = torus_unfitted(ring_radius, tube_radius, ring_segments, tube_segments);
    fit_curvature(mesh);
    return mesh;
}

Mesh make_cylinder(float radius, float height, int segments, int rows) {
    Mesh mesh = cylinder_unfitted(radius, height, segments, rows);
    fit_curvature(mesh);
    return mesh;
}

Mesh make_widened_cylinder(float radius, float height, float margin, int segments, int rows) {
    const float grow = 1.0f + 2.0f * margin;
    Mesh mesh = cylinder_unfitted(radius, height * grow, segments, rows);
    for (Vertex& v : mesh.vertices) v.uv.y = v.uv.y * grow - margin;
    (void)generate_tangents(mesh);  // the frame and uv density again, for the new v
    fit_curvature(mesh);
    return mesh;
}

Mesh make_tube_rim_caps(const Mesh& tube, float radius, float inner, float outer) {
    Mesh caps;
    caps.units_per_uv = tube.units_per_uv;
    caps.chord_sag = tube.chord_sag;
    if (!(inner >= 0.0f && inner < outer && radius > 0.0f && std::isfinite(outer))) return caps;
    for (const float rim_v : {0.0f, 1.0f}) {
        std::vector<const Vertex*> rim;
        for (const Vertex& v : tube.vertices)
            if (v.uv.y == rim_v) rim.push_back(&v);
        if (rim.size() < 3) continue;
        // In order of u: make_cylinder lays each ring out that way.
        const auto first = static_cast<std::uint32_t>(caps.vertices.size());
        for (const Vertex* v : rim) {
            for (const float r : {inner, outer}) {
                Vertex c = *v;
                const glm::vec2 radial = glm::vec2(v->position) / radius;
                c.position = glm::vec3(radial * r, v->position.z);
                caps.vertices.push_back(c);
            }
        }
        // Counter-clockwise seen from the tube's inside: from +z at the
        // bottom end (v = 0), from -z at the top (u runs counter-clockwise
        // seen from +z).
        const bool top = rim_v == 1.0f;
        for (std::uint32_t k = 0; k + 1 < rim.size(); ++k) {
            const std::uint32_t ia = first + 2 * k, oa = ia + 1, ib = ia + 2, ob = ia + 3;
            if (top) caps.indices.insert(caps.indices.end(), {oa, ib, ob, oa, ia, ib});
            else caps.indices.insert(caps.indices.end(), {oa, ob, ib, oa, ib, ia});
        }
    }
    return caps;
}

Mesh make_tile_walls(const Mesh& plane, float below, float above) {
    Mesh walls;
    walls.units_per_uv = plane.units_per_uv;
    if (!(std::isfinite(below) && std::isfinite(above) && -below < above)) return walls;
    // Each edge: the vertices with one uv coordinate at 0 or 1, in order of
    // the other; its outward direction from the plane's centre.
    for (int axis = 0; axis < 2; ++axis) {
        for (const float side : {0.0f, 1.0f}) {
            std::vector<const Vertex*> edge;
            for (const Vertex& v : plane.vertices)
                if (v.uv[axis] == side) edge.push_back(&v);
            if (edge.size() < 2) continue;
            // In order of the other coordinate: make_plane lays its grid out
            // row by row, u then v.
            glm::vec3 centre(0.0f);
            for (const Vertex& v : plane.vertices) centre += v.position;
            centre /= static_cast<float>(plane.vertices.size());
            const auto first = static_cast<std::uint32_t>(walls.vertices.size());
            for (const Vertex* v : edge) {
                for (const float z : {-below, above}) {
                    Vertex w = *v;
                    w.position.z = v->position.z + z;
                    walls.vertices.push_back(w);
                }
            }
            for (std::uint32_t k = 0; k + 1 < edge.size(); ++k) {
                const std::uint32_t a0 = first + 2 * k, a1 = a0 + 1, b0 = a0 + 2, b1 = a0 + 3;
                const glm::vec3 pa = walls.vertices[a0].position, pb = walls.vertices[b0].position;
                const glm::vec3 pt = walls.vertices[a1].position;
                const glm::vec3 outward = 0.5f * (pa + pb) - centre;
                // Counter-clockwise seen from outside the tile.
                if (glm::dot(glm::cross(pb - pa, pt - pa), outward) > 0.0f)
                    walls.indices.insert(walls.indices.end(), {a0, b0, b1, a0, b1, a1});
                else
                    walls.indices.insert(walls.indices.end(), {a0, b1, b0, a0, a1, b1});
            }
        }
    }
    return walls;
}

namespace {
// "one vertex per texel", "2 vertices per texel": for the budget's message.
std::string per_texel_text(int per_texel) {
    return per_texel <= 1 ? std::string("one vertex per texel") : std::to_string(per_texel) + " vertices per texel";
}
}  // namespace

DisplacedGrid displaced_curved_grid(MeshKind kind, int field_width, int field_height, const glm::dmat2& uv_matrix,
                                    int per_texel) {
    DisplacedGrid grid = displaced_plane_grid(field_width, field_height, uv_matrix, per_texel);
    // At least the parallax mesh's own tessellation, so that the displaced
    // surface is never coarser than the polygon it is compared with.
    grid.columns = std::max<std::int64_t>(grid.columns, kind == MeshKind::torus ? 64 : 48);
    grid.rows = std::max<std::int64_t>(grid.rows, kind == MeshKind::cylinder ? 1 : kind == MeshKind::torus ? 32 : 24);
    return grid;
}

Result<Mesh> make_displaced_curved(MeshKind kind, const CurvedMeshSize& size, const HeightField& field,
                                   const glm::dmat2& uv_matrix, const glm::dvec2& uv_offset, float height_scale,
                                   float polygon_height, float units_per_uv, int per_texel) {
    counters::count(counters::Step::mesh_build);
    const char* name = mesh_kind_name(kind);
    if (kind != MeshKind::sphere && kind != MeshKind::torus && kind != MeshKind::cylinder)
        return make_error(std::string("displaced ") + name + ": only a sphere, torus or cylinder is curved here");
    if (field.width < 1 || field.height < 1) return make_error(std::string("displaced ") + name + ": the height field is empty");
    const DisplacedGrid grid = displaced_curved_grid(kind, field.width, field.height, uv_matrix, per_texel);
    const std::int64_t columns = grid.columns, rows = grid.rows;
    const std::int64_t vertex_count = grid.vertex_count() + 2 * columns;  // a sphere's poles: a row each
    if (vertex_count > kMaxSceneVertices)
        return make_error(std::string("displaced ") + name + ": a " + std::to_string(field.width) + "x" +
                          std::to_string(field.height) + " height field under this uv transform needs a " +
                          std::to_string(columns) + "x" + std::to_string(rows) +
                          " grid (" + per_texel_text(per_texel) + " of the transformed uv), " +
                          std::to_string(vertex_count) + " vertices, over the limit of " +
                          std::to_string(kMaxSceneVertices));
    const double area_scale = std::sqrt(std::fabs(glm::determinant(uv_matrix)));
    if (!(area_scale > 0.0) || !std::isfinite(area_scale))
        return make_error(std::string("displaced ") + name + ": the uv transform is singular");
    const int c = static_cast<int>(columns), r = static_cast<int>(rows);
    // Drawn as geometry: no curvature to fit (a pass over every vertex's
    // neighbours, up to kMaxSceneVertices of them).
    Mesh mesh = kind == MeshKind::sphere  ? uv_sphere_unfitted(size.radius, c, r)
                : kind == MeshKind::torus ? torus_unfitted(size.radius, size.tube_radius, c, r)
                                          : cylinder_unfitted(size.radius, size.height, c, r);
    const double depth = static_cast<double>(height_scale) * static_cast<double>(units_per_uv) / area_scale;
    for (Vertex& v : mesh.vertices) {
        const glm::dvec2 tiled = uv_matrix * glm::dvec2(v.uv) + uv_offset;
        const double h = field.sample_bilinear(tiled.x, tiled.y);
        v.position += v.normal * static_cast<float>((h - polygon_height) * depth);
    }
    mesh.units_per_uv = units_per_uv;
    return mesh;
}

DisplacedGrid displaced_plane_grid(int field_width, int field_height, const glm::dmat2& uv_matrix, int per_texel) {
    const double k = std::clamp(per_texel, 1, kMaxDisplacedVerticesPerTexel);
    // Texels crossed along a mesh edge: the edge's image in texel space. The
    // small slack keeps an exact count (512.0000000001 from a rotation's
    // rounding) from gaining a quad.
    const auto quads = [&](const glm::dvec2& mesh_edge) {
        const glm::dvec2 tiles = uv_matrix * mesh_edge;
        const double texels = glm::length(tiles * glm::dvec2(field_width, field_height));
        // Clamped before the conversion: a uv scale of 16384 on a 4096 field is
        // 2^26 quads a side, far over any budget, but must not overflow.
        return static_cast<std::int64_t>(std::clamp(k * std::ceil(texels - 1e-6), 1.0, 1e9));
    };
    return DisplacedGrid{quads({1.0, 0.0}), quads({0.0, 1.0})};
}

Result<Mesh> make_displaced_plane(float size, const HeightField& field, const glm::dmat2& uv_matrix,
                                  const glm::dvec2& uv_offset, float height_scale, float polygon_height,
                                  int per_texel) {
    counters::count(counters::Step::mesh_build);
    if (field.width < 1 || field.height < 1) return make_error("displaced plane: the height field is empty");
    const DisplacedGrid grid = displaced_plane_grid(field.width, field.height, uv_matrix, per_texel);
    const std::int64_t vertex_count = grid.vertex_count();
    if (vertex_count > kMaxSceneVertices)
        return make_error("displaced plane: a " + std::to_string(field.width) + "x" + std::to_string(field.height) +
                          " height field under this uv transform needs a " + std::to_string(grid.columns) + "x" +
                          std::to_string(grid.rows) + " grid (" + per_texel_text(per_texel) + " of the transformed uv), " +
                          std::to_string(vertex_count) + " vertices, over the limit of " +
                          std::to_string(kMaxSceneVertices));
    const double area_scale = std::sqrt(std::fabs(glm::determinant(uv_matrix)));
    if (!(area_scale > 0.0) || !std::isfinite(area_scale))
        return make_error("displaced plane: the uv transform is singular");
    // Mesh units per tile: the relief is height_scale tiles deep.
    const double units_per_tile = static_cast<double>(size) / area_scale;
    const int columns = static_cast<int>(grid.columns);
    const int rows = static_cast<int>(grid.rows);
    Mesh mesh;
    mesh.vertices.reserve(static_cast<size_t>(vertex_count));
    for (int j = 0; j <= rows; ++j)
        for (int i = 0; i <= columns; ++i) {
            const glm::dvec2 uv(static_cast<double>(i) / columns, static_cast<double>(j) / rows);
            const glm::dvec2 tiled = uv_matrix * uv + uv_offset;
            const double h = field.sample_bilinear(tiled.x, tiled.y);
            Vertex v;
            v.uv = glm::vec2(uv);
            v.position = glm::vec3(static_cast<float>((uv.x - 0.5) * size), static_cast<float>((uv.y - 0.5) * size),
                                   static_cast<float>((h - polygon_height) * height_scale * units_per_tile));
            v.normal = glm::vec3(0.0f, 0.0f, 1.0f);
            v.tangent = glm::vec4(1.0f, 0.0f, 0.0f, 1.0f);
            mesh.vertices.push_back(v);
        }
    const auto index = [columns](int i, int j) { return static_cast<std::uint32_t>(j * (columns + 1) + i); };
    mesh.indices.reserve(static_cast<size_t>(columns) * rows * 6);
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < columns; ++i) {
            // Counter-clockwise seen from +z, as make_plane.
            mesh.indices.insert(mesh.indices.end(), {index(i, j), index(i + 1, j), index(i + 1, j + 1),
                                                     index(i, j), index(i + 1, j + 1), index(i, j + 1)});
        }
    mesh.units_per_uv = size;
    return mesh;
}

}  // namespace px
