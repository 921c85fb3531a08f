#include "parallaxes/render/renderer.h"

#include "parallaxes/planner/object_plan.h"
#include "parallaxes/core/text.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "parallaxes/core/counters.h"
#include "parallaxes/core/limits.h"
#include "parallaxes/gl/state.h"
#include "parallaxes/gl/texture.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/shaders/interface.h"

namespace px {

// The state guard (gl/state.h) saves every texture unit and, on ES 2.0,
// every attribute slot the library touches: point_attributes enables each
// slot of the interface table.
static_assert(shader::kAttributeCount <= static_cast<std::size_t>(kLibraryAttributeSlots),
              "SavedGlState must save every attribute slot the interface table points");
static_assert(shader::kSamplerCount <= static_cast<std::size_t>(kLibraryTextureUnits),
              "SavedGlState must save every texture unit the interface table binds");

namespace slot = shader::slot;

namespace {

// A GL error check after each object names the object and its program; in
// release builds one check per frame (building the message on every draw
// costs more than the check).
#ifdef NDEBUG
constexpr bool kCheckEveryDraw = false;
#else
constexpr bool kCheckEveryDraw = true;
#endif


struct GpuMesh {
    BufferHandle vertices;
    BufferHandle indices;
    VertexArrayHandle vertex_array;  // ES 3.0: the library's own, so the host's VAO is never written
    GLsizei index_count = 0;
    GLenum index_type = GL_UNSIGNED_SHORT;
    float units_per_uv = 1.0f;
    float chord_sag = 0.0f;  // Mesh::chord_sag
    // A bounded relief's mesh drawn wider (upload_object_mesh) keeps its own
    // polygon too, for the variants without a trace: they shade the polygon,
    // and the wider one would show the texture's next tiles around the tile.
    std::unique_ptr<GpuMesh> unwidened;
    // A bounded tube with a curved silhouette: its rim caps
    // (make_tube_rim_caps), which the exact shape search draws with the
    // unwidened tube (draw_object).
    std::unique_ptr<GpuMesh> rim_caps;
    // A bounded plane's side walls (make_tile_walls), which the variants
    // whose trace starts part way (px_start_t) draw with it.
    std::unique_ptr<GpuMesh> tile_walls;
};

struct GpuMaterial {
    const MaterialDesc* desc = nullptr;
    Texture albedo;
    Texture normal;
    // What tracing loops read: the separate height map, or on GLSL ES 1.00 a
    // base-level-only copy of the packed normal map (or of the height map).
    // Empty when the traced reads come from `normal` (packed, ES 3.0).
    Texture height;
    Texture max_map;    // maxmip: the max pyramid (GLSL ES 1.00: its atlas)
    int max_levels = 0;
    glm::vec4 max_atlas{0.0f};  // GLSL ES 1.00: 1 / atlas size, field width, log2(field height)
    // Texels of the texture the trace reads (u_texture_size): the height map
    // where there is one, which need not be the normal map's size.
    glm::vec2 traced_size{0.0f};
    bool planned = false;  // declares effects: each object's plan picks the variant
};

struct GpuObject {
    const ObjectDesc* desc = nullptr;
    size_t mesh = 0;
    size_t material = 0;
    ObjectPlan plan;  // this frame's variant and options
};

// Where each attribute's data sits in a Vertex.
std::size_t vertex_offset(shader::Attribute a) {
    switch (a) {
        case shader::Attribute::position: return offsetof(Vertex, position);
        case shader::Attribute::normal: return offsetof(Vertex, normal);
        case shader::Attribute::tangent: return offsetof(Vertex, tangent);
        case shader::Attribute::uv: return offsetof(Vertex, uv);
        case shader::Attribute::curvature: return offsetof(Vertex, curvature);
        case shader::Attribute::uv_stretch: return offsetof(Vertex, uv_stretch);
        case shader::Attribute::uv_bend_u: return offsetof(Vertex, uv_bend_u);
        case shader::Attribute::uv_bend_v: return offsetof(Vertex, uv_bend_v);
    }
    return 0;
}

// Points every attribute of the interface table at the bound vertex buffer.
void point_attributes() {
    for (const shader::AttributeInfo& a : shader::attributes()) {
        const GLuint slot_index = static_cast<GLuint>(a.slot);
        glEnableVertexAttribArray(slot_index);
        glVertexAttribPointer(slot_index, a.components, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                              reinterpret_cast<void*>(vertex_offset(a.id)));
    }
}

Result<GpuMesh> upload_mesh(const Mesh& mesh, const Caps& caps, const std::string& what);

// The relief's depth in mesh units over a mesh of `units_per_uv`.
float relief_depth(const MaterialDesc& m, float units_per_uv) {
    return m.height_scale * units_per_uv / m.uv.area_scale<float>();
}

// An object's drawn meshes as prepared (PreparedObject): the mesh, or for a
// bounded relief the widened one with the object's own beside it, and a
// bounded tube's rim caps or a bounded plane's side walls.
Result<GpuMesh> upload_object_mesh(const ObjectDesc& o, const PreparedObject& prepared, const Caps& caps) {
    const std::string what = "object '" + echo(o.name) + "'";
    if (!prepared.widened) return upload_mesh(prepared.mesh, caps, what);
    Result<GpuMesh> widened = upload_mesh(*prepared.widened, caps, what);
    if (!widened) return widened;
    Result<GpuMesh> own = upload_mesh(prepared.mesh, caps, what);
    if (!own) return own.error();
    widened->unwidened = std::make_unique<GpuMesh>(std::move(*own));
    if (prepared.rim_caps) {
        Result<GpuMesh> uploaded = upload_mesh(*prepared.rim_caps, caps, what + " (its rim caps)");
        if (!uploaded) return uploaded.error();
        widened->rim_caps = std::make_unique<GpuMesh>(std::move(*uploaded));
    }
    if (prepared.tile_walls) {
        Result<GpuMesh> uploaded = upload_mesh(*prepared.tile_walls, caps, what + " (its side walls)");
        if (!uploaded) return uploaded.error();
        widened->tile_walls = std::make_unique<GpuMesh>(std::move(*uploaded));
    }
    return widened;
}

Result<GpuMesh> upload_mesh(const Mesh& mesh, const Caps& caps, const std::string& what) {
    GpuMesh g;
    g.units_per_uv = mesh.units_per_uv;
    g.chord_sag = mesh.chord_sag;
    if (caps.es_major >= 3) {
        // Bound first: the element buffer binding below is state of the VAO.
        g.vertex_array = make_vertex_array();
        glBindVertexArray(g.vertex_array.get());
    }
    g.vertices = make_buffer();
    glBindBuffer(GL_ARRAY_BUFFER, g.vertices.get());
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.vertices.size() * sizeof(Vertex)),
                 mesh.vertices.data(), GL_STATIC_DRAW);
    g.indices = make_buffer();
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.indices.get());
    if (mesh.vertices.size() <= 0xFFFF) {  // 16-bit indices: every ES 2.0 context has them
        std::vector<std::uint16_t> narrow(mesh.indices.begin(), mesh.indices.end());
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(narrow.size() * 2), narrow.data(), GL_STATIC_DRAW);
        g.index_type = GL_UNSIGNED_SHORT;
    } else {
        if (!caps.uint_indices())
            return make_error(what + ": " + std::to_string(mesh.vertices.size()) +
                              " vertices need 32-bit indices, which this ES 2.0 context lacks "
                              "(GL_OES_element_index_uint)");
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.indices.size() * 4), mesh.indices.data(),
                     GL_STATIC_DRAW);
        g.index_type = GL_UNSIGNED_INT;
    }
    if (g.vertex_array) point_attributes();  // recorded in the VAO once
    g.index_count = static_cast<GLsizei>(mesh.indices.size());
    Status s = check_gl("uploading " + what);
    if (!s) return s.error();
    return g;
}

// What every draw of a frame shares.
struct FrameValues {
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f};
    glm::vec3 camera_position{0.0f};
    glm::vec3 ambient{0.0f};
    int light_count = 0;
    std::array<glm::vec4, kMaxLights> light_vectors{};  // xyz toward the light (w 0) or its position (w 1)
    std::array<glm::vec3, kMaxLights> light_colors{};   // colour times intensity
    std::array<float, kMaxLights> light_radii{};        // angular radius, radians
};

FrameValues frame_values(const SceneDesc& scene, const HostFrame& frame) {
    FrameValues f;
    f.view = frame.view;
    f.projection = frame.projection;
    f.camera_position = glm::vec3(glm::inverse(frame.view)[3]);
    f.ambient = scene.ambient;
    f.light_count = static_cast<int>(std::min<size_t>(scene.lights.size(), kMaxLights));
    for (size_t i = 0; i < static_cast<size_t>(f.light_count); ++i) {
        const LightDesc& l = scene.lights[i];
        const bool point = l.kind == LightKind::point;
        f.light_vectors[i] = glm::vec4(point ? l.position : -glm::normalize(l.direction), point ? 1.0f : 0.0f);
        f.light_colors[i] = l.color * l.intensity;
        f.light_radii[i] = glm::radians(l.angular_radius_deg);
    }
    return f;
}

void set_frame_uniforms(const Program& p, const FrameValues& f) {
    p.set(slot::view, f.view);
    p.set(slot::projection, f.projection);
    p.set(slot::depth_projection, f.projection);
    p.set(slot::camera_position, f.camera_position);
    p.set(slot::ambient, f.ambient);
    p.set(slot::light_count, f.light_count);
    p.set(slot::light_vector, f.light_vectors.data(), kMaxLights);
    p.set(slot::light_color, f.light_colors.data(), kMaxLights);
    p.set(slot::light_angular_radius, f.light_radii.data(), kMaxLights);
}

// The model's mean scale (its 3x3's determinant, cube-rooted).
float mean_scale(const glm::mat4& model) { return std::cbrt(std::fabs(glm::determinant(glm::mat3(model)))); }

// The relief's depth in mesh units: height_scale tiles of units_per_uv /
// area_scale mesh units each (as make_displaced_curved displaces).
float relief_depth(const MaterialDesc& m, const GpuMesh& mesh) { return relief_depth(m, mesh.units_per_uv); }

// The object's transform; returns whether it mirrors.
bool set_object_uniforms(const Program& p, const glm::mat4& model, const GpuMesh& mesh, const MaterialDesc& m) {
    const glm::mat3 model3(model);
    const bool mirrored = glm::determinant(model3) < 0.0f;
    p.set(slot::model, model);
    p.set(slot::normal_matrix, glm::inverseTranspose(model3));
    p.set(slot::model_handedness, mirrored ? -1.0f : 1.0f);
    // View-space units per texture tile: mesh units per uv, times the
    // model's mean scale, over tiles per mesh uv.
    const float model_scale = mean_scale(model);
    const float units_per_tile = mesh.units_per_uv * model_scale / m.uv.area_scale<float>();
    p.set(slot::units_per_tile, units_per_tile);
    // The quadric (mesh units) into relief depths per squared tile: world
    // bend = mesh bend / model scale, offsets of units_per_tile per tile,
    // depths of height_scale * units_per_tile.
    const float curvature_scale = units_per_tile / (m.height_scale * model_scale);
    p.set(slot::curvature_scale, std::isfinite(curvature_scale) ? curvature_scale : 0.0f);
    // The curved relief's shell (surface.vert): the mesh drawn out along its
    // normals past its triangles' chord sag, so that its polygon covers the
    // smooth surface's outline; x in mesh units, y the same in relief depths,
    // z relief depths per view-space unit.
    const float shell = kShellOverSag * mesh.chord_sag;
    const float depths_per_unit = 1.0f / (m.height_scale * units_per_tile);
    const glm::vec3 shell_uniform(shell, shell * model_scale * depths_per_unit, depths_per_unit);
    p.set(slot::shell, std::isfinite(shell_uniform.y) && std::isfinite(shell_uniform.z) ? shell_uniform : glm::vec3(0.0f));
    // The mesh's uv bend (Vertex::uv_bend_u/v, per squared mesh unit) per
    // squared ray parameter: the curved search's ray moves height_scale *
    // units_per_uv / area_scale mesh units along the tangent plane per unit
    // of its parameter (a relief depth), times the view's tangent part.
    const float bend_step = relief_depth(m, mesh);
    const float bend_scale = bend_step * bend_step;
    p.set(slot::uv_bend_scale, std::isfinite(bend_scale) ? bend_scale : 0.0f);
    return mirrored;
}

// The exact curved search's shape (march.glsl, PX_SHAPE): the mesh's sizes,
// its relief depth in mesh units (as make_displaced_curved displaces), the
// view-space units of a relief depth (the search's ray parameter), the
// camera in mesh space, and the material's uv transform.
void set_shape_uniforms(const Program& p, const glm::mat4& model, const FrameValues& frame, const MeshDesc& shape,
                        const GpuMesh& mesh, const MaterialDesc& m) {
    const float model_scale = mean_scale(model);
    const float depth = relief_depth(m, mesh);
    const float second = shape.kind == MeshKind::torus ? shape.tube_radius : shape.size;
    glm::vec4 u(shape.radius, second, 1.0f / depth, depth * model_scale);
    if (!(std::isfinite(u.z) && std::isfinite(u.w) && depth > 0.0f)) u = glm::vec4(shape.radius, second, 0.0f, 0.0f);
    p.set(slot::shape, &u, 1);
    p.set(slot::object_camera, glm::vec3(glm::inverse(model) * glm::vec4(frame.camera_position, 1.0f)));
    p.set(slot::shape_uv_matrix, m.uv.matrix<float>());
    p.set(slot::shape_uv_offset, m.uv.offset - glm::floor(m.uv.offset));
}

void bind_texture_unit(shader::Sampler sampler, const Texture& texture) {
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + shader::info(sampler).unit));
    bind_texture(texture);
}

void set_material_uniforms(const Program& p, const GpuMaterial& material, const VariantKey& key,
                           const TechniqueOptions& options, MeshKind mesh_kind) {
    const MaterialDesc& m = *material.desc;
    p.set(slot::uv_matrix, m.uv.matrix<float>());
    // Whole tiles of offset change no texel (GL_REPEAT), but uvs 1000 tiles
    // out leave fp32 a 2^-14-tile grid and mediump none: only the fraction
    // goes to the shader (exact: Sterbenz), so every technique is invariant.
    p.set(slot::uv_offset, m.uv.offset - glm::floor(m.uv.offset));
    p.set(slot::uv_frame, m.uv.frame<float>());
    if (key.bounded) {
        // The uv transform inverted (in double, then rounded once), with the
        // same fractional offset the vertex stage adds.
        const glm::dmat2 matrix = m.uv.matrix<double>();
        const double det = glm::determinant(matrix);
        glm::mat2 bounds = det != 0.0 ? glm::mat2(glm::inverse(matrix)) : glm::mat2(0.0f);
        // An open cylinder is bounded along v only (its ends), u wraps around
        // it: mesh u comes out 0 for every uv, always inside [0, 1].
        if (mesh_kind == MeshKind::cylinder) bounds[0][0] = bounds[1][0] = 0.0f;
        p.set(slot::bounds_matrix, bounds);
        p.set(slot::bounds_offset, m.uv.offset - glm::floor(m.uv.offset));
    }
    const float scale = m.height_scale;
    p.set(slot::height_scale, scale);
    p.set(slot::parallax_scale, scale);
    p.set(slot::inv_height_scale, scale > 0.0f ? 1.0f / scale : 0.0f);
    p.set(slot::polygon_height, static_cast<float>(m.polygon_height()));
    p.set(slot::texture_size, material.traced_size);
    // The planner's loop bound is the top of the dynamic range (it may
    // differ from the material's, e.g. on a fallback technique).
    const float top = static_cast<float>(key.max_samples > 0 ? key.max_samples : options.max_samples);
    p.set(slot::sample_range, glm::vec2(std::min(static_cast<float>(options.min_samples), top), top));
    p.set(slot::lod_range, glm::vec2(options.lod_threshold, options.lod_band));
    p.set(slot::specular, m.specular);
    p.set(slot::shininess, m.shininess);
    p.set(slot::max_levels, material.max_levels);
    p.set(slot::max_atlas, &material.max_atlas, 1);

    bind_texture_unit(shader::Sampler::albedo, material.albedo);
    bind_texture_unit(shader::Sampler::normal, material.normal);
    if (material.height.handle) bind_texture_unit(shader::Sampler::height, material.height);
    if (material.max_map.handle) bind_texture_unit(shader::Sampler::max_map, material.max_map);
}

void draw_mesh(const GpuMesh& mesh) {
    if (mesh.vertex_array) {
        glBindVertexArray(mesh.vertex_array.get());
    } else {
        glBindBuffer(GL_ARRAY_BUFFER, mesh.vertices.get());
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh.indices.get());
        point_attributes();
    }
    glDrawElements(GL_TRIANGLES, mesh.index_count, mesh.index_type, nullptr);
}

// The fixed-function state every draw assumes, whatever the host left set
// (SavedGlState gives the host's back afterwards), and the frame's clears,
// inside the viewport only.
void set_draw_state(const Caps& caps, const HostFrame& frame, const Viewport& vp, const glm::vec4& clear_color) {
    glBindFramebuffer(GL_FRAMEBUFFER, frame.target.framebuffer);
    glViewport(vp.x, vp.y, vp.width, vp.height);
    // The state table's set-aside column (gl/state.h): scissor, stencil,
    // blend, dither (the debug outputs are exact bit patterns), colour and
    // depth masks, depth test LESS, back-face culling, sampler objects, ...
    set_aside_host_state(caps);
    const GLbitfield clears = (frame.clear_color ? GL_COLOR_BUFFER_BIT : 0u) | (frame.clear_depth ? GL_DEPTH_BUFFER_BIT : 0u);
    if (clears) {
        const bool whole = vp.x == 0 && vp.y == 0 && vp.width == frame.target.width && vp.height == frame.target.height;
        if (!whole) {  // a clear ignores the viewport: the scissor keeps it inside
            glEnable(GL_SCISSOR_TEST);
            glScissor(vp.x, vp.y, vp.width, vp.height);
        }
        glClearDepthf(1.0f);
        glClearColor(clear_color.r, clear_color.g, clear_color.b, clear_color.a);
        glClear(clears);
        glDisable(GL_SCISSOR_TEST);
    }
}

}  // namespace


struct Renderer::GpuScene {
    std::vector<GpuMesh> meshes;
    std::vector<GpuMaterial> materials;
    std::vector<GpuObject> objects;
    ProgramCache programs;
    std::unique_ptr<FramePlanner> planner;  // the effect planner, or the named-technique one
    CameraDesc camera;     // draw(target)'s camera (set_view)
    PlanView planned_for;  // the frame the objects' plans are for
    bool planned = false;  // whether they are planned at all
};

namespace {

// Whether a bounded plane's side walls can show what its wider polygon does
// not: a ray that comes into the tile through its side, a relief depth
// down at most, crossed the polygon's plane depth * tan(view angle) out,
// and the polygon reaches bounded_margin; the angle is largest at a corner
// (the farthest point of an edge from the camera's foot). From under the
// plane (whose polygon is culled there) the walls are not drawn either.
// Without them the frame costs what it did before (1.34 against 1.46 times
// the unbounded tile's at 60 degrees, llvmpipe, 512x512; docs/silhouettes.md).
bool walls_needed(const ObjectDesc& o, const MaterialDesc& m, const GpuMesh& walls, const glm::mat4& model,
                  const glm::vec3& camera) {
    const glm::vec3 eye = glm::vec3(glm::inverse(model) * glm::vec4(camera, 1.0f));
    if (!(eye.z > 0.0f)) return false;
    const float half = 0.5f * o.mesh.size;
    const double reach = bounded_margin(m) * static_cast<double>(o.mesh.size);
    const double depth = relief_depth(m, walls);
    for (const glm::vec2 corner : {glm::vec2(-half, -half), glm::vec2(half, -half), glm::vec2(half, half),
                                   glm::vec2(-half, half)}) {
        const double across = glm::length(glm::vec2(eye) - corner);
        if (depth * across > reach * static_cast<double>(eye.z)) return true;
    }
    return false;
}

// One object with one variant, into the bound framebuffer.
Status draw_object(Renderer::GpuScene& scene, const GpuObject& object, const glm::mat4& model, const VariantKey& key,
                   const TechniqueOptions& options, const FrameValues& frame) {
    const GpuMaterial& material = scene.materials[object.material];
    Result<const Program*> program = scene.programs.get(key);
    if (!program) return with_context("material '" + material.desc->name + "'", program.error());
    const Program& p = **program;
    glUseProgram(p.id());
    set_frame_uniforms(p, frame);
    // Only a variant that traces (and so discards outside the bounds) draws
    // a bounded relief's wider polygon.
    const GpuMesh& uploaded = scene.meshes[object.mesh];
    const VariantKey drawn = key.canonical();
    // The exact shape search on a bounded tube traces the rays that come
    // onto the tube's length through its rim caps, not through a wider tube.
    const bool rim_caps = drawn.bounded && drawn.shape == kShapeCylinder && uploaded.rim_caps;
    const GpuMesh& mesh = uploaded.unwidened && (!drawn.bounded || rim_caps) ? *uploaded.unwidened : uploaded;
    const bool mirrored = set_object_uniforms(p, model, mesh, *material.desc);
    // A mirroring model matrix reverses the triangles' winding on screen:
    // flip the front face so the object's outside stays the drawn side.
    glFrontFace(mirrored ? GL_CW : GL_CCW);
    set_material_uniforms(p, material, key, options, object.desc->mesh.kind);
    if (drawn.shape) set_shape_uniforms(p, model, frame, object.desc->mesh, mesh, *material.desc);
    if (drawn.bounded && !drawn.curved) {
        // Relief depths per mesh unit: a side wall's height (surface.vert).
        // Only a plane has walls; 0 elsewhere, where a vertex's z is not a
        // height above the polygon (a bounded cube's faces).
        const float depth = uploaded.tile_walls ? relief_depth(*material.desc, *uploaded.tile_walls) : 0.0f;
        p.set(slot::wall_scale, std::isfinite(1.0f / depth) && depth > 0.0f ? 1.0f / depth : 0.0f);
    }
    if (object.desc->mesh.displaced && object.desc->mesh.kind == MeshKind::cylinder) {
        // An open tube as real geometry: its inside (the back faces) goes
        // into depth first, so that what lies behind its far wall stays
        // hidden, as behind any wall. One-sided, the far wall's bump flanks
        // that turn toward the camera showed through its culled inside
        // where the parallax tube (whose far wall is culled whole) shows
        // what lies behind: the silhouettes' reference differed from it in
        // the opening, not at the outline (docs/silhouettes.md).
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glCullFace(GL_FRONT);
        draw_mesh(mesh);
        glCullFace(GL_BACK);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    }
    draw_mesh(mesh);
    if (drawn.bounded && !drawn.curved && uploaded.tile_walls &&
        (technique_info(drawn.technique).options & (kOptSamples | kOptSteps)) != 0 &&
        walls_needed(*object.desc, *material.desc, *uploaded.tile_walls, model, frame.camera_position)) {
        // A bounded tile's side walls, for the traces that start where the
        // ray comes in (px_start_t): past about 80 degrees from the normal
        // rays come into the tile through its side farther out than the
        // wider polygon reaches.
        draw_mesh(*uploaded.tile_walls);
    }
    if (rim_caps) {
        // The caps face into the tube: drawn by their back faces, seen from
        // beyond each end (march.glsl PX_SHAPE_TUBE tells them by
        // gl_FrontFacing); what a cap fragment's ray does not meet on the
        // tube's length it discards.
        glCullFace(GL_FRONT);
        draw_mesh(*uploaded.rim_caps);
        glCullFace(GL_BACK);
    }
    if (!kCheckEveryDraw) return {};
    return check_gl("drawing object '" + object.desc->name + "' with " + p.description());
}

// Where a texture's data came from, for messages about it.
std::string source_label(const TextureSource& source) {
    switch (source.kind) {
        case TextureSource::Kind::file:
            return "file '" + echo_path(source.path) + "'" +
                   (source.channel == TextureSource::Channel::grey ? std::string()
                                                                   : std::string(", channel ") + channel_name(source.channel));
        case TextureSource::Kind::procedural: return std::string("procedural '") + field_kind_name(source.field.kind) + "'";
        case TextureSource::Kind::color: return "a colour";
        case TextureSource::Kind::none: return "the default";
    }
    return "unknown";
}

std::string normal_label(const MaterialDesc& m, bool packed) {
    std::string label = m.normal.kind == TextureSource::Kind::none ? "derived from the height, " + source_label(m.height)
                                                                   : source_label(m.normal);
    if (m.normal.kind == TextureSource::Kind::file)
        label += m.normal.green == TextureSource::Green::down ? ", green down (DirectX style)" : ", green up (OpenGL style)";
    if (packed && m.normal.kind != TextureSource::Kind::none)
        label += m.height.kind == TextureSource::Kind::file && m.height.path == m.normal.path
                     ? ", with the height in its own alpha"
                     : ", with the height (" + source_label(m.height) + ") in alpha";
    return label;
}

// One texture slot from its texture file (every level as given) or from the
// CPU image (RGBA8, mipmapped by the GPU); what happened goes to `uploads`.
struct FileUpload {
    const TextureFileSupport* files;
    DecodeLevel decode;
};

Result<Texture> upload_slot(const std::optional<TextureData>& file, const Image& image, const std::string& label,
                            bool mipmaps, const Caps& caps, bool force_decode, std::vector<TextureUpload>& uploads,
                            const FileUpload& files, bool srgb_unit = false) {
    TextureUpload report;
    if (file) {
        if (!files.files || !files.files->upload)
            return make_error(label + ": the scene was prepared with texture files, and this renderer uploads none: "
                                      "set RendererOptions::texture_files = px::texture_files()");
        Result<Texture> t =
            files.files->upload(*file, caps, label, mipmaps, force_decode, &report, files.decode, srgb_unit);
        if (t) uploads.push_back(report);
        return t;
    }
    Result<Texture> t = upload_texture(image, caps, label, mipmaps, srgb_unit);
    if (t) {
        report.color_space = srgb_unit ? "sRGB" : "linear";
        report.what = label;
        report.container = "image";
        report.format = TextureFormat::rgba8;
        report.width = static_cast<std::uint32_t>(image.width);
        report.height = static_cast<std::uint32_t>(image.height);
        report.levels = mipmaps ? full_mip_count(report.width, report.height) : 1;
        report.path = mipmaps ? "RGBA8, mip chain generated by the GPU" : "RGBA8, base level";
        std::uint64_t bytes = 0;
        for (int l = 0; l < report.levels; ++l) bytes += 4ull * mip_extent(report.width, l) * mip_extent(report.height, l);
        report.gpu_bytes = bytes;
        uploads.push_back(report);
    }
    return t;
}

// maxmip's pyramid of the traced field: mip levels on GLSL ES 3.00, one
// atlas on GLSL ES 1.00 (assets/max_mipmap.h).
Status upload_pyramid(GpuMaterial& g, const HeightField& field, bool height_11bit, const Caps& caps,
                      const std::string& what, const std::string& source) {
    const std::string label = what + " max pyramid of the height (" + source + ")";
    if (caps.es_major >= 3) {
        Result<MaxMipmap> max_pyramid = build_max_mipmap(field, height_11bit ? 11 : 8);
        if (!max_pyramid) return with_context(what + " height (" + source + ")", max_pyramid.error());
        Result<Texture> max_map = upload_max_mipmap(*max_pyramid, caps, label);
        if (!max_map) return max_map.error();
        g.max_map = std::move(*max_map);
        g.max_levels = max_pyramid->level_count();
        return {};
    }
    Result<MaxAtlas> atlas = build_max_atlas(field);
    if (!atlas) return with_context(what + " height (" + source + ")", atlas.error());
    Result<Texture> max_map = upload_max_atlas(*atlas, caps, label);
    if (!max_map) return max_map.error();
    g.max_map = std::move(*max_map);
    g.max_levels = atlas->levels;
    g.max_atlas = glm::vec4(1.0f / static_cast<float>(atlas->image.width), 1.0f / static_cast<float>(atlas->image.height),
                            static_cast<float>(field.width), std::log2(static_cast<float>(field.height)));
    return {};
}

// A material's textures on the GPU: what its planned variants read, or
// for a material that names its technique (`named`: the planner's plan of
// it on this context), what that variant reads.
Result<GpuMaterial> upload_material(const MaterialDesc& m, const MaterialImages& images, const Caps& caps,
                                    const VariantPlan* named, bool force_decode, std::vector<TextureUpload>& uploads,
                                    std::vector<std::string>& notes, const TextureFileSupport* files) {
    GpuMaterial g;
    g.desc = &m;
    const std::string what = "material '" + echo(m.name) + "'";
    for (const std::string& note : images.notes) notes.push_back(what + ": " + note);
    const HeightField& field = images.traced;
    g.planned = m.effects.has_value();
    bool traced = false, pyramid = false;
    if (g.planned) {
        // Any technique may be chosen as the camera moves: upload what
        // tracing needs wherever there is a relief to trace.
        traced = m.effects->parallax && m.height_scale > 0.0f;
        // Where this context can draw maxmip on this field (a power of two
        // each way; on ES 2.0 an atlas within GL_MAX_TEXTURE_SIZE).
        pyramid = traced && why_technique_cannot_run(Technique::maxmip, caps, field.width, field.height).empty();
    } else {
        if (!named) return make_error(what + ": the planner has no plan for it");
        traced = (technique_info(named->key.technique).options & kOptHeight) != 0;
        // The techniques with an exact walk's budget (kOptSteps) walk a max pyramid.
        pyramid = (technique_info(named->key.technique).options & kOptSteps) != 0;
    }
    const FileUpload file_upload{files, images.decode};
    Result<Texture> albedo = upload_slot(images.albedo_texture, images.albedo,
                                         what + " albedo (" + source_label(m.albedo) + ")", true, caps, force_decode,
                                         uploads, file_upload, images.albedo_srgb && !images.layout.albedo_srgb_decode);
    if (!albedo) return albedo.error();
    // How its colour is read, and what decided it.
    uploads.back().color_space = (!images.albedo_srgb                   ? "linear, "
                                  : images.layout.albedo_srgb_decode ? "sRGB, decoded in the shader (no sRGB textures here), "
                                                                     : "sRGB, decoded by the texture unit, ") +
                                 images.albedo_color_space;
    g.albedo = std::move(*albedo);
    Result<Texture> normal =
        upload_slot(images.normal_texture, images.normal,
                    what + " normal map (" + normal_label(m, images.layout.packed_height) + ")", true, caps, force_decode, uploads,
                    file_upload);
    if (!normal) return normal.error();
    g.normal = std::move(*normal);
    const bool base_level_trace = traced && caps.es_major < 3;
    const bool separate = images.height.has_value() || images.height_texture.has_value();
    if (separate || base_level_trace) {
        const std::string label = what + " height (" +
                                  (separate ? source_label(m.height) : normal_label(m, images.layout.packed_height)) + ")" +
                                  (base_level_trace ? ", base level for the trace" : "");
        Result<Texture> height =
            separate ? upload_slot(images.height_texture, images.height ? *images.height : images.normal, label,
                                   !base_level_trace, caps, force_decode, uploads, file_upload)
                     : upload_slot(images.normal_texture, images.normal, label, false, caps, force_decode, uploads,
                                   file_upload);
        if (!height) return height.error();
        g.height = std::move(*height);
    }
    const Texture& traced_texture = g.height.handle ? g.height : g.normal;
    g.traced_size = glm::vec2(static_cast<float>(traced_texture.width), static_cast<float>(traced_texture.height));
    if (pyramid) {
        Status built = upload_pyramid(g, field, images.layout.height_11bit, caps, what, source_label(m.height));
        if (!built) return built.error();
    }
    return g;
}

// A planned variant as a default frame (HostFrame::target_color) draws it:
// what load and set_view build ahead of the frame.
VariantKey as_default_frame(VariantKey key) {
    key.srgb_output = HostFrame{}.target_color == HostFrame::TargetColor::srgb_encoded;
    return key;
}

bool same_plan_view(const PlanView& a, const PlanView& b) {
    return a.width == b.width && a.height == b.height && a.view == b.view && a.projection == b.projection &&
           a.models == b.models;
}

// The size of a framebuffer's renderbuffer attachments, where GL can tell
// (a texture attachment's size cannot be queried on ES 3.0, nor the default
// framebuffer's: the host knows those). {0, 0}: nothing to compare with.
glm::ivec2 renderbuffer_extent(GLuint framebuffer) {
    glm::ivec2 extent(0);
    if (framebuffer == 0) return extent;
    GLint previous = 0;
    glGetIntegerv(GL_RENDERBUFFER_BINDING, &previous);
    const GLenum attachments[] = {GL_COLOR_ATTACHMENT0, GL_DEPTH_ATTACHMENT, GL_STENCIL_ATTACHMENT};
    for (GLenum a : attachments) {
        GLint type = GL_NONE, name = 0;
        glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER, a, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
        if (type != GL_RENDERBUFFER) continue;
        glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER, a, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
        glBindRenderbuffer(GL_RENDERBUFFER, static_cast<GLuint>(name));
        GLint w = 0, h = 0;
        glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_WIDTH, &w);
        glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_HEIGHT, &h);
        // The framebuffer's extent is its smallest attachment's.
        extent.x = extent.x == 0 ? w : std::min(extent.x, w);
        extent.y = extent.y == 0 ? h : std::min(extent.y, h);
    }
    glBindRenderbuffer(GL_RENDERBUFFER, static_cast<GLuint>(previous));
    return extent;
}

std::string size_text(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

}  // namespace

HostFrame HostFrame::from_camera(const CameraDesc& camera, const RenderTarget& target, const Viewport& viewport) {
    HostFrame f;
    f.target = target;
    f.viewport = viewport;
    const bool whole = viewport.width == 0 && viewport.height == 0;
    const PlanView v = PlanView::from_camera(camera, whole ? target.width : viewport.width,
                                             whole ? target.height : viewport.height);
    f.view = v.view;
    f.projection = v.projection;
    return f;
}

Renderer::~Renderer() {
    // The library's debug callback goes with it, where it put one (a host's
    // own is never touched) and its context is current.
    if (owns_debug_callback_ && check_context("destroy")) remove_debug_messages(get_proc_address_);
    release();
}

Result<std::unique_ptr<Renderer>> Renderer::create(const RendererOptions& options) {
    const GLubyte* version = glGetString(GL_VERSION);
    if (!version) return make_error("no current OpenGL ES context: make one current before creating the renderer");
    std::unique_ptr<Renderer> r(new Renderer());
    r->caps_ = query_caps();
    if (r->caps_.es_major < 2)
        return make_error("the current context is '" + r->caps_.version + "'; ParallaxES needs OpenGL ES 2.0 or later");
    if (options.emulate_es2 && r->caps_.es_major >= 3) {
        // Everything the ES 2.0 path keys on is the major version (the
        // planner, uploads, draws, capture); the extensions stay this
        // context's, which offers every ES 2.0 one it lists. The ES 3.0
        // state the context has is still saved and reset (context_es3).
        r->caps_.context_es_major = r->caps_.es_major;
        r->caps_.es_major = 2;
        r->caps_.es_minor = 0;
    }
    if (options.emulate_no_fragment_highp && r->caps_.es_major < 3) r->caps_.fragment_highp = false;
    if (options.emulate_no_texture_npot && r->caps_.es_major < 3) r->caps_.extensions.erase("GL_OES_texture_npot");
    r->shader_transform_ = options.shader_transform;
    r->count_work_ = options.count_work;
    r->capture_ray_ = options.capture_ray;
    r->variant_transform_ = options.variant_transform;
    r->force_texture_decode_ = options.force_texture_decode;
    r->planner_options_ = options.planner;
    r->effect_planner_ = options.effect_planner;
    r->texture_files_ = options.texture_files;
    r->preserve_host_state_ = options.preserve_host_state;
    // Which context is current: the host's function, or EGL's through the
    // loader (EGL 1.5 and EGL_KHR_get_all_proc_addresses return core EGL
    // functions from eglGetProcAddress).
    if (options.current_context) {
        r->current_context_ = options.current_context;
    } else if (options.get_proc_address) {
        using CurrentContext = void* (*)();
        if (void* f = options.get_proc_address("eglGetCurrentContext")) {
            const auto current = reinterpret_cast<CurrentContext>(f);
            r->current_context_ = [current]() -> const void* { return current(); };
        }
    }
    if (r->current_context_) r->context_ = r->current_context_();
    r->get_proc_address_ = options.get_proc_address;
    r->owns_debug_callback_ =
        install_debug_messages(options.get_proc_address, r->caps_.khr_debug()) == DebugMessages::installed;
    if (options.program_binaries.enabled()) {
        r->program_binaries_ = options.program_binaries;
        r->binary_support_ = query_program_binary_support(r->caps_, options.get_proc_address);
    }
    return r;
}

Status Renderer::check_context(const char* what) const {
    if (!current_context_) return {};
    const void* now = current_context_();
    if (now == context_) return {};
    return make_error(std::string(what) + ": " +
                      (now ? "another OpenGL ES context is current than the one the renderer was created in"
                           : "no OpenGL ES context is current") +
                      "; make the renderer's context current first (a renderer draws only in its own context)");
}

MaterialImageOptions Renderer::material_image_options() const {
    MaterialImageOptions o;
    o.power_of_two_textures = !caps_.npot_mipmaps();
    o.srgb_textures = caps_.srgb_textures();
    o.files = texture_files_ ? texture_files_->readers : nullptr;
    return o;
}

PrepareOptions Renderer::prepare_options() const {
    PrepareOptions o;
    o.images = material_image_options();
    return o;
}

size_t Renderer::program_count() const { return scene_ ? scene_->programs.size() : 0; }

ProgramStats Renderer::program_stats() const {
    if (scene_) return scene_->programs.stats();
    return ProgramCache(shader_transform_, program_binaries_, binary_support_).stats();
}

void Renderer::release() {
    if (scene_ && !check_context("release")) {
        abandon();  // another context's objects may have the same names
        return;
    }
    scene_.reset();
    prepared_.reset();
}

void Renderer::abandon() {
    prepared_.reset();
    if (!scene_) return;
    for (GpuMesh& m : scene_->meshes) {
        m.vertices.abandon();
        m.indices.abandon();
        m.vertex_array.abandon();
    }
    for (GpuMaterial& m : scene_->materials) {
        m.albedo.handle.abandon();
        m.normal.handle.abandon();
        m.height.handle.abandon();
        m.max_map.handle.abandon();
    }
    scene_->programs.abandon();
    scene_.reset();
}

Status Renderer::load(const SceneDesc& scene) {
    if (Status c = check_context("load"); !c) return c;
    Result<std::shared_ptr<const PreparedScene>> prepared = prepare_scene(scene, prepare_options());
    if (!prepared) return prepared.error();
    return load(std::move(*prepared));
}

Status Renderer::load(std::shared_ptr<const PreparedScene> scene) {
    if (Status c = check_context("load"); !c) return c;
    if (!scene) return make_error("load: no prepared scene (null)");
    const MaterialImageOptions needed = material_image_options();
    if (scene->options.images.power_of_two_textures != needed.power_of_two_textures && needed.power_of_two_textures)
        return make_error("load: scene '" + echo(scene->desc.name) +
                          "' was prepared for a context with non-power-of-two textures; this one has none "
                          "(prepare it with Renderer::prepare_options())");
    const std::string name = scene->desc.name;
    // Any partial GPU scene is released by its handles' destructors, and the
    // host's GL state restored, on the way out.
    return out_of_memory_is_an_error("loading scene '" + echo(name) + "'",
                                     [&] { return load_checked(std::move(scene)); });
}

Status Renderer::load_checked(std::shared_ptr<const PreparedScene> prepared) {
    discard_pending_errors();
    std::optional<SavedGlState> saved;
    if (preserve_host_state_) saved.emplace(caps_);
    set_unpack_defaults(caps_);
    auto gpu = std::make_unique<GpuScene>();
    gpu->programs = ProgramCache(shader_transform_, program_binaries_, binary_support_);
    const SceneDesc& desc = prepared->desc;

    // The planner first: it refuses a scene it cannot plan before anything
    // is uploaded, and says what each named material draws (plan_variant,
    // once per material).
    Result<std::unique_ptr<FramePlanner>> planner = make_planner(prepared, {});
    if (!planner) return planner.error();
    gpu->planner = std::move(*planner);
    std::vector<TextureUpload> uploads;
    std::vector<std::string> notes;
    for (size_t i = 0; i < desc.materials.size(); ++i) {
        Result<GpuMaterial> g = upload_material(desc.materials[i], prepared->materials[i]->images, caps_,
                                                gpu->planner->material_plan(i), force_texture_decode_, uploads, notes,
                                                texture_files_);
        if (!g) return g.error();
        gpu->materials.push_back(std::move(*g));
    }
    gpu->camera = desc.camera;
    for (size_t i = 0; i < desc.objects.size(); ++i) {
        const ObjectDesc& o = desc.objects[i];
        Result<GpuMesh> g = upload_object_mesh(o, *prepared->objects[i], caps_);
        if (!g) return g.error();
        gpu->meshes.push_back(std::move(*g));
        GpuObject object;
        object.desc = &o;
        object.mesh = gpu->meshes.size() - 1;
        object.material = prepared->objects[i]->material;
        gpu->objects.push_back(object);
    }
    // The variants of materials that name their technique do not depend on
    // the frame: build them now, so that a shader error surfaces at load.
    // Those the planner picks per frame are built by the frame that draws them.
    for (auto [object, named] : gpu->planner->named_variants()) {
        VariantKey key = as_default_frame(named);
        key = variant_transform_ ? variant_transform_(key).canonical() : key.canonical();
        Result<const Program*> program = gpu->programs.get(key);
        if (!program)
            return with_context("material '" + echo(gpu->materials[gpu->objects[object].material].desc->name) + "'",
                                program.error());
    }
    scene_ = std::move(gpu);
    prepared_ = std::move(prepared);
    texture_uploads_ = std::move(uploads);
    texture_notes_ = std::move(notes);
    reports_.clear();
    return {};
}

Status Renderer::replace_material(const MaterialDesc& material) {
    if (Status c = check_context("replace_material"); !c) return c;
    if (!scene_ || !prepared_) return make_error("replace_material: no scene loaded");
    Result<std::shared_ptr<const PreparedScene>> next = px::replace_material(*prepared_, material);
    if (!next) return next.error();
    const PreparedScene& p = **next;
    const size_t mi = p.desc.material_index(material.name);
    return out_of_memory_is_an_error("replacing material '" + echo(material.name) + "'", [&]() -> Status {
        discard_pending_errors();
        std::optional<SavedGlState> saved;
        if (preserve_host_state_) saved.emplace(caps_);
        set_unpack_defaults(caps_);
        // The planner of the new scene first (the other materials' reliefs
        // as measured at load): it refuses what it cannot plan, and plans
        // the new material if it names its technique.
        std::vector<MaterialRelief> reliefs = scene_->planner->reliefs();
        reliefs[mi] = MaterialRelief{};  // measured again by the factory
        Result<std::unique_ptr<FramePlanner>> planner = make_planner(*next, std::move(reliefs));
        if (!planner) return planner.error();
        std::vector<TextureUpload> uploads;
        std::vector<std::string> notes;
        Result<GpuMaterial> g = upload_material(p.desc.materials[mi], p.materials[mi]->images, caps_,
                                                (*planner)->material_plan(mi), force_texture_decode_, uploads, notes,
                                                texture_files_);
        if (!g) return g.error();
        // Meshes displaced from the new relief, before anything is replaced.
        std::vector<std::pair<size_t, GpuMesh>> meshes;
        for (size_t i = 0; i < p.objects.size(); ++i) {
            // Prepared again (displaced from the new relief, or widened by
            // other bounds): uploaded again.
            if (p.objects[i].get() == prepared_->objects[i].get()) continue;
            Result<GpuMesh> m = upload_object_mesh(p.desc.objects[i], *p.objects[i], caps_);
            if (!m) return m.error();
            meshes.emplace_back(scene_->objects[i].mesh, std::move(*m));
        }
        for (auto [object, named] : (*planner)->named_variants()) {
            if (p.objects[object]->material != mi) continue;
            VariantKey key = as_default_frame(named);
        key = variant_transform_ ? variant_transform_(key).canonical() : key.canonical();
            Result<const Program*> program = scene_->programs.get(key);
            if (!program) return with_context("material '" + echo(material.name) + "'", program.error());
        }
        // Nothing can fail from here: swap it all in.
        scene_->materials[mi] = std::move(*g);
        for (auto& [index, mesh] : meshes) scene_->meshes[index] = std::move(mesh);
        for (size_t i = 0; i < scene_->materials.size(); ++i) scene_->materials[i].desc = &p.desc.materials[i];
        for (size_t i = 0; i < scene_->objects.size(); ++i) scene_->objects[i].desc = &p.desc.objects[i];
        scene_->planner = std::move(*planner);
        scene_->planned = false;
        prepared_ = std::move(*next);
        texture_uploads_.insert(texture_uploads_.end(), uploads.begin(), uploads.end());
        return {};
    });
}

Result<std::vector<ObjectPlan>> Renderer::plan_view(const CameraDesc& camera, int width, int height) const {
    if (!scene_) return make_error("plan: no scene loaded");
    if (width < 1 || height < 1) return make_error("plan: image size " + size_text(width, height) + " is empty");
    return scene_->planner->plan(PlanView::from_camera(camera, width, height));
}

Result<std::unique_ptr<FramePlanner>> Renderer::make_planner(const std::shared_ptr<const PreparedScene>& scene,
                                                             std::vector<MaterialRelief> reliefs) const {
    if (effect_planner_) return effect_planner_(*scene, caps_, planner_options_, std::move(reliefs));
    return named_planner(scene, caps_);
}

Result<int> Renderer::apply_plans(const PlanView& view) {
    if (scene_->planned && same_plan_view(view, scene_->planned_for)) return 0;
    Result<std::vector<ObjectPlan>> plans = scene_->planner->plan(view);
    if (!plans) return plans.error();
    int changed = 0;
    std::vector<DrawReport> reports;
    for (size_t i = 0; i < scene_->objects.size(); ++i) {
        GpuObject& object = scene_->objects[i];
        ObjectPlan& plan = (*plans)[i];
        if (variant_transform_) plan.key = variant_transform_(plan.key).canonical();
        if (!(plan.key == object.plan.key)) ++changed;
        object.plan = std::move(plan);
        const MaterialDesc& m = *scene_->materials[object.material].desc;
        reports.push_back(DrawReport{object.desc->name, object.desc->material, m.technique.technique, object.plan.key,
                                     object.plan.notes, object.plan});
    }
    scene_->planned_for = view;
    scene_->planned = true;
    ++stats_.plans;
    reports_ = std::move(reports);
    return changed;
}

Result<int> Renderer::set_view(const CameraDesc& camera, int width, int height) {
    if (Status c = check_context("set_view"); !c) return c.error();
    if (!scene_) return make_error("set_view: no scene loaded");
    if (width < 1 || height < 1) return make_error("set_view: image size " + size_text(width, height) + " is empty");
    std::optional<SavedGlState> saved;
    if (preserve_host_state_) saved.emplace(caps_);
    Result<int> changed = apply_plans(PlanView::from_camera(camera, width, height));
    if (!changed) return changed;
    scene_->camera = camera;
    // Build what the plans draw now, outside the frame.
    for (const GpuObject& object : scene_->objects) {
        Result<const Program*> program = scene_->programs.get(as_default_frame(object.plan.key));
        if (!program)
            return with_context("material '" + echo(scene_->materials[object.material].desc->name) + "'", program.error());
    }
    return changed;
}

Status Renderer::prepare(const std::vector<VariantKey>& keys) {
    if (Status c = check_context("prepare"); !c) return c;
    if (!scene_) return make_error("prepare: no scene loaded");
    discard_pending_errors();
    std::optional<SavedGlState> saved;
    if (preserve_host_state_) saved.emplace(caps_);
    for (const VariantKey& key : keys) {
        Result<const Program*> program = scene_->programs.get(key);
        if (!program) return program.error();
    }
    return {};
}

HostFrame Renderer::scene_frame(const RenderTarget& target, std::uint8_t debug_output) const {
    HostFrame f = HostFrame::from_camera(scene_ ? scene_->camera : CameraDesc{}, target);
    f.clear_color = true;
    f.clear_depth = true;
    f.debug_output = debug_output;
    return f;
}

Status Renderer::draw(const RenderTarget& target, std::uint8_t debug_output) {
    if (target.width < 1 || target.height < 1)
        return make_error("draw: target size " + size_text(target.width, target.height) + " is empty");
    return draw(scene_frame(target, debug_output));
}

Status Renderer::draw(const HostFrame& frame) {
    if (Status c = check_context("draw"); !c) return c;
    if (!scene_) return make_error("draw: no scene loaded");
    const RenderTarget& target = frame.target;
    if (target.width < 1 || target.height < 1)
        return make_error("draw: target size " + size_text(target.width, target.height) + " is empty");
    const Viewport& v = frame.viewport;
    const bool whole = v.width == 0 && v.height == 0 && v.x == 0 && v.y == 0;
    if (!whole && (v.width < 1 || v.height < 1 || v.x < 0 || v.y < 0 || v.x > target.width - v.width ||
                   v.y > target.height - v.height))
        return make_error("draw: viewport " + size_text(v.width, v.height) + " at (" + std::to_string(v.x) + ", " +
                          std::to_string(v.y) + ") is empty or not inside the " + size_text(target.width, target.height) +
                          " target");
    if (!frame.models.empty() && frame.models.size() != scene_->objects.size())
        return make_error("draw: " + std::to_string(frame.models.size()) + " model transforms for " +
                          std::to_string(scene_->objects.size()) + " objects (give one per object, in scene order, "
                          "or none)");
    discard_pending_errors();
    std::optional<SavedGlState> saved;
    if (preserve_host_state_) saved.emplace(caps_);
    return draw_checked(frame);
}

Status Renderer::draw_checked(const HostFrame& frame) {
    const RenderTarget& target = frame.target;
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return make_error("draw: target framebuffer " + std::to_string(target.framebuffer) +
                          " is incomplete: " + framebuffer_status_name(status));
    const glm::ivec2 extent = renderbuffer_extent(target.framebuffer);
    if ((extent.x > 0 && target.width > extent.x) || (extent.y > 0 && target.height > extent.y))
        return make_error("draw: target size " + size_text(target.width, target.height) + " does not fit framebuffer " +
                          std::to_string(target.framebuffer) + ", whose attachments are " +
                          size_text(extent.x, extent.y));
    Viewport vp = frame.viewport;
    if (vp.width == 0 && vp.height == 0) vp = Viewport{0, 0, target.width, target.height};
    PlanView view;
    view.view = frame.view;
    view.projection = frame.projection;
    view.width = vp.width;
    view.height = vp.height;
    view.models = frame.models;
    Result<int> planned = apply_plans(view);
    if (!planned) return planned.error();
    // Debug outputs: alpha marks drawn pixels, -1 (float target) or 0 (packed) where nothing is.
    const SceneDesc& scene = prepared_->desc;
    const std::uint8_t debug = frame.debug_output;
    const glm::vec4 clear = debug == 0 ? glm::vec4(scene.background, 1.0f)
                                       : glm::vec4(0.0f, 0.0f, 0.0f, debug == 1 ? -1.0f : 0.0f);
    set_draw_state(caps_, frame, vp, clear);
    const FrameValues values = frame_values(scene, frame);
    for (size_t i = 0; i < scene_->objects.size(); ++i) {
        const GpuObject& object = scene_->objects[i];
        VariantKey key = object.plan.key;
        key.debug_output = debug;
        key.srgb_output = frame.target_color == HostFrame::TargetColor::srgb_encoded && debug == 0;
        key.count_work = count_work_ && debug != 0;
        key.capture_ray = capture_ray_ && debug == 1;
        const glm::mat4 model = frame.models.empty() ? object.desc->transform.matrix() : frame.models[i];
        Status s = draw_object(*scene_, object, model, key, object.plan.options, values);
        if (!s) return s;
    }
    ++stats_.frames;
    stats_.objects_drawn += scene_->objects.size();
    return check_gl("drawing scene '" + echo(scene.name) + "'");
}

Status Renderer::prepare(const std::vector<std::vector<ObjectPlan>>& frames, const RenderTarget& warm_target) {
    if (Status c = check_context("prepare"); !c) return c;
    if (!scene_) return make_error("prepare: no scene loaded");
    if (warm_target.width < 1 || warm_target.height < 1) return make_error("prepare: the warm-up target is empty");
    discard_pending_errors();
    std::optional<SavedGlState> saved;
    if (preserve_host_state_) saved.emplace(caps_);
    glBindFramebuffer(GL_FRAMEBUFFER, warm_target.framebuffer);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return make_error(std::string("prepare: warm-up framebuffer is incomplete: ") + framebuffer_status_name(status));
    // Drivers finish compiling at a program's first draw (Mesa's llvmpipe
    // JITs its shader variant then): draw each object once with each
    // variant it will need, so that no frame of the path pays for it.
    HostFrame frame = scene_frame(warm_target);
    const Viewport whole{0, 0, warm_target.width, warm_target.height};
    set_draw_state(caps_, frame, whole, glm::vec4(0.0f));
    const FrameValues values = frame_values(prepared_->desc, frame);
    std::vector<std::vector<std::string>> warmed(scene_->objects.size());
    for (const std::vector<ObjectPlan>& plans : frames) {
        if (plans.size() != scene_->objects.size())
            return make_error("prepare: a frame has " + std::to_string(plans.size()) + " plans for " +
                              std::to_string(scene_->objects.size()) + " objects");
        for (size_t i = 0; i < plans.size(); ++i) {
            const std::string id = plans[i].key.id();
            if (std::find(warmed[i].begin(), warmed[i].end(), id) != warmed[i].end()) continue;
            warmed[i].push_back(id);
            const GpuObject& object = scene_->objects[i];
            // As a default frame draws it: encoded for an sRGB display.
            VariantKey key = plans[i].key;
            key.srgb_output = frame.target_color == HostFrame::TargetColor::srgb_encoded;
            Status s = draw_object(*scene_, object, object.desc->transform.matrix(), key, plans[i].options, values);
            if (!s) return s;
        }
    }
    glFinish();
    return check_gl("warming the programs of scene '" + echo(prepared_->desc.name) + "'");
}

}  // namespace px
