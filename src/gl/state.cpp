#include "parallaxes/gl/state.h"

namespace px {

namespace {

struct AttributeState {
    GLint enabled = 0, size = 4, type = GL_FLOAT, normalized = 0, stride = 0, buffer = 0;
    void* pointer = nullptr;
};

struct StencilFace {
    GLint func = GL_ALWAYS, ref = 0, value_mask = -1, fail = GL_KEEP, pass_depth_fail = GL_KEEP,
          pass_depth_pass = GL_KEEP, write_mask = -1;
};

GLint get_int(GLenum name) {
    GLint v = 0;
    glGetIntegerv(name, &v);
    return v;
}

void enable(GLenum cap, GLboolean on) { on ? glEnable(cap) : glDisable(cap); }

}  // namespace

struct SavedGlState::Snapshot {
    bool es3 = false;         // the context has ES 3.0 state
    bool points_attributes = false;  // the library points the context's attribute slots (the ES 2.0 path)
    GLint draw_framebuffer = 0, read_framebuffer = 0, renderbuffer = 0, program = 0;
    GLint array_buffer = 0, element_buffer = 0, vertex_array = 0, pack_buffer = 0, unpack_buffer = 0;
    GLint active_texture = GL_TEXTURE0;
    std::array<GLint, kLibraryTextureUnits> textures{}, samplers{};
    GLint pack_alignment = 4, unpack_alignment = 4;
    GLint unpack_row_length = 0, unpack_skip_rows = 0, unpack_skip_pixels = 0, unpack_image_height = 0,
          unpack_skip_images = 0, pack_row_length = 0, pack_skip_rows = 0, pack_skip_pixels = 0;
    GLint viewport[4] = {0, 0, 0, 0}, scissor_box[4] = {0, 0, 0, 0};
    GLboolean scissor_test = GL_FALSE, cull_face = GL_FALSE, polygon_offset_fill = GL_FALSE,
              rasterizer_discard = GL_FALSE;
    GLint cull_face_mode = GL_BACK, front_face = GL_CCW;
    GLboolean depth_test = GL_FALSE, depth_mask = GL_TRUE;
    GLint depth_func = GL_LESS;
    GLfloat depth_range[2] = {0.0f, 1.0f}, clear_depth = 1.0f;
    GLboolean blend = GL_FALSE;
    GLint blend_src_rgb = GL_ONE, blend_dst_rgb = GL_ZERO, blend_src_alpha = GL_ONE, blend_dst_alpha = GL_ZERO;
    GLint blend_equation_rgb = GL_FUNC_ADD, blend_equation_alpha = GL_FUNC_ADD;
    GLfloat blend_color[4] = {0, 0, 0, 0}, clear_color[4] = {0, 0, 0, 0};
    GLboolean color_mask[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
    GLboolean stencil_test = GL_FALSE, dither = GL_TRUE, sample_coverage = GL_FALSE,
              sample_alpha_to_coverage = GL_FALSE, primitive_restart = GL_FALSE;
    StencilFace stencil_front, stencil_back;
    std::array<AttributeState, kLibraryAttributeSlots> attributes{};
};

SavedGlState::SavedGlState(const Caps& caps) : saved_(std::make_unique<Snapshot>()) {
    Snapshot& s = *saved_;
    s.es3 = caps.context_es3();
    s.points_attributes = caps.es_major < 3;
    if (s.es3) {
        s.draw_framebuffer = get_int(GL_DRAW_FRAMEBUFFER_BINDING);
        s.read_framebuffer = get_int(GL_READ_FRAMEBUFFER_BINDING);
        s.vertex_array = get_int(GL_VERTEX_ARRAY_BINDING);
        s.pack_buffer = get_int(GL_PIXEL_PACK_BUFFER_BINDING);
        s.unpack_buffer = get_int(GL_PIXEL_UNPACK_BUFFER_BINDING);
        s.unpack_row_length = get_int(GL_UNPACK_ROW_LENGTH);
        s.unpack_skip_rows = get_int(GL_UNPACK_SKIP_ROWS);
        s.unpack_skip_pixels = get_int(GL_UNPACK_SKIP_PIXELS);
        s.unpack_image_height = get_int(GL_UNPACK_IMAGE_HEIGHT);
        s.unpack_skip_images = get_int(GL_UNPACK_SKIP_IMAGES);
        s.pack_row_length = get_int(GL_PACK_ROW_LENGTH);
        s.pack_skip_rows = get_int(GL_PACK_SKIP_ROWS);
        s.pack_skip_pixels = get_int(GL_PACK_SKIP_PIXELS);
        s.rasterizer_discard = glIsEnabled(GL_RASTERIZER_DISCARD);
        s.primitive_restart = glIsEnabled(GL_PRIMITIVE_RESTART_FIXED_INDEX);
    } else {
        s.draw_framebuffer = s.read_framebuffer = get_int(GL_FRAMEBUFFER_BINDING);
    }
    s.renderbuffer = get_int(GL_RENDERBUFFER_BINDING);
    s.program = get_int(GL_CURRENT_PROGRAM);
    s.array_buffer = get_int(GL_ARRAY_BUFFER_BINDING);
    s.element_buffer = get_int(GL_ELEMENT_ARRAY_BUFFER_BINDING);  // of the bound VAO on ES 3.0
    s.active_texture = get_int(GL_ACTIVE_TEXTURE);
    for (int i = 0; i < kLibraryTextureUnits; ++i) {
        glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + i));
        s.textures[static_cast<size_t>(i)] = get_int(GL_TEXTURE_BINDING_2D);
        if (s.es3) s.samplers[static_cast<size_t>(i)] = get_int(GL_SAMPLER_BINDING);
    }
    glActiveTexture(static_cast<GLenum>(s.active_texture));
    s.pack_alignment = get_int(GL_PACK_ALIGNMENT);
    s.unpack_alignment = get_int(GL_UNPACK_ALIGNMENT);

    glGetIntegerv(GL_VIEWPORT, s.viewport);
    glGetIntegerv(GL_SCISSOR_BOX, s.scissor_box);
    s.scissor_test = glIsEnabled(GL_SCISSOR_TEST);
    s.cull_face = glIsEnabled(GL_CULL_FACE);
    s.cull_face_mode = get_int(GL_CULL_FACE_MODE);
    s.front_face = get_int(GL_FRONT_FACE);
    s.polygon_offset_fill = glIsEnabled(GL_POLYGON_OFFSET_FILL);

    s.depth_test = glIsEnabled(GL_DEPTH_TEST);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &s.depth_mask);
    s.depth_func = get_int(GL_DEPTH_FUNC);
    glGetFloatv(GL_DEPTH_RANGE, s.depth_range);
    glGetFloatv(GL_DEPTH_CLEAR_VALUE, &s.clear_depth);
    s.blend = glIsEnabled(GL_BLEND);
    s.blend_src_rgb = get_int(GL_BLEND_SRC_RGB);
    s.blend_dst_rgb = get_int(GL_BLEND_DST_RGB);
    s.blend_src_alpha = get_int(GL_BLEND_SRC_ALPHA);
    s.blend_dst_alpha = get_int(GL_BLEND_DST_ALPHA);
    s.blend_equation_rgb = get_int(GL_BLEND_EQUATION_RGB);
    s.blend_equation_alpha = get_int(GL_BLEND_EQUATION_ALPHA);
    glGetFloatv(GL_BLEND_COLOR, s.blend_color);
    glGetBooleanv(GL_COLOR_WRITEMASK, s.color_mask);
    glGetFloatv(GL_COLOR_CLEAR_VALUE, s.clear_color);
    s.stencil_test = glIsEnabled(GL_STENCIL_TEST);
    s.stencil_front = {get_int(GL_STENCIL_FUNC), get_int(GL_STENCIL_REF), get_int(GL_STENCIL_VALUE_MASK),
                       get_int(GL_STENCIL_FAIL), get_int(GL_STENCIL_PASS_DEPTH_FAIL),
                       get_int(GL_STENCIL_PASS_DEPTH_PASS), get_int(GL_STENCIL_WRITEMASK)};
    s.stencil_back = {get_int(GL_STENCIL_BACK_FUNC), get_int(GL_STENCIL_BACK_REF),
                      get_int(GL_STENCIL_BACK_VALUE_MASK), get_int(GL_STENCIL_BACK_FAIL),
                      get_int(GL_STENCIL_BACK_PASS_DEPTH_FAIL), get_int(GL_STENCIL_BACK_PASS_DEPTH_PASS),
                      get_int(GL_STENCIL_BACK_WRITEMASK)};
    s.dither = glIsEnabled(GL_DITHER);
    s.sample_coverage = glIsEnabled(GL_SAMPLE_COVERAGE);
    s.sample_alpha_to_coverage = glIsEnabled(GL_SAMPLE_ALPHA_TO_COVERAGE);

    // Attribute state lives in the bound vertex array object. On ES 3.0 the
    // library binds a VAO of its own for every mesh it uploads or draws, so it
    // never writes the host's; on ES 2.0 it points the slots of the context
    // (or of an OES VAO the host bound): save those.
    for (int i = 0; i < kLibraryAttributeSlots && s.points_attributes; ++i) {
        AttributeState& a = s.attributes[static_cast<size_t>(i)];
        const GLuint slot = static_cast<GLuint>(i);
        glGetVertexAttribiv(slot, GL_VERTEX_ATTRIB_ARRAY_ENABLED, &a.enabled);
        glGetVertexAttribiv(slot, GL_VERTEX_ATTRIB_ARRAY_SIZE, &a.size);
        glGetVertexAttribiv(slot, GL_VERTEX_ATTRIB_ARRAY_TYPE, &a.type);
        glGetVertexAttribiv(slot, GL_VERTEX_ATTRIB_ARRAY_NORMALIZED, &a.normalized);
        glGetVertexAttribiv(slot, GL_VERTEX_ATTRIB_ARRAY_STRIDE, &a.stride);
        glGetVertexAttribiv(slot, GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING, &a.buffer);
        glGetVertexAttribPointerv(slot, GL_VERTEX_ATTRIB_ARRAY_POINTER, &a.pointer);
    }
}

SavedGlState::~SavedGlState() {
    const Snapshot& s = *saved_;
    if (s.es3) {
        glBindVertexArray(static_cast<GLuint>(s.vertex_array));
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(s.draw_framebuffer));
        glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(s.read_framebuffer));
    } else {
        glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(s.draw_framebuffer));
    }
    // ES 2.0: the attributes go back into the context (or an OES VAO the host
    // bound), each pointer with the buffer it was taken from. ES 3.0: the
    // library only points attributes of its own VAOs, and the host's VAO is
    // bound again above.
    for (int i = 0; i < kLibraryAttributeSlots && s.points_attributes; ++i) {
        const AttributeState& a = s.attributes[static_cast<size_t>(i)];
        const GLuint slot = static_cast<GLuint>(i);
        glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(a.buffer));
        glVertexAttribPointer(slot, a.size, static_cast<GLenum>(a.type), a.normalized ? GL_TRUE : GL_FALSE,
                              a.stride, a.pointer);
        a.enabled ? glEnableVertexAttribArray(slot) : glDisableVertexAttribArray(slot);
    }
    glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(s.array_buffer));
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLuint>(s.element_buffer));
    glBindRenderbuffer(GL_RENDERBUFFER, static_cast<GLuint>(s.renderbuffer));
    // A program the host deleted while it was current lives only as long as
    // it stays current: once the library's draw replaced it, it is gone, and
    // making it current again would be GL_INVALID_VALUE. Then none is.
    const GLuint program = static_cast<GLuint>(s.program);
    glUseProgram(program != 0 && glIsProgram(program) ? program : 0);
    for (int i = 0; i < kLibraryTextureUnits; ++i) {
        glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + i));
        glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(s.textures[static_cast<size_t>(i)]));
        if (s.es3) glBindSampler(static_cast<GLuint>(i), static_cast<GLuint>(s.samplers[static_cast<size_t>(i)]));
    }
    glActiveTexture(static_cast<GLenum>(s.active_texture));
    glPixelStorei(GL_PACK_ALIGNMENT, s.pack_alignment);
    glPixelStorei(GL_UNPACK_ALIGNMENT, s.unpack_alignment);
    if (s.es3) {
        glBindBuffer(GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(s.pack_buffer));
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(s.unpack_buffer));
        glPixelStorei(GL_UNPACK_ROW_LENGTH, s.unpack_row_length);
        glPixelStorei(GL_UNPACK_SKIP_ROWS, s.unpack_skip_rows);
        glPixelStorei(GL_UNPACK_SKIP_PIXELS, s.unpack_skip_pixels);
        glPixelStorei(GL_UNPACK_IMAGE_HEIGHT, s.unpack_image_height);
        glPixelStorei(GL_UNPACK_SKIP_IMAGES, s.unpack_skip_images);
        glPixelStorei(GL_PACK_ROW_LENGTH, s.pack_row_length);
        glPixelStorei(GL_PACK_SKIP_ROWS, s.pack_skip_rows);
        glPixelStorei(GL_PACK_SKIP_PIXELS, s.pack_skip_pixels);
        enable(GL_RASTERIZER_DISCARD, s.rasterizer_discard);
        enable(GL_PRIMITIVE_RESTART_FIXED_INDEX, s.primitive_restart);
    }
    glViewport(s.viewport[0], s.viewport[1], s.viewport[2], s.viewport[3]);
    glScissor(s.scissor_box[0], s.scissor_box[1], s.scissor_box[2], s.scissor_box[3]);
    enable(GL_SCISSOR_TEST, s.scissor_test);
    enable(GL_CULL_FACE, s.cull_face);
    glCullFace(static_cast<GLenum>(s.cull_face_mode));
    glFrontFace(static_cast<GLenum>(s.front_face));
    enable(GL_POLYGON_OFFSET_FILL, s.polygon_offset_fill);
    enable(GL_DEPTH_TEST, s.depth_test);
    glDepthMask(s.depth_mask);
    glDepthFunc(static_cast<GLenum>(s.depth_func));
    glDepthRangef(s.depth_range[0], s.depth_range[1]);
    glClearDepthf(s.clear_depth);
    enable(GL_BLEND, s.blend);
    glBlendFuncSeparate(static_cast<GLenum>(s.blend_src_rgb), static_cast<GLenum>(s.blend_dst_rgb),
                        static_cast<GLenum>(s.blend_src_alpha), static_cast<GLenum>(s.blend_dst_alpha));
    glBlendEquationSeparate(static_cast<GLenum>(s.blend_equation_rgb), static_cast<GLenum>(s.blend_equation_alpha));
    glBlendColor(s.blend_color[0], s.blend_color[1], s.blend_color[2], s.blend_color[3]);
    glColorMask(s.color_mask[0], s.color_mask[1], s.color_mask[2], s.color_mask[3]);
    glClearColor(s.clear_color[0], s.clear_color[1], s.clear_color[2], s.clear_color[3]);
    enable(GL_STENCIL_TEST, s.stencil_test);
    const StencilFace& f = s.stencil_front;
    const StencilFace& b = s.stencil_back;
    glStencilFuncSeparate(GL_FRONT, static_cast<GLenum>(f.func), f.ref, static_cast<GLuint>(f.value_mask));
    glStencilFuncSeparate(GL_BACK, static_cast<GLenum>(b.func), b.ref, static_cast<GLuint>(b.value_mask));
    glStencilOpSeparate(GL_FRONT, static_cast<GLenum>(f.fail), static_cast<GLenum>(f.pass_depth_fail),
                        static_cast<GLenum>(f.pass_depth_pass));
    glStencilOpSeparate(GL_BACK, static_cast<GLenum>(b.fail), static_cast<GLenum>(b.pass_depth_fail),
                        static_cast<GLenum>(b.pass_depth_pass));
    glStencilMaskSeparate(GL_FRONT, static_cast<GLuint>(f.write_mask));
    glStencilMaskSeparate(GL_BACK, static_cast<GLuint>(b.write_mask));
    enable(GL_DITHER, s.dither);
    enable(GL_SAMPLE_COVERAGE, s.sample_coverage);
    enable(GL_SAMPLE_ALPHA_TO_COVERAGE, s.sample_alpha_to_coverage);
}

void set_unpack_defaults(const Caps& caps) {
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (!caps.context_es3()) return;
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    glPixelStorei(GL_UNPACK_IMAGE_HEIGHT, 0);
    glPixelStorei(GL_UNPACK_SKIP_IMAGES, 0);
}

void set_pack_defaults(const Caps& caps) {
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (!caps.context_es3()) return;
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glPixelStorei(GL_PACK_SKIP_ROWS, 0);
    glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
}

}  // namespace px
