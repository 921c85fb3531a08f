/* A minimal reproducer for the arm64 crash of a depth-tested draw into a
 * multisampled target (issue 47): a surfaceless OpenGL ES 3.0 context, a
 * 32x32 framebuffer of multisampled RGBA8 and depth renderbuffers, one
 * quad drawn with a constant-colour shader, then resolved and read back.
 * Each case (samples, depth format, depth test on or off, gl_FragDepth
 * written or not) runs in its own child process, so a crash is reported as
 * the signal that ended it instead of ending the run. One line per case.
 * Exit 0: every case drew the right colour; 1: a case crashed or drew
 * wrong; 2: no context.
 *   tools/cross/reproduce.sh msaa_depth arm64|armhf|native builds and runs it
 */
#include "es_helpers.h"
#include <GLES3/gl3.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

enum { kSize = 32 };

static const char* kVertex =
    "#version 300 es\n"
    "in vec2 p;\n"
    "void main() { gl_Position = vec4(p, 0.25 * p.x, 1.0); }\n";
static const char* kFragment =
    "#version 300 es\n"
    "precision highp float;\n"
    "out vec4 colour;\n"
    "void main() { colour = vec4(0.0, 1.0, 0.0, 1.0); }\n";
static const char* kFragmentWithDepth =
    "#version 300 es\n"
    "precision highp float;\n"
    "out vec4 colour;\n"
    "void main() { colour = vec4(0.0, 1.0, 0.0, 1.0); gl_FragDepth = gl_FragCoord.z; }\n";

struct Case {
    int samples;
    GLenum depth_format;
    const char* depth_name;
    int depth_test;
    int writes_depth;
};

/* A stage, or exit 2 with its log (in the child). */
static GLuint shader(GLenum kind, const char* text) {
    char error[600];
    GLuint s = px_compile_shader(kind, text, error, sizeof error);
    if (!s) {
        fprintf(stderr, "%s\n", error);
        exit(2);
    }
    return s;
}

/* In the child: draws the case; exit 0 when the resolved centre is green.
 * The parent never makes a context (a forked child would inherit an
 * initialised display without the driver's threads). */
static int draw_case(const struct Case* c, int print_renderer) {
    if (!px_surfaceless_context(3, NULL)) return 2;
    if (print_renderer) {
        printf("%s | %s\n", (const char*)glGetString(GL_RENDERER), (const char*)glGetString(GL_VERSION));
        fflush(stdout);
    }
    GLuint rb[2], fb[2], colour;
    glGenRenderbuffers(2, rb);
    glGenFramebuffers(2, fb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[0]);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, c->samples, GL_RGBA8, kSize, kSize);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[1]);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, c->samples, c->depth_format, kSize, kSize);
    glBindFramebuffer(GL_FRAMEBUFFER, fb[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb[1]);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) return 3;
    GLuint prog = glCreateProgram();
    glAttachShader(prog, shader(GL_VERTEX_SHADER, kVertex));
    glAttachShader(prog, shader(GL_FRAGMENT_SHADER, c->writes_depth ? kFragmentWithDepth : kFragment));
    glBindAttribLocation(prog, 0, "p");
    glLinkProgram(prog);
    glUseProgram(prog);
    const float quad[] = {-1, -1, 1, -1, -1, 1, 1, 1};
    GLuint buffer;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, 0);
    glEnableVertexAttribArray(0);
    glViewport(0, 0, kSize, kSize);
    glClearColor(1, 0, 0, 1);
    glClearDepthf(1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (c->depth_test) {
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LEQUAL);
    }
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    /* Resolve into a single-sampled target and read its centre. */
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenTextures(1, &colour);
    glBindTexture(GL_TEXTURE_2D, colour);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, kSize, kSize);
    glBindFramebuffer(GL_FRAMEBUFFER, fb[1]);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour, 0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fb[0]);
    glBlitFramebuffer(0, 0, kSize, kSize, 0, 0, kSize, kSize, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, fb[1]);
    unsigned char px[4] = {0, 0, 0, 0};
    glReadPixels(kSize / 2, kSize / 2, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, px);
    if (glGetError() != GL_NO_ERROR) return 4;
    return (px[0] < 8 && px[1] > 247) ? 0 : 5;
}

int main(void) {
    const struct Case cases[] = {
        {4, GL_DEPTH_COMPONENT24, "DEPTH_COMPONENT24", 1, 0}, {4, GL_DEPTH_COMPONENT24, "DEPTH_COMPONENT24", 1, 1},
        {4, GL_DEPTH_COMPONENT24, "DEPTH_COMPONENT24", 0, 0}, {4, GL_DEPTH_COMPONENT16, "DEPTH_COMPONENT16", 1, 0},
        {4, GL_DEPTH_COMPONENT32F, "DEPTH_COMPONENT32F", 1, 0}, {4, GL_DEPTH24_STENCIL8, "DEPTH24_STENCIL8", 1, 0},
        {2, GL_DEPTH_COMPONENT24, "DEPTH_COMPONENT24", 1, 0},
    };
    const char* outcome[] = {"right", "?", "no context", "incomplete framebuffer", "GL error", "wrong colour"};
    int failed = 0;
    fflush(stdout);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        const struct Case* c = &cases[i];
        pid_t child = fork();
        if (child == 0) _exit(draw_case(c, i == 0));
        int status = 0;
        if (child < 0 || waitpid(child, &status, 0) != child) return 2;
        char result[64];
        if (WIFSIGNALED(status))
            snprintf(result, sizeof result, "CRASHED (signal %d, %s)", WTERMSIG(status), strsignal(WTERMSIG(status)));
        else
            snprintf(result, sizeof result, "%s", WEXITSTATUS(status) <= 5 ? outcome[WEXITSTATUS(status)] : "?");
        if (WIFEXITED(status) && WEXITSTATUS(status) == 2) {
            fprintf(stderr, "no surfaceless OpenGL ES 3.0 context\n");
            return 2;
        }
        if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) failed = 1;
        printf("%d samples, %-18s depth test %-3s, gl_FragDepth %-7s: %s\n", c->samples, c->depth_name,
               c->depth_test ? "on" : "off", c->writes_depth ? "written" : "not", result);
        fflush(stdout);
    }
    return failed;
}
