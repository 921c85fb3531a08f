#include "parallaxes/gl/state.h"

#include <array>
#include <cstdint>
#include <cstring>

namespace px {

namespace {

GLint get_int(GLenum name) {
    GLint v = 0;
    glGetIntegerv(name, &v);
    return v;
}

void enable(GLenum cap, GLboolean on) { on ? glEnable(cap) : glDisable(cap); }

std::int64_t float_bits(GLfloat f) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, sizeof bits);
    return bits;
}

GLfloat bits_float(std::int64_t v) {
    const auto bits = static_cast<std::uint32_t>(v);
    GLfloat f = 0.0f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

// The GL call that writes an entry back (and sets its probe and set-aside
// values): one switch, so that the table itself is data.
enum class Setter : std::uint8_t {
    vertex_array, framebuffer, renderbuffer, program, texture_2d, sampler, active_texture, attribute,
    enable, pixel_store, buffer, viewport, scissor, cull_face, front_face, depth_mask, depth_func,
    depth_range, clear_depth, blend_func, blend_equation, blend_color, color_mask, clear_color, stencil,
};

// One piece of GL state: how it is read (glGet of `pname`, `count` values,
// floats kept as bit patterns; a few rows read several names), the call that
// writes it back, a value other than GL's default for the test's probe (for
// bindings, which of GlStateProbe's objects), and where every draw needs a
// value of its own, that value (`aside`). `index` is the texture unit or
// attribute slot of a per-unit or per-slot row.
struct Entry {
    const char* name;
    GlStateScope scope;
    GlStateRepeat repeat;
    Setter setter;
    GLenum pname;   // what glGet reads (the first of several where the setter reads more)
    GLenum target;  // the framebuffer or buffer target, the capability, the pixel-store name, the stencil face
    std::uint8_t count;
    bool floats;
    std::array<std::uint32_t, 4> probe;
    bool has_aside;
    std::array<std::uint32_t, 4> aside;
};

constexpr std::uint32_t f32(float f) {
    // The bit patterns of the few floats the table holds.
    return f == 0.0f ? 0x00000000u : f == 1.0f ? 0x3f800000u : f == 0.5f ? 0x3f000000u : f == 0.25f ? 0x3e800000u
         : f == 0.75f ? 0x3f400000u : f == 0.125f ? 0x3e000000u : f == 0.375f ? 0x3ec00000u : 0xffffffffu;
}

constexpr std::array<std::uint32_t, 4> none{};

// In restore order: what binds objects first (a vertex array before the
// element buffer it holds, the attributes before the array buffer their
// restore binds), the active texture unit after the units.
constexpr Entry kEntries[] = {
    {"vertex array", GlStateScope::es3_context, GlStateRepeat::once, Setter::vertex_array, GL_VERTEX_ARRAY_BINDING, 0, 1, false, none, false, none},
    {"draw framebuffer", GlStateScope::es3_context, GlStateRepeat::once, Setter::framebuffer, GL_DRAW_FRAMEBUFFER_BINDING, GL_DRAW_FRAMEBUFFER, 1, false, none, false, none},
    {"read framebuffer", GlStateScope::es3_context, GlStateRepeat::once, Setter::framebuffer, GL_READ_FRAMEBUFFER_BINDING, GL_READ_FRAMEBUFFER, 1, false, none, false, none},
    {"framebuffer", GlStateScope::es2_context, GlStateRepeat::once, Setter::framebuffer, GL_FRAMEBUFFER_BINDING, GL_FRAMEBUFFER, 1, false, none, false, none},
    // ES 2.0: the library points the context's attribute slots (or an OES
    // vertex array's the host bound). ES 3.0 draws through vertex arrays of
    // the library's own, so the host's is only bound again.
    {"attribute", GlStateScope::es2_path, GlStateRepeat::per_attribute_slot, Setter::attribute, 0, 0, 7, false, none, false, none},
    {"array buffer", GlStateScope::all, GlStateRepeat::once, Setter::buffer, GL_ARRAY_BUFFER_BINDING, GL_ARRAY_BUFFER, 1, false, {1}, false, none},
    // Of the bound vertex array on ES 3.0 (the host's own).
    {"element array buffer", GlStateScope::all, GlStateRepeat::once, Setter::buffer, GL_ELEMENT_ARRAY_BUFFER_BINDING, GL_ELEMENT_ARRAY_BUFFER, 1, false, {2}, false, none},
    {"renderbuffer", GlStateScope::all, GlStateRepeat::once, Setter::renderbuffer, GL_RENDERBUFFER_BINDING, 0, 1, false, none, false, none},
    // A program the host deleted while it was current lives only as long
    // as it stays current: once the library's draw replaced it, it is gone,
    // and making it current again would be GL_INVALID_VALUE. Then none is.
    {"program", GlStateScope::all, GlStateRepeat::once, Setter::program, GL_CURRENT_PROGRAM, 0, 1, false, none, false, none},
    // Every unit the library binds, and whichever the host left active:
    // uploads bind on the active unit.
    {"texture 2d", GlStateScope::all, GlStateRepeat::per_texture_unit, Setter::texture_2d, GL_TEXTURE_BINDING_2D, 0, 1, false, none, false, none},
    // A sampler object overrides a texture's own filtering and wrapping.
    {"sampler", GlStateScope::es3_context, GlStateRepeat::per_texture_unit, Setter::sampler, GL_SAMPLER_BINDING, 0, 1, false, none, true, {0}},
    // Read before the units above changed it (its index is the unit).
    {"active texture", GlStateScope::all, GlStateRepeat::host_active_unit, Setter::active_texture, 0, 0, 1, false, none, false, none},
    {"pack alignment", GlStateScope::all, GlStateRepeat::once, Setter::pixel_store, GL_PACK_ALIGNMENT, GL_PACK_ALIGNMENT, 1, false, {2}, false, none},
    {"unpack alignment", GlStateScope::all, GlStateRepeat::once, Setter::pixel_store, GL_UNPACK_ALIGNMENT, GL_UNPACK_ALIGNMENT, 1, false, {8}, false, none},
    // A pixel buffer bound for unpacking: an upload that did not unbind it
    // would read the host's buffer instead of the image.
    {"pixel pack buffer", GlStateScope::es3_context, GlStateRepeat::once, Setter::buffer, GL_PIXEL_PACK_BUFFER_BINDING, GL_PIXEL_PACK_BUFFER, 1, false, {3}, false, none},
    {"pixel unpack buffer", GlStateScope::es3_context, GlStateRepeat::once, Setter::buffer, GL_PIXEL_UNPACK_BUFFER_BINDING, GL_PIXEL_UNPACK_BUFFER, 1, false, {4}, false, none},
    {"unpack row length", GlStateScope::es3_context, GlStateRepeat::once, Setter::pixel_store, GL_UNPACK_ROW_LENGTH, GL_UNPACK_ROW_LENGTH, 1, false, {7}, false, none},
    {"unpack skip rows", GlStateScope::es3_context, GlStateRepeat::once, Setter::pixel_store, GL_UNPACK_SKIP_ROWS, GL_UNPACK_SKIP_ROWS, 1, false, {1}, false, none},
    {"unpack skip pixels", GlStateScope::es3_context, GlStateRepeat::once, Setter::pixel_store, GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SKIP_PIXELS, 1, false, {2}, false, none},
    {"unpack image height", GlStateScope::es3_context, GlStateRepeat::once, Setter::pixel_store, GL_UNPACK_IMAGE_HEIGHT, GL_UNPACK_IMAGE_HEIGHT, 1, false, {3}, false, none},
    {"unpack skip images", GlStateScope::es3_context, GlStateRepeat::once, Setter::pixel_store, GL_UNPACK_SKIP_IMAGES, GL_UNPACK_SKIP_IMAGES, 1, false, {4}, false, none},
    {"pack row length", GlStateScope::es3_context, GlStateRepeat::once, Setter::pixel_store, GL_PACK_ROW_LENGTH, GL_PACK_ROW_LENGTH, 1, false, {5}, false, none},
    {"pack skip rows", GlStateScope::es3_context, GlStateRepeat::once, Setter::pixel_store, GL_PACK_SKIP_ROWS, GL_PACK_SKIP_ROWS, 1, false, {1}, false, none},
    {"pack skip pixels", GlStateScope::es3_context, GlStateRepeat::once, Setter::pixel_store, GL_PACK_SKIP_PIXELS, GL_PACK_SKIP_PIXELS, 1, false, {3}, false, none},
    // On, rasterizer discard would drop every triangle (and clear): the draw sets it aside.
    {"rasterizer discard", GlStateScope::es3_context, GlStateRepeat::once, Setter::enable, GL_RASTERIZER_DISCARD, GL_RASTERIZER_DISCARD, 1, false, {1}, true, {0}},
    {"primitive restart", GlStateScope::es3_native, GlStateRepeat::once, Setter::enable, GL_PRIMITIVE_RESTART_FIXED_INDEX, GL_PRIMITIVE_RESTART_FIXED_INDEX, 1, false, {1}, true, {0}},
    {"viewport", GlStateScope::all, GlStateRepeat::once, Setter::viewport, GL_VIEWPORT, 0, 4, false, {3, 5, 7, 9}, false, none},
    {"scissor box", GlStateScope::all, GlStateRepeat::once, Setter::scissor, GL_SCISSOR_BOX, 0, 4, false, {5, 6, 7, 8}, false, none},
    // Scissor, stencil and the colour mask would each stop the draw: it
    // sets them aside and gives them back.
    {"scissor test", GlStateScope::all, GlStateRepeat::once, Setter::enable, GL_SCISSOR_TEST, GL_SCISSOR_TEST, 1, false, {1}, true, {0}},
    {"cull face", GlStateScope::all, GlStateRepeat::once, Setter::enable, GL_CULL_FACE, GL_CULL_FACE, 1, false, {1}, true, {1}},
    {"cull face mode", GlStateScope::all, GlStateRepeat::once, Setter::cull_face, GL_CULL_FACE_MODE, 0, 1, false, {GL_FRONT}, true, {GL_BACK}},
    {"front face", GlStateScope::all, GlStateRepeat::once, Setter::front_face, GL_FRONT_FACE, 0, 1, false, {GL_CW}, false, none},
    {"polygon offset fill", GlStateScope::all, GlStateRepeat::once, Setter::enable, GL_POLYGON_OFFSET_FILL, GL_POLYGON_OFFSET_FILL, 1, false, {1}, true, {0}},
    {"depth test", GlStateScope::all, GlStateRepeat::once, Setter::enable, GL_DEPTH_TEST, GL_DEPTH_TEST, 1, false, {1}, true, {1}},
    {"depth write mask", GlStateScope::all, GlStateRepeat::once, Setter::depth_mask, GL_DEPTH_WRITEMASK, 0, 1, false, {0}, true, {1}},
    {"depth func", GlStateScope::all, GlStateRepeat::once, Setter::depth_func, GL_DEPTH_FUNC, 0, 1, false, {GL_GREATER}, true, {GL_LESS}},
    {"depth range", GlStateScope::all, GlStateRepeat::once, Setter::depth_range, GL_DEPTH_RANGE, 0, 2, true, {f32(0.25f), f32(0.75f)}, true, {f32(0.0f), f32(1.0f)}},
    {"depth clear value", GlStateScope::all, GlStateRepeat::once, Setter::clear_depth, GL_DEPTH_CLEAR_VALUE, 0, 1, true, {f32(0.5f)}, false, none},
    {"blend", GlStateScope::all, GlStateRepeat::once, Setter::enable, GL_BLEND, GL_BLEND, 1, false, {1}, true, {0}},
    {"blend func", GlStateScope::all, GlStateRepeat::once, Setter::blend_func, GL_BLEND_SRC_RGB, 0, 4, false, {GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_DST_COLOR, GL_ONE_MINUS_DST_ALPHA}, false, none},
    {"blend equation", GlStateScope::all, GlStateRepeat::once, Setter::blend_equation, GL_BLEND_EQUATION_RGB, 0, 2, false, {GL_FUNC_SUBTRACT, GL_FUNC_REVERSE_SUBTRACT}, false, none},
    {"blend color", GlStateScope::all, GlStateRepeat::once, Setter::blend_color, GL_BLEND_COLOR, 0, 4, true, {f32(0.125f), f32(0.25f), f32(0.5f), f32(0.75f)}, false, none},
    {"color write mask", GlStateScope::all, GlStateRepeat::once, Setter::color_mask, GL_COLOR_WRITEMASK, 0, 4, false, {1, 0, 1, 0}, true, {1, 1, 1, 1}},
    {"color clear value", GlStateScope::all, GlStateRepeat::once, Setter::clear_color, GL_COLOR_CLEAR_VALUE, 0, 4, true, {f32(0.125f), f32(0.25f), f32(0.375f), f32(0.5f)}, false, none},
    {"stencil test", GlStateScope::all, GlStateRepeat::once, Setter::enable, GL_STENCIL_TEST, GL_STENCIL_TEST, 1, false, {1}, true, {0}},
    // The reference value reads back clamped to the bound framebuffer's
    // stencil bits; it is saved and given back like the rest.
    {"stencil front", GlStateScope::all, GlStateRepeat::once, Setter::stencil, GL_STENCIL_FUNC, GL_FRONT, 7, false, none, false, none},
    {"stencil back", GlStateScope::all, GlStateRepeat::once, Setter::stencil, GL_STENCIL_BACK_FUNC, GL_BACK, 7, false, none, false, none},
    {"dither", GlStateScope::all, GlStateRepeat::once, Setter::enable, GL_DITHER, GL_DITHER, 1, false, {0}, true, {0}},
    {"sample coverage", GlStateScope::all, GlStateRepeat::once, Setter::enable, GL_SAMPLE_COVERAGE, GL_SAMPLE_COVERAGE, 1, false, {1}, true, {0}},
    {"sample alpha to coverage", GlStateScope::all, GlStateRepeat::once, Setter::enable, GL_SAMPLE_ALPHA_TO_COVERAGE, GL_SAMPLE_ALPHA_TO_COVERAGE, 1, false, {1}, true, {0}},
};

constexpr size_t kEntryCount = sizeof kEntries / sizeof kEntries[0];

void save_entry(const Entry& e, GlStateValue::Values& v, int index) {
    switch (e.setter) {
        case Setter::active_texture: v[0] = GL_TEXTURE0 + index; return;
        case Setter::texture_2d:
        case Setter::sampler:
            glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + index));
            v[0] = get_int(e.pname);
            return;
        case Setter::enable: v[0] = glIsEnabled(e.pname) ? 1 : 0; return;
        case Setter::attribute: {
            const GLuint a = static_cast<GLuint>(index);
            const GLenum names[] = {GL_VERTEX_ATTRIB_ARRAY_ENABLED, GL_VERTEX_ATTRIB_ARRAY_SIZE,
                                    GL_VERTEX_ATTRIB_ARRAY_TYPE,    GL_VERTEX_ATTRIB_ARRAY_NORMALIZED,
                                    GL_VERTEX_ATTRIB_ARRAY_STRIDE,  GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING};
            for (size_t k = 0; k < 6; ++k) {
                GLint r = 0;
                glGetVertexAttribiv(a, names[k], &r);
                v[k] = r;
            }
            void* pointer = nullptr;
            glGetVertexAttribPointerv(a, GL_VERTEX_ATTRIB_ARRAY_POINTER, &pointer);
            v[6] = static_cast<std::int64_t>(reinterpret_cast<std::uintptr_t>(pointer));
            return;
        }
        case Setter::blend_func: {
            const GLenum names[] = {GL_BLEND_SRC_RGB, GL_BLEND_DST_RGB, GL_BLEND_SRC_ALPHA, GL_BLEND_DST_ALPHA};
            for (size_t k = 0; k < 4; ++k) v[k] = get_int(names[k]);
            return;
        }
        case Setter::blend_equation:
            v[0] = get_int(GL_BLEND_EQUATION_RGB);
            v[1] = get_int(GL_BLEND_EQUATION_ALPHA);
            return;
        case Setter::stencil: {
            const bool front = e.target == GL_FRONT;
            const GLenum names[] = {
                static_cast<GLenum>(front ? GL_STENCIL_FUNC : GL_STENCIL_BACK_FUNC),
                static_cast<GLenum>(front ? GL_STENCIL_VALUE_MASK : GL_STENCIL_BACK_VALUE_MASK),
                static_cast<GLenum>(front ? GL_STENCIL_FAIL : GL_STENCIL_BACK_FAIL),
                static_cast<GLenum>(front ? GL_STENCIL_PASS_DEPTH_FAIL : GL_STENCIL_BACK_PASS_DEPTH_FAIL),
                static_cast<GLenum>(front ? GL_STENCIL_PASS_DEPTH_PASS : GL_STENCIL_BACK_PASS_DEPTH_PASS),
                static_cast<GLenum>(front ? GL_STENCIL_WRITEMASK : GL_STENCIL_BACK_WRITEMASK),
                static_cast<GLenum>(front ? GL_STENCIL_REF : GL_STENCIL_BACK_REF)};
            for (size_t k = 0; k < 7; ++k) v[k] = get_int(names[k]);
            return;
        }
        default: break;
    }
    if (e.floats) {
        GLfloat r[4] = {0, 0, 0, 0};
        glGetFloatv(e.pname, r);
        for (size_t k = 0; k < e.count; ++k) v[k] = float_bits(r[k]);
    } else {
        GLint r[4] = {0, 0, 0, 0};
        glGetIntegerv(e.pname, r);
        for (size_t k = 0; k < e.count; ++k) v[k] = r[k];
    }
}

void restore_entry(const Entry& e, const GlStateValue::Values& v, int index) {
    const auto u = [&v](size_t k) { return static_cast<GLuint>(v[k]); };
    const auto i = [&v](size_t k) { return static_cast<GLint>(v[k]); };
    const auto f = [&v](size_t k) { return bits_float(v[k]); };
    const auto b = [&v](size_t k) -> GLboolean { return v[k] ? GL_TRUE : GL_FALSE; };
    switch (e.setter) {
        case Setter::vertex_array: glBindVertexArray(u(0)); return;
        case Setter::framebuffer: glBindFramebuffer(e.target, u(0)); return;
        case Setter::renderbuffer: glBindRenderbuffer(GL_RENDERBUFFER, u(0)); return;
        case Setter::program: glUseProgram(u(0) != 0 && glIsProgram(u(0)) ? u(0) : 0); return;
        case Setter::texture_2d:
            glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + index));
            glBindTexture(GL_TEXTURE_2D, u(0));
            return;
        case Setter::sampler: glBindSampler(static_cast<GLuint>(index), u(0)); return;
        case Setter::active_texture: glActiveTexture(u(0)); return;
        case Setter::attribute: {
            const GLuint a = static_cast<GLuint>(index);
            glBindBuffer(GL_ARRAY_BUFFER, u(5));
            glVertexAttribPointer(a, i(1), u(2), b(3), i(4), reinterpret_cast<void*>(static_cast<std::uintptr_t>(v[6])));
            v[0] ? glEnableVertexAttribArray(a) : glDisableVertexAttribArray(a);
            return;
        }
        case Setter::enable: enable(e.target, b(0)); return;
        case Setter::pixel_store: glPixelStorei(e.target, i(0)); return;
        case Setter::buffer: glBindBuffer(e.target, u(0)); return;
        case Setter::viewport: glViewport(i(0), i(1), i(2), i(3)); return;
        case Setter::scissor: glScissor(i(0), i(1), i(2), i(3)); return;
        case Setter::cull_face: glCullFace(u(0)); return;
        case Setter::front_face: glFrontFace(u(0)); return;
        case Setter::depth_mask: glDepthMask(b(0)); return;
        case Setter::depth_func: glDepthFunc(u(0)); return;
        case Setter::depth_range: glDepthRangef(f(0), f(1)); return;
        case Setter::clear_depth: glClearDepthf(f(0)); return;
        case Setter::blend_func: glBlendFuncSeparate(u(0), u(1), u(2), u(3)); return;
        case Setter::blend_equation: glBlendEquationSeparate(u(0), u(1)); return;
        case Setter::blend_color: glBlendColor(f(0), f(1), f(2), f(3)); return;
        case Setter::color_mask: glColorMask(b(0), b(1), b(2), b(3)); return;
        case Setter::clear_color: glClearColor(f(0), f(1), f(2), f(3)); return;
        case Setter::stencil:
            glStencilFuncSeparate(e.target, u(0), i(6), u(1));
            glStencilOpSeparate(e.target, u(2), u(3), u(4));
            glStencilMaskSeparate(e.target, u(5));
            return;
    }
}

GlStateValue::Values values_of(const std::array<std::uint32_t, 4>& a) {
    GlStateValue::Values v{};
    for (size_t k = 0; k < a.size(); ++k) v[k] = a[k];
    return v;
}

void probe_entry(const Entry& e, const GlStateProbe& o, int index) {
    GlStateValue::Values v = values_of(e.probe);
    switch (e.setter) {
        case Setter::vertex_array: v[0] = o.vertex_array; break;
        case Setter::framebuffer: v[0] = e.target == GL_READ_FRAMEBUFFER ? o.read_framebuffer : o.draw_framebuffer; break;
        case Setter::renderbuffer: v[0] = o.renderbuffer; break;
        case Setter::program: v[0] = o.program; break;
        case Setter::texture_2d: v[0] = o.textures[static_cast<size_t>(index) % GlStateProbe::kTextures]; break;
        case Setter::sampler: v[0] = o.samplers[static_cast<size_t>(index) % GlStateProbe::kSamplers]; break;
        case Setter::active_texture: v[0] = GL_TEXTURE0 + GlStateProbe::kActiveUnit; break;
        case Setter::buffer: v[0] = o.buffers[e.probe[0]]; break;
        case Setter::attribute:
            if (index % 2) return;  // odd slots stay disabled: both kinds covered
            v = {1, 1 + index % 3, GL_FLOAT, 0, 12 + 4 * index, o.buffers[0], 0, 4 + 4 * index};
            break;
        case Setter::stencil:
            v = e.target == GL_FRONT ? GlStateValue::Values{GL_NEVER, 0x0F, GL_INCR, GL_DECR, GL_INVERT, 0x55, 3, 0}
                                     : GlStateValue::Values{GL_LESS, 0x07, GL_DECR_WRAP, GL_INCR_WRAP, GL_ZERO, 0x33, 1, 0};
            break;
        default: break;
    }
    if (e.setter == Setter::attribute) v[6] = v[7];  // the pointer
    restore_entry(e, v, index);
}

void set_aside_entry(const Entry& e, int index) {
    if (e.has_aside) restore_entry(e, values_of(e.aside), index);
}

// Whether an entry is state of this context that the library touches.
bool in_scope(GlStateScope scope, const Caps& caps) {
    switch (scope) {
        case GlStateScope::all: return true;
        case GlStateScope::es3_context: return caps.context_es3();
        case GlStateScope::es3_native: return caps.context_es3() && !caps.webgl();
        case GlStateScope::es2_context: return !caps.context_es3();
        // The attribute slots wherever the library points them: the ES 2.0
        // path, also on an ES 3.x context drawing as ES 2.0 (emulate_es2).
        case GlStateScope::es2_path: return caps.es_major < 3;
    }
    return false;
}

// The units and slots an entry covers on this context, now: every unit
// the library binds and the host's active one (uploads bind there), every
// attribute slot the library points.
std::vector<int> indices(GlStateRepeat repeat, int host_active_unit) {
    std::vector<int> out;
    switch (repeat) {
        case GlStateRepeat::once: out.push_back(0); break;
        case GlStateRepeat::host_active_unit: out.push_back(host_active_unit); break;
        case GlStateRepeat::per_texture_unit:
            for (int u = 0; u < kLibraryTextureUnits; ++u) out.push_back(u);
            if (host_active_unit >= kLibraryTextureUnits) out.push_back(host_active_unit);
            break;
        case GlStateRepeat::per_attribute_slot:
            for (int a = 0; a < kLibraryAttributeSlots; ++a) out.push_back(a);
            break;
    }
    return out;
}

// Walks the table's entries in scope for this context, each index, in
// restore order; gives back the active texture unit afterwards.
template <typename F>
void for_each_entry(const Caps& caps, F&& f) {
    const int active_unit = get_int(GL_ACTIVE_TEXTURE) - GL_TEXTURE0;
    for (size_t i = 0; i < kEntryCount; ++i) {
        if (!in_scope(kEntries[i].scope, caps)) continue;
        for (int index : indices(kEntries[i].repeat, active_unit)) f(i, kEntries[i], index);
    }
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + active_unit));
}

}  // namespace

std::vector<GlStateValue> read_gl_state(const Caps& caps) {
    std::vector<GlStateValue> out;
    const bool webgl = caps.webgl();
    for_each_entry(caps, [&out, webgl](size_t entry, const Entry& e, int index) {
        GlStateValue v;
        v.name = e.name;
        v.entry = entry;
        v.index = e.repeat == GlStateRepeat::once ? -1 : index;
        save_entry(e, v.values, index);
        if (e.setter == Setter::attribute) {
            // An attribute whose buffer was deleted (WebGL still reports the
            // deleted object's name): binding that name again would bind
            // nothing (WebGL) or make a new, empty buffer (OpenGL ES), so it
            // comes back as no buffer.
            if (v.values[5] != 0 && !glIsBuffer(static_cast<GLuint>(v.values[5]))) v.values[5] = 0;
            // WebGL has no client-side arrays: an offset into no buffer
            // cannot be set again (WebGL refuses the call), so it is 0.
            if (webgl && v.values[5] == 0) v.values[6] = 0;
        }
        out.push_back(std::move(v));
    });
    return out;
}

void set_gl_state_probe(const Caps& caps, const GlStateProbe& objects) {
    // The host's active unit is one past the library's, so that the table
    // covers a unit the library binds only because it is active.
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + GlStateProbe::kActiveUnit));
    for_each_entry(caps, [&objects](size_t, const Entry& e, int index) { probe_entry(e, objects, index); });
    // for_each_entry gave back the unit active when it began; the probe's own
    // is the active-texture entry's value.
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + GlStateProbe::kActiveUnit));
}

std::vector<std::string> gl_state_entry_names() {
    std::vector<std::string> out;
    for (const Entry& e : kEntries) out.push_back(e.name);
    return out;
}

struct SavedGlState::Snapshot {
    std::vector<GlStateValue> values;  // in restore order
};

SavedGlState::SavedGlState(const Caps& caps) : saved_(std::make_unique<Snapshot>()) {
    saved_->values = read_gl_state(caps);
}

SavedGlState::~SavedGlState() {
    for (const GlStateValue& v : saved_->values) restore_entry(kEntries[v.entry], v.values, v.index < 0 ? 0 : v.index);
}

void set_aside_host_state(const Caps& caps) {
    for_each_entry(caps, [](size_t, const Entry& e, int index) {
        if (!(e.repeat == GlStateRepeat::per_texture_unit && index >= kLibraryTextureUnits)) set_aside_entry(e, index);
    });
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
