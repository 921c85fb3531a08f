#include "parallaxes/gl/state.h"

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

// How an entry is read and written: most are one of three plain kinds,
// held as data; the rest have their own functions.
enum class Kind : std::uint8_t {
    custom,       // save, restore, probe (and set_aside) below
    enable,       // glIsEnabled / glEnable(pname)
    pixel_store,  // glGetIntegerv / glPixelStorei(pname)
    buffer,       // glGetIntegerv(pname) / glBindBuffer(target)
};

// One piece of GL state: read (save), written back (restore), set to a
// value other than GL's default (probe, for the test) and, where every draw
// needs a value of its own, set aside. `index` is the texture unit or
// attribute slot of a per-unit or per-slot entry.
struct Entry {
    const char* name;
    GlStateScope scope;
    GlStateRepeat repeat;
    void (*save)(GlStateValue::Values& v, int index);
    void (*restore)(const GlStateValue::Values& v, int index);
    void (*probe)(const GlStateProbe& objects, int index);
    // The value every draw of the library uses, whatever the host left
    // (set_aside_host_state); null: the draw sets it from the frame, or not at all.
    void (*set_aside)(int index) = nullptr;
    Kind kind = Kind::custom;
    GLenum pname = 0;       // enable: the capability; pixel_store: the parameter; buffer: the binding read
    GLenum target = 0;      // buffer: the target bound
    GLint probe_value = 0;  // enable: on (1) or off; pixel_store: the value; buffer: which GlStateProbe::buffers
    int aside = -1;         // enable: what every draw sets (1 on, 0 off); -1: nothing
};

void save_entry(const Entry& e, GlStateValue::Values& v, int index) {
    switch (e.kind) {
        case Kind::enable: v[0] = glIsEnabled(e.pname) ? 1 : 0; return;
        case Kind::pixel_store:
        case Kind::buffer: v[0] = get_int(e.pname); return;
        case Kind::custom: e.save(v, index); return;
    }
}

void restore_entry(const Entry& e, const GlStateValue::Values& v, int index) {
    switch (e.kind) {
        case Kind::enable: enable(e.pname, v[0] != 0 ? GL_TRUE : GL_FALSE); return;
        case Kind::pixel_store: glPixelStorei(e.pname, static_cast<GLint>(v[0])); return;
        case Kind::buffer: glBindBuffer(e.target, static_cast<GLuint>(v[0])); return;
        case Kind::custom: e.restore(v, index); return;
    }
}

void probe_entry(const Entry& e, const GlStateProbe& o, int index) {
    switch (e.kind) {
        case Kind::enable: enable(e.pname, e.probe_value ? GL_TRUE : GL_FALSE); return;
        case Kind::pixel_store: glPixelStorei(e.pname, e.probe_value); return;
        case Kind::buffer: glBindBuffer(e.target, o.buffers[static_cast<size_t>(e.probe_value)]); return;
        case Kind::custom: e.probe(o, index); return;
    }
}

void set_aside_entry(const Entry& e, int index) {
    if (e.set_aside) e.set_aside(index);
    else if (e.kind == Kind::enable && e.aside >= 0) enable(e.pname, e.aside ? GL_TRUE : GL_FALSE);
}

// An entry that glGetIntegerv reads `count` values of and one call sets.
#define PX_INTS(pname, count) [](GlStateValue::Values& v, int) { \
        GLint r[4] = {0, 0, 0, 0};                                \
        glGetIntegerv(pname, r);                                  \
        for (int k = 0; k < (count); ++k) v[static_cast<size_t>(k)] = r[k]; }
// Floats are kept as their bit patterns: exact, and compared exactly.
#define PX_FLOATS(pname, count) [](GlStateValue::Values& v, int) { \
        GLfloat r[4] = {0, 0, 0, 0};                                \
        glGetFloatv(pname, r);                                      \
        for (int k = 0; k < (count); ++k) v[static_cast<size_t>(k)] = float_bits(r[k]); }
#define PX_INT(i) static_cast<GLint>(v[i])
#define PX_UINT(i) static_cast<GLuint>(v[i])
#define PX_ENUM(i) static_cast<GLenum>(v[i])
#define PX_FLOAT(i) bits_float(v[i])

// In restore order: what binds objects first (a vertex array before the
// element buffer it holds, the attributes before the array buffer their
// restore binds), the active texture unit after the units.
const std::vector<Entry>& entries() {
    static const std::vector<Entry> table = {
        {"vertex array", GlStateScope::es3_context, GlStateRepeat::once, PX_INTS(GL_VERTEX_ARRAY_BINDING, 1),
         [](const GlStateValue::Values& v, int) { glBindVertexArray(PX_UINT(0)); },
         [](const GlStateProbe& o, int) { glBindVertexArray(o.vertex_array); }},
        {"draw framebuffer", GlStateScope::es3_context, GlStateRepeat::once, PX_INTS(GL_DRAW_FRAMEBUFFER_BINDING, 1),
         [](const GlStateValue::Values& v, int) { glBindFramebuffer(GL_DRAW_FRAMEBUFFER, PX_UINT(0)); },
         [](const GlStateProbe& o, int) { glBindFramebuffer(GL_DRAW_FRAMEBUFFER, o.draw_framebuffer); }},
        {"read framebuffer", GlStateScope::es3_context, GlStateRepeat::once, PX_INTS(GL_READ_FRAMEBUFFER_BINDING, 1),
         [](const GlStateValue::Values& v, int) { glBindFramebuffer(GL_READ_FRAMEBUFFER, PX_UINT(0)); },
         [](const GlStateProbe& o, int) { glBindFramebuffer(GL_READ_FRAMEBUFFER, o.read_framebuffer); }},
        {"framebuffer", GlStateScope::es2_context, GlStateRepeat::once, PX_INTS(GL_FRAMEBUFFER_BINDING, 1),
         [](const GlStateValue::Values& v, int) { glBindFramebuffer(GL_FRAMEBUFFER, PX_UINT(0)); },
         [](const GlStateProbe& o, int) { glBindFramebuffer(GL_FRAMEBUFFER, o.draw_framebuffer); }},
        // ES 2.0: the library points the context's attribute slots (or an
        // OES vertex array's the host bound). ES 3.0 draws through vertex
        // arrays of the library's own, so the host's is only bound again.
        {"attribute", GlStateScope::es2_path, GlStateRepeat::per_attribute_slot,
         [](GlStateValue::Values& v, int slot) {
             const GLuint a = static_cast<GLuint>(slot);
             GLint r = 0;
             const GLenum names[] = {GL_VERTEX_ATTRIB_ARRAY_ENABLED, GL_VERTEX_ATTRIB_ARRAY_SIZE,
                                     GL_VERTEX_ATTRIB_ARRAY_TYPE,    GL_VERTEX_ATTRIB_ARRAY_NORMALIZED,
                                     GL_VERTEX_ATTRIB_ARRAY_STRIDE,  GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING};
             for (size_t k = 0; k < 6; ++k) {
                 glGetVertexAttribiv(a, names[k], &r);
                 v[k] = r;
             }
             void* pointer = nullptr;
             glGetVertexAttribPointerv(a, GL_VERTEX_ATTRIB_ARRAY_POINTER, &pointer);
             v[6] = static_cast<std::int64_t>(reinterpret_cast<std::uintptr_t>(pointer));
         },
         [](const GlStateValue::Values& v, int slot) {
             const GLuint a = static_cast<GLuint>(slot);
             glBindBuffer(GL_ARRAY_BUFFER, PX_UINT(5));
             glVertexAttribPointer(a, PX_INT(1), PX_ENUM(2), v[3] ? GL_TRUE : GL_FALSE, PX_INT(4),
                                   reinterpret_cast<void*>(static_cast<std::uintptr_t>(v[6])));
             v[0] ? glEnableVertexAttribArray(a) : glDisableVertexAttribArray(a);
         },
         [](const GlStateProbe& o, int slot) {
             if (slot % 2) return;  // odd slots stay disabled: both kinds covered
             glBindBuffer(GL_ARRAY_BUFFER, o.buffers[0]);
             glEnableVertexAttribArray(static_cast<GLuint>(slot));
             glVertexAttribPointer(static_cast<GLuint>(slot), 1 + slot % 3, GL_FLOAT, GL_FALSE, 12 + 4 * slot,
                                   reinterpret_cast<void*>(static_cast<std::uintptr_t>(4 + 4 * slot)));
         }},
        {"array buffer", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::buffer, GL_ARRAY_BUFFER_BINDING, GL_ARRAY_BUFFER, 1},
        // Of the bound vertex array on ES 3.0 (the host's own).
        {"element array buffer", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::buffer, GL_ELEMENT_ARRAY_BUFFER_BINDING, GL_ELEMENT_ARRAY_BUFFER, 2},
        {"renderbuffer", GlStateScope::all, GlStateRepeat::once, PX_INTS(GL_RENDERBUFFER_BINDING, 1),
         [](const GlStateValue::Values& v, int) { glBindRenderbuffer(GL_RENDERBUFFER, PX_UINT(0)); },
         [](const GlStateProbe& o, int) { glBindRenderbuffer(GL_RENDERBUFFER, o.renderbuffer); }},
        // A program the host deleted while it was current lives only as
        // long as it stays current: once the library's draw replaced it, it
        // is gone, and making it current again would be GL_INVALID_VALUE.
        // Then none is.
        {"program", GlStateScope::all, GlStateRepeat::once, PX_INTS(GL_CURRENT_PROGRAM, 1),
         [](const GlStateValue::Values& v, int) {
             const GLuint program = PX_UINT(0);
             glUseProgram(program != 0 && glIsProgram(program) ? program : 0);
         },
         [](const GlStateProbe& o, int) { glUseProgram(o.program); }},
        // Every unit the library binds, and whichever the host left active:
        // uploads bind on the active unit.
        {"texture 2d", GlStateScope::all, GlStateRepeat::per_texture_unit,
         [](GlStateValue::Values& v, int unit) {
             glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
             v[0] = get_int(GL_TEXTURE_BINDING_2D);
         },
         [](const GlStateValue::Values& v, int unit) {
             glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
             glBindTexture(GL_TEXTURE_2D, PX_UINT(0));
         },
         [](const GlStateProbe& o, int unit) {
             glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
             glBindTexture(GL_TEXTURE_2D, o.textures[static_cast<size_t>(unit) % GlStateProbe::kTextures]);
         }},
        // A sampler object overrides a texture's own filtering and wrapping.
        {"sampler", GlStateScope::es3_context, GlStateRepeat::per_texture_unit,
         [](GlStateValue::Values& v, int unit) {
             glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
             v[0] = get_int(GL_SAMPLER_BINDING);
         },
         [](const GlStateValue::Values& v, int unit) { glBindSampler(static_cast<GLuint>(unit), PX_UINT(0)); },
         [](const GlStateProbe& o, int unit) {
             glBindSampler(static_cast<GLuint>(unit), o.samplers[static_cast<size_t>(unit) % GlStateProbe::kSamplers]);
         },
         [](int unit) { glBindSampler(static_cast<GLuint>(unit), 0); }},
        // Read before the units above changed it (its index is the unit).
        {"active texture", GlStateScope::all, GlStateRepeat::host_active_unit,
         [](GlStateValue::Values& v, int unit) { v[0] = GL_TEXTURE0 + unit; },
         [](const GlStateValue::Values& v, int) { glActiveTexture(PX_ENUM(0)); },
         [](const GlStateProbe&, int) { glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + GlStateProbe::kActiveUnit)); }},
        {"pack alignment", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::pixel_store, GL_PACK_ALIGNMENT, 0, 2},
        {"unpack alignment", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::pixel_store, GL_UNPACK_ALIGNMENT, 0, 8},
        // A pixel buffer bound for unpacking: an upload that did not unbind
        // it would read the host's buffer instead of the image.
        {"pixel pack buffer", GlStateScope::es3_context, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::buffer, GL_PIXEL_PACK_BUFFER_BINDING, GL_PIXEL_PACK_BUFFER, 3},
        {"pixel unpack buffer", GlStateScope::es3_context, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::buffer, GL_PIXEL_UNPACK_BUFFER_BINDING, GL_PIXEL_UNPACK_BUFFER, 4},
        {"unpack row length", GlStateScope::es3_context, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::pixel_store, GL_UNPACK_ROW_LENGTH, 0, 7},
        {"unpack skip rows", GlStateScope::es3_context, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::pixel_store, GL_UNPACK_SKIP_ROWS, 0, 1},
        {"unpack skip pixels", GlStateScope::es3_context, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::pixel_store, GL_UNPACK_SKIP_PIXELS, 0, 2},
        {"unpack image height", GlStateScope::es3_context, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::pixel_store, GL_UNPACK_IMAGE_HEIGHT, 0, 3},
        {"unpack skip images", GlStateScope::es3_context, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::pixel_store, GL_UNPACK_SKIP_IMAGES, 0, 4},
        {"pack row length", GlStateScope::es3_context, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::pixel_store, GL_PACK_ROW_LENGTH, 0, 5},
        {"pack skip rows", GlStateScope::es3_context, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::pixel_store, GL_PACK_SKIP_ROWS, 0, 1},
        {"pack skip pixels", GlStateScope::es3_context, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::pixel_store, GL_PACK_SKIP_PIXELS, 0, 3},
        // On, rasterizer discard would drop every triangle (and clear): the draw sets it aside.
        {"rasterizer discard", GlStateScope::es3_context, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::enable, GL_RASTERIZER_DISCARD, 0, 1, 0},
        {"primitive restart", GlStateScope::es3_context, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::enable, GL_PRIMITIVE_RESTART_FIXED_INDEX, 0, 1, 0},
        {"viewport", GlStateScope::all, GlStateRepeat::once, PX_INTS(GL_VIEWPORT, 4),
         [](const GlStateValue::Values& v, int) { glViewport(PX_INT(0), PX_INT(1), PX_INT(2), PX_INT(3)); },
         [](const GlStateProbe&, int) { glViewport(3, 5, 7, 9); }},
        {"scissor box", GlStateScope::all, GlStateRepeat::once, PX_INTS(GL_SCISSOR_BOX, 4),
         [](const GlStateValue::Values& v, int) { glScissor(PX_INT(0), PX_INT(1), PX_INT(2), PX_INT(3)); },
         [](const GlStateProbe&, int) { glScissor(5, 6, 7, 8); }},
        // Scissor, stencil and the colour mask would each stop the draw: it
        // sets them aside and gives them back.
        {"scissor test", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::enable, GL_SCISSOR_TEST, 0, 1, 0},
        {"cull face", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::enable, GL_CULL_FACE, 0, 1, 1},
        {"cull face mode", GlStateScope::all, GlStateRepeat::once, PX_INTS(GL_CULL_FACE_MODE, 1),
         [](const GlStateValue::Values& v, int) { glCullFace(PX_ENUM(0)); },
         [](const GlStateProbe&, int) { glCullFace(GL_FRONT); },
         [](int) { glCullFace(GL_BACK); }},
        {"front face", GlStateScope::all, GlStateRepeat::once, PX_INTS(GL_FRONT_FACE, 1),
         [](const GlStateValue::Values& v, int) { glFrontFace(PX_ENUM(0)); },
         [](const GlStateProbe&, int) { glFrontFace(GL_CW); }},
        {"polygon offset fill", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::enable, GL_POLYGON_OFFSET_FILL, 0, 1, 0},
        {"depth test", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::enable, GL_DEPTH_TEST, 0, 1, 1},
        {"depth write mask", GlStateScope::all, GlStateRepeat::once, PX_INTS(GL_DEPTH_WRITEMASK, 1),
         [](const GlStateValue::Values& v, int) { glDepthMask(v[0] ? GL_TRUE : GL_FALSE); },
         [](const GlStateProbe&, int) { glDepthMask(GL_FALSE); },
         [](int) { glDepthMask(GL_TRUE); }},
        {"depth func", GlStateScope::all, GlStateRepeat::once, PX_INTS(GL_DEPTH_FUNC, 1),
         [](const GlStateValue::Values& v, int) { glDepthFunc(PX_ENUM(0)); },
         [](const GlStateProbe&, int) { glDepthFunc(GL_GREATER); },
         [](int) { glDepthFunc(GL_LESS); }},
        {"depth range", GlStateScope::all, GlStateRepeat::once, PX_FLOATS(GL_DEPTH_RANGE, 2),
         [](const GlStateValue::Values& v, int) { glDepthRangef(PX_FLOAT(0), PX_FLOAT(1)); },
         [](const GlStateProbe&, int) { glDepthRangef(0.25f, 0.75f); },
         [](int) { glDepthRangef(0.0f, 1.0f); }},
        {"depth clear value", GlStateScope::all, GlStateRepeat::once, PX_FLOATS(GL_DEPTH_CLEAR_VALUE, 1),
         [](const GlStateValue::Values& v, int) { glClearDepthf(PX_FLOAT(0)); },
         [](const GlStateProbe&, int) { glClearDepthf(0.5f); }},
        {"blend", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::enable, GL_BLEND, 0, 1, 0},
        {"blend func",
         GlStateScope::all,
         GlStateRepeat::once,
         [](GlStateValue::Values& v, int) {
             v[0] = get_int(GL_BLEND_SRC_RGB);
             v[1] = get_int(GL_BLEND_DST_RGB);
             v[2] = get_int(GL_BLEND_SRC_ALPHA);
             v[3] = get_int(GL_BLEND_DST_ALPHA);
         },
         [](const GlStateValue::Values& v, int) { glBlendFuncSeparate(PX_ENUM(0), PX_ENUM(1), PX_ENUM(2), PX_ENUM(3)); },
         [](const GlStateProbe&, int) {
             glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_DST_COLOR, GL_ONE_MINUS_DST_ALPHA);
         }},
        {"blend equation",
         GlStateScope::all,
         GlStateRepeat::once,
         [](GlStateValue::Values& v, int) {
             v[0] = get_int(GL_BLEND_EQUATION_RGB);
             v[1] = get_int(GL_BLEND_EQUATION_ALPHA);
         },
         [](const GlStateValue::Values& v, int) { glBlendEquationSeparate(PX_ENUM(0), PX_ENUM(1)); },
         [](const GlStateProbe&, int) { glBlendEquationSeparate(GL_FUNC_SUBTRACT, GL_FUNC_REVERSE_SUBTRACT); }},
        {"blend color", GlStateScope::all, GlStateRepeat::once, PX_FLOATS(GL_BLEND_COLOR, 4),
         [](const GlStateValue::Values& v, int) { glBlendColor(PX_FLOAT(0), PX_FLOAT(1), PX_FLOAT(2), PX_FLOAT(3)); },
         [](const GlStateProbe&, int) { glBlendColor(0.125f, 0.25f, 0.5f, 0.75f); }},
        {"color write mask",
         GlStateScope::all,
         GlStateRepeat::once,
         [](GlStateValue::Values& v, int) {
             GLboolean m[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
             glGetBooleanv(GL_COLOR_WRITEMASK, m);
             for (size_t k = 0; k < 4; ++k) v[k] = m[k] ? 1 : 0;
         },
         [](const GlStateValue::Values& v, int) {
             glColorMask(v[0] ? GL_TRUE : GL_FALSE, v[1] ? GL_TRUE : GL_FALSE, v[2] ? GL_TRUE : GL_FALSE,
                         v[3] ? GL_TRUE : GL_FALSE);
         },
         [](const GlStateProbe&, int) { glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE); },
         [](int) { glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE); }},
        {"color clear value", GlStateScope::all, GlStateRepeat::once, PX_FLOATS(GL_COLOR_CLEAR_VALUE, 4),
         [](const GlStateValue::Values& v, int) { glClearColor(PX_FLOAT(0), PX_FLOAT(1), PX_FLOAT(2), PX_FLOAT(3)); },
         [](const GlStateProbe&, int) { glClearColor(0.125f, 0.25f, 0.375f, 0.5f); }},
        {"stencil test", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::enable, GL_STENCIL_TEST, 0, 1, 0},
        // The reference value reads back clamped to the bound framebuffer's
        // stencil bits: saved and restored, not compared by the test.
        {"stencil front",
         GlStateScope::all,
         GlStateRepeat::once,
         [](GlStateValue::Values& v, int) {
             const GLenum names[] = {GL_STENCIL_FUNC,       GL_STENCIL_VALUE_MASK,      GL_STENCIL_FAIL,
                                     GL_STENCIL_PASS_DEPTH_FAIL, GL_STENCIL_PASS_DEPTH_PASS, GL_STENCIL_WRITEMASK,
                                     GL_STENCIL_REF};
             for (size_t k = 0; k < 7; ++k) v[k] = get_int(names[k]);
         },
         [](const GlStateValue::Values& v, int) {
             glStencilFuncSeparate(GL_FRONT, PX_ENUM(0), PX_INT(6), PX_UINT(1));
             glStencilOpSeparate(GL_FRONT, PX_ENUM(2), PX_ENUM(3), PX_ENUM(4));
             glStencilMaskSeparate(GL_FRONT, PX_UINT(5));
         },
         [](const GlStateProbe&, int) {
             glStencilFuncSeparate(GL_FRONT, GL_NEVER, 3, 0x0F);
             glStencilOpSeparate(GL_FRONT, GL_INCR, GL_DECR, GL_INVERT);
             glStencilMaskSeparate(GL_FRONT, 0x55);
         }},
        {"stencil back",
         GlStateScope::all,
         GlStateRepeat::once,
         [](GlStateValue::Values& v, int) {
             const GLenum names[] = {GL_STENCIL_BACK_FUNC,            GL_STENCIL_BACK_VALUE_MASK,
                                     GL_STENCIL_BACK_FAIL,            GL_STENCIL_BACK_PASS_DEPTH_FAIL,
                                     GL_STENCIL_BACK_PASS_DEPTH_PASS, GL_STENCIL_BACK_WRITEMASK,
                                     GL_STENCIL_BACK_REF};
             for (size_t k = 0; k < 7; ++k) v[k] = get_int(names[k]);
         },
         [](const GlStateValue::Values& v, int) {
             glStencilFuncSeparate(GL_BACK, PX_ENUM(0), PX_INT(6), PX_UINT(1));
             glStencilOpSeparate(GL_BACK, PX_ENUM(2), PX_ENUM(3), PX_ENUM(4));
             glStencilMaskSeparate(GL_BACK, PX_UINT(5));
         },
         [](const GlStateProbe&, int) {
             glStencilFuncSeparate(GL_BACK, GL_LESS, 1, 0x07);
             glStencilOpSeparate(GL_BACK, GL_DECR_WRAP, GL_INCR_WRAP, GL_ZERO);
             glStencilMaskSeparate(GL_BACK, 0x33);
         }},
        {"dither", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::enable, GL_DITHER, 0, 0, 0},
        {"sample coverage", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::enable, GL_SAMPLE_COVERAGE, 0, 1, 0},
        {"sample alpha to coverage", GlStateScope::all, GlStateRepeat::once, nullptr, nullptr, nullptr, nullptr, Kind::enable, GL_SAMPLE_ALPHA_TO_COVERAGE, 0, 1, 0},
    };
    return table;
}

#undef PX_INTS
#undef PX_FLOATS
#undef PX_INT
#undef PX_UINT
#undef PX_ENUM
#undef PX_FLOAT

// Whether an entry is state of this context that the library touches.
bool in_scope(GlStateScope scope, const Caps& caps) {
    switch (scope) {
        case GlStateScope::all: return true;
        case GlStateScope::es3_context: return caps.context_es3();
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
    const std::vector<Entry>& table = entries();
    for (size_t i = 0; i < table.size(); ++i) {
        if (!in_scope(table[i].scope, caps)) continue;
        for (int index : indices(table[i].repeat, active_unit)) f(i, table[i], index);
    }
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + active_unit));
}

}  // namespace

std::vector<GlStateValue> read_gl_state(const Caps& caps) {
    std::vector<GlStateValue> out;
    for_each_entry(caps, [&out](size_t entry, const Entry& e, int index) {
        GlStateValue v;
        v.name = e.name;
        v.entry = entry;
        v.index = e.repeat == GlStateRepeat::once ? -1 : index;
        save_entry(e, v.values, index);
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
    for (const Entry& e : entries()) out.push_back(e.name);
    return out;
}

struct SavedGlState::Snapshot {
    std::vector<GlStateValue> values;  // in restore order
};

SavedGlState::SavedGlState(const Caps& caps) : saved_(std::make_unique<Snapshot>()) {
    saved_->values = read_gl_state(caps);
}

SavedGlState::~SavedGlState() {
    const std::vector<Entry>& table = entries();
    for (const GlStateValue& v : saved_->values) restore_entry(table[v.entry], v.values, v.index < 0 ? 0 : v.index);
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
