/* A minimal reproducer for linear texture sampling under emulation
 * (issue 47): a surfaceless EGL context, a 4x4 RGBA8 texture of distinct
 * colours, one full-screen triangle pair that samples it with NEAREST and
 * then with LINEAR filtering into a 4x4 target, and the pixels read back
 * and checked against what the GLES spec's filtering gives (the pixel
 * centres of a 4x4 target over a 4x4 texture fall on texel centres, so
 * LINEAR must equal NEAREST there, and at an offset of half a texel it
 * must be the average of two neighbours).
 * Exit 0: both right; 1: a filter gave wrong texels; 2: no context.
 *   tools/cross/reproduce.sh linear_sampling arm64|armhf|native builds and runs it
 */
#include "es_helpers.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char* kVertex =
    "attribute vec2 p;\n"
    "uniform vec2 shift;\n"
    "varying vec2 uv;\n"
    "void main() { uv = p * 0.5 + 0.5 + shift; gl_Position = vec4(p, 0.0, 1.0); }\n";
static const char* kFragment =
    "precision highp float;\n"
    "uniform sampler2D t;\n"
    "varying vec2 uv;\n"
    "void main() { gl_FragColor = texture2D(t, uv); }\n";

/* A stage, or exit 2 with its log. */
static GLuint shader(GLenum kind, const char* text) {
    char error[600];
    GLuint s = px_compile_shader(kind, text, error, sizeof error);
    if (!s) {
        fprintf(stderr, "%s\n", error);
        exit(2);
    }
    return s;
}

static unsigned char texel(int x, int y, int c) {
    return (unsigned char)(c == 3 ? 255 : (x * 64 + y * 16 + c * 85 + 7) & 255);
}

/* Draws with `filter`, shifted by (sx, 0) in uv, and counts channels off the
 * expected value by more than 1 level. */
static GLuint prog;

static int draw_and_check(GLint filter, float sx, const char* name) {
    unsigned char out[4 * 4 * 4];
    int wrong = 0;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    glUniform2f(glGetUniformLocation(prog, "shift"), sx, 0.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glReadPixels(0, 0, 4, 4, GL_RGBA, GL_UNSIGNED_BYTE, out);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            for (int c = 0; c < 4; ++c) {
                /* Half a texel right: LINEAR averages texel x and x+1
                 * (clamped at the edge); NEAREST takes x+1 from the centre's
                 * tie rounding, which the check leaves out (x shift 0 only). */
                int want = texel(x, y, c);
                if (sx != 0.0f) want = (texel(x, y, c) + texel(x < 3 ? x + 1 : 3, y, c) + 1) / 2;
                int got = out[(y * 4 + x) * 4 + c];
                if (abs(got - want) > 1) {
                    if (wrong < 6) printf("  %s: pixel (%d,%d) channel %d: %d, expected %d\n", name, x, y, c, got, want);
                    ++wrong;
                }
            }
    printf("%s: %d of 64 channels wrong\n", name, wrong);
    return wrong;
}

int main(void) {
    if (!px_surfaceless_context(2, NULL)) {
        fprintf(stderr, "no surfaceless OpenGL ES 2.0 context\n");
        return 2;
    }
    printf("%s | %s\n", (const char*)glGetString(GL_RENDERER), (const char*)glGetString(GL_VERSION));
    GLuint fb, rb, tex;
    prog = glCreateProgram();
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glGenRenderbuffers(1, &rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA4, 4, 4);
    /* RGBA8 where the context has it (ES 2.0 core lacks it: OES_rgb8_rgba8). */
    glRenderbufferStorage(GL_RENDERBUFFER, 0x8058 /* GL_RGBA8_OES */, 4, 4);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) { fprintf(stderr, "incomplete\n"); return 2; }
    glViewport(0, 0, 4, 4);
    unsigned char pixels[4 * 4 * 4];
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            for (int c = 0; c < 4; ++c) pixels[(y * 4 + x) * 4 + c] = texel(x, y, c);
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 4, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glAttachShader(prog, shader(GL_VERTEX_SHADER, kVertex));
    glAttachShader(prog, shader(GL_FRAGMENT_SHADER, kFragment));
    glBindAttribLocation(prog, 0, "p");
    glLinkProgram(prog);
    glUseProgram(prog);
    const float quad[] = {-1, -1, 1, -1, -1, 1, 1, 1};
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, quad);
    glEnableVertexAttribArray(0);
    int wrong = draw_and_check(GL_NEAREST, 0.0f, "NEAREST");
    wrong += draw_and_check(GL_LINEAR, 0.0f, "LINEAR at texel centres");
    wrong += draw_and_check(GL_LINEAR, 0.125f, "LINEAR half a texel right");
    return wrong ? 1 : 0;
}
