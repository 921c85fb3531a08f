/* Compiles OpenGL ES shader programs with whatever driver EGL loads, and
 * draws each once so that drivers which compile at the first draw (shader
 * variants keyed on state) do: `parallax profile --gpu` runs it for arm64
 * under qemu-aarch64 with one of Mesa's drm-shim "noop" libraries
 * preloaded, so that Mesa's Panfrost, Freedreno, V3D or Lima driver loads
 * with no device and its real shader compiler prints its statistics
 * (BIFROST_MESA_DEBUG=shaderdb and the like). Pixels are meaningless.
 *
 *   shader_probe ES_MAJOR VERTEX FRAGMENT [VERTEX FRAGMENT ...]
 *
 * Everything goes to stdout, stderr joined to it and unbuffered, so that a
 * driver's statistics lines fall between this program's markers:
 *   px-probe context <GL_RENDERER> | <GL_VERSION>
 *   px-probe begin N            (program N, counting from 0)
 *   px-probe end N ok | px-probe end N error <message>
 * Exit 0 when every program compiled, linked and drew; 1 when one did not
 * (its error is in its end line); 2 on bad arguments or no context.
 */
#include "../cross/es_helpers.h"
#include <GLES3/gl3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { kMaxSource = 1 << 20, kTarget = 16 };

static char* read_file(const char* path) {
    FILE* f = fopen(path, "rb");
    if (!f) return NULL;
    char* text = malloc(kMaxSource + 1);
    size_t n = text ? fread(text, 1, kMaxSource + 1, f) : 0;
    fclose(f);
    if (!text || n > kMaxSource) {
        free(text);
        return NULL;
    }
    text[n] = 0;
    return text;
}

static int probe(const char* vertex_path, const char* fragment_path, char* error, size_t error_size) {
    char* vertex = read_file(vertex_path);
    char* fragment = read_file(fragment_path);
    int ok = 0;
    GLuint vs = 0, fs = 0, prog = 0;
    if (!vertex || !fragment) {
        snprintf(error, error_size, "cannot read %s", !vertex ? vertex_path : fragment_path);
        goto done;
    }
    vs = px_compile_shader(GL_VERTEX_SHADER, vertex, error, error_size);
    fs = vs ? px_compile_shader(GL_FRAGMENT_SHADER, fragment, error, error_size) : 0;
    if (!fs) goto done;
    prog = glCreateProgram();
    glAttachShader(prog, vs);
    glAttachShader(prog, fs);
    glLinkProgram(prog);
    GLint linked = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &linked);
    if (!linked) {
        char log[512] = "";
        glGetProgramInfoLog(prog, sizeof log, NULL, log);
        snprintf(error, error_size, "link: %s", log);
        goto done;
    }
    glUseProgram(prog);
    /* PX_PROBE_NO_DRAW=1: compile and link only (for drivers that compile
     * at link, and to tell a compiler's hang from a draw's). */
    const char* no_draw = getenv("PX_PROBE_NO_DRAW");
    if (no_draw && strcmp(no_draw, "1") == 0) {
        ok = 1;
        goto done;
    }
    /* Every attribute a constant (no arrays enabled): the draw only has to
     * make the driver build the program's variants. */
    GLint attributes = 0;
    glGetProgramiv(prog, GL_ACTIVE_ATTRIBUTES, &attributes);
    for (GLint i = 0; i < attributes && i < 16; ++i) glDisableVertexAttribArray((GLuint)i);
    /* No glFinish: the statistics are printed as the draw compiles, and
     * Lima's no-device shim never signals a submitted job's fence. */
    glDrawArrays(GL_TRIANGLES, 0, 3);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        snprintf(error, error_size, "GL error 0x%04x drawing", e);
        goto done;
    }
    ok = 1;
done:
    if (prog) glDeleteProgram(prog);
    if (vs) glDeleteShader(vs);
    if (fs) glDeleteShader(fs);
    free(vertex);
    free(fragment);
    return ok;
}

int main(int argc, char** argv) {
    setvbuf(stdout, NULL, _IONBF, 0);
    dup2(1, 2);
    if (argc < 4 || (argc - 2) % 2 != 0 || (strcmp(argv[1], "2") != 0 && strcmp(argv[1], "3") != 0)) {
        fprintf(stdout, "usage: %s 2|3 VERTEX FRAGMENT [VERTEX FRAGMENT ...]\n", argv[0]);
        return 2;
    }
    EGLint egl_error = EGL_SUCCESS;
    if (!px_surfaceless_context(atoi(argv[1]), &egl_error)) {
        printf("px-probe no-context no surfaceless OpenGL ES %s context (EGL error 0x%04x)\n", argv[1], egl_error);
        return 2;
    }
    printf("px-probe context %s | %s\n", (const char*)glGetString(GL_RENDERER), (const char*)glGetString(GL_VERSION));
    /* A small colour target to draw into. */
    GLuint fb, rb;
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glGenRenderbuffers(1, &rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA4, kTarget, kTarget);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb);
    glViewport(0, 0, kTarget, kTarget);
    /* A complete 4x4 texture on the first 8 units, so that no driver takes
     * its path for a sampler with nothing bound. */
    static unsigned char texels[4 * 4 * 4];
    memset(texels, 128, sizeof texels);
    GLuint tex;
    glGenTextures(1, &tex);
    for (int unit = 7; unit >= 0; --unit) {
        glActiveTexture(GL_TEXTURE0 + unit);
        glBindTexture(GL_TEXTURE_2D, tex);
    }
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 4, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    int failed = 0;
    for (int i = 2; i + 1 < argc; i += 2) {
        char error[600] = "";
        int n = (i - 2) / 2;
        printf("px-probe begin %d\n", n);
        if (probe(argv[i], argv[i + 1], error, sizeof error)) {
            printf("px-probe end %d ok\n", n);
        } else {
            for (char* c = error; *c; ++c)
                if (*c == '\n' || *c == '\r') *c = ' ';
            printf("px-probe end %d error %s\n", n, error);
            failed = 1;
        }
    }
    return failed;
}
