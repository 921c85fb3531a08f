/* What the small C programs of tools/cross/ and tools/gpu/ share: a
 * surfaceless OpenGL ES context, and compiling one shader stage with its
 * log kept. Header-only: each program is one file built by its script. */
#ifndef PX_TOOLS_ES_HELPERS_H
#define PX_TOOLS_ES_HELPERS_H

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES2/gl2.h>
#include <stdio.h>

/* Makes an OpenGL ES `es_major` context current on EGL's surfaceless
 * platform; 0 when there is none, with EGL's error in *egl_error. */
static int px_surfaceless_context(int es_major, EGLint* egl_error) {
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_display =
        (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    EGLDisplay d = get_display ? get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL) : EGL_NO_DISPLAY;
    int ok = d != EGL_NO_DISPLAY && eglInitialize(d, NULL, NULL);
    if (ok) {
        const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, es_major, EGL_NONE};
        eglBindAPI(EGL_OPENGL_ES_API);
        EGLContext ctx = eglCreateContext(d, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
        ok = ctx != EGL_NO_CONTEXT && eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx);
    }
    if (egl_error) *egl_error = ok ? EGL_SUCCESS : eglGetError();
    return ok;
}

/* Compiles one stage; 0 on failure, with the stage and its log in `error`. */
static GLuint px_compile_shader(GLenum kind, const char* text, char* error, size_t error_size) {
    GLuint s = glCreateShader(kind);
    GLint ok = 0;
    glShaderSource(s, 1, &text, NULL);
    glCompileShader(s);
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        snprintf(error, error_size, "%s shader: %s", kind == GL_VERTEX_SHADER ? "vertex" : "fragment", log);
        glDeleteShader(s);
        return 0;
    }
    return s;
}

#endif
