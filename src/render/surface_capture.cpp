#include "parallaxes/render/surface_capture.h"

#include <limits>
#include <string>
#include <vector>

#include "parallaxes/gl/errors.h"
#include "parallaxes/gl/framebuffer.h"
#include "parallaxes/gl/handles.h"
#include "parallaxes/gl/state.h"

namespace px {

namespace {

// Alpha of a drawn pixel in the packed passes: 255 for the highp packing
// (24 and 16 bits), 128 for the 11-bit packing of a fragment stage without
// highp (shaders_es/chunks/debug_output.glsl). 0: nothing drawn.
constexpr std::uint8_t kDrawnHighp = 255;
constexpr std::uint8_t kDrawnMediump = 128;
// A drawn pixel where the shader computed NaN or Inf (packing would hide it).
constexpr std::uint8_t kNonFinite = 64;

double unpack(const std::uint8_t* p, int bytes, double levels) {
    double e = 0.0;
    for (int i = 0; i < bytes; ++i) e = e * 256.0 + p[i];
    return e / levels;
}

}  // namespace

bool captures_floats(const Caps& caps) { return caps.context_es3() && caps.has("GL_EXT_color_buffer_float"); }

namespace {

// ES 3.0 with float colour buffers: one pass, hit uv, height and visibility
// as they are.
Status capture_floats(Renderer& renderer, const RenderTarget& target, const Caps& caps, SurfaceImage& out) {
    const size_t count = out.samples.size();
    Status drawn = renderer.draw(target, 1);
    if (!drawn) return drawn;
    std::vector<float> pixels(count * 4);
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
    set_pack_defaults(caps);
    glReadPixels(0, 0, target.width, target.height, GL_RGBA, GL_FLOAT, pixels.data());
    Status read = check_gl("reading the debug outputs (RGBA32F)");
    if (!read) return read;
    for (size_t i = 0; i < count; ++i) {
        SurfaceSample& s = out.samples[i];
        // Cleared to -1, which no visibility (0..1) takes; a NaN there is drawn.
        s.covered = pixels[4 * i + 3] != -1.0f;
        s.uv = {pixels[4 * i + 0], pixels[4 * i + 1]};
        s.height = pixels[4 * i + 2];
        s.visibility = pixels[4 * i + 3];
    }
    return {};
}

// Pass 2's alpha: whether a pixel was drawn, and with which packing.
Status read_packing_mark(const std::uint8_t* p, size_t i, int width, SurfaceSample& s, std::uint8_t& mark,
                         SurfaceImage& out) {
    if (p[3] != 0 && p[3] != kDrawnHighp && p[3] != kDrawnMediump)
        return make_error("debug outputs: pixel " + std::to_string(i % static_cast<size_t>(width)) + "," +
                          std::to_string(i / static_cast<size_t>(width)) + " has alpha " + std::to_string(p[3]) +
                          ", which marks no packing (0, 64, 128 or 255)");
    mark = p[3];
    s.covered = p[3] != 0;
    if (p[3] != 0) {
        const int bits = p[3] == kDrawnHighp ? 24 : 11;
        if (out.packing_bits != 0 && out.packing_bits != bits)
            return make_error("debug outputs: pixels of both packings (24 and 11 bits) in one image");
        out.packing_bits = bits;
    }
    return {};
}

// One RGBA8 pass's pixel into its sample: pass 2 the uv's x, 3 its y, 4 the
// height and visibility.
Status decode_packed_pixel(const std::uint8_t* p, std::uint8_t pass, size_t i, int width, SurfaceSample& s,
                           std::uint8_t& mark, SurfaceImage& out) {
    if (pass < 4 && p[3] == kNonFinite) {  // passes 2 and 3: the values are unknown, and not finite
        s.covered = true;
        mark = kNonFinite;
        s.uv = glm::dvec2(std::numeric_limits<double>::quiet_NaN());
        s.height = s.visibility = std::numeric_limits<double>::quiet_NaN();
        return {};
    }
    if (mark == kNonFinite) return {};
    if (pass == 2)
        if (Status m = read_packing_mark(p, i, width, s, mark, out); !m) return m;
    // 24 and 16 bits, or 11 bits everywhere without fragment highp.
    const bool highp = mark == kDrawnHighp;
    const double levels24 = highp ? 16777215.0 : 2047.0;
    const double levels16 = highp ? 65535.0 : 2047.0;
    switch (pass) {
        case 2: s.uv.x = unpack(p, 3, levels24); break;
        case 3: s.uv.y = unpack(p, 3, levels24); break;
        default:
            s.height = unpack(p, 2, levels16);
            s.visibility = unpack(p + 2, 2, levels16);
            break;
    }
    return {};
}

// RGBA8 only (ES 2.0, or no float colour buffers): three passes of packed values.
Status capture_packed(Renderer& renderer, const RenderTarget& target, const Caps& caps, SurfaceImage& out) {
    const size_t count = out.samples.size();
    std::vector<std::uint8_t> pixels(count * 4);
    std::vector<std::uint8_t> drawn_mark(count, 0);  // pass 2's alpha: which packing each pixel has
    for (std::uint8_t pass = 2; pass <= 4; ++pass) {
        Status drawn = renderer.draw(target, pass);
        if (!drawn) return drawn;
        glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
        set_pack_defaults(caps);
        glReadPixels(0, 0, target.width, target.height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
        Status read = check_gl("reading the debug outputs (RGBA8 pass " + std::to_string(pass - 1) + " of 3)");
        if (!read) return read;
        for (size_t i = 0; i < count; ++i) {
            Status decoded = decode_packed_pixel(&pixels[4 * i], pass, i, target.width, out.samples[i], drawn_mark[i], out);
            if (!decoded) return decoded;
        }
    }
    return {};
}

}  // namespace

Result<SurfaceImage> capture_surfaces(Renderer& renderer, int width, int height) {
    if (width < 1 || height < 1) return make_error("capture_surfaces: empty size");
    const Caps& caps = renderer.caps();
    // The context's own version decides: an ES 3.0 context drawing ES 2.0
    // variants (RendererOptions::emulate_es2) still reads them back as floats.
    const bool float_color = captures_floats(caps);
    SavedGlState saved(caps);

    Result<ColorDepthFramebuffer> target =
        make_color_depth_framebuffer(width, height, float_color ? ColorFormat::rgba32f : ColorFormat::rgba8, caps);
    if (!target) return with_context("debug-output target", target.error());
    const RenderTarget render_target{target->framebuffer.get(), width, height};
    SurfaceImage out;
    out.width = width;
    out.height = height;
    out.samples.resize(static_cast<size_t>(width) * height);
    Status captured = float_color ? capture_floats(renderer, render_target, caps, out)
                                  : capture_packed(renderer, render_target, caps, out);
    if (!captured) return captured.error();
    return out;
}

}  // namespace px
