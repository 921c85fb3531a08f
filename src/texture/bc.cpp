// BC1..BC5 (S3TC and RGTC) CPU decoders and simple encoders.
//
// Sources: EXT_texture_compression_s3tc (DXT1/3/5 block layout and palette
// rules) and EXT/ARB_texture_compression_rgtc (RED_RGTC1 / RG_RGTC2 block
// layout and the 8- and 6-value palettes).
//
// Precision: the specs define the interpolated palette entries as exact
// fractions ((2 c0 + c1) / 3, ((7 - i) r0 + i r1) / 7, ...). The rgba8
// decoders round those fractions to the nearest 8-bit value (ties up). The
// unorm16 decoders for BC4/BC5 round the exact fraction to the nearest
// 16-bit value: endpoints come out as v * 257 exactly (the 8-bit value
// widened), interpolants as round(257 * fraction), so v / 65535 is within
// 1/131070 of the value the spec defines.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "parallaxes/texture/codecs.h"

namespace px {

namespace {

using F = TextureFormat;

bool is_bc(F f) { return f == F::bc1_rgb || f == F::bc1_rgba || f == F::bc2 || f == F::bc3 || f == F::bc4 || f == F::bc5; }

Status check_dims(const char* fn, F format, std::uint32_t w, std::uint32_t h) {
    if (w == 0 || h == 0)
        return make_error(std::string(fn) + ": " + format_name(format) + " image of " + std::to_string(w) + "x" +
                          std::to_string(h) + " texels (width and height must be at least 1)");
    return {};
}

Status check_size(const char* fn, F format, std::uint32_t w, std::uint32_t h, std::size_t size) {
    const auto expected = image_bytes(format, w, h);
    if (!expected)
        return make_error(std::string(fn) + ": " + format_name(format) + " image of " + std::to_string(w) + "x" +
                          std::to_string(h) + " texels is too large");
    if (*expected != size)
        return make_error(std::string(fn) + ": " + format_name(format) + " " + std::to_string(w) + "x" +
                          std::to_string(h) + " image needs " + std::to_string(*expected) + " bytes, " +
                          std::to_string(size) + " given");
    return {};
}

Status check_decode(const char* fn, F format, bool format_ok, std::uint32_t w, std::uint32_t h,
                    const void* data, std::size_t size, const void* out) {
    if (!format_ok)
        return make_error(std::string(fn) + ": format " + format_name(format) + " is not handled here");
    if (Status s = check_dims(fn, format, w, h); !s) return s;
    if (Status s = check_size(fn, format, w, h, size); !s) return s;
    if (!data || !out) return make_error(std::string(fn) + ": null data or output pointer");
    return {};
}

std::uint16_t le16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
std::uint32_t le32(const std::uint8_t* p) {
    return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
           (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
std::uint64_t le48(const std::uint8_t* p) {
    std::uint64_t v = 0;
    for (int i = 5; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}

struct Rgb {
    int r, g, b;
};

// RGB 5:6:5 to 8 bits per channel by bit replication.
Rgb expand565(std::uint16_t c) {
    const int r = (c >> 11) & 31, g = (c >> 5) & 63, b = c & 31;
    return {(r << 3) | (r >> 2), (g << 2) | (g >> 4), (b << 3) | (b >> 2)};
}

// The four palette entries of a DXT colour block (RGBA). `three_colour_ok`:
// DXT1 only; DXT3/DXT5 always use the four-colour palette.
void colour_palette(std::uint16_t c0, std::uint16_t c1, bool three_colour_ok, bool transparent_black,
                    std::uint8_t pal[4][4]) {
    const Rgb a = expand565(c0), b = expand565(c1);
    const Rgb e[2] = {a, b};
    for (int i = 0; i < 2; ++i) {
        pal[i][0] = static_cast<std::uint8_t>(e[i].r);
        pal[i][1] = static_cast<std::uint8_t>(e[i].g);
        pal[i][2] = static_cast<std::uint8_t>(e[i].b);
        pal[i][3] = 255;
    }
    auto mix = [](int x, int y, int wx, int wy, int d) { return static_cast<std::uint8_t>((wx * x + wy * y + d / 2) / d); };
    if (c0 > c1 || !three_colour_ok) {
        pal[2][0] = mix(a.r, b.r, 2, 1, 3);
        pal[2][1] = mix(a.g, b.g, 2, 1, 3);
        pal[2][2] = mix(a.b, b.b, 2, 1, 3);
        pal[3][0] = mix(a.r, b.r, 1, 2, 3);
        pal[3][1] = mix(a.g, b.g, 1, 2, 3);
        pal[3][2] = mix(a.b, b.b, 1, 2, 3);
        pal[2][3] = pal[3][3] = 255;
    } else {
        pal[2][0] = mix(a.r, b.r, 1, 1, 2);
        pal[2][1] = mix(a.g, b.g, 1, 1, 2);
        pal[2][2] = mix(a.b, b.b, 1, 1, 2);
        pal[2][3] = 255;
        pal[3][0] = pal[3][1] = pal[3][2] = 0;
        pal[3][3] = transparent_black ? 0 : 255;
    }
}

// The 8 palette entries of an RGTC / DXT5 alpha block as fractions of 255
// numerators over a common denominator: value = num[i] / den.
void single_palette(int r0, int r1, int num[8], int& den) {
    num[0] = r0;
    num[1] = r1;
    if (r0 > r1) {
        den = 7;
        num[0] = 7 * r0;
        num[1] = 7 * r1;
        for (int i = 2; i < 8; ++i) num[i] = (8 - i) * r0 + (i - 1) * r1;
    } else {
        den = 5;
        num[0] = 5 * r0;
        num[1] = 5 * r1;
        for (int i = 2; i < 6; ++i) num[i] = (6 - i) * r0 + (i - 1) * r1;
        num[6] = 0;
        num[7] = 5 * 255;
    }
}

// Decodes an 8-byte BC4 / DXT5-alpha block: 16 values, 8-bit or 16-bit.
void decode_single8(const std::uint8_t* p, std::uint8_t out[16]) {
    int num[8], den;
    single_palette(p[0], p[1], num, den);
    const std::uint64_t bits = le48(p + 2);
    for (int i = 0; i < 16; ++i) {
        const int k = static_cast<int>((bits >> (3 * i)) & 7);
        out[i] = static_cast<std::uint8_t>((num[k] + den / 2) / den);
    }
}
void decode_single16(const std::uint8_t* p, std::uint16_t out[16]) {
    int num[8], den;
    single_palette(p[0], p[1], num, den);
    const std::uint64_t bits = le48(p + 2);
    for (int i = 0; i < 16; ++i) {
        const int k = static_cast<int>((bits >> (3 * i)) & 7);
        out[i] = static_cast<std::uint16_t>((257 * num[k] + den / 2) / den);
    }
}

void decode_colour_block(const std::uint8_t* p, bool three_colour_ok, bool transparent_black,
                         std::uint8_t out[16][4]) {
    std::uint8_t pal[4][4];
    colour_palette(le16(p), le16(p + 2), three_colour_ok, transparent_black, pal);
    const std::uint32_t idx = le32(p + 4);
    for (int i = 0; i < 16; ++i) std::memcpy(out[i], pal[(idx >> (2 * i)) & 3], 4);
}

// ---- encoding ---------------------------------------------------------------

// Gathers the 4x4 block at (bx, by), repeating edge texels, `ch` channels.
template <typename T>
void gather(const T* src, std::uint32_t w, std::uint32_t h, int ch, std::uint32_t bx, std::uint32_t by, T* out) {
    for (std::uint32_t y = 0; y < 4; ++y)
        for (std::uint32_t x = 0; x < 4; ++x) {
            const std::uint32_t sx = std::min(bx * 4 + x, w - 1), sy = std::min(by * 4 + y, h - 1);
            for (int c = 0; c < ch; ++c) out[(y * 4 + x) * ch + c] = src[(std::size_t{sy} * w + sx) * ch + c];
        }
}

std::uint16_t pack565(float r, float g, float b) {
    auto q = [](float v, int maxv) {
        const float s = std::round(std::clamp(v, 0.0f, 255.0f) * static_cast<float>(maxv) / 255.0f);
        return static_cast<int>(s);
    };
    return static_cast<std::uint16_t>((q(r, 31) << 11) | (q(g, 63) << 5) | q(b, 31));
}

// Picks the nearest palette entry per texel; returns the squared error.
long choose_colour_indices(const std::uint8_t px[16][4], std::uint16_t c0, std::uint16_t c1, bool three_ok,
                           std::uint32_t& idx) {
    std::uint8_t pal[4][4];
    colour_palette(c0, c1, three_ok, false, pal);
    long total = 0;
    idx = 0;
    for (int i = 0; i < 16; ++i) {
        long best = std::numeric_limits<long>::max();
        int bi = 0;
        for (int k = 0; k < 4; ++k) {
            long e = 0;
            for (int c = 0; c < 3; ++c) {
                const long d = static_cast<long>(px[i][c]) - pal[k][c];
                e += d * d;
            }
            if (e < best) {
                best = e;
                bi = k;
            }
        }
        total += best;
        idx |= static_cast<std::uint32_t>(bi) << (2 * i);
    }
    return total;
}

// DXT colour block (four-colour mode) by a principal-axis endpoint fit,
// then two least-squares refinements of the endpoints given the indices.
void encode_colour_block(const std::uint8_t px[16][4], std::uint8_t* out) {
    float mean[3] = {0, 0, 0};
    for (int i = 0; i < 16; ++i)
        for (int c = 0; c < 3; ++c) mean[c] += px[i][c] / 16.0f;
    float cov[3][3] = {};
    for (int i = 0; i < 16; ++i)
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) cov[a][b] += (px[i][a] - mean[a]) * (px[i][b] - mean[b]);
    float axis[3] = {1, 1, 1};
    for (int it = 0; it < 12; ++it) {
        float n[3];
        for (int a = 0; a < 3; ++a) n[a] = cov[a][0] * axis[0] + cov[a][1] * axis[1] + cov[a][2] * axis[2];
        const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len < 1e-6f) break;
        for (int a = 0; a < 3; ++a) axis[a] = n[a] / len;
    }
    {
        const float len = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
        for (float& v : axis) v /= len;
    }
    float tmin = 0, tmax = 0;
    for (int i = 0; i < 16; ++i) {
        float t = 0;
        for (int c = 0; c < 3; ++c) t += (px[i][c] - mean[c]) * axis[c];
        tmin = std::min(tmin, t);
        tmax = std::max(tmax, t);
    }
    std::uint16_t c0 = pack565(mean[0] + tmax * axis[0], mean[1] + tmax * axis[1], mean[2] + tmax * axis[2]);
    std::uint16_t c1 = pack565(mean[0] + tmin * axis[0], mean[1] + tmin * axis[1], mean[2] + tmin * axis[2]);
    std::uint32_t idx = 0;
    long best = choose_colour_indices(px, c0, c1, false, idx);
    std::uint16_t b0 = c0, b1 = c1;
    std::uint32_t bidx = idx;
    static const float w0s[4] = {1.0f, 0.0f, 2.0f / 3.0f, 1.0f / 3.0f};
    for (int it = 0; it < 2; ++it) {
        // Least squares for e0, e1 with texel i = w_i e0 + (1 - w_i) e1.
        float aa = 0, ab = 0, bb = 0, ax[3] = {}, bx[3] = {};
        for (int i = 0; i < 16; ++i) {
            const float w = w0s[(bidx >> (2 * i)) & 3], v = 1.0f - w;
            aa += w * w;
            ab += w * v;
            bb += v * v;
            for (int c = 0; c < 3; ++c) {
                ax[c] += w * px[i][c];
                bx[c] += v * px[i][c];
            }
        }
        const float det = aa * bb - ab * ab;
        if (std::fabs(det) < 1e-6f) break;
        float e0[3], e1[3];
        for (int c = 0; c < 3; ++c) {
            e0[c] = (ax[c] * bb - bx[c] * ab) / det;
            e1[c] = (bx[c] * aa - ax[c] * ab) / det;
        }
        c0 = pack565(e0[0], e0[1], e0[2]);
        c1 = pack565(e1[0], e1[1], e1[2]);
        const long e = choose_colour_indices(px, c0, c1, false, idx);
        if (e >= best) break;
        best = e;
        b0 = c0;
        b1 = c1;
        bidx = idx;
    }
    // Four-colour mode needs c0 > c1: swap (indices 0<->1, 2<->3); equal
    // endpoints give the three-colour palette, where index 0 is still c0.
    if (b0 < b1) {
        std::swap(b0, b1);
        bidx ^= 0x55555555u;
    } else if (b0 == b1) {
        bidx = 0;
    }
    out[0] = static_cast<std::uint8_t>(b0);
    out[1] = static_cast<std::uint8_t>(b0 >> 8);
    out[2] = static_cast<std::uint8_t>(b1);
    out[3] = static_cast<std::uint8_t>(b1 >> 8);
    for (int i = 0; i < 4; ++i) out[4 + i] = static_cast<std::uint8_t>(bidx >> (8 * i));
}

// RGTC / DXT5 alpha block in 8-value mode (r0 > r1) from 16 targets given
// as 16-bit values: min/max endpoints, then a search of +-2 around each.
void encode_single_block(const std::uint16_t v[16], std::uint8_t* out) {
    int lo = 255, hi = 0;
    for (int i = 0; i < 16; ++i) {
        lo = std::min(lo, static_cast<int>(v[i] / 257));
        hi = std::max(hi, static_cast<int>((v[i] + 256) / 257));
    }
    // 64-bit sums: a 16-bit value's squared error reaches 4.3e9, past a
    // 32-bit long (armhf: BcRoundTrip.Bc4Bc5Unorm16 picked wrong indices).
    std::int64_t best = std::numeric_limits<std::int64_t>::max();
    int br0 = 1, br1 = 0;
    std::uint64_t bbits = 0;
    for (int r0 = std::max(0, hi - 2); r0 <= std::min(255, hi + 2); ++r0)
        for (int r1 = std::max(0, lo - 2); r1 <= std::min(255, lo + 2); ++r1) {
            if (r0 <= r1) continue;
            int num[8], den;
            single_palette(r0, r1, num, den);
            std::int64_t pal[8];
            for (int k = 0; k < 8; ++k) pal[k] = (std::int64_t{257} * num[k] + den / 2) / den;
            std::int64_t err = 0;
            std::uint64_t bits = 0;
            for (int i = 0; i < 16; ++i) {
                std::int64_t be = std::numeric_limits<std::int64_t>::max();
                int bk = 0;
                for (int k = 0; k < 8; ++k) {
                    const std::int64_t d = pal[k] - v[i];
                    if (d * d < be) {
                        be = d * d;
                        bk = k;
                    }
                }
                err += be;
                bits |= static_cast<std::uint64_t>(bk) << (3 * i);
            }
            if (err < best) {
                best = err;
                br0 = r0;
                br1 = r1;
                bbits = bits;
            }
        }
    out[0] = static_cast<std::uint8_t>(br0);
    out[1] = static_cast<std::uint8_t>(br1);
    for (int i = 0; i < 6; ++i) out[2 + i] = static_cast<std::uint8_t>(bbits >> (8 * i));
}

}  // namespace

Status decode_bc_rgba8(TextureFormat format, std::uint32_t width, std::uint32_t height, const std::uint8_t* data,
                       std::size_t size, std::uint8_t* rgba) {
    if (Status s = check_decode("decode_bc_rgba8", format, is_bc(format), width, height, data, size, rgba); !s)
        return s;
    const std::size_t bb = static_cast<std::size_t>(format_info(format).block_bytes);
    const std::uint32_t bw = (width + 3) / 4, bh = (height + 3) / 4;
    for (std::uint32_t by = 0; by < bh; ++by)
        for (std::uint32_t bx = 0; bx < bw; ++bx) {
            const std::uint8_t* p = data + (std::size_t{by} * bw + bx) * bb;
            std::uint8_t t[16][4];
            switch (format) {
            case F::bc1_rgb: decode_colour_block(p, true, false, t); break;
            case F::bc1_rgba: decode_colour_block(p, true, true, t); break;
            case F::bc2: {
                decode_colour_block(p + 8, false, false, t);
                for (int i = 0; i < 16; ++i) {
                    const int a = (p[i / 2] >> (4 * (i & 1))) & 15;
                    t[i][3] = static_cast<std::uint8_t>(a * 17);
                }
                break;
            }
            case F::bc3: {
                decode_colour_block(p + 8, false, false, t);
                std::uint8_t a[16];
                decode_single8(p, a);
                for (int i = 0; i < 16; ++i) t[i][3] = a[i];
                break;
            }
            case F::bc4:
            case F::bc5: {
                std::uint8_t r[16], g[16] = {};
                decode_single8(p, r);
                if (format == F::bc5) decode_single8(p + 8, g);
                for (int i = 0; i < 16; ++i) {
                    t[i][0] = r[i];
                    t[i][1] = g[i];
                    t[i][2] = 0;
                    t[i][3] = 255;
                }
                break;
            }
            default: break;
            }
            for (std::uint32_t y = 0; y < 4 && by * 4 + y < height; ++y)
                for (std::uint32_t x = 0; x < 4 && bx * 4 + x < width; ++x)
                    std::memcpy(rgba + ((std::size_t{by} * 4 + y) * width + bx * 4 + x) * 4, t[y * 4 + x], 4);
        }
    return {};
}

Status decode_bc_unorm16(TextureFormat format, std::uint32_t width, std::uint32_t height, const std::uint8_t* data,
                         std::size_t size, std::uint16_t* values) {
    if (Status s = check_decode("decode_bc_unorm16", format, format == F::bc4 || format == F::bc5, width, height,
                                data, size, values);
        !s)
        return s;
    const int ch = format == F::bc5 ? 2 : 1;
    const std::size_t bb = static_cast<std::size_t>(format_info(format).block_bytes);
    const std::uint32_t bw = (width + 3) / 4, bh = (height + 3) / 4;
    for (std::uint32_t by = 0; by < bh; ++by)
        for (std::uint32_t bx = 0; bx < bw; ++bx) {
            const std::uint8_t* p = data + (std::size_t{by} * bw + bx) * bb;
            std::uint16_t t[2][16];
            for (int c = 0; c < ch; ++c) decode_single16(p + 8 * c, t[c]);
            for (std::uint32_t y = 0; y < 4 && by * 4 + y < height; ++y)
                for (std::uint32_t x = 0; x < 4 && bx * 4 + x < width; ++x)
                    for (int c = 0; c < ch; ++c)
                        values[((std::size_t{by} * 4 + y) * width + bx * 4 + x) * ch + c] = t[c][y * 4 + x];
        }
    return {};
}

Result<std::vector<std::uint8_t>> encode_bc_rgba8(TextureFormat format, std::uint32_t width, std::uint32_t height,
                                                  const std::uint8_t* rgba) {
    const char* fn = "encode_bc_rgba8";
    if (format != F::bc1_rgb && format != F::bc3)
        return make_error(std::string(fn) + ": format " + format_name(format) +
                          " is not encodable here (bc1_rgb and bc3 are)");
    if (Status s = check_dims(fn, format, width, height); !s) return s.error();
    const auto bytes = image_bytes(format, width, height);
    if (!bytes) return make_error(std::string(fn) + ": image too large");
    if (!rgba) return make_error(std::string(fn) + ": null pixel pointer");
    return out_of_memory_is_an_error(fn, [&]() -> Result<std::vector<std::uint8_t>> {
        std::vector<std::uint8_t> out(static_cast<std::size_t>(*bytes));
        const std::size_t bb = static_cast<std::size_t>(format_info(format).block_bytes);
        const std::uint32_t bw = (width + 3) / 4, bh = (height + 3) / 4;
        for (std::uint32_t by = 0; by < bh; ++by)
            for (std::uint32_t bx = 0; bx < bw; ++bx) {
                std::uint8_t px[16][4];
                gather(rgba, width, height, 4, bx, by, &px[0][0]);
                std::uint8_t* o = out.data() + (std::size_t{by} * bw + bx) * bb;
                if (format == F::bc3) {
                    std::uint16_t a[16];
                    for (int i = 0; i < 16; ++i) a[i] = static_cast<std::uint16_t>(px[i][3] * 257);
                    encode_single_block(a, o);
                    o += 8;
                }
                encode_colour_block(px, o);
            }
        return out;
    });
}

Result<std::vector<std::uint8_t>> encode_bc_unorm16(TextureFormat format, std::uint32_t width,
                                                    std::uint32_t height, const std::uint16_t* values) {
    const char* fn = "encode_bc_unorm16";
    if (format != F::bc4 && format != F::bc5)
        return make_error(std::string(fn) + ": format " + format_name(format) +
                          " is not encodable here (bc4 and bc5 are)");
    if (Status s = check_dims(fn, format, width, height); !s) return s.error();
    const auto bytes = image_bytes(format, width, height);
    if (!bytes) return make_error(std::string(fn) + ": image too large");
    if (!values) return make_error(std::string(fn) + ": null value pointer");
    return out_of_memory_is_an_error(fn, [&]() -> Result<std::vector<std::uint8_t>> {
        std::vector<std::uint8_t> out(static_cast<std::size_t>(*bytes));
        const int ch = format == F::bc5 ? 2 : 1;
        const std::size_t bb = static_cast<std::size_t>(format_info(format).block_bytes);
        const std::uint32_t bw = (width + 3) / 4, bh = (height + 3) / 4;
        for (std::uint32_t by = 0; by < bh; ++by)
            for (std::uint32_t bx = 0; bx < bw; ++bx) {
                std::uint16_t px[32];
                gather(values, width, height, ch, bx, by, px);
                for (int c = 0; c < ch; ++c) {
                    std::uint16_t v[16];
                    for (int i = 0; i < 16; ++i) v[i] = px[i * ch + c];
                    encode_single_block(v, out.data() + (std::size_t{by} * bw + bx) * bb + 8 * static_cast<std::size_t>(c));
                }
            }
        return out;
    });
}

}  // namespace px
