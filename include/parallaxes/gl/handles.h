// Move-only owners of GL object names: nothing hands a raw GLuint's ownership
// across the API, and every object is deleted exactly once.
#pragma once

#include <utility>

#include "parallaxes/gl/gl.h"

namespace px {

template <void (*Delete)(GLuint)>
class GlHandle {
public:
    GlHandle() = default;
    explicit GlHandle(GLuint id) : id_(id) {}
    ~GlHandle() { reset(); }
    GlHandle(const GlHandle&) = delete;
    GlHandle& operator=(const GlHandle&) = delete;
    GlHandle(GlHandle&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
    GlHandle& operator=(GlHandle&& o) noexcept {
        if (this != &o) {
            reset();
            id_ = std::exchange(o.id_, 0);
        }
        return *this;
    }

    GLuint get() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    void reset() {
        if (id_ != 0) Delete(id_);
        id_ = 0;
    }
    // Forget the name without deleting it: after a context loss the names are gone already.
    void abandon() { id_ = 0; }

private:
    GLuint id_ = 0;
};

namespace gl_delete {
inline void buffer(GLuint id) { glDeleteBuffers(1, &id); }
inline void texture(GLuint id) { glDeleteTextures(1, &id); }
inline void framebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
inline void renderbuffer(GLuint id) { glDeleteRenderbuffers(1, &id); }
inline void shader(GLuint id) { glDeleteShader(id); }
inline void program(GLuint id) { glDeleteProgram(id); }
inline void vertex_array(GLuint id) { glDeleteVertexArrays(1, &id); }  // OpenGL ES 3.0
}  // namespace gl_delete

using BufferHandle = GlHandle<gl_delete::buffer>;
using TextureHandle = GlHandle<gl_delete::texture>;
using FramebufferHandle = GlHandle<gl_delete::framebuffer>;
using RenderbufferHandle = GlHandle<gl_delete::renderbuffer>;
using ShaderHandle = GlHandle<gl_delete::shader>;
using ProgramHandle = GlHandle<gl_delete::program>;
using VertexArrayHandle = GlHandle<gl_delete::vertex_array>;

inline BufferHandle make_buffer() { GLuint id = 0; glGenBuffers(1, &id); return BufferHandle(id); }
inline TextureHandle make_texture() { GLuint id = 0; glGenTextures(1, &id); return TextureHandle(id); }
inline FramebufferHandle make_framebuffer() { GLuint id = 0; glGenFramebuffers(1, &id); return FramebufferHandle(id); }
inline VertexArrayHandle make_vertex_array() { GLuint id = 0; glGenVertexArrays(1, &id); return VertexArrayHandle(id); }
inline RenderbufferHandle make_renderbuffer() { GLuint id = 0; glGenRenderbuffers(1, &id); return RenderbufferHandle(id); }

}  // namespace px
