// PVRTC1 2 and 4 bpp CPU decoder and a simple encoder.
//
// Sources: S. Fenney, "Texture Compression using Low-Frequency Signal
// Modulation" (Graphics Hardware 2003), and Imagination's PVRTC format
// description; the integer arithmetic (widening of the bilinear sums, the
// truncating / 8 of the modulation, the rounding of the 2 bpp averages) is
// that of Imagination's published reference decompressor (PowerVR SDK,
// PVRTDecompress), which this file reimplements from its description. It
// matches Basis Universal's PVRTC1 decoder exactly on the test image in
// tests/data/textures. Facts used:
//
//  * A 64-bit block (little-endian) is a 32-bit modulation word followed by
//    a 32-bit colour word. Blocks cover 4x4 texels (4 bpp) or 8x4 (2 bpp)
//    and are stored in Morton order: bit 2k of the block index is bit k of
//    the block row, bit 2k + 1 bit k of the block column, for the bits both
//    coordinates have; the longer axis' remaining bits follow.
//  * Colour word: bit 0 the modulation mode; bits 1..15 colour A, bits
//    16..31 colour B. The top bit of each (15, 31) set: opaque, RGB 5:5:4 (A)
//    or 5:5:5 (B); clear: translucent ARGB 3:4:4:3 (A) or 3:4:4:4 (B).
//    Colours are widened to 5 bits per colour channel and 4 bits of alpha
//    (3-bit alpha gets a 0 below) before interpolation.
//  * The A and B images (one texel per block, at the block's centre) are
//    upscaled bilinearly with wrap-around; each texel blends the 4 nearest
//    block colours with weights in quarters (and eighths horizontally for
//    2 bpp), then widens to 8 bits.
//  * 4 bpp modulation: 2 bits per texel, raster order; mode 0: weights 0,
//    3/8, 5/8, 1 of B; mode 1 (punch-through): 0, 1/2, 1/2 with alpha 0, 1.
//  * 2 bpp modulation: mode 0: 1 bit per texel (weight 0 or 1); mode 1:
//    2-bit values for the texels of one checkerboard colour ((x ^ y) even),
//    the others the average of their stored neighbours (H and V, H only or
//    V only, chosen by bit 0 and the centre texel's low bit).
//  * The texel colour is (A (8 - m) + B m) / 8 per 8-bit channel.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "parallaxes/texture/codecs.h"

namespace px {

namespace {

using F = TextureFormat;

bool is_pvrtc(F f) { return format_info(f).family == FormatFamily::pvrtc; }
bool is_2bpp(F f) { return f == F::pvrtc1_rgb_2bpp || f == F::pvrtc1_rgba_2bpp; }
bool has_alpha(F f) { return f == F::pvrtc1_rgba_2bpp || f == F::pvrtc1_rgba_4bpp; }
bool pot(std::uint32_t v) { return v != 0 && (v & (v - 1)) == 0; }

struct Layout {
    std::uint32_t block_w, block_h;  // texels per block
    std::uint32_t bw, bh;            // blocks, at least 2 x 2
    std::uint32_t tex_w() const { return bw * block_w; }
    std::uint32_t tex_h() const { return bh * block_h; }
};

Layout layout_of(F f, std::uint32_t w, std::uint32_t h) {
    Layout l;
    l.block_w = is_2bpp(f) ? 8u : 4u;
    l.block_h = 4;
    l.bw = std::max<std::uint32_t>(2, (w + l.block_w - 1) / l.block_w);
    l.bh = std::max<std::uint32_t>(2, (h + l.block_h - 1) / l.block_h);
    return l;
}

// The blocks a level covers, without the 2 x 2 minimum.
Layout unpadded_layout_of(F f, std::uint32_t w, std::uint32_t h) {
    Layout l;
    l.block_w = is_2bpp(f) ? 8u : 4u;
    l.block_h = 4;
    l.bw = (w + l.block_w - 1) / l.block_w;
    l.bh = (h + l.block_h - 1) / l.block_h;
    return l;
}

// Block index of block (x, y) in Morton order (the sizes are powers of two).
std::uint32_t morton(std::uint32_t x, std::uint32_t y, std::uint32_t bw, std::uint32_t bh) {
    const std::uint32_t min_dim = std::min(bw, bh);
    std::uint32_t out = 0, bit = 0;
    for (std::uint32_t m = 1; m < min_dim; m <<= 1, bit += 2) {
        if (y & m) out |= 1u << bit;
        if (x & m) out |= 1u << (bit + 1);
    }
    const std::uint32_t rest = bw > bh ? x : y;
    const std::uint32_t shift = bit / 2;
    return out | ((rest >> shift) << bit);
}

struct Colour {
    int r, g, b, a;  // 5-bit colour, 4-bit alpha
};

Colour colour_a(std::uint32_t word) {
    if (word & 0x8000u) {
        const int b4 = static_cast<int>((word >> 1) & 15);
        return {static_cast<int>((word >> 10) & 31), static_cast<int>((word >> 5) & 31), (b4 << 1) | (b4 >> 3), 15};
    }
    const int r4 = static_cast<int>((word >> 8) & 15), g4 = static_cast<int>((word >> 4) & 15);
    const int b3 = static_cast<int>((word >> 1) & 7);
    return {(r4 << 1) | (r4 >> 3), (g4 << 1) | (g4 >> 3), (b3 << 2) | (b3 >> 1),
            static_cast<int>((word >> 12) & 7) << 1};
}

Colour colour_b(std::uint32_t word) {
    if (word & 0x80000000u)
        return {static_cast<int>((word >> 26) & 31), static_cast<int>((word >> 21) & 31),
                static_cast<int>((word >> 16) & 31), 15};
    const int r4 = static_cast<int>((word >> 24) & 15), g4 = static_cast<int>((word >> 20) & 15);
    const int b4 = static_cast<int>((word >> 16) & 15);
    return {(r4 << 1) | (r4 >> 3), (g4 << 1) | (g4 >> 3), (b4 << 1) | (b4 >> 3),
            static_cast<int>((word >> 28) & 7) << 1};
}

// The decoded blocks of an image: words in block raster order.
struct Blocks {
    Layout l;
    std::vector<std::uint32_t> mod, col;  // [by * bw + bx]
    std::vector<Colour> a, b;
    std::uint32_t at(std::uint32_t bx, std::uint32_t by) const { return by * l.bw + bx; }
};

void unpack_colours(Blocks& k) {
    k.a.resize(k.col.size());
    k.b.resize(k.col.size());
    for (std::size_t i = 0; i < k.col.size(); ++i) {
        k.a[i] = colour_a(k.col[i]);
        k.b[i] = colour_b(k.col[i]);
    }
}

// Bilinearly upscaled A and B at texel (x, y) of the padded image, 8 bits.
void upscale(const Blocks& k, std::uint32_t x, std::uint32_t y, int a8[4], int b8[4]) {
    const Layout& l = k.l;
    const std::uint32_t xs = x + l.tex_w() - l.block_w / 2, ys = y + l.tex_h() - l.block_h / 2;
    const std::uint32_t bx0 = (xs / l.block_w) % l.bw, by0 = (ys / l.block_h) % l.bh;
    const std::uint32_t bx1 = (bx0 + 1) % l.bw, by1 = (by0 + 1) % l.bh;
    const int fx = static_cast<int>(xs % l.block_w), fy = static_cast<int>(ys % l.block_h);
    const int bw = static_cast<int>(l.block_w), bh = static_cast<int>(l.block_h);
    const int w00 = (bw - fx) * (bh - fy), w10 = fx * (bh - fy), w01 = (bw - fx) * fy, w11 = fx * fy;
    const std::uint32_t i00 = k.at(bx0, by0), i10 = k.at(bx1, by0), i01 = k.at(bx0, by1), i11 = k.at(bx1, by1);
    const bool two = l.block_w == 8;
    auto widen = [two](int s, bool alpha) {
        // s = sum of weights (16 for 4 bpp, 32 for 2 bpp) times a 5-bit
        // colour or 4-bit alpha; these map 31 * W and 15 * W to 255.
        if (two) return alpha ? (s >> 5) + (s >> 1) : (s >> 7) + (s >> 2);
        return alpha ? (s >> 4) + s : (s >> 6) + (s >> 1);
    };
    const std::vector<Colour>* src[2] = {&k.a, &k.b};
    int* dst[2] = {a8, b8};
    for (int j = 0; j < 2; ++j) {
        const Colour& c00 = (*src[j])[i00];
        const Colour& c10 = (*src[j])[i10];
        const Colour& c01 = (*src[j])[i01];
        const Colour& c11 = (*src[j])[i11];
        dst[j][0] = widen(w00 * c00.r + w10 * c10.r + w01 * c01.r + w11 * c11.r, false);
        dst[j][1] = widen(w00 * c00.g + w10 * c10.g + w01 * c01.g + w11 * c11.g, false);
        dst[j][2] = widen(w00 * c00.b + w10 * c10.b + w01 * c01.b + w11 * c11.b, false);
        dst[j][3] = widen(w00 * c00.a + w10 * c10.a + w01 * c01.a + w11 * c11.a, true);
    }
}

// 2 bpp: the 2-bit value of a stored texel (local x, y with (x ^ y) even)
// of a block in interpolated mode, after the two 1-bit texels' fix-ups.
int stored_2bpp(std::uint32_t mod, std::uint32_t x, std::uint32_t y) {
    const std::uint32_t index = y * 4 + x / 2;
    if (index == 0) return (mod & 2u) ? 3 : 0;
    if (index == 10 && (mod & 1u)) return (mod & (1u << 21)) ? 3 : 0;
    return static_cast<int>((mod >> (2 * index)) & 3);
}

const int kRep[4] = {0, 3, 5, 8};

// 2 bpp: the value (0..3) a neighbouring texel contributes, from its own
// block (direct mode: 0 or 3).
int raw_2bpp(const Blocks& k, std::uint32_t x, std::uint32_t y) {
    const std::uint32_t bi = k.at(x / 8, y / 4);
    const std::uint32_t lx = x % 8, ly = y % 4;
    if (!(k.col[bi] & 1u)) return ((k.mod[bi] >> (ly * 8 + lx)) & 1u) ? 3 : 0;
    return stored_2bpp(k.mod[bi], lx, ly);
}

// The modulation weight (0..8) of texel (x, y); `punch` for alpha 0.
int modulation(const Blocks& k, std::uint32_t x, std::uint32_t y, bool& punch) {
    punch = false;
    const Layout& l = k.l;
    const std::uint32_t bi = k.at(x / l.block_w, y / l.block_h);
    const std::uint32_t lx = x % l.block_w, ly = y % l.block_h;
    const std::uint32_t mod = k.mod[bi];
    const bool mode = (k.col[bi] & 1u) != 0;
    if (l.block_w == 4) {
        const int v = static_cast<int>((mod >> (2 * (ly * 4 + lx))) & 3);
        if (!mode) return kRep[v];
        punch = v == 2;
        return v == 0 ? 0 : v == 3 ? 8 : 4;
    }
    if (!mode) return ((mod >> (ly * 8 + lx)) & 1u) ? 8 : 0;
    if (((lx ^ ly) & 1u) == 0) return kRep[stored_2bpp(mod, lx, ly)];
    const std::uint32_t W = l.tex_w(), H = l.tex_h();
    const int left = kRep[raw_2bpp(k, (x + W - 1) % W, y)], right = kRep[raw_2bpp(k, (x + 1) % W, y)];
    const int up = kRep[raw_2bpp(k, x, (y + H - 1) % H)], down = kRep[raw_2bpp(k, x, (y + 1) % H)];
    if (!(mod & 1u)) return (left + right + up + down + 2) / 4;
    if (mod & (1u << 20)) return (up + down + 1) / 2;  // vertical only
    return (left + right + 1) / 2;                      // horizontal only
}

void decode_texel(const Blocks& k, std::uint32_t x, std::uint32_t y, bool alpha, std::uint8_t* out) {
    int a[4], b[4];
    upscale(k, x, y, a, b);
    bool punch = false;
    const int m = modulation(k, x, y, punch);
    for (int c = 0; c < 4; ++c) out[c] = static_cast<std::uint8_t>((a[c] * (8 - m) + b[c] * m) / 8);
    if (punch) out[3] = 0;
    if (!alpha) out[3] = 255;
}

std::string dims(F f, std::uint32_t w, std::uint32_t h) {
    return std::string(format_name(f)) + " " + std::to_string(w) + "x" + std::to_string(h);
}

Status check_common(const char* fn, F format, std::uint32_t w, std::uint32_t h) {
    if (!is_pvrtc(format)) return make_error(std::string(fn) + ": format " + format_name(format) + " is not PVRTC1");
    if (w == 0 || h == 0)
        return make_error(std::string(fn) + ": " + dims(format, w, h) + " (width and height must be at least 1)");
    if (!pot(w) || !pot(h))
        return make_error(std::string(fn) + ": " + dims(format, w, h) +
                          ": PVRTC1 needs power-of-two width and height");
    if (w > (1u << 16) || h > (1u << 16))
        return make_error(std::string(fn) + ": " + dims(format, w, h) + " is too large (at most 65536 each way)");
    return {};
}

// ---- encoding ---------------------------------------------------------------

int q(float v, int maxv) {
    return static_cast<int>(std::lround(std::clamp(v, 0.0f, 255.0f) * static_cast<float>(maxv) / 255.0f));
}

// Packs an 8-bit RGBA endpoint as colour A (b_colour false) or B.
std::uint32_t pack_colour(const float c[4], bool b_colour, bool opaque) {
    if (opaque) {
        const std::uint32_t r = static_cast<std::uint32_t>(q(c[0], 31)), g = static_cast<std::uint32_t>(q(c[1], 31));
        if (b_colour) return 0x8000u | (r << 10) | (g << 5) | static_cast<std::uint32_t>(q(c[2], 31));
        return 0x8000u | (r << 10) | (g << 5) | (static_cast<std::uint32_t>(q(c[2], 15)) << 1);
    }
    const std::uint32_t a = static_cast<std::uint32_t>(q(c[3], 7)), r = static_cast<std::uint32_t>(q(c[0], 15)),
                        g = static_cast<std::uint32_t>(q(c[1], 15));
    if (b_colour) return (a << 12) | (r << 8) | (g << 4) | static_cast<std::uint32_t>(q(c[2], 15));
    return (a << 12) | (r << 8) | (g << 4) | (static_cast<std::uint32_t>(q(c[2], 7)) << 1);
}

}  // namespace

Status decode_pvrtc_rgba8(TextureFormat format, std::uint32_t width, std::uint32_t height,
                          const std::uint8_t* data, std::size_t size, std::uint8_t* rgba) {
    const char* fn = "decode_pvrtc_rgba8";
    if (Status s = check_common(fn, format, width, height); !s) return s;
    const auto expected = image_bytes(format, width, height);
    if (!expected || *expected != size)
        return make_error(std::string(fn) + ": " + dims(format, width, height) + " image needs " +
                          std::to_string(expected ? *expected : 0) + " bytes, " + std::to_string(size) + " given");
    if (!data || !rgba) return make_error(std::string(fn) + ": null data or output pointer");
    return out_of_memory_is_an_error(fn, [&]() -> Status {
        Blocks k;
        k.l = layout_of(format, width, height);
        const std::size_t n = std::size_t{k.l.bw} * k.l.bh;
        k.mod.resize(n);
        k.col.resize(n);
        for (std::uint32_t by = 0; by < k.l.bh; ++by)
            for (std::uint32_t bx = 0; bx < k.l.bw; ++bx) {
                const std::uint8_t* p = data + std::size_t{morton(bx, by, k.l.bw, k.l.bh)} * 8;
                std::uint32_t m = 0, c = 0;
                for (int i = 3; i >= 0; --i) {
                    m = (m << 8) | p[i];
                    c = (c << 8) | p[4 + i];
                }
                k.mod[k.at(bx, by)] = m;
                k.col[k.at(bx, by)] = c;
            }
        unpack_colours(k);
        const bool alpha = has_alpha(format);
        for (std::uint32_t y = 0; y < height; ++y)
            for (std::uint32_t x = 0; x < width; ++x)
                decode_texel(k, x, y, alpha, rgba + (std::size_t{y} * width + x) * 4);
        return Status{};
    });
}

// Encoder: each block's A (low) and B (high) colours from the extremes of
// its texels along their principal axis; then, with the A and B images
// upscaled exactly as the decoder does, each texel's modulation value is
// the one nearest the source texel (4 bpp: weights 0, 3/8, 5/8, 1; 2 bpp:
// direct 1-bit mode, weights 0 and 1). Then refinement: each step moves
// every block's colours down the gradient of the squared error of its
// texels given those modulation values, and the modulation is chosen again;
// up to 48 such steps, a step that does not lower the error is undone and
// the step size halved.
Result<std::vector<std::uint8_t>> encode_pvrtc_rgba8(TextureFormat format, std::uint32_t width,
                                                     std::uint32_t height, const std::uint8_t* rgba) {
    const char* fn = "encode_pvrtc_rgba8";
    if (Status s = check_common(fn, format, width, height); !s) return s.error();
    if (!rgba) return make_error(std::string(fn) + ": null pixel pointer");
    return out_of_memory_is_an_error(fn, [&]() -> Result<std::vector<std::uint8_t>> {
        const bool alpha = has_alpha(format);
        Blocks k;
        k.l = layout_of(format, width, height);
        const Layout& l = k.l;
        const std::uint32_t W = l.tex_w(), H = l.tex_h();
        // The padded source (edge texels repeated), alpha 255 for RGB.
        std::vector<float> src(std::size_t{W} * H * 4);
        for (std::uint32_t y = 0; y < H; ++y)
            for (std::uint32_t x = 0; x < W; ++x)
                for (int c = 0; c < 4; ++c) {
                    const std::uint8_t* p = rgba + (std::size_t{std::min(y, height - 1)} * width + std::min(x, width - 1)) * 4;
                    src[(std::size_t{y} * W + x) * 4 + c] = (c == 3 && !alpha) ? 255.0f : p[c];
                }
        const std::size_t n = std::size_t{l.bw} * l.bh;
        std::vector<float> lo(n * 4), hi(n * 4);
        const std::uint32_t per = l.block_w * l.block_h;
        for (std::uint32_t by = 0; by < l.bh; ++by)
            for (std::uint32_t bx = 0; bx < l.bw; ++bx) {
                float mean[4] = {};
                for (std::uint32_t y = 0; y < l.block_h; ++y)
                    for (std::uint32_t x = 0; x < l.block_w; ++x)
                        for (int c = 0; c < 4; ++c)
                            mean[c] += src[((by * l.block_h + y) * std::size_t{W} + bx * l.block_w + x) * 4 + c];
                for (float& v : mean) v /= static_cast<float>(per);
                float cov[4][4] = {};
                for (std::uint32_t y = 0; y < l.block_h; ++y)
                    for (std::uint32_t x = 0; x < l.block_w; ++x) {
                        const float* p = &src[((by * l.block_h + y) * std::size_t{W} + bx * l.block_w + x) * 4];
                        for (int i = 0; i < 4; ++i)
                            for (int j = 0; j < 4; ++j) cov[i][j] += (p[i] - mean[i]) * (p[j] - mean[j]);
                    }
                float axis[4] = {1, 1, 1, 1};
                for (int it = 0; it < 12; ++it) {
                    float nv[4] = {}, len = 0;
                    for (int i = 0; i < 4; ++i) {
                        for (int j = 0; j < 4; ++j) nv[i] += cov[i][j] * axis[j];
                        len += nv[i] * nv[i];
                    }
                    len = std::sqrt(len);
                    if (len < 1e-6f) break;
                    for (int i = 0; i < 4; ++i) axis[i] = nv[i] / len;
                }
                {
                    float len = 0;
                    for (float v : axis) len += v * v;
                    len = std::sqrt(len);
                    for (float& v : axis) v /= len;
                }
                float tmin = 0, tmax = 0;
                for (std::uint32_t y = 0; y < l.block_h; ++y)
                    for (std::uint32_t x = 0; x < l.block_w; ++x) {
                        const float* p = &src[((by * l.block_h + y) * std::size_t{W} + bx * l.block_w + x) * 4];
                        float t = 0;
                        for (int c = 0; c < 4; ++c) t += (p[c] - mean[c]) * axis[c];
                        tmin = std::min(tmin, t);
                        tmax = std::max(tmax, t);
                    }
                const std::size_t bi = k.at(bx, by);
                for (int c = 0; c < 4; ++c) {
                    lo[bi * 4 + c] = std::clamp(mean[c] + tmin * axis[c], 0.0f, 255.0f);
                    hi[bi * 4 + c] = std::clamp(mean[c] + tmax * axis[c], 0.0f, 255.0f);
                }
            }
        k.mod.assign(n, 0);
        k.col.assign(n, 0);
        auto pack_all = [&]() {
            for (std::size_t i = 0; i < n; ++i) {
                // A block's colours are opaque when their alpha rounds to 255
                // in the translucent encoding's 3 bits or better.
                const bool oa = !alpha || lo[i * 4 + 3] >= 247.0f, ob = !alpha || hi[i * 4 + 3] >= 247.0f;
                k.col[i] = (pack_colour(&lo[i * 4], false, oa) & 0xFFFEu) | (pack_colour(&hi[i * 4], true, ob) << 16);
            }
            unpack_colours(k);
        };
        // Chooses every texel's modulation; returns the total squared error.
        std::vector<std::uint8_t> weight(std::size_t{W} * H);
        auto choose = [&]() {
            double total = 0;
            std::fill(k.mod.begin(), k.mod.end(), 0u);
            const bool two = l.block_w == 8;
            for (std::uint32_t y = 0; y < H; ++y)
                for (std::uint32_t x = 0; x < W; ++x) {
                    int a[4], b[4];
                    upscale(k, x, y, a, b);
                    const float* p = &src[(std::size_t{y} * W + x) * 4];
                    double best = std::numeric_limits<double>::max();
                    int bv = 0;
                    for (int v = 0; v < 4; ++v) {
                        if (two && v != 0 && v != 3) continue;
                        const int m = kRep[v];
                        double e = 0;
                        for (int c = 0; c < 4; ++c) {
                            const double d = (a[c] * (8 - m) + b[c] * m) / 8 - static_cast<double>(p[c]);
                            e += d * d;
                        }
                        if (e < best) {
                            best = e;
                            bv = v;
                        }
                    }
                    total += best;
                    weight[std::size_t{y} * W + x] = static_cast<std::uint8_t>(kRep[bv]);
                    const std::size_t bi = k.at(x / l.block_w, y / l.block_h);
                    const std::uint32_t lx = x % l.block_w, ly = y % l.block_h;
                    if (two)
                        k.mod[bi] |= (bv ? 1u : 0u) << (ly * 8 + lx);
                    else
                        k.mod[bi] |= static_cast<std::uint32_t>(bv) << (2 * (ly * 4 + lx));
                }
            return total;
        };
        pack_all();
        double err = choose();
        // Refinement: gradient steps on all block colours (the decode is
        // linear in them given the modulation), each kept only if it helps.
        float step = 0.5f;
        for (int pass = 0; pass < 48 && step > 0.06f; ++pass) {
            std::vector<float> glo(n * 4, 0.0f), ghi(n * 4, 0.0f), wsum(n, 0.0f);
            for (std::uint32_t y = 0; y < H; ++y)
                for (std::uint32_t x = 0; x < W; ++x) {
                    int a[4], b[4];
                    upscale(k, x, y, a, b);
                    const int m = weight[std::size_t{y} * W + x];
                    const float* p = &src[(std::size_t{y} * W + x) * 4];
                    float r[4];
                    for (int c = 0; c < 4; ++c)
                        r[c] = static_cast<float>(a[c] * (8 - m) + b[c] * m) / 8.0f - p[c];
                    const std::uint32_t xs = x + W - l.block_w / 2, ys = y + H - l.block_h / 2;
                    const std::uint32_t bx0 = (xs / l.block_w) % l.bw, by0 = (ys / l.block_h) % l.bh;
                    const float fx = static_cast<float>(xs % l.block_w) / static_cast<float>(l.block_w);
                    const float fy = static_cast<float>(ys % l.block_h) / static_cast<float>(l.block_h);
                    const std::uint32_t bxs[2] = {bx0, (bx0 + 1) % l.bw}, bys[2] = {by0, (by0 + 1) % l.bh};
                    const float wx[2] = {1 - fx, fx}, wy[2] = {1 - fy, fy};
                    const float mb = static_cast<float>(m) / 8.0f;
                    for (int j = 0; j < 2; ++j)
                        for (int i = 0; i < 2; ++i) {
                            const std::size_t bi = k.at(bxs[i], bys[j]);
                            const float w = wx[i] * wy[j];
                            wsum[bi] += w * w;
                            for (int c = 0; c < 4; ++c) {
                                glo[bi * 4 + c] += w * (1 - mb) * r[c];
                                ghi[bi * 4 + c] += w * mb * r[c];
                            }
                        }
                }
            const std::vector<float> old_lo = lo, old_hi = hi;
            const std::vector<std::uint32_t> old_col = k.col, old_mod = k.mod;
            const std::vector<std::uint8_t> old_w = weight;
            for (std::size_t i = 0; i < n; ++i) {
                const float s = wsum[i] > 0 ? 1.0f / wsum[i] : 0.0f;
                for (int c = 0; c < 4; ++c) {
                    lo[i * 4 + c] = std::clamp(lo[i * 4 + c] - step * s * glo[i * 4 + c], 0.0f, 255.0f);
                    hi[i * 4 + c] = std::clamp(hi[i * 4 + c] - step * s * ghi[i * 4 + c], 0.0f, 255.0f);
                }
            }
            pack_all();
            const double e = choose();
            if (e >= err) {
                lo = old_lo;
                hi = old_hi;
                k.col = old_col;
                k.mod = old_mod;
                weight = old_w;
                unpack_colours(k);
                step *= 0.5f;
                continue;
            }
            err = e;
        }
        std::vector<std::uint8_t> out(n * 8);
        for (std::uint32_t by = 0; by < l.bh; ++by)
            for (std::uint32_t bx = 0; bx < l.bw; ++bx) {
                std::uint8_t* o = out.data() + std::size_t{morton(bx, by, l.bw, l.bh)} * 8;
                const std::uint32_t m = k.mod[k.at(bx, by)], c = k.col[k.at(bx, by)];
                for (int i = 0; i < 4; ++i) {
                    o[i] = static_cast<std::uint8_t>(m >> (8 * i));
                    o[4 + i] = static_cast<std::uint8_t>(c >> (8 * i));
                }
            }
        return out;
    });
}

std::uint64_t pvrtc_stored_bytes(TextureFormat format, std::uint32_t width, std::uint32_t height) {
    const Layout l = unpadded_layout_of(format, width, height);
    return std::uint64_t{l.bw} * l.bh * 8;
}

std::vector<std::uint8_t> pvrtc_pad_level(TextureFormat format, std::uint32_t width, std::uint32_t height,
                                          const std::uint8_t* stored) {
    const Layout given = unpadded_layout_of(format, width, height), full = layout_of(format, width, height);
    std::vector<std::uint8_t> out(std::size_t{full.bw} * full.bh * 8);
    for (std::uint32_t by = 0; by < full.bh; ++by)
        for (std::uint32_t bx = 0; bx < full.bw; ++bx) {
            const std::uint32_t from = morton(bx % given.bw, by % given.bh, given.bw, given.bh);
            std::memcpy(out.data() + std::size_t{morton(bx, by, full.bw, full.bh)} * 8, stored + std::size_t{from} * 8, 8);
        }
    return out;
}

}  // namespace px
