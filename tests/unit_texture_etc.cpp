// ETC1 / ETC2 / EAC CPU codecs (texture/etc.cpp).
//
// The decoder tests build single blocks bit by bit from the Khronos Data
// Format Specification 1.3 and compare against texels worked out by hand
// from the spec's tables (the numbers are written out, never computed by
// the code under test):
//   chapter 21 "ETC1 compressed texture image formats": individual and
//     differential modes, table "Intensity modifier sets for ETC1".
//   chapter 22 "ETC2 compressed texture image formats":
//     "Format RGB ETC2" (individual, differential, T, H and planar modes,
//     the distance table of T and H modes),
//     "Format RGB ETC2 with punchthrough alpha" (the opaque bit),
//     "Format RGBA ETC2" (EAC alpha block first, then the RGB block),
//     "Format Unsigned R11 EAC" / "Format Unsigned RG11 EAC".
// Block bits: 64 bits, big-endian (bit 63 = top bit of byte 0); the pixel
// index of texel (x, y) is at bit x * 4 + y of each 16-bit index plane (MSB
// plane bits 31..16, LSB plane bits 15..0); EAC's 3-bit index of texel
// (x, y) is at bits 47 - 3 i .. 45 - 3 i, i = x * 4 + y.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "parallaxes/texture/codecs.h"

namespace px {
namespace {

using F = TextureFormat;

struct Bits {
    std::uint64_t v = 0;
    // Field of n bits whose top bit is `hi`.
    Bits& set(int hi, int n, unsigned value) {
        const std::uint64_t mask = (std::uint64_t{1} << n) - 1;
        v &= ~(mask << (hi - n + 1));
        v |= (static_cast<std::uint64_t>(value) & mask) << (hi - n + 1);
        return *this;
    }
    // ETC 2-bit pixel index of texel (x, y).
    Bits& index(int x, int y, unsigned idx) {
        const int pos = x * 4 + y;
        set(16 + pos, 1, idx >> 1);
        return set(pos, 1, idx & 1);
    }
    // EAC 3-bit pixel index of texel (x, y).
    Bits& eac_index(int x, int y, unsigned idx) { return set(47 - 3 * (x * 4 + y), 3, idx); }
    void append(std::vector<std::uint8_t>& out) const {
        for (int i = 7; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    }
};

using Rgba = std::array<int, 4>;

std::vector<Rgba> decode_block(F format, const std::vector<std::uint8_t>& bytes) {
    std::vector<std::uint8_t> out(64, 0xCD);
    const Status s = decode_etc_rgba8(format, 4, 4, bytes.data(), bytes.size(), out.data());
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    std::vector<Rgba> texels(16);
    for (std::size_t i = 0; i < 16; ++i)
        texels[i] = {out[4 * i], out[4 * i + 1], out[4 * i + 2], out[4 * i + 3]};
    return texels;
}

void expect_texels(const std::vector<Rgba>& got, const std::vector<Rgba>& want, const char* what) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < want.size(); ++i) {
        EXPECT_EQ(got[i], want[i]) << what << ": texel x=" << i % 4 << " y=" << i / 4 << " got " << got[i][0] << ","
                                   << got[i][1] << "," << got[i][2] << "," << got[i][3];
    }
}

// ---------------------------------------------------------------------------
// Chapter 21 (ETC1) / "Format RGB ETC2": individual mode (diff bit 33 = 0).
// R1 = 0xA (170), G1 = 0x5 (85), B1 = 0x0 (0); R2 = 0x1 (17), G2 = 0xF (255),
// B2 = 0x8 (136) (4 bits extended by replication); table codeword 1 = 2
// {9, 29}, codeword 2 = 7 {47, 183}; flip 0: sub-block 1 is x = 0..1,
// sub-block 2 is x = 2..3. Pixel index 0 -> +a, 1 -> +b, 2 -> -a, 3 -> -b.
std::vector<std::uint8_t> individual_block() {
    Bits b;
    b.set(63, 4, 0xA).set(59, 4, 0x1).set(55, 4, 0x5).set(51, 4, 0xF).set(47, 4, 0x0).set(43, 4, 0x8);
    b.set(39, 3, 2).set(36, 3, 7).set(33, 1, 0).set(32, 1, 0);
    b.index(1, 0, 1).index(0, 1, 2).index(1, 1, 3);
    b.index(3, 0, 1).index(2, 1, 2).index(3, 1, 3);
    std::vector<std::uint8_t> out;
    b.append(out);
    return out;
}

const std::vector<Rgba> kIndividualTexels = {
    // y = 0: 170+9, 85+9, 0+9 | 170+29 ... | 17+47, 255, 136+47 | 17+183, 255, 255
    {179, 94, 9, 255}, {199, 114, 29, 255}, {64, 255, 183, 255}, {200, 255, 255, 255},
    // y = 1: -9 | -29 | -47 | -183, clamped at 0
    {161, 76, 0, 255}, {141, 56, 0, 255}, {0, 208, 89, 255}, {0, 72, 0, 255},
    {179, 94, 9, 255}, {179, 94, 9, 255}, {64, 255, 183, 255}, {64, 255, 183, 255},
    {179, 94, 9, 255}, {179, 94, 9, 255}, {64, 255, 183, 255}, {64, 255, 183, 255},
};

TEST(EtcDecode, IndividualModeEtc1AndEtc2) {
    expect_texels(decode_block(F::etc1_rgb8, individual_block()), kIndividualTexels, "etc1");
    expect_texels(decode_block(F::etc2_rgb8, individual_block()), kIndividualTexels, "etc2");
}

// Chapter 21 / "Format RGB ETC2": differential mode (diff bit = 1).
// R1 = 20 (5 bits -> 165), dR = -4 -> R2 = 16 (132); G1 = 31 (255), dG = 0;
// B1 = 0 (0), dB = +3 -> B2 = 3 (24). Codeword 1 = 0 {2, 8}, codeword 2 = 4
// {18, 60}; flip 1: sub-block 1 is y = 0..1, sub-block 2 is y = 2..3.
// ETC2: 20 - 4, 31 + 0, 0 + 3 all within 0..31, so no T/H/planar mode.
std::vector<std::uint8_t> differential_block(unsigned diff_bit = 1) {
    Bits b;
    b.set(63, 5, 20).set(58, 3, 4 /* -4 */).set(55, 5, 31).set(50, 3, 0).set(47, 5, 0).set(42, 3, 3);
    b.set(39, 3, 0).set(36, 3, 4).set(33, 1, diff_bit).set(32, 1, 1);
    b.index(0, 0, 1).index(3, 1, 3);
    b.index(0, 2, 2).index(3, 3, 1);
    std::vector<std::uint8_t> out;
    b.append(out);
    return out;
}

TEST(EtcDecode, DifferentialModeEtc1AndEtc2) {
    const std::vector<Rgba> want = {
        {173, 255, 8, 255}, {167, 255, 2, 255}, {167, 255, 2, 255}, {167, 255, 2, 255},
        {167, 255, 2, 255}, {167, 255, 2, 255}, {167, 255, 2, 255}, {157, 247, 0, 255},
        {114, 237, 6, 255}, {150, 255, 42, 255}, {150, 255, 42, 255}, {150, 255, 42, 255},
        {150, 255, 42, 255}, {150, 255, 42, 255}, {150, 255, 42, 255}, {192, 255, 84, 255},
    };
    expect_texels(decode_block(F::etc1_rgb8, differential_block()), want, "etc1");
    expect_texels(decode_block(F::etc2_rgb8, differential_block()), want, "etc2");
}

// "Format RGB ETC2", T mode: R1 + dR (bits 63..59 + bits 58..56) overflows.
// Bits 63..61 = 111, 58 = 0; R1a (60..59) = 10, R1b (57..56) = 11 -> R1 = 0xB;
// R = 11110b = 30, dR = 011b = +3: 33 > 31. G1 = 0x2, B1 = 0xC, R2 = 0x4,
// G2 = 0x8, B2 = 0xF. Distance index da (35..34) = 10b, db (32) = 1 -> 5 ->
// d = 32. Paint colours: 0 = base 1 (187, 34, 204), 1 = base 2 + d
// (100, 168, 255), 2 = base 2 (68, 136, 255), 3 = base 2 - d (36, 104, 223).
std::vector<std::uint8_t> t_block(unsigned diff_bit = 1) {
    Bits b;
    b.set(63, 3, 7).set(60, 2, 2).set(58, 1, 0).set(57, 2, 3);
    b.set(55, 4, 0x2).set(51, 4, 0xC).set(47, 4, 0x4).set(43, 4, 0x8).set(39, 4, 0xF);
    b.set(35, 2, 2).set(33, 1, diff_bit).set(32, 1, 1);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) b.index(x, y, y == 0 ? static_cast<unsigned>(x) : 2u);
    std::vector<std::uint8_t> out;
    b.append(out);
    return out;
}

TEST(EtcDecode, TMode) {
    std::vector<Rgba> want(16, Rgba{68, 136, 255, 255});
    want[0] = {187, 34, 204, 255};
    want[1] = {100, 168, 255, 255};
    want[2] = {68, 136, 255, 255};
    want[3] = {36, 104, 223, 255};
    expect_texels(decode_block(F::etc2_rgb8, t_block()), want, "etc2 T");
}

// "Format RGB ETC2", H mode: R1 + dR within range, G1 + dG (55..51 + 50..48)
// overflows. R1 (62..59) = 0x3, G1a (58..56) = 100b, G1b (52) = 1 -> G1 = 0x9,
// B1a (51) = 0, B1b (49..47) = 110b -> B1 = 0x6: base 1 = (51, 153, 102).
// Bit 63 = 1: R = 10011b = 19, dR = 100b = -4 -> 15, fine. Bits 55..53 = 111,
// bit 50 = 0: G = 11110b = 30, dG = 011b = +3 -> 33, overflow.
// Distance index = da (34) << 2 | db (32) << 1 | (base 1 >= base 2), where
// base = R << 16 | G << 8 | B. Paint colours: base 1 +- d, base 2 +- d.
std::vector<std::uint8_t> h_block(unsigned r2, unsigned g2, unsigned b2, unsigned diff_bit = 1) {
    Bits b;
    b.set(63, 1, 1).set(62, 4, 0x3).set(58, 3, 4).set(55, 3, 7).set(52, 1, 1).set(51, 1, 0).set(50, 1, 0);
    b.set(49, 3, 6).set(46, 4, r2).set(42, 4, g2).set(38, 4, b2).set(34, 1, 1).set(33, 1, diff_bit).set(32, 1, 0);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) b.index(x, y, y == 0 ? static_cast<unsigned>(x) : 1u);
    std::vector<std::uint8_t> out;
    b.append(out);
    return out;
}

TEST(EtcDecode, HMode) {
    // Base 2 = (0x0, 0xF, 0x7) = (0, 255, 119) < base 1: index 1<<2|0<<1|1 = 5, d = 32.
    std::vector<Rgba> want(16, Rgba{19, 121, 70, 255});
    want[0] = {83, 185, 134, 255};  // base 1 + 32
    want[1] = {19, 121, 70, 255};   // base 1 - 32
    want[2] = {32, 255, 151, 255};  // base 2 + 32
    want[3] = {0, 223, 87, 255};    // base 2 - 32
    expect_texels(decode_block(F::etc2_rgb8, h_block(0x0, 0xF, 0x7)), want, "etc2 H, base 1 >= base 2");
    // Base 2 = (0xE, 0x1, 0x0) = (238, 17, 0) > base 1: index 4, d = 23.
    std::vector<Rgba> want2(16, Rgba{28, 130, 79, 255});
    want2[0] = {74, 176, 125, 255};
    want2[1] = {28, 130, 79, 255};
    want2[2] = {255, 40, 23, 255};
    want2[3] = {215, 0, 0, 255};
    expect_texels(decode_block(F::etc2_rgb8, h_block(0xE, 0x1, 0x0)), want2, "etc2 H, base 1 < base 2");
}

// "Format RGB ETC2", planar mode: R and G sums in range, B1 + dB (47..43 +
// 42..40) overflows. RO = 0, RH = 63, RV = 0 (6 bits); GO = 64, GH = 64,
// GV = 127 (7 bits); BO = 63, BH = 0, BV = 0. Extended: R 0/255/0, G
// 129/129/255, B 255/0/0. Each channel is
//   clamp((x (H - O) + y (V - O) + 4 O + 2) >> 2).
// R: (255 x + 2) >> 2 = 0, 64, 128, 191 by x; G: (126 y + 518) >> 2 = 129,
// 161, 192, 224 by y; B: (1022 - 255 (x + y)) >> 2 = 255, 191, 128, 64, 0
// (then negative, clamped to 0) by x + y.
// Field check: R = 0 + dR (RO1, RO0, GO6 = 001b) = 1; G = 0 + (GO1, GO0, BO5 =
// 001b) = 1; bits 47..45 = 111, 42 = 0: B = 11111b + 011b = 34, overflow.
std::vector<std::uint8_t> planar_block() {
    Bits b;
    const unsigned ro = 0, go = 64, bo = 63, rh = 63, gh = 64, bh = 0, rv = 0, gv = 127, bv = 0;
    b.set(63, 1, 0).set(62, 6, ro).set(56, 1, go >> 6).set(55, 1, 0).set(54, 6, go & 63).set(48, 1, bo >> 5);
    b.set(47, 3, 7).set(44, 2, (bo >> 3) & 3).set(42, 1, 0).set(41, 3, bo & 7).set(38, 5, rh >> 1).set(33, 1, 1);
    b.set(32, 1, rh & 1).set(31, 7, gh).set(24, 6, bh).set(18, 6, rv).set(12, 7, gv).set(5, 6, bv);
    std::vector<std::uint8_t> out;
    b.append(out);
    return out;
}

TEST(EtcDecode, PlanarMode) {
    const int r[4] = {0, 64, 128, 191}, g[4] = {129, 161, 192, 224}, bl[7] = {255, 191, 128, 64, 0, 0, 0};
    std::vector<Rgba> want(16);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) want[static_cast<std::size_t>(x + 4 * y)] = {r[x], g[y], bl[x + y], 255};
    expect_texels(decode_block(F::etc2_rgb8, planar_block()), want, "etc2 planar");
}

// "Format RGB ETC2 with punchthrough alpha": bit 33 is the opaque bit (no
// individual mode). Opaque = 0 in differential mode: modifiers become
// index 0 -> 0, 1 -> +b, 3 -> -b, and index 2 (MSB 1, LSB 0) is a
// transparent texel (RGBA 0, 0, 0, 0). In T and H modes, index 2 is the
// transparent one. Planar mode ignores the opaque bit.
TEST(EtcDecode, PunchThroughAlpha) {
    // The differential block above, opaque bit clear: base 1 (165, 255, 0),
    // table {2, 8}; base 2 (132, 255, 24), table {18, 60}.
    const std::vector<Rgba> want = {
        {173, 255, 8, 255}, {165, 255, 0, 255}, {165, 255, 0, 255}, {165, 255, 0, 255},
        {165, 255, 0, 255}, {165, 255, 0, 255}, {165, 255, 0, 255}, {157, 247, 0, 255},
        {0, 0, 0, 0},       {132, 255, 24, 255}, {132, 255, 24, 255}, {132, 255, 24, 255},
        {132, 255, 24, 255}, {132, 255, 24, 255}, {132, 255, 24, 255}, {192, 255, 84, 255},
    };
    expect_texels(decode_block(F::etc2_rgb8a1, differential_block(0)), want, "a1 differential, opaque 0");
    // Opaque bit set: the plain ETC2 differential block.
    const auto opaque = decode_block(F::etc2_rgb8a1, differential_block(1));
    EXPECT_EQ(opaque[0], (Rgba{173, 255, 8, 255}));
    EXPECT_EQ(opaque[1], (Rgba{167, 255, 2, 255}));
    EXPECT_EQ(opaque[8], (Rgba{114, 237, 6, 255}));
    // T mode, opaque 0: index 2 texels transparent, the others as in T mode.
    std::vector<Rgba> want_t(16, Rgba{0, 0, 0, 0});
    want_t[0] = {187, 34, 204, 255};
    want_t[1] = {100, 168, 255, 255};
    want_t[3] = {36, 104, 223, 255};
    expect_texels(decode_block(F::etc2_rgb8a1, t_block(0)), want_t, "a1 T, opaque 0");
    // H mode, opaque 0: only (2, 0) has index 2.
    std::vector<Rgba> want_h(16, Rgba{19, 121, 70, 255});
    want_h[0] = {83, 185, 134, 255};
    want_h[2] = {0, 0, 0, 0};
    want_h[3] = {0, 223, 87, 255};
    expect_texels(decode_block(F::etc2_rgb8a1, h_block(0x0, 0xF, 0x7, 0)), want_h, "a1 H, opaque 0");
    // Planar with the opaque bit clear stays opaque: bit 33 is not a planar
    // field, clearing it changes nothing else here.
    auto planar = planar_block();
    planar[3] = static_cast<std::uint8_t>(planar[3] & ~0x02);  // byte 3 holds bits 39..32
    const auto p = decode_block(F::etc2_rgb8a1, planar);
    EXPECT_EQ(p[0], (Rgba{0, 129, 255, 255}));
    EXPECT_EQ(p[15], (Rgba{191, 224, 0, 255}));
}

// "Format RGBA ETC2": 8 bytes of EAC alpha, then the ETC2 RGB block. Alpha:
// base codeword (63..56), multiplier (55..52), table (51..48), 3-bit
// indices; alpha = clamp(base + modifier * multiplier, 0, 255).
TEST(EtcDecode, Etc2RgbaAlphaBlock) {
    // Base 128, multiplier 2, table 5 {-3, -7, -9, -11, 2, 6, 8, 10}:
    // 122, 114, 110, 106, 132, 140, 144, 148 by index.
    const int alpha_by_index[8] = {122, 114, 110, 106, 132, 140, 144, 148};
    Bits a;
    a.set(63, 8, 128).set(55, 4, 2).set(51, 4, 5);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) a.eac_index(x, y, static_cast<unsigned>((x * 4 + y) % 8));
    std::vector<std::uint8_t> bytes;
    a.append(bytes);
    const auto colour = individual_block();
    bytes.insert(bytes.end(), colour.begin(), colour.end());
    const auto got = decode_block(F::etc2_rgba8, bytes);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const std::size_t t = static_cast<std::size_t>(x + 4 * y);
            Rgba want = kIndividualTexels[t];
            want[3] = alpha_by_index[(x * 4 + y) % 8];
            EXPECT_EQ(got[t], want) << "x=" << x << " y=" << y;
        }
    // Clamping: base 5, multiplier 15, table 0 {-3, -6, -9, -15, 2, 5, 8, 14}:
    // 0, 0, 0, 0, 35, 80, 125, 215.
    const int clamped[8] = {0, 0, 0, 0, 35, 80, 125, 215};
    Bits c;
    c.set(63, 8, 5).set(55, 4, 15).set(51, 4, 0);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) c.eac_index(x, y, static_cast<unsigned>((x * 4 + y) % 8));
    std::vector<std::uint8_t> bytes2;
    c.append(bytes2);
    bytes2.insert(bytes2.end(), colour.begin(), colour.end());
    const auto got2 = decode_block(F::etc2_rgba8, bytes2);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_EQ(got2[static_cast<std::size_t>(x + 4 * y)][3], clamped[(x * 4 + y) % 8]);
}

// "Format Unsigned R11 EAC": value = clamp(base * 8 + 4 + modifier *
// multiplier * 8, 0, 2047); multiplier 0 counts as 1/8 (value = base * 8 + 4
// + modifier). Widened to 16 bits as v << 5 | v >> 6 (codecs.h).
std::vector<std::uint8_t> eac_block(unsigned base, unsigned mult, unsigned table) {
    Bits b;
    b.set(63, 8, base).set(55, 4, mult).set(51, 4, table);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) b.eac_index(x, y, static_cast<unsigned>((x * 4 + y) % 8));
    std::vector<std::uint8_t> out;
    b.append(out);
    return out;
}

std::vector<int> decode_r11(const std::vector<std::uint8_t>& bytes) {
    std::vector<std::uint16_t> v(16, 0xABCD);
    const Status s = decode_eac_unorm16(F::eac_r11, 4, 4, bytes.data(), bytes.size(), v.data());
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    return std::vector<int>(v.begin(), v.end());
}

// Texel (x, y) of these test blocks has pixel index (x * 4 + y) % 8.
void expect_by_index(const std::vector<int>& got, const int (&by_index)[8], const char* what) {
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            EXPECT_EQ(got[static_cast<std::size_t>(x + 4 * y)], by_index[(x * 4 + y) % 8])
                << what << " x=" << x << " y=" << y;
}

TEST(EacDecode, R11MultiplierZero) {
    // Base 100, multiplier 0, table 13 {-1, -2, -3, -10, 0, 1, 2, 9}: 804 +
    // modifier = 803, 802, 801, 794, 804, 805, 806, 813 (11 bits).
    const int want[8] = {25708, 25676, 25644, 25420, 25740, 25772, 25804, 26028};
    expect_by_index(decode_r11(eac_block(100, 0, 13)), want, "r11 mult 0");
}

TEST(EacDecode, R11MultiplierAndClamping) {
    // Base 128, multiplier 3, table 2 {-2, -5, -8, -13, 1, 4, 7, 12}: 1028 +
    // 24 m = 980, 908, 836, 716, 1052, 1124, 1196, 1316.
    const int want[8] = {31375, 29070, 26765, 22923, 33680, 35985, 38290, 42132};
    expect_by_index(decode_r11(eac_block(128, 3, 2)), want, "r11 mult 3");
    // Base 250, multiplier 10, table 0 {-3, -6, -9, -15, 2, 5, 8, 14}: 2004 +
    // 80 m = 1764, 1524, 1284, 804, then 2164.. clamped to 2047.
    const int high[8] = {56475, 48791, 41108, 25740, 65535, 65535, 65535, 65535};
    expect_by_index(decode_r11(eac_block(250, 10, 0)), high, "r11 clamp high");
    // Base 2: 20 + 80 m = below 0 (clamped) for the negative modifiers, then
    // 180, 420, 660, 1140.
    const int low[8] = {0, 0, 0, 0, 5762, 13446, 21130, 36497};
    expect_by_index(decode_r11(eac_block(2, 10, 0)), low, "r11 clamp low");
}

// "Format Unsigned RG11 EAC": the R block, then the G block.
TEST(EacDecode, Rg11TwoBlocks) {
    auto bytes = eac_block(100, 0, 13);
    const auto g = eac_block(128, 3, 2);
    bytes.insert(bytes.end(), g.begin(), g.end());
    std::vector<std::uint16_t> v(32, 0);
    ASSERT_TRUE(decode_eac_unorm16(F::eac_rg11, 4, 4, bytes.data(), bytes.size(), v.data()).ok());
    const int r[8] = {25708, 25676, 25644, 25420, 25740, 25772, 25804, 26028};
    const int gg[8] = {31375, 29070, 26765, 22923, 33680, 35985, 38290, 42132};
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const std::size_t t = static_cast<std::size_t>(x + 4 * y);
            EXPECT_EQ(v[2 * t], r[(x * 4 + y) % 8]);
            EXPECT_EQ(v[2 * t + 1], gg[(x * 4 + y) % 8]);
        }
    // As rgba8: (v * 255 + 1023) / 2047; B = 0, A = 255.
    // R: 803 -> 100, 794 -> 99, 813 -> 101; G: 980 -> 122, 716 -> 89, 1316 -> 164.
    const int r8[8] = {100, 100, 100, 99, 100, 100, 100, 101};
    const int g8[8] = {122, 113, 104, 89, 131, 140, 149, 164};
    const auto texels = decode_block(F::eac_rg11, bytes);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const int i = (x * 4 + y) % 8;
            EXPECT_EQ(texels[static_cast<std::size_t>(x + 4 * y)], (Rgba{r8[i], g8[i], 0, 255}));
        }
    // R11 as rgba8: G = B = 0.
    const auto r11 = decode_block(F::eac_r11, eac_block(100, 0, 13));
    EXPECT_EQ(r11[0], (Rgba{100, 0, 0, 255}));
    EXPECT_EQ(r11[12], (Rgba{99, 0, 0, 255}));  // (0, 3): index 3 -> 794 -> 99
}

// Partial blocks: a 5 x 3 image of 2 x 1 blocks; only in-image texels are
// written, block rows in data order.
TEST(EtcDecode, PartialBlocksWriteOnlyInsideTexels) {
    auto bytes = individual_block();
    const auto second = differential_block();
    bytes.insert(bytes.end(), second.begin(), second.end());
    std::vector<std::uint8_t> out(5 * 3 * 4 + 4, 0xEE);
    ASSERT_TRUE(decode_etc_rgba8(F::etc2_rgb8, 5, 3, bytes.data(), bytes.size(), out.data()).ok());
    EXPECT_EQ(out[5 * 3 * 4], 0xEE);  // nothing past the image
    // (4, 0) is texel (0, 0) of block 2: 173, 255, 8; (4, 2): texel (0, 2): 114, 237, 6.
    EXPECT_EQ(out[(0 * 5 + 4) * 4 + 0], 173);
    EXPECT_EQ(out[(2 * 5 + 4) * 4 + 0], 114);
    EXPECT_EQ(out[(2 * 5 + 4) * 4 + 1], 237);
    // (1, 1) of block 1: 141, 56, 0.
    EXPECT_EQ(out[(1 * 5 + 1) * 4 + 0], 141);
    EXPECT_EQ(out[(1 * 5 + 1) * 4 + 1], 56);
}

// ---------------------------------------------------------------------------
// Round trips.

std::vector<std::uint8_t> gradient(std::uint32_t w, std::uint32_t h) {
    std::vector<std::uint8_t> img(static_cast<std::size_t>(w) * h * 4);
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
            std::uint8_t* p = &img[(static_cast<std::size_t>(y) * w + x) * 4];
            p[0] = static_cast<std::uint8_t>(x * 255 / (w > 1 ? w - 1 : 1));
            p[1] = static_cast<std::uint8_t>(y * 255 / (h > 1 ? h - 1 : 1));
            p[2] = static_cast<std::uint8_t>(((x + y) * 255) / (w + h));
            p[3] = static_cast<std::uint8_t>(255 - (x * 255 / (w > 1 ? w - 1 : 1)));
        }
    return img;
}

// A gentle gradient (a few levels a texel), for partial-block sizes.
std::vector<std::uint8_t> gentle(std::uint32_t w, std::uint32_t h) {
    std::vector<std::uint8_t> img(static_cast<std::size_t>(w) * h * 4);
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
            std::uint8_t* p = &img[(static_cast<std::size_t>(y) * w + x) * 4];
            p[0] = static_cast<std::uint8_t>(60 + 5 * x);
            p[1] = static_cast<std::uint8_t>(90 + 3 * x + 4 * y);
            p[2] = static_cast<std::uint8_t>(200 - 6 * y);
            p[3] = static_cast<std::uint8_t>(100 + 7 * x);
        }
    return img;
}

std::uint32_t lcg(std::uint32_t& s) {
    s = s * 1664525u + 1013904223u;
    return s >> 8;
}

std::vector<std::uint8_t> noise(std::uint32_t w, std::uint32_t h, std::uint32_t seed) {
    std::vector<std::uint8_t> img(static_cast<std::size_t>(w) * h * 4);
    for (auto& v : img) v = static_cast<std::uint8_t>(lcg(seed) & 0xFF);
    return img;
}

// Hard-edged shapes: a disc and stripes of saturated colours, alpha 0 / 255.
std::vector<std::uint8_t> edges(std::uint32_t w, std::uint32_t h) {
    std::vector<std::uint8_t> img(static_cast<std::size_t>(w) * h * 4);
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
            std::uint8_t* p = &img[(static_cast<std::size_t>(y) * w + x) * 4];
            const double dx = x - w / 2.0, dy = y - h / 2.0;
            const bool disc = dx * dx + dy * dy < (w * w) / 9.0;
            const bool stripe = ((x + 2 * y) / 5) % 2 == 0;
            p[0] = disc ? 230 : 20;
            p[1] = stripe ? 200 : 40;
            p[2] = disc != stripe ? 250 : 10;
            p[3] = (x / 3 + y / 3) % 2 ? 255 : 0;
        }
    return img;
}

struct Stats {
    double psnr_rgb;
    int max_rgb;
    int max_alpha;
};

Stats compare(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
    double se = 0;
    int max_rgb = 0, max_alpha = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const int d = std::abs(int(a[i]) - int(b[i]));
        if (i % 4 == 3) {
            max_alpha = std::max(max_alpha, d);
            continue;
        }
        max_rgb = std::max(max_rgb, d);
        se += double(d) * d;
        ++n;
    }
    const double mse = se / double(n);
    return {mse == 0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse), max_rgb, max_alpha};
}

std::vector<std::uint8_t> round_trip(F format, std::uint32_t w, std::uint32_t h, const std::vector<std::uint8_t>& img) {
    auto enc = encode_etc_rgba8(format, w, h, img.data());
    EXPECT_TRUE(enc.ok()) << (enc.ok() ? "" : enc.error().message);
    if (!enc.ok()) return {};
    EXPECT_EQ(enc->size(), *image_bytes(format, w, h));
    std::vector<std::uint8_t> out(static_cast<std::size_t>(w) * h * 4);
    const Status s = decode_etc_rgba8(format, w, h, enc->data(), enc->size(), out.data());
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    return out;
}

void report(const char* what, const Stats& s) {
    std::printf("  %-34s PSNR %6.2f dB, max RGB error %3d, max alpha error %3d\n", what, s.psnr_rgb, s.max_rgb,
                s.max_alpha);
}

// Bounds, from what this encoder measured (printed; see the values in the
// comments) less a margin:
//  - smooth 64x64 gradient: ETC1 39.1 dB -> >= 37; ETC2 49.4 dB (planar
//    mode) -> >= 45.
//  - uniform random bytes, every channel independent: 13.1 dB -> >= 12. ETC
//    modulates only luminance within a sub-block, so this is the worst case.
//  - hard-edged saturated disc and stripes, several unrelated colours a
//    block: 15.0 (ETC1) / 15.1 (ETC2) dB -> >= 14. The encoder emits no T or
//    H blocks, which would do better here.
//  - 13x7 gradient: steep (21 and 42 levels a texel in R and G, plus edge
//    replication in the partial blocks): ETC1 25.7 dB -> >= 24, ETC2
//    30.3 dB -> >= 28.5.
TEST(EtcRoundTrip, Etc1) {
    const auto g = gradient(64, 64);
    const Stats sg = compare(g, round_trip(F::etc1_rgb8, 64, 64, g));
    report("etc1 gradient 64x64", sg);
    EXPECT_GE(sg.psnr_rgb, 37.0);
    const auto n = noise(32, 32, 7);
    const Stats sn = compare(n, round_trip(F::etc1_rgb8, 32, 32, n));
    report("etc1 noise 32x32", sn);
    EXPECT_GE(sn.psnr_rgb, 12.0);
    const auto e = edges(48, 48);
    const Stats se = compare(e, round_trip(F::etc1_rgb8, 48, 48, e));
    report("etc1 edges 48x48", se);
    EXPECT_GE(se.psnr_rgb, 14.0);
    const auto odd = gradient(13, 7);
    const Stats so = compare(odd, round_trip(F::etc1_rgb8, 13, 7, odd));
    report("etc1 gradient 13x7", so);
    EXPECT_GE(so.psnr_rgb, 24.0);
    const auto soft = gentle(13, 7);
    const Stats ss = compare(soft, round_trip(F::etc1_rgb8, 13, 7, soft));
    report("etc1 gentle gradient 13x7", ss);
    EXPECT_GE(ss.psnr_rgb, 35.0);  // measured 36.9 dB
}

TEST(EtcRoundTrip, Etc1DataDecodesTheSameAsEtc2) {
    // ETC1 output uses only individual / differential blocks with in-range
    // sums, so an ETC2 decoder reads it identically.
    const auto n = noise(32, 32, 11);
    auto enc = encode_etc_rgba8(F::etc1_rgb8, 32, 32, n.data());
    ASSERT_TRUE(enc.ok());
    std::vector<std::uint8_t> a(32 * 32 * 4), b(32 * 32 * 4);
    ASSERT_TRUE(decode_etc_rgba8(F::etc1_rgb8, 32, 32, enc->data(), enc->size(), a.data()).ok());
    ASSERT_TRUE(decode_etc_rgba8(F::etc2_rgb8, 32, 32, enc->data(), enc->size(), b.data()).ok());
    EXPECT_EQ(a, b);
}

TEST(EtcRoundTrip, Etc2Rgb) {
    const auto g = gradient(64, 64);
    const Stats sg = compare(g, round_trip(F::etc2_rgb8, 64, 64, g));
    report("etc2_rgb gradient 64x64", sg);
    EXPECT_GE(sg.psnr_rgb, 45.0);
    const auto n = noise(32, 32, 7);
    const Stats sn = compare(n, round_trip(F::etc2_rgb8, 32, 32, n));
    report("etc2_rgb noise 32x32", sn);
    EXPECT_GE(sn.psnr_rgb, 12.0);
    const auto e = edges(48, 48);
    const Stats se = compare(e, round_trip(F::etc2_rgb8, 48, 48, e));
    report("etc2_rgb edges 48x48", se);
    EXPECT_GE(se.psnr_rgb, 14.0);
    const auto odd = gradient(13, 7);
    const Stats so = compare(odd, round_trip(F::etc2_rgb8, 13, 7, odd));
    report("etc2_rgb gradient 13x7", so);
    EXPECT_GE(so.psnr_rgb, 28.5);
    const auto soft = gentle(13, 7);
    const Stats ss = compare(soft, round_trip(F::etc2_rgb8, 13, 7, soft));
    report("etc2_rgb gentle gradient 13x7", ss);
    EXPECT_GE(ss.psnr_rgb, 45.0);  // measured 48.1 dB
    // A flat colour is exact or within one step of the 5-bit base + modifier.
    std::vector<std::uint8_t> flat(8 * 8 * 4);
    for (std::size_t i = 0; i < flat.size(); ++i) flat[i] = i % 4 == 3 ? 255 : static_cast<std::uint8_t>(60 + 50 * (i % 4));
    const Stats sf = compare(flat, round_trip(F::etc2_rgb8, 8, 8, flat));
    EXPECT_LE(sf.max_rgb, 2);
}

TEST(EtcRoundTrip, Etc2Rgba) {
    const auto g = gradient(64, 64);
    const Stats sg = compare(g, round_trip(F::etc2_rgba8, 64, 64, g));
    report("etc2_rgba gradient 64x64", sg);
    EXPECT_GE(sg.psnr_rgb, 45.0);
    EXPECT_LE(sg.max_alpha, 2);  // a horizontal alpha ramp
    const auto n = noise(32, 32, 9);
    const Stats sn = compare(n, round_trip(F::etc2_rgba8, 32, 32, n));
    report("etc2_rgba noise 32x32", sn);
    EXPECT_GE(sn.psnr_rgb, 12.0);
    EXPECT_LE(sn.max_alpha, 80);
    const auto e = edges(48, 48);
    const Stats se = compare(e, round_trip(F::etc2_rgba8, 48, 48, e));
    report("etc2_rgba edges 48x48", se);
    EXPECT_GE(se.psnr_rgb, 14.0);
    EXPECT_EQ(se.max_alpha, 0);  // two alpha values a block: exact
    const auto odd = gradient(13, 7);
    const Stats so = compare(odd, round_trip(F::etc2_rgba8, 13, 7, odd));
    report("etc2_rgba gradient 13x7", so);
    EXPECT_GE(so.psnr_rgb, 28.5);
    const auto soft = gentle(13, 7);
    const Stats ss = compare(soft, round_trip(F::etc2_rgba8, 13, 7, soft));
    report("etc2_rgba gentle gradient 13x7", ss);
    EXPECT_GE(ss.psnr_rgb, 45.0);  // measured 48.1 dB
    EXPECT_LE(compare(soft, round_trip(F::etc2_rgba8, 13, 7, soft)).max_alpha, 2);
    EXPECT_LE(so.max_alpha, 3);
}

TEST(EtcRoundTrip, Etc2RgbA1) {
    // Alpha < 128 -> transparent (decodes RGBA 0, 0, 0, 0), else opaque.
    const auto e = edges(48, 48);
    const auto out = round_trip(F::etc2_rgb8a1, 48, 48, e);
    ASSERT_EQ(out.size(), e.size());
    double se = 0;
    std::size_t n = 0;
    for (std::size_t t = 0; t < e.size() / 4; ++t) {
        const bool transparent = e[4 * t + 3] < 128;
        if (transparent) {
            EXPECT_EQ(out[4 * t + 3], 0);
            EXPECT_EQ(out[4 * t + 0] | out[4 * t + 1] | out[4 * t + 2], 0);
            continue;
        }
        EXPECT_EQ(out[4 * t + 3], 255);
        for (int c = 0; c < 3; ++c) {
            const double d = double(out[4 * t + c]) - e[4 * t + c];
            se += d * d;
            ++n;
        }
    }
    const double psnr = 10.0 * std::log10(255.0 * 255.0 / (se / double(n)));
    std::printf("  %-34s PSNR %6.2f dB (opaque texels)\n", "etc2_rgb_a1 edges 48x48", psnr);
    EXPECT_GE(psnr, 13.5);  // measured 14.6 dB on the opaque texels
    // Opaque gradient: ETC2 without individual mode.
    auto g = gradient(64, 64);
    for (std::size_t i = 3; i < g.size(); i += 4) g[i] = 255;
    const Stats sg = compare(g, round_trip(F::etc2_rgb8a1, 64, 64, g));
    report("etc2_rgb_a1 opaque gradient 64x64", sg);
    EXPECT_GE(sg.psnr_rgb, 45.0);
    EXPECT_EQ(sg.max_alpha, 0);
    auto odd = gradient(13, 7);
    for (std::size_t i = 3; i < odd.size(); i += 4) odd[i] = (i / 4) % 3 ? 255 : 0;
    const auto oo = round_trip(F::etc2_rgb8a1, 13, 7, odd);
    ASSERT_EQ(oo.size(), odd.size());
    for (std::size_t i = 3; i < odd.size(); i += 4) EXPECT_EQ(oo[i], odd[i]) << "texel " << i / 4;
}

// EAC R11 / RG11 from unorm16: errors in 11-bit steps (value * 2047 / 65535).
std::vector<std::uint16_t> eac_round_trip(F format, std::uint32_t w, std::uint32_t h,
                                          const std::vector<std::uint16_t>& v) {
    auto enc = encode_eac_unorm16(format, w, h, v.data());
    EXPECT_TRUE(enc.ok()) << (enc.ok() ? "" : enc.error().message);
    if (!enc.ok()) return {};
    EXPECT_EQ(enc->size(), *image_bytes(format, w, h));
    std::vector<std::uint16_t> out(v.size());
    EXPECT_TRUE(decode_eac_unorm16(format, w, h, enc->data(), enc->size(), out.data()).ok());
    return out;
}

double max_steps(const std::vector<std::uint16_t>& a, const std::vector<std::uint16_t>& b) {
    double m = 0;
    for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(double(a[i]) - double(b[i])) * 2047.0 / 65535.0);
    return m;
}

TEST(EacRoundTrip, R11Ramp) {
    // A horizontal ramp over the full range, 256 wide: 8 11-bit steps a texel.
    const std::uint32_t w = 256, h = 8;
    std::vector<std::uint16_t> v(w * h);
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) v[y * w + x] = static_cast<std::uint16_t>(x * 65535u / (w - 1));
    const double m = max_steps(v, eac_round_trip(F::eac_r11, w, h, v));
    std::printf("  eac_r11 ramp 256x8: max error %.2f 11-bit steps\n", m);
    EXPECT_LE(m, 4.0);
    // A steep 2D ramp, 13 x 7 with partial blocks: 9.4 and 5.3 steps a texel,
    // so up to 16 distinct values a block against 8 levels (measured 6.25).
    std::vector<std::uint16_t> s(13 * 7);
    for (std::uint32_t y = 0; y < 7; ++y)
        for (std::uint32_t x = 0; x < 13; ++x) s[y * 13 + x] = static_cast<std::uint16_t>(20000 + 300 * x + 170 * y);
    const double ms = max_steps(s, eac_round_trip(F::eac_r11, 13, 7, s));
    std::printf("  eac_r11 ramp 13x7: max error %.2f 11-bit steps\n", ms);
    EXPECT_LE(ms, 7.0);
    // Flat blocks at any value are exact (multiplier 0 reaches every value).
    std::vector<std::uint16_t> flat(16, 12345);
    EXPECT_LE(max_steps(flat, eac_round_trip(F::eac_r11, 4, 4, flat)), 0.5);
}

TEST(EacRoundTrip, R11NoiseAndEdges) {
    std::uint32_t seed = 5;
    std::vector<std::uint16_t> n(32 * 32);
    for (auto& x : n) x = static_cast<std::uint16_t>(lcg(seed) & 0xFFFF);
    const auto nd = eac_round_trip(F::eac_r11, 32, 32, n);
    double se = 0;
    for (std::size_t i = 0; i < n.size(); ++i) se += std::pow((double(n[i]) - nd[i]) / 65535.0, 2);
    const double psnr = 10.0 * std::log10(1.0 / (se / double(n.size())));
    std::printf("  eac_r11 noise 32x32: PSNR %.2f dB\n", psnr);
    EXPECT_GE(psnr, 28.0);  // measured 31.3 dB
    // Two-level edges: both levels reachable within a few steps.
    std::vector<std::uint16_t> e(24 * 24);
    for (std::uint32_t y = 0; y < 24; ++y)
        for (std::uint32_t x = 0; x < 24; ++x) e[y * 24 + x] = (x + y) % 7 < 3 ? 3000 : 60000;
    const double me = max_steps(e, eac_round_trip(F::eac_r11, 24, 24, e));
    std::printf("  eac_r11 edges 24x24: max error %.2f 11-bit steps\n", me);
    EXPECT_LE(me, 12.0);  // measured 9.7
}

TEST(EacRoundTrip, Rg11) {
    const std::uint32_t w = 13, h = 7;
    std::vector<std::uint16_t> v(w * h * 2);
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
            v[(y * w + x) * 2] = static_cast<std::uint16_t>(x * 65535u / (w - 1));
            v[(y * w + x) * 2 + 1] = static_cast<std::uint16_t>(65535u - y * 65535u / (h - 1));
        }
    const auto out = eac_round_trip(F::eac_rg11, w, h, v);
    const double m = max_steps(v, out);
    std::printf("  eac_rg11 ramps 13x7: max error %.2f 11-bit steps\n", m);
    // R rises 170 steps a texel: 4 values a block far apart (measured 7.3).
    EXPECT_LE(m, 8.0);
    // The channels stay apart: decoding as rgba8 gives R rising with x, G falling with y.
    auto enc = encode_eac_unorm16(F::eac_rg11, w, h, v.data());
    ASSERT_TRUE(enc.ok());
    std::vector<std::uint8_t> rgba(w * h * 4);
    ASSERT_TRUE(decode_etc_rgba8(F::eac_rg11, w, h, enc->data(), enc->size(), rgba.data()).ok());
    EXPECT_LE(rgba[0], 2);                    // R at x = 0
    EXPECT_GE(rgba[(w - 1) * 4], 253);        // R at x = 12
    EXPECT_GE(rgba[1], 253);                  // G at y = 0
    EXPECT_LE(rgba[((h - 1) * w) * 4 + 1], 2);  // G at y = 6
    EXPECT_EQ(rgba[2], 0);
    EXPECT_EQ(rgba[3], 255);
}

// ---------------------------------------------------------------------------
// Bad input.

TEST(EtcErrors, WrongSizeZeroSizeWrongFormat) {
    std::vector<std::uint8_t> data(64, 0);
    std::vector<std::uint8_t> rgba(8 * 8 * 4);
    // 8 x 8 etc2_rgb needs 4 blocks = 32 bytes.
    Status s = decode_etc_rgba8(F::etc2_rgb8, 8, 8, data.data(), 31, rgba.data());
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("etc2_rgb"), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find("32"), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find("31"), std::string::npos) << s.error().message;
    EXPECT_FALSE(decode_etc_rgba8(F::etc2_rgb8, 8, 8, data.data(), 33, rgba.data()).ok());
    EXPECT_FALSE(decode_etc_rgba8(F::etc2_rgba8, 8, 8, data.data(), 32, rgba.data()).ok());  // needs 64
    EXPECT_TRUE(decode_etc_rgba8(F::etc2_rgba8, 8, 8, data.data(), 64, rgba.data()).ok());
    EXPECT_FALSE(decode_etc_rgba8(F::etc2_rgb8, 8, 8, data.data(), 0, rgba.data()).ok());
    EXPECT_FALSE(decode_etc_rgba8(F::etc2_rgb8, 8, 8, nullptr, 0, rgba.data()).ok());
    EXPECT_FALSE(decode_etc_rgba8(F::etc1_rgb8, 0, 8, data.data(), 0, rgba.data()).ok());
    EXPECT_FALSE(decode_etc_rgba8(F::etc1_rgb8, 8, 0, data.data(), 0, rgba.data()).ok());
    EXPECT_FALSE(decode_etc_rgba8(F::rgba8, 4, 4, data.data(), 64, rgba.data()).ok());
    EXPECT_FALSE(decode_etc_rgba8(F::astc_4x4, 4, 4, data.data(), 16, rgba.data()).ok());
    EXPECT_FALSE(decode_etc_rgba8(F::bc1_rgb, 4, 4, data.data(), 8, rgba.data()).ok());

    std::vector<std::uint16_t> values(8 * 8 * 2);
    s = decode_eac_unorm16(F::eac_rg11, 8, 8, data.data(), 32, values.data());
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("eac_rg11"), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find("64"), std::string::npos) << s.error().message;
    EXPECT_TRUE(decode_eac_unorm16(F::eac_rg11, 8, 8, data.data(), 64, values.data()).ok());
    EXPECT_FALSE(decode_eac_unorm16(F::eac_r11, 8, 8, data.data(), 0, values.data()).ok());
    EXPECT_FALSE(decode_eac_unorm16(F::eac_r11, 0, 0, data.data(), 0, values.data()).ok());
    EXPECT_FALSE(decode_eac_unorm16(F::etc2_rgb8, 8, 8, data.data(), 32, values.data()).ok());
    EXPECT_FALSE(decode_eac_unorm16(F::bc4, 8, 8, data.data(), 32, values.data()).ok());

    EXPECT_FALSE(encode_etc_rgba8(F::eac_r11, 8, 8, rgba.data()).ok());
    EXPECT_FALSE(encode_etc_rgba8(F::rgba8, 8, 8, rgba.data()).ok());
    EXPECT_FALSE(encode_etc_rgba8(F::etc2_rgb8, 0, 8, rgba.data()).ok());
    EXPECT_FALSE(encode_etc_rgba8(F::etc2_rgb8, 8, 8, nullptr).ok());
    EXPECT_FALSE(encode_eac_unorm16(F::etc2_rgb8, 8, 8, values.data()).ok());
    EXPECT_FALSE(encode_eac_unorm16(F::eac_r11, 8, 0, values.data()).ok());
    EXPECT_FALSE(encode_eac_unorm16(F::eac_rg11, 8, 8, nullptr).ok());
}

TEST(EtcErrors, ArbitraryBytesDecodeWithoutCrashing) {
    // Every mode, every opaque bit: random blocks in every format.
    std::uint32_t seed = 99;
    std::vector<std::uint8_t> data(16 * 16 * 2);
    for (auto& b : data) b = static_cast<std::uint8_t>(lcg(seed));
    std::vector<std::uint8_t> rgba(16 * 16 * 4);
    std::vector<std::uint16_t> values(16 * 16 * 2);
    for (F f : {F::etc1_rgb8, F::etc2_rgb8, F::etc2_rgb8a1, F::etc2_rgba8, F::eac_r11, F::eac_rg11}) {
        const std::size_t size = static_cast<std::size_t>(*image_bytes(f, 15, 13));
        EXPECT_TRUE(decode_etc_rgba8(f, 15, 13, data.data(), size, rgba.data()).ok()) << format_name(f);
    }
    EXPECT_TRUE(decode_eac_unorm16(F::eac_rg11, 15, 13, data.data(), *image_bytes(F::eac_rg11, 15, 13), values.data()).ok());
}

}  // namespace
}  // namespace px
