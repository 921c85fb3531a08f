#include "render/renderer.h"

#include <cmath>
#include <cstddef>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "core/limits.h"
#include "gl/texture.h"
#include "scene/material_images.h"

namespace px {

namespace {

struct GpuMesh {
    BufferHandle vertices;
    BufferHandle indices;
    GLsizei index_count = 0;
    GLenum index_type = GL_UNSIGNED_SHORT;
    float units_per_uv = 1.0f;
};

struct GpuMaterial {
    const MaterialDesc* desc = nullptr;
    Texture albedo;
    Texture normal;
    // What tracing loops read: the separate height map, or on GLSL ES 1.00 a
    // base-level-only copy of the packed normal map (or of the height map).
    // Empty when the traced reads come from `normal` (packed, ES 3.0).
    Texture height;
    Texture max_map;    // maxmip: the max pyramid
    int max_levels = 0;
    VariantPlan plan;
    HeightField field;  // 8-bit quantised, as uploaded: for displaced meshes
};

struct GpuObject {
    const ObjectDesc* desc = nullptr;
    size_t mesh = 0;
    size_t material = 0;
};

Mesh build_mesh(const MeshDesc& d) {
    switch (d.kind) {
        case MeshKind::plane: return make_plane(d.size, d.segments);
        case MeshKind::cube: return make_cube(d.size);
        case MeshKind::sphere: return make_uv_sphere(d.radius);
        case MeshKind::torus: return make_torus(d.radius, d.tube_radius);
    }
    return make_plane();
}

Result<GpuMesh> upload_mesh(const Mesh& mesh, const Caps& caps, const std::string& what) {
    GpuMesh g;
    g.units_per_uv = mesh.units_per_uv;
    g.vertices = make_buffer();
    glBindBuffer(GL_ARRAY_BUFFER, g.vertices.get());
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.vertices.size() * sizeof(Vertex)),
                 mesh.vertices.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
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
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    g.index_count = static_cast<GLsizei>(mesh.indices.size());
    Status s = check_gl("uploading " + what);
    if (!s) return s.error();
    return g;
}


// Restores the host's GL state on scope exit (the renderer draws into
// contexts it does not own).
class SavedState {
public:
    SavedState() {
        glGetIntegerv(GL_FRAMEBUFFER_BINDING, &framebuffer_);
        glGetIntegerv(GL_VIEWPORT, viewport_);
        glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
        glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer_);
        glGetIntegerv(GL_ELEMENT_ARRAY_BUFFER_BINDING, &element_buffer_);
        glGetIntegerv(GL_ACTIVE_TEXTURE, &active_texture_);
        for (int i = 0; i < 4; ++i) {
            glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + i));
            glGetIntegerv(GL_TEXTURE_BINDING_2D, &textures_[i]);
        }
        depth_test_ = glIsEnabled(GL_DEPTH_TEST);
        cull_face_ = glIsEnabled(GL_CULL_FACE);
        blend_ = glIsEnabled(GL_BLEND);
        glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
        glGetIntegerv(GL_DEPTH_FUNC, &depth_func_);
        glGetIntegerv(GL_FRONT_FACE, &front_face_);
        glGetFloatv(GL_COLOR_CLEAR_VALUE, clear_color_);
    }
    ~SavedState() {
        glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(framebuffer_));
        glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
        glUseProgram(static_cast<GLuint>(program_));
        glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(array_buffer_));
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLuint>(element_buffer_));
        for (int i = 0; i < 4; ++i) {
            glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + i));
            glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(textures_[i]));
        }
        glActiveTexture(static_cast<GLenum>(active_texture_));
        enable(GL_DEPTH_TEST, depth_test_);
        enable(GL_CULL_FACE, cull_face_);
        enable(GL_BLEND, blend_);
        glDepthMask(depth_mask_);
        glDepthFunc(static_cast<GLenum>(depth_func_));
        glFrontFace(static_cast<GLenum>(front_face_));
        glClearColor(clear_color_[0], clear_color_[1], clear_color_[2], clear_color_[3]);
        for (GLuint a = 0; a < 4; ++a) glDisableVertexAttribArray(a);
    }
    SavedState(const SavedState&) = delete;
    SavedState& operator=(const SavedState&) = delete;

private:
    static void enable(GLenum cap, GLboolean on) { on ? glEnable(cap) : glDisable(cap); }
    GLint framebuffer_ = 0, viewport_[4] = {0, 0, 0, 0}, program_ = 0, array_buffer_ = 0, element_buffer_ = 0;
    GLint active_texture_ = GL_TEXTURE0, textures_[4] = {0, 0, 0, 0}, depth_func_ = GL_LESS, front_face_ = GL_CCW;
    GLboolean depth_test_ = GL_FALSE, cull_face_ = GL_FALSE, blend_ = GL_FALSE, depth_mask_ = GL_TRUE;
    GLfloat clear_color_[4] = {0, 0, 0, 0};
};

}  // namespace

struct Renderer::GpuScene {
    SceneDesc desc;  // owned copy: materials and objects point into it
    std::vector<GpuMesh> meshes;
    std::vector<GpuMaterial> materials;
    std::vector<GpuObject> objects;
    ProgramCache programs;
};

Renderer::~Renderer() { release(); }

Result<std::unique_ptr<Renderer>> Renderer::create(const RendererOptions& options) {
    const GLubyte* version = glGetString(GL_VERSION);
    if (!version) return make_error("no current OpenGL ES context: make one current before creating the renderer");
    std::unique_ptr<Renderer> r(new Renderer());
    r->caps_ = query_caps();
    if (r->caps_.es_major < 2)
        return make_error("the current context is '" + r->caps_.version + "'; ParallaxES needs OpenGL ES 2.0 or later");
    install_debug_messages(options.get_proc_address, r->caps_.khr_debug());
    return r;
}

size_t Renderer::program_count() const { return scene_ ? scene_->programs.size() : 0; }

void Renderer::release() { scene_.reset(); }

void Renderer::abandon() {
    if (!scene_) return;
    for (GpuMesh& m : scene_->meshes) {
        m.vertices.abandon();
        m.indices.abandon();
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
    Status valid = validate_scene(scene);
    if (!valid) return valid;
    auto gpu = std::make_unique<GpuScene>();
    gpu->desc = scene;
    const SceneDesc& desc = gpu->desc;
    std::vector<DrawReport> reports;

    for (const MaterialDesc& m : desc.materials) {
        GpuMaterial g;
        g.desc = &m;
        Result<VariantPlan> plan = plan_variant(m, caps_);
        if (!plan) return with_context("material '" + m.name + "'", plan.error());
        g.plan = std::move(*plan);
        Result<MaterialImages> images = build_material_images(m, desc.base_dir);
        if (!images) return images.error();
        const std::string what = "material '" + m.name + "'";
        g.field = images->field;
        for (float& h : g.field.texels) h = std::round(h * 255.0f) / 255.0f;
        Result<Texture> albedo = upload_texture(images->albedo, caps_, what + " albedo");
        if (!albedo) return albedo.error();
        g.albedo = std::move(*albedo);
        Result<Texture> normal = upload_texture(images->normal, caps_, what + " normal map");
        if (!normal) return normal.error();
        g.normal = std::move(*normal);
        const bool traced = (technique_info(g.plan.key.technique).options & kOptHeight) != 0;
        const bool base_level_trace = traced && g.plan.key.es_major < 3;
        const Image* trace_image = images->height ? &*images->height
                                   : base_level_trace ? &images->normal
                                                      : nullptr;
        if (trace_image) {
            Result<Texture> height = upload_texture(*trace_image, caps_, what + " traced height", !base_level_trace);
            if (!height) return height.error();
            g.height = std::move(*height);
        }
        if (g.plan.key.technique == Technique::maxmip) {
            Result<MaxMipmap> pyramid = build_max_mipmap(g.field);
            if (!pyramid) return with_context(what, pyramid.error());
            Result<Texture> max_map = upload_max_mipmap(*pyramid, caps_, what + " max pyramid");
            if (!max_map) return max_map.error();
            g.max_map = std::move(*max_map);
            g.max_levels = pyramid->level_count();
        }
        // Build the colour program now, so a shader error surfaces at load.
        Result<const Program*> program = gpu->programs.get(g.plan.key);
        if (!program) return with_context(what, program.error());
        gpu->materials.push_back(std::move(g));
    }
    for (const ObjectDesc& o : desc.objects) {
        const std::string what = "object '" + o.name + "'";
        size_t material_index = 0;
        for (size_t i = 0; i < desc.materials.size(); ++i)
            if (desc.materials[i].name == o.material) material_index = i;
        Mesh mesh;
        if (o.mesh.displaced) {
            if (o.mesh.kind != MeshKind::plane)
                return make_error(what + ": only planes can be displaced (mesh.displaced)");
            const GpuMaterial& material = gpu->materials[material_index];
            const MaterialDesc& m = *material.desc;
            const float tiles = std::sqrt(std::fabs(glm::determinant(m.uv.matrix<float>())));
            const float scale = m.height_scale;
            Result<Mesh> displaced = make_displaced_plane(o.mesh.size, material.field, scale,
                                                          static_cast<float>(m.polygon_height()), o.mesh.size / tiles);
            if (!displaced) return with_context(what, displaced.error());
            mesh = std::move(*displaced);
        } else {
            mesh = build_mesh(o.mesh);
        }
        Result<GpuMesh> g = upload_mesh(mesh, caps_, what);
        if (!g) return g.error();
        gpu->meshes.push_back(std::move(*g));
        GpuObject object;
        object.desc = &o;
        object.mesh = gpu->meshes.size() - 1;
        object.material = material_index;
        gpu->objects.push_back(object);
        const GpuMaterial& material = gpu->materials[object.material];
        reports.push_back(DrawReport{o.name, o.material, material.desc->technique.technique, material.plan.key,
                                     material.plan.notes});
    }
    scene_ = std::move(gpu);
    reports_ = std::move(reports);
    return {};
}

Status Renderer::draw(const RenderTarget& target, std::uint8_t debug_output) {
    if (!scene_) return make_error("draw: no scene loaded");
    if (target.width < 1 || target.height < 1)
        return make_error("draw: target size " + std::to_string(target.width) + "x" + std::to_string(target.height) +
                          " is empty");
    SavedState saved;
    const SceneDesc& scene = scene_->desc;
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return make_error(std::string("draw: target framebuffer ") + std::to_string(target.framebuffer) +
                          " is incomplete: " + framebuffer_status_name(status));
    glViewport(0, 0, target.width, target.height);
    if (debug_output == 0)
        glClearColor(scene.background.r, scene.background.g, scene.background.b, 1.0f);
    else  // alpha marks drawn pixels: -1 (float target) or 0 (packed) where nothing is
        glClearColor(0.0f, 0.0f, 0.0f, debug_output == 1 ? -1.0f : 0.0f);
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glDisable(GL_BLEND);

    const CameraDesc& cam = scene.camera;
    const float aspect = static_cast<float>(target.width) / static_cast<float>(target.height);
    const glm::mat4 view = glm::lookAt(cam.position, cam.target, cam.up);
    const glm::mat4 projection = glm::perspective(glm::radians(cam.fov_y_deg), aspect, cam.near_plane, cam.far_plane);

    // Lights, shared by every draw.
    const int light_count = static_cast<int>(std::min<size_t>(scene.lights.size(), kMaxLights));
    float light_vectors[4 * kMaxLights] = {};
    float light_colors[3 * kMaxLights] = {};
    float light_radii[kMaxLights] = {};
    for (int i = 0; i < light_count; ++i) {
        const LightDesc& l = scene.lights[static_cast<size_t>(i)];
        const glm::vec3 v = l.kind == LightKind::point ? l.position : -glm::normalize(l.direction);
        light_vectors[4 * i + 0] = v.x;
        light_vectors[4 * i + 1] = v.y;
        light_vectors[4 * i + 2] = v.z;
        light_vectors[4 * i + 3] = l.kind == LightKind::point ? 1.0f : 0.0f;
        for (int c = 0; c < 3; ++c) light_colors[3 * i + c] = l.color[c] * l.intensity;
        light_radii[i] = glm::radians(l.angular_radius_deg);
    }

    for (const GpuObject& object : scene_->objects) {
        const GpuMaterial& material = scene_->materials[object.material];
        const GpuMesh& mesh = scene_->meshes[object.mesh];
        const MaterialDesc& m = *material.desc;
        VariantKey key = material.plan.key;
        key.debug_output = debug_output;
        Result<const Program*> program = scene_->programs.get(key);
        if (!program) return with_context("material '" + m.name + "'", program.error());
        const Program& p = **program;
        glUseProgram(p.id());

        const glm::mat4 model = object.desc->transform.matrix();
        const glm::mat3 model3(model);
        const glm::mat3 normal_matrix = glm::inverseTranspose(model3);
        const float handedness = glm::determinant(model3) < 0.0f ? -1.0f : 1.0f;
        glUniformMatrix4fv(p.uniform("u_model"), 1, GL_FALSE, glm::value_ptr(model));
        glUniformMatrix4fv(p.uniform("u_view"), 1, GL_FALSE, glm::value_ptr(view));
        glUniformMatrix4fv(p.uniform("u_projection"), 1, GL_FALSE, glm::value_ptr(projection));
        glUniformMatrix4fv(p.uniform("u_depth_projection"), 1, GL_FALSE, glm::value_ptr(projection));
        glUniformMatrix3fv(p.uniform("u_normal_matrix"), 1, GL_FALSE, glm::value_ptr(normal_matrix));
        glUniform1f(p.uniform("u_model_handedness"), handedness);
        // A mirroring model matrix reverses the triangles' winding on screen:
        // flip the front face so the object's outside stays the drawn side.
        glFrontFace(handedness < 0.0f ? GL_CW : GL_CCW);
        glUniform3fv(p.uniform("u_camera_position"), 1, glm::value_ptr(cam.position));

        const glm::mat2 uv = m.uv.matrix<float>();
        const float uv_det = std::fabs(glm::determinant(uv));
        const float uv_area_scale = std::sqrt(uv_det);
        const glm::mat2 uv_frame = uv / uv_area_scale;
        glUniformMatrix2fv(p.uniform("u_uv_matrix"), 1, GL_FALSE, glm::value_ptr(uv));
        glUniform2f(p.uniform("u_uv_offset"), m.uv.offset.x, m.uv.offset.y);
        glUniformMatrix2fv(p.uniform("u_uv_frame"), 1, GL_FALSE, glm::value_ptr(uv_frame));
        // View-space units per texture tile: mesh units per uv, times the
        // model's mean scale, over tiles per mesh uv.
        const float model_scale = std::cbrt(std::fabs(glm::determinant(model3)));
        glUniform1f(p.uniform("u_units_per_tile"), mesh.units_per_uv * model_scale / uv_area_scale);

        const float scale = m.height_scale;
        glUniform1f(p.uniform("u_height_scale"), scale);
        glUniform1f(p.uniform("u_inv_height_scale"), scale > 0.0f ? 1.0f / scale : 0.0f);
        glUniform1f(p.uniform("u_polygon_height"), static_cast<float>(m.polygon_height()));
        glUniform4fv(p.uniform("u_light_vector"), kMaxLights, light_vectors);
        glUniform3fv(p.uniform("u_light_color"), kMaxLights, light_colors);
        glUniform1fv(p.uniform("u_light_angular_radius"), kMaxLights, light_radii);
        glUniform1i(p.uniform("u_light_count"), light_count);
        glUniform3fv(p.uniform("u_ambient"), 1, glm::value_ptr(scene.ambient));
        glUniform2f(p.uniform("u_texture_size"), static_cast<float>(material.normal.width),
                    static_cast<float>(material.normal.height));
        // The planner's loop bound is the top of the dynamic range (it may
        // differ from the material's, e.g. on a fallback technique).
        const float top = static_cast<float>(key.max_samples > 0 ? key.max_samples : m.technique.max_samples);
        glUniform2f(p.uniform("u_sample_range"), std::min(static_cast<float>(m.technique.min_samples), top), top);
        glUniform2f(p.uniform("u_lod_range"), m.technique.lod_threshold, m.technique.lod_band);
        glUniform1f(p.uniform("u_specular"), 0.25f);
        glUniform1f(p.uniform("u_shininess"), 32.0f);

        glActiveTexture(GL_TEXTURE0);
        bind_texture(material.albedo);
        glUniform1i(p.uniform("u_albedo_map"), 0);
        glActiveTexture(GL_TEXTURE1);
        bind_texture(material.normal);
        glUniform1i(p.uniform("u_normal_map"), 1);
        if (material.height.handle) {
            glActiveTexture(GL_TEXTURE2);
            bind_texture(material.height);
            glUniform1i(p.uniform("u_height_map"), 2);
        }
        if (material.max_map.handle) {
            glActiveTexture(GL_TEXTURE3);
            bind_texture(material.max_map);
            glUniform1i(p.uniform("u_max_map"), 3);
            glUniform1i(p.uniform("u_max_levels"), material.max_levels);
        }

        glBindBuffer(GL_ARRAY_BUFFER, mesh.vertices.get());
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh.indices.get());
        const GLsizei stride = sizeof(Vertex);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(offsetof(Vertex, position)));
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(offsetof(Vertex, normal)));
        glEnableVertexAttribArray(2);
        glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(offsetof(Vertex, tangent)));
        glEnableVertexAttribArray(3);
        glVertexAttribPointer(3, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(offsetof(Vertex, uv)));
        glDrawElements(GL_TRIANGLES, mesh.index_count, mesh.index_type, nullptr);
        Status s = check_gl("drawing object '" + object.desc->name + "' with " + p.description());
        if (!s) return s;
    }
    return {};
}

}  // namespace px
