#include "render/surface_capture.h"

#include <string>
#include <vector>

#include "gl/errors.h"
#include "gl/framebuffer.h"
#include "gl/handles.h"

namespace px {

namespace {

double unpack24(const std::uint8_t* p) { return (p[0] * 65536.0 + p[1] * 256.0 + p[2]) / 16777215.0; }
double unpack16(const std::uint8_t* p) { return (p[0] * 256.0 + p[1]) / 65535.0; }

}  // namespace

Result<SurfaceImage> capture_surfaces(Renderer& renderer, int width, int height) {
    if (width < 1 || height < 1) return make_error("capture_surfaces: empty size");
    const Caps& caps = renderer.caps();
    const bool float_color = caps.es_major >= 3 && caps.has("GL_EXT_color_buffer_float");
    GLint host_framebuffer = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &host_framebuffer);
    struct Rebind {
        GLint id;
        ~Rebind() { glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(id)); }
    } rebind{host_framebuffer};

    Result<ColorDepthFramebuffer> target =
        make_color_depth_framebuffer(width, height, float_color ? ColorFormat::rgba32f : ColorFormat::rgba8, caps);
    if (!target) return with_context("debug-output target", target.error());
    const RenderTarget render_target{target->framebuffer.get(), width, height};
    SurfaceImage out;
    out.width = width;
    out.height = height;
    out.samples.resize(static_cast<size_t>(width) * height);
    const size_t count = out.samples.size();

    if (float_color) {
        Status drawn = renderer.draw(render_target, 1);
        if (!drawn) return drawn.error();
        std::vector<float> pixels(count * 4);
        glBindFramebuffer(GL_FRAMEBUFFER, render_target.framebuffer);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, pixels.data());
        Status read = check_gl("reading the debug outputs (RGBA32F)");
        if (!read) return read.error();
        for (size_t i = 0; i < count; ++i) {
            SurfaceSample& s = out.samples[i];
            s.covered = pixels[4 * i + 3] >= 0.0f;  // cleared to -1
            s.uv = {pixels[4 * i + 0], pixels[4 * i + 1]};
            s.height = pixels[4 * i + 2];
            s.visibility = pixels[4 * i + 3];
        }
        return out;
    }
    std::vector<std::uint8_t> pixels(count * 4);
    for (std::uint8_t pass = 2; pass <= 4; ++pass) {
        Status drawn = renderer.draw(render_target, pass);
        if (!drawn) return drawn.error();
        glBindFramebuffer(GL_FRAMEBUFFER, render_target.framebuffer);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
        Status read = check_gl("reading the debug outputs (RGBA8 pass " + std::to_string(pass - 1) + " of 3)");
        if (!read) return read.error();
        for (size_t i = 0; i < count; ++i) {
            SurfaceSample& s = out.samples[i];
            const std::uint8_t* p = &pixels[4 * i];
            switch (pass) {
                case 2:
                    s.covered = p[3] == 255;
                    s.uv.x = unpack24(p);
                    break;
                case 3: s.uv.y = unpack24(p); break;
                default:
                    s.height = unpack16(p);
                    s.visibility = unpack16(p + 2);
                    break;
            }
        }
    }
    return out;
}

}  // namespace px
