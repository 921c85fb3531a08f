// ETC1, ETC2 (RGB, RGB A1, RGBA) and EAC (R11, RG11) CPU codecs.
// Khronos Data Format Specification 1.3: chapter 21 (ETC1) and chapter 22
// (ETC2 / EAC). Every block is 64 bits, stored big-endian (bit 63 is the
// top bit of the first byte). Pixel indices are column-major: the index of
// texel (x, y) of a block sits at bit x * 4 + y of a 16-bit index field.
#include <algorithm>
#include <array>
#include <climits>
#include <cstdlib>
#include <cmath>
#include <cstring>
#include <string>

#include "parallaxes/texture/codecs.h"

namespace px {

namespace {

using F = TextureFormat;

// 21.1: intensity modifier tables {a, b}; pixel index 0 -> +a, 1 -> +b,
// 2 -> -a, 3 -> -b.
constexpr int kEtcTable[8][2] = {{2, 8}, {5, 17}, {9, 29}, {13, 42}, {18, 60}, {24, 80}, {33, 106}, {47, 183}};
// 22.1 T and H modes: the distance table.
constexpr int kThDistance[8] = {3, 6, 11, 16, 23, 32, 41, 64};
// 22.5 / 22.6: EAC modifier tables, by 3-bit pixel index.
constexpr int kEacTable[16][8] = {
    {-3, -6, -9, -15, 2, 5, 8, 14}, {-3, -7, -10, -13, 2, 6, 9, 12}, {-2, -5, -8, -13, 1, 4, 7, 12},
    {-2, -4, -6, -13, 1, 3, 5, 12}, {-3, -6, -8, -12, 2, 5, 7, 11}, {-3, -7, -9, -11, 2, 6, 8, 10},
    {-4, -7, -8, -11, 3, 6, 7, 10}, {-3, -5, -8, -11, 2, 4, 7, 10}, {-2, -6, -8, -10, 1, 5, 7, 9},
    {-2, -5, -8, -10, 1, 4, 7, 9},  {-2, -4, -8, -10, 1, 3, 7, 9},  {-2, -5, -7, -10, 1, 4, 6, 9},
    {-3, -4, -7, -10, 2, 3, 6, 9},  {-1, -2, -3, -10, 0, 1, 2, 9},  {-4, -6, -8, -9, 3, 5, 7, 8},
    {-3, -5, -7, -9, 2, 4, 6, 8},
};

inline int clamp_to(int v, int lo, int hi) { return v < lo ? lo : (v > hi ? hi : v); }
inline int clamp255(int v) { return clamp_to(v, 0, 255); }

std::uint64_t load_be64(const std::uint8_t* p) {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v = v << 8 | p[i];
    return v;
}

void store_be64(std::uint8_t* p, std::uint64_t v) {
    for (int i = 7; i >= 0; --i) {
        p[i] = static_cast<std::uint8_t>(v & 0xFF);
        v >>= 8;
    }
}

// Bits hi .. hi - n + 1 of v.
inline int field(std::uint64_t v, int hi, int n) {
    return static_cast<int>((v >> (hi - n + 1)) & ((std::uint64_t{1} << n) - 1));
}
inline std::uint64_t put(int value, int hi, int n) {
    return (static_cast<std::uint64_t>(value) & ((std::uint64_t{1} << n) - 1)) << (hi - n + 1);
}
inline int sext3(int v) { return v >= 4 ? v - 8 : v; }
inline int ext4(int v) { return v << 4 | v; }
inline int ext5(int v) { return v << 3 | v >> 2; }
inline int ext6(int v) { return v << 2 | v >> 4; }
inline int ext7(int v) { return v << 1 | v >> 6; }

enum class Mode { individual, differential, t, h, planar };

// 21.1 / 22.1: the diff bit (bit 33; the opaque bit in RGB A1, where there
// is no individual mode) and, in ETC2, overflow of the differential R, G, B
// sums selecting T, H and planar modes.
Mode etc_mode(std::uint64_t v, bool etc1, bool punch) {
    if (!punch && field(v, 33, 1) == 0) return Mode::individual;
    if (etc1) return Mode::differential;
    const int r = field(v, 63, 5) + sext3(field(v, 58, 3));
    if (r < 0 || r > 31) return Mode::t;
    const int g = field(v, 55, 5) + sext3(field(v, 50, 3));
    if (g < 0 || g > 31) return Mode::h;
    const int b = field(v, 47, 5) + sext3(field(v, 42, 3));
    if (b < 0 || b > 31) return Mode::planar;
    return Mode::differential;
}

inline int pixel_index(std::uint64_t v, int x, int y) {
    const int pos = x * 4 + y;
    return static_cast<int>(((v >> (16 + pos)) & 1) << 1 | ((v >> pos) & 1));
}

using Texels = std::array<std::array<int, 4>, 16>;  // texel x + 4 y: R, G, B, A

// One ETC1 / ETC2 colour block (RGB A1 when `punch`).
void decode_colour_block(std::uint64_t v, bool etc1, bool punch, Texels& out) {
    const Mode mode = etc_mode(v, etc1, punch);
    const bool opaque = !punch || field(v, 33, 1) == 1;
    if (mode == Mode::individual || mode == Mode::differential) {
        int base[2][3];
        for (int c = 0; c < 3; ++c) {
            if (mode == Mode::individual) {
                base[0][c] = ext4(field(v, 63 - 8 * c, 4));
                base[1][c] = ext4(field(v, 59 - 8 * c, 4));
            } else {
                const int b1 = field(v, 63 - 8 * c, 5);
                base[0][c] = ext5(b1);
                // ETC1 (and any stream we are handed) may hold a sum outside
                // 0..31; ETC1 has no other modes, so keep its low 5 bits.
                base[1][c] = ext5((b1 + sext3(field(v, 58 - 8 * c, 3))) & 31);
            }
        }
        const int cw[2] = {field(v, 39, 3), field(v, 36, 3)};
        const bool flip = field(v, 32, 1) == 1;
        for (int y = 0; y < 4; ++y) {
            for (int x = 0; x < 4; ++x) {
                const int s = flip ? (y >= 2) : (x >= 2);
                const int idx = pixel_index(v, x, y);
                auto& t = out[static_cast<std::size_t>(x + 4 * y)];
                if (!opaque && idx == 2) {
                    t = {0, 0, 0, 0};
                    continue;
                }
                const int a = kEtcTable[cw[s]][0], b = kEtcTable[cw[s]][1];
                const int mods_opaque[4] = {a, b, -a, -b};
                const int mods_punch[4] = {0, b, 0, -b};
                const int m = opaque ? mods_opaque[idx] : mods_punch[idx];
                t = {clamp255(base[s][0] + m), clamp255(base[s][1] + m), clamp255(base[s][2] + m), 255};
            }
        }
        return;
    }
    if (mode == Mode::t || mode == Mode::h) {
        int c1[3], c2[3], paint[4][3];
        if (mode == Mode::t) {
            c1[0] = ext4(field(v, 60, 2) << 2 | field(v, 57, 2));
            c1[1] = ext4(field(v, 55, 4));
            c1[2] = ext4(field(v, 51, 4));
            c2[0] = ext4(field(v, 47, 4));
            c2[1] = ext4(field(v, 43, 4));
            c2[2] = ext4(field(v, 39, 4));
            const int d = kThDistance[field(v, 35, 2) << 1 | field(v, 32, 1)];
            for (int c = 0; c < 3; ++c) {
                paint[0][c] = c1[c];
                paint[1][c] = clamp255(c2[c] + d);
                paint[2][c] = c2[c];
                paint[3][c] = clamp255(c2[c] - d);
            }
        } else {
            c1[0] = ext4(field(v, 62, 4));
            c1[1] = ext4(field(v, 58, 3) << 1 | field(v, 52, 1));
            c1[2] = ext4(field(v, 51, 1) << 3 | field(v, 49, 3));
            c2[0] = ext4(field(v, 46, 4));
            c2[1] = ext4(field(v, 42, 4));
            c2[2] = ext4(field(v, 38, 4));
            const int k1 = c1[0] << 16 | c1[1] << 8 | c1[2];
            const int k2 = c2[0] << 16 | c2[1] << 8 | c2[2];
            const int d = kThDistance[field(v, 34, 1) << 2 | field(v, 32, 1) << 1 | (k1 >= k2 ? 1 : 0)];
            for (int c = 0; c < 3; ++c) {
                paint[0][c] = clamp255(c1[c] + d);
                paint[1][c] = clamp255(c1[c] - d);
                paint[2][c] = clamp255(c2[c] + d);
                paint[3][c] = clamp255(c2[c] - d);
            }
        }
        for (int y = 0; y < 4; ++y) {
            for (int x = 0; x < 4; ++x) {
                const int idx = pixel_index(v, x, y);
                auto& t = out[static_cast<std::size_t>(x + 4 * y)];
                if (!opaque && idx == 2)
                    t = {0, 0, 0, 0};
                else
                    t = {paint[idx][0], paint[idx][1], paint[idx][2], 255};
            }
        }
        return;
    }
    // Planar: always opaque.
    const int o[3] = {ext6(field(v, 62, 6)), ext7(field(v, 56, 1) << 6 | field(v, 54, 6)),
                      ext6(field(v, 48, 1) << 5 | field(v, 44, 2) << 3 | field(v, 41, 3))};
    const int hh[3] = {ext6(field(v, 38, 5) << 1 | field(v, 32, 1)), ext7(field(v, 31, 7)), ext6(field(v, 24, 6))};
    const int vv[3] = {ext6(field(v, 18, 6)), ext7(field(v, 12, 7)), ext6(field(v, 5, 6))};
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 4; ++x) {
            auto& t = out[static_cast<std::size_t>(x + 4 * y)];
            for (int c = 0; c < 3; ++c) {
                const int s = x * (hh[c] - o[c]) + y * (vv[c] - o[c]) + 4 * o[c] + 2;
                t[static_cast<std::size_t>(c)] = s < 0 ? 0 : clamp255(s >> 2);
            }
            t[3] = 255;
        }
    }
}

// 22.5 (8-bit EAC alpha) and 22.6 (11-bit R11): base codeword (63..56),
// multiplier (55..52), table index (51..48), 3-bit pixel indices from bit 47
// down, texel (x, y) at position x * 4 + y.
inline int eac_index(std::uint64_t v, int i) { return field(v, 47 - 3 * i, 3); }

void decode_eac8_block(std::uint64_t v, std::array<int, 16>& out) {
    const int base = field(v, 63, 8), mult = field(v, 55, 4), table = field(v, 51, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            out[static_cast<std::size_t>(x + 4 * y)] =
                clamp255(base + kEacTable[table][eac_index(v, x * 4 + y)] * mult);
}

void decode_eac11_block(std::uint64_t v, std::array<int, 16>& out) {
    const int base = field(v, 63, 8), mult = field(v, 55, 4), table = field(v, 51, 4);
    const int scale = mult == 0 ? 1 : mult * 8;  // multiplier 0 counts as 1/8
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            out[static_cast<std::size_t>(x + 4 * y)] =
                clamp_to(base * 8 + 4 + kEacTable[table][eac_index(v, x * 4 + y)] * scale, 0, 2047);
}

bool is_etc_colour(F f) { return f == F::etc1_rgb8 || f == F::etc2_rgb8 || f == F::etc2_rgb8a1 || f == F::etc2_rgba8; }
bool is_eac(F f) { return f == F::eac_r11 || f == F::eac_rg11; }

Status check_size(const char* what, F format, std::uint32_t width, std::uint32_t height, const void* data,
                  std::size_t size) {
    const std::string name = std::string(what) + ": " + format_name(format);
    if (width < 1 || height < 1)
        return make_error(name + ": image size " + std::to_string(width) + "x" + std::to_string(height) +
                          " (each side must be at least 1)");
    const auto bytes = image_bytes(format, width, height);
    if (!bytes) return make_error(name + ": image " + std::to_string(width) + "x" + std::to_string(height) + " is too large");
    if (size != *bytes)
        return make_error(name + ": " + std::to_string(width) + "x" + std::to_string(height) + " needs " +
                          std::to_string(*bytes) + " bytes, given " + std::to_string(size));
    if (!data) return make_error(name + ": no data");
    return {};
}

// ---------------------------------------------------------------- encoder

inline int sq(int v) { return v * v; }

// A sub-block's texels (opaque ones only, in RGB A1) with their positions.
struct Sub {
    int px[8][3];
    int pos[8][2];
    int n = 0;
};

struct Fit {
    int err = INT_MAX;
    int q[3] = {0, 0, 0};  // quantised base colour (4 or 5 bits)
    int table = 0;
};

// Squared error of `sub` against base colour `base` (8 bits a channel) and
// modifier table `table`, stopping once it reaches `limit`. `punch`: the
// RGB A1 non-opaque modifiers (0, +b, -b).
int table_error(const Sub& sub, const int base[3], int table, bool punch, int limit) {
    const int a = kEtcTable[table][0], b = kEtcTable[table][1];
    // Four candidates, laid out for the compiler to vectorise; RGB A1's
    // three (0, +b, -b) repeat -b.
    const int mods[4] = {punch ? 0 : a, b, punch ? -b : -a, -b};
    int cr[4], cg[4], cb[4];
    for (int k = 0; k < 4; ++k) {
        cr[k] = clamp255(base[0] + mods[k]);
        cg[k] = clamp255(base[1] + mods[k]);
        cb[k] = clamp255(base[2] + mods[k]);
    }
    int err = 0;
    for (int i = 0; i < sub.n; ++i) {
        const int pr = sub.px[i][0], pg = sub.px[i][1], pb = sub.px[i][2];
        int e[4];
        for (int k = 0; k < 4; ++k) e[k] = sq(cr[k] - pr) + sq(cg[k] - pg) + sq(cb[k] - pb);
        err += std::min(std::min(e[0], e[1]), std::min(e[2], e[3]));
        if (err >= limit) return err;
    }
    return err;
}

// Best pixel index (spec numbering) of one texel.
int best_index(const int p[3], const int base[3], int table, bool punch) {
    const int a = kEtcTable[table][0], b = kEtcTable[table][1];
    const int mods[4] = {a, b, -a, -b};
    const int mods_punch[4] = {0, b, 0, -b};
    int best = INT_MAX, best_idx = 0;
    for (int idx = 0; idx < 4; ++idx) {
        if (punch && idx == 2) continue;
        const int m = punch ? mods_punch[idx] : mods[idx];
        const int e = sq(clamp255(base[0] + m) - p[0]) + sq(clamp255(base[1] + m) - p[1]) + sq(clamp255(base[2] + m) - p[2]);
        if (e < best) {
            best = e;
            best_idx = idx;
        }
    }
    return best_idx;
}

inline int dequant(int q, int bits) { return bits == 4 ? ext4(q) : ext5(q); }

// All eight tables for one base colour. Where no modifier of a table can
// clamp (base - b >= 0 and base + b <= 255 in every channel) the error of
// a texel p with modifier m is |p - base|^2 - 2 m sum(p - base) + 3 m^2,
// so the per-texel sums are shared by all tables; otherwise table_error.
void eval_base(const Sub& sub, const int q[3], int bits, bool punch, Fit& best, int t_lo = 0, int t_hi = 7) {
    const int base[3] = {dequant(q[0], bits), dequant(q[1], bits), dequant(q[2], bits)};
    int norm[8], sum[8];
    for (int i = 0; i < sub.n; ++i) {
        const int e0 = sub.px[i][0] - base[0], e1 = sub.px[i][1] - base[1], e2 = sub.px[i][2] - base[2];
        norm[i] = e0 * e0 + e1 * e1 + e2 * e2;
        sum[i] = e0 + e1 + e2;
    }
    const int lo = std::min(base[0], std::min(base[1], base[2]));
    const int hi = std::max(base[0], std::max(base[1], base[2]));
    for (int t = t_lo; t <= t_hi; ++t) {
        const int a = kEtcTable[t][0], b = kEtcTable[t][1];
        int e;
        if (lo - b >= 0 && hi + b <= 255) {
            const int ma = punch ? 0 : a;
            e = 0;
            for (int i = 0; i < sub.n && e < best.err; ++i) {
                const int d = sum[i];
                // Candidates +-ma and +-b: the sign matching d is the better one.
                const int sa = d >= 0 ? ma : -ma, sb = d >= 0 ? b : -b;
                e += norm[i] + std::min(3 * sa * sa - 2 * sa * d, 3 * sb * sb - 2 * sb * d);
            }
        } else {
            e = table_error(sub, base, t, punch, best.err);
        }
        if (e < best.err) {
            best.err = e;
            best.table = t;
            std::copy(q, q + 3, best.q);
        }
    }
}

// Hill climbing over the quantised base colour (each channel within
// lo..hi), from `start`, over all eight tables: each step looks at the 26
// neighbours (+-1 a channel) of the best so far.
Fit search_base(const Sub& sub, int bits, const int lo[3], const int hi[3], const int start[3], bool punch) {
    Fit best;
    int cur[3];
    for (int c = 0; c < 3; ++c) cur[c] = clamp_to(start[c], lo[c], hi[c]);
    if (sub.n == 0) {
        best.err = 0;
        std::copy(cur, cur + 3, best.q);
        return best;
    }
    // Bases already tried in this search (by generation stamp, so nothing
    // needs clearing between searches).
    thread_local std::array<std::uint32_t, 32 * 32 * 32> seen{};
    thread_local std::uint32_t generation = 0;
    if (++generation == 0) {
        seen.fill(0);
        generation = 1;
    }
    auto key = [](const int* v) { return static_cast<std::size_t>(v[0] << 10 | v[1] << 5 | v[2]); };
    seen[key(cur)] = generation;
    eval_base(sub, cur, bits, punch, best);
    for (int step = 0; step < 16; ++step) {
        const int before = best.err, table = best.table;
        for (int dr = -1; dr <= 1; ++dr)
            for (int dg = -1; dg <= 1; ++dg)
                for (int db = -1; db <= 1; ++db) {
                    if (!dr && !dg && !db) continue;
                    const int q[3] = {cur[0] + dr, cur[1] + dg, cur[2] + db};
                    bool inside = true;
                    for (int c = 0; c < 3; ++c) inside = inside && q[c] >= lo[c] && q[c] <= hi[c];
                    if (!inside || seen[key(q)] == generation) continue;
                    seen[key(q)] = generation;
                    // Neighbours: the tables next to the best one so far.
                    eval_base(sub, q, bits, punch, best, std::max(0, table - 1), std::min(7, table + 1));
                }
        if (best.err >= before || best.err == 0) break;
        std::copy(best.q, best.q + 3, cur);
    }
    // Every table at the base found.
    eval_base(sub, best.q, bits, punch, best);
    return best;
}

void quant_start(const Sub& sub, int bits, int out[3]) {
    const int maxq = (1 << bits) - 1;
    for (int c = 0; c < 3; ++c) {
        int sum = 0;
        for (int i = 0; i < sub.n; ++i) sum += sub.px[i][c];
        const int avg2 = sub.n ? (2 * sum + sub.n) / (2 * sub.n) : 0;  // rounded mean
        out[c] = clamp_to((avg2 * maxq + 127) / 255, 0, maxq);
    }
}

struct ColourChoice {
    long long err = LLONG_MAX;
    std::uint64_t bits = 0;
};

void set_indices(std::uint64_t& v, const Sub& sub, const int base[3], int table, bool punch) {
    for (int i = 0; i < sub.n; ++i) {
        const int idx = best_index(sub.px[i], base, table, punch);
        const int pos = sub.pos[i][0] * 4 + sub.pos[i][1];
        v |= static_cast<std::uint64_t>(idx >> 1) << (16 + pos);
        v |= static_cast<std::uint64_t>(idx & 1) << pos;
    }
}

// Individual and differential modes, both flips. `transparent`: texels that
// must decode transparent (RGB A1 with the opaque bit clear).
void encode_ind_diff(const Texels& px, bool allow_individual, bool punch, const bool transparent[16],
                     ColourChoice& best) {
    for (int flip = 0; flip < 2; ++flip) {
        Sub subs[2];
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                const int t = x + 4 * y;
                if (punch && transparent[t]) continue;
                Sub& s = subs[flip ? (y >= 2) : (x >= 2)];
                for (int c = 0; c < 3; ++c) s.px[s.n][c] = px[static_cast<std::size_t>(t)][static_cast<std::size_t>(c)];
                s.pos[s.n][0] = x;
                s.pos[s.n][1] = y;
                ++s.n;
            }
        std::uint64_t common = put(flip, 32, 1);
        if (punch) {
            // Opaque bit clear, transparent texels at pixel index 2 (binary 10).
            for (int t = 0; t < 16; ++t)
                if (transparent[t]) common |= std::uint64_t{1} << (16 + (t % 4) * 4 + t / 4);
        }
        if (allow_individual) {
            const int lo[3] = {0, 0, 0}, hi[3] = {15, 15, 15};
            Fit fit[2];
            for (int s = 0; s < 2; ++s) {
                int start[3];
                quant_start(subs[s], 4, start);
                fit[s] = search_base(subs[s], 4, lo, hi, start, false);
            }
            const long long err = static_cast<long long>(fit[0].err) + fit[1].err;
            if (err < best.err) {
                std::uint64_t v = common;
                for (int c = 0; c < 3; ++c) v |= put(fit[0].q[c], 63 - 8 * c, 4) | put(fit[1].q[c], 59 - 8 * c, 4);
                v |= put(fit[0].table, 39, 3) | put(fit[1].table, 36, 3);
                for (int s = 0; s < 2; ++s) {
                    const int base[3] = {ext4(fit[s].q[0]), ext4(fit[s].q[1]), ext4(fit[s].q[2])};
                    set_indices(v, subs[s], base, fit[s].table, false);
                }
                best.err = err;
                best.bits = v;
            }
        }
        // Differential: base 2 = base 1 + (-4 .. 3) a channel.
        const int lo[3] = {0, 0, 0}, hi[3] = {31, 31, 31};
        Fit f[2];
        for (int s = 0; s < 2; ++s) {
            int start[3];
            quant_start(subs[s], 5, start);
            f[s] = search_base(subs[s], 5, lo, hi, start, punch);
        }
        bool fits = true;
        for (int c = 0; c < 3; ++c) fits = fits && f[1].q[c] - f[0].q[c] >= -4 && f[1].q[c] - f[0].q[c] <= 3;
        if (!fits) {
            // Keep one sub-block's base and search the other's within reach,
            // then the first again within reach of that.
            Fit options[2][2];
            for (int keep = 0; keep < 2; ++keep) {
                const int other = 1 - keep;
                Fit a = f[keep];
                int l[3], h[3];
                for (int c = 0; c < 3; ++c) {
                    l[c] = std::max(0, keep == 0 ? a.q[c] - 4 : a.q[c] - 3);
                    h[c] = std::min(31, keep == 0 ? a.q[c] + 3 : a.q[c] + 4);
                }
                Fit b = search_base(subs[other], 5, l, h, f[other].q, punch);
                for (int c = 0; c < 3; ++c) {
                    l[c] = std::max(0, keep == 0 ? b.q[c] - 3 : b.q[c] - 4);
                    h[c] = std::min(31, keep == 0 ? b.q[c] + 4 : b.q[c] + 3);
                }
                Fit a2 = search_base(subs[keep], 5, l, h, a.q, punch);
                options[keep][keep] = a2;
                options[keep][other] = b;
            }
            const long long e0 = static_cast<long long>(options[0][0].err) + options[0][1].err;
            const long long e1 = static_cast<long long>(options[1][0].err) + options[1][1].err;
            f[0] = e0 <= e1 ? options[0][0] : options[1][0];
            f[1] = e0 <= e1 ? options[0][1] : options[1][1];
        }
        const long long err = static_cast<long long>(f[0].err) + f[1].err;
        if (err < best.err) {
            std::uint64_t v = common | put(1, 33, 1);
            if (punch) v &= ~put(1, 33, 1);  // opaque bit clear
            for (int c = 0; c < 3; ++c) v |= put(f[0].q[c], 63 - 8 * c, 5) | put(f[1].q[c] - f[0].q[c], 58 - 8 * c, 3);
            v |= put(f[0].table, 39, 3) | put(f[1].table, 36, 3);
            for (int s = 0; s < 2; ++s) {
                const int base[3] = {ext5(f[s].q[0]), ext5(f[s].q[1]), ext5(f[s].q[2])};
                set_indices(v, subs[s], base, f[s].table, punch);
            }
            best.err = err;
            best.bits = v;
        }
    }
}

// Fills the bits no field of the mode uses so that the block decodes in
// `mode` (the overflow rules of 22.1); returns false where none does.
bool settle_free_bits(std::uint64_t& v, const int* free_bits, int count, Mode mode, bool punch) {
    for (int combo = 0; combo < (1 << count); ++combo) {
        std::uint64_t w = v;
        for (int i = 0; i < count; ++i) {
            const std::uint64_t bit = std::uint64_t{1} << free_bits[i];
            w = (combo >> i & 1) ? (w | bit) : (w & ~bit);
        }
        if (etc_mode(w, false, punch) == mode) {
            v = w;
            return true;
        }
    }
    return false;
}

long long block_error(std::uint64_t v, bool punch, const Texels& px, const bool transparent[16]) {
    Texels d;
    decode_colour_block(v, false, punch, d);
    long long err = 0;
    for (std::size_t t = 0; t < 16; ++t) {
        if (punch && transparent[t] != (d[t][3] == 0)) return LLONG_MAX;
        if (punch && transparent[t]) continue;
        for (std::size_t c = 0; c < 3; ++c) err += sq(d[t][c] - px[t][c]);
    }
    return err;
}

// Planar mode: a least-squares plane a channel (channels are independent),
// O, H, V quantised, each +-1 searched.
void encode_planar(const Texels& px, bool punch, const bool transparent[16], ColourChoice& best) {
    int q[3][3];  // channel, {O, H, V}
    for (int c = 0; c < 3; ++c) {
        double mean = 0, sx = 0, sy = 0;
        for (int t = 0; t < 16; ++t) mean += px[static_cast<std::size_t>(t)][static_cast<std::size_t>(c)];
        mean /= 16.0;
        for (int t = 0; t < 16; ++t) {
            const double v = px[static_cast<std::size_t>(t)][static_cast<std::size_t>(c)] - mean;
            sx += (t % 4 - 1.5) * v;
            sy += (t / 4 - 1.5) * v;
        }
        const double a = sx / 20.0, b = sy / 20.0;
        const double o = mean - 1.5 * (a + b);
        const double target[3] = {o, o + 4.0 * a, o + 4.0 * b};
        const int bits = c == 1 ? 7 : 6, maxq = (1 << bits) - 1;
        int start[3];
        for (int k = 0; k < 3; ++k)
            start[k] = clamp_to(static_cast<int>(std::lround(target[k] * maxq / 255.0)), 0, maxq);
        auto channel_error = [&](int qo, int qh, int qv) {
            const int eo = bits == 7 ? ext7(qo) : ext6(qo), eh = bits == 7 ? ext7(qh) : ext6(qh),
                      ev = bits == 7 ? ext7(qv) : ext6(qv);
            int err = 0;
            for (int t = 0; t < 16; ++t) {
                const int x = t % 4, y = t / 4;
                const int s = x * (eh - eo) + y * (ev - eo) + 4 * eo + 2;
                const int r = s < 0 ? 0 : clamp255(s >> 2);
                err += sq(r - px[static_cast<std::size_t>(t)][static_cast<std::size_t>(c)]);
            }
            return err;
        };
        // Hill climbing from the rounded fit: where the plane leaves 0..255
        // (H or V clamped) the other two points have to move to make up.
        int cur[3] = {start[0], start[1], start[2]};
        int best_err = channel_error(cur[0], cur[1], cur[2]);
        for (int step = 0; step < 256 && best_err > 0; ++step) {
            int next[3] = {cur[0], cur[1], cur[2]};
            for (int d0 = -1; d0 <= 1; ++d0)
                for (int d1 = -1; d1 <= 1; ++d1)
                    for (int d2 = -1; d2 <= 1; ++d2) {
                        const int qo = cur[0] + d0, qh = cur[1] + d1, qv = cur[2] + d2;
                        if (qo < 0 || qo > maxq || qh < 0 || qh > maxq || qv < 0 || qv > maxq) continue;
                        const int err = channel_error(qo, qh, qv);
                        if (err < best_err) {
                            best_err = err;
                            next[0] = qo;
                            next[1] = qh;
                            next[2] = qv;
                        }
                    }
            if (next[0] == cur[0] && next[1] == cur[1] && next[2] == cur[2]) break;
            std::copy(next, next + 3, cur);
        }
        std::copy(cur, cur + 3, q[c]);
    }
    std::uint64_t v = put(q[0][0], 62, 6) | put(q[1][0] >> 6, 56, 1) | put(q[1][0], 54, 6) | put(q[2][0] >> 5, 48, 1) |
                      put(q[2][0] >> 3, 44, 2) | put(q[2][0], 41, 3) | put(q[0][1] >> 1, 38, 5) | put(q[0][1], 32, 1) |
                      put(q[1][1], 31, 7) | put(q[2][1], 24, 6) | put(q[0][2], 18, 6) | put(q[1][2], 12, 7) |
                      put(q[2][2], 5, 6) | put(1, 33, 1);
    const int free_bits[6] = {63, 55, 47, 46, 45, 42};
    if (!settle_free_bits(v, free_bits, 6, Mode::planar, punch)) return;
    const long long err = block_error(v, punch, px, transparent);
    if (err < best.err) {
        best.err = err;
        best.bits = v;
    }
}

std::uint64_t encode_colour_block(const Texels& px, F format) {
    ColourChoice best;
    bool transparent[16] = {};
    bool any_transparent = false;
    const bool punch = format == F::etc2_rgb8a1;
    if (punch)
        for (std::size_t t = 0; t < 16; ++t) {
            transparent[t] = px[t][3] < 128;
            any_transparent = any_transparent || transparent[t];
        }
    if (punch && any_transparent) {
        encode_ind_diff(px, false, true, transparent, best);
        return best.bits;
    }
    // Opaque: ETC1 individual + differential; ETC2 also planar; RGB A1 with
    // the opaque bit set has no individual mode.
    encode_ind_diff(px, !punch, false, transparent, best);
    if (punch) best.bits |= put(1, 33, 1);
    if (format != F::etc1_rgb8 && best.err > 0) encode_planar(px, punch, transparent, best);
    return best.bits;
}

// EAC: base codeword, multiplier and table searched for the least squared
// error; `eleven`: R11 (values 0..2047, multipliers 0..15), else 8-bit
// alpha (values 0..255, multipliers 1..15).
std::uint64_t encode_eac_block(const std::array<int, 16>& val, bool eleven) {
    int vmin = INT_MAX, vmax = INT_MIN;
    for (int v : val) {
        vmin = std::min(vmin, v);
        vmax = std::max(vmax, v);
    }
    std::array<int, 16> sorted = val;
    std::sort(sorted.begin(), sorted.end());
    const int maxv = eleven ? 2047 : 255;
    const int unit = eleven ? 8 : 1, offset = eleven ? 4 : 0;  // value = base * unit + offset + modifier * step
    auto step_of = [eleven](int mult) { return eleven ? (mult == 0 ? 1 : mult * 8) : mult; };
    int best_err = INT_MAX, best_base = 0, best_mult = 1, best_table = 0;
    for (int t = 0; t < 16 && best_err > 0; ++t) {
        int lo = INT_MAX, hi = INT_MIN;
        for (int m : kEacTable[t]) {
            lo = std::min(lo, m);
            hi = std::max(hi, m);
        }
        // Multipliers from the smallest whose reach spans the block's range
        // upwards, then the smaller ones (a good fit early makes the early
        // exits below bite).
        const int first = eleven ? 0 : 1;
        const int span = (hi - lo) * (eleven ? 8 : 1);
        const int m_fit = clamp_to((vmax - vmin + span - 1) / span, first, 15);
        int mults[16], count = 0;
        for (int m = m_fit; m <= 15; ++m) mults[count++] = m;
        for (int m = m_fit - 1; m >= first; --m) mults[count++] = m;
        for (int mi = 0; mi < count && best_err > 0; ++mi) {
            const int mult = mults[mi];
            const int step = step_of(mult);
            // The base that centres the table's reach on the block's range,
            // and enough bases around it to move by half a step either way.
            const double centre = ((vmin + vmax) / 2.0 - offset - (lo + hi) * step / 2.0) / unit;
            const int base_c = static_cast<int>(std::lround(centre));
            // No base can do better than leaving the part of the block's
            // range that the table's reach does not cover.
            const int reach = (hi - lo) * step;
            if (reach < vmax - vmin) {
                const int gap = vmax - vmin - reach;
                if (gap * gap / 2 >= best_err) continue;
            }
            auto try_base = [&](int base) {
                // Levels in ascending order (every table's modifiers rise
                // in index order 3, 2, 1, 0, 4, 5, 6, 7), merged with the
                // sorted values: each value's nearest level never moves down.
                constexpr int order[8] = {3, 2, 1, 0, 4, 5, 6, 7};
                int level[8];
                for (int k = 0; k < 8; ++k)
                    level[k] = clamp_to(base * unit + offset + kEacTable[t][order[k]] * step, 0, maxv);
                int err = 0, k = 0;
                for (int v : sorted) {
                    while (k < 7 && std::abs(level[k + 1] - v) <= std::abs(level[k] - v)) ++k;
                    err += sq(level[k] - v);
                    if (err >= best_err) return false;
                }
                best_err = err;
                best_base = base;
                best_mult = mult;
                best_table = t;
                return true;
            };
            // Bases that keep the block's range inside the table's reach
            // (at most about half a multiplier step a side), and two more.
            const int radius = 2 + std::min(mult / 2 + 1, std::max(0, reach - (vmax - vmin)) / (2 * unit));
            int local = -1;
            for (int base = std::max(0, base_c - radius); base <= std::min(255, base_c + radius); ++base)
                if (try_base(base)) local = base;
            // Refine the best base of this table and multiplier: pick each
            // value's level, move the base to the least-squares fit of those
            // levels, and look around it (two rounds).
            for (int round = 0; round < 2 && local >= 0; ++round) {
                double sum = 0;
                for (int v : val) {
                    int e = INT_MAX, mod = 0;
                    for (int k = 0; k < 8; ++k) {
                        const int r = clamp_to(local * unit + offset + kEacTable[t][k] * step, 0, maxv);
                        if (sq(r - v) < e) {
                            e = sq(r - v);
                            mod = kEacTable[t][k] * step;
                        }
                    }
                    sum += v - offset - mod;
                }
                const int fit = static_cast<int>(std::lround(sum / 16.0 / unit));
                int next = -1;
                for (int base = std::max(0, fit - 1); base <= std::min(255, fit + 1); ++base)
                    if (base != local && try_base(base)) next = base;
                local = next;
            }
        }
    }
    std::uint64_t v = put(best_base, 63, 8) | put(best_mult, 55, 4) | put(best_table, 51, 4);
    const int step = step_of(best_mult);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const int value = val[static_cast<std::size_t>(x + 4 * y)];
            int e = INT_MAX, idx = 0;
            for (int k = 0; k < 8; ++k) {
                const int r = clamp_to(best_base * unit + offset + kEacTable[best_table][k] * step, 0, maxv);
                if (sq(r - value) < e) {
                    e = sq(r - value);
                    idx = k;
                }
            }
            v |= put(idx, 47 - 3 * (x * 4 + y), 3);
        }
    return v;
}

std::string size_text(std::uint32_t w, std::uint32_t h) { return std::to_string(w) + "x" + std::to_string(h); }

}  // namespace

Status decode_etc_rgba8(TextureFormat format, std::uint32_t width, std::uint32_t height, const std::uint8_t* data,
                        std::size_t size, std::uint8_t* rgba) {
    if (!is_etc_colour(format) && !is_eac(format))
        return make_error(std::string("decode_etc_rgba8: ") + format_name(format) + " is not an ETC or EAC format");
    if (Status s = check_size("decode_etc_rgba8", format, width, height, data, size); !s) return s;
    if (!rgba) return make_error("decode_etc_rgba8: no output buffer");
    const std::uint32_t bx_count = (width + 3) / 4, by_count = (height + 3) / 4;
    const std::size_t block_bytes = static_cast<std::size_t>(format_info(format).block_bytes);
    const std::uint8_t* p = data;
    Texels texels;
    std::array<int, 16> r{}, g{};
    for (std::uint32_t by = 0; by < by_count; ++by) {
        for (std::uint32_t bx = 0; bx < bx_count; ++bx, p += block_bytes) {
            if (is_eac(format)) {
                decode_eac11_block(load_be64(p), r);
                if (format == F::eac_rg11) decode_eac11_block(load_be64(p + 8), g);
                for (std::size_t t = 0; t < 16; ++t) {
                    texels[t][0] = (r[t] * 255 + 1023) / 2047;
                    texels[t][1] = format == F::eac_rg11 ? (g[t] * 255 + 1023) / 2047 : 0;
                    texels[t][2] = 0;
                    texels[t][3] = 255;
                }
            } else if (format == F::etc2_rgba8) {
                decode_colour_block(load_be64(p + 8), false, false, texels);
                decode_eac8_block(load_be64(p), r);
                for (std::size_t t = 0; t < 16; ++t) texels[t][3] = r[t];
            } else {
                decode_colour_block(load_be64(p), format == F::etc1_rgb8, format == F::etc2_rgb8a1, texels);
            }
            for (std::uint32_t y = 0; y < 4 && by * 4 + y < height; ++y)
                for (std::uint32_t x = 0; x < 4 && bx * 4 + x < width; ++x) {
                    std::uint8_t* out = rgba + (static_cast<std::size_t>(by * 4 + y) * width + bx * 4 + x) * 4;
                    for (std::size_t c = 0; c < 4; ++c) out[c] = static_cast<std::uint8_t>(texels[x + 4 * y][c]);
                }
        }
    }
    return {};
}

Status decode_eac_unorm16(TextureFormat format, std::uint32_t width, std::uint32_t height,
                          const std::uint8_t* data, std::size_t size, std::uint16_t* values) {
    if (!is_eac(format))
        return make_error(std::string("decode_eac_unorm16: ") + format_name(format) + " is not eac_r11 or eac_rg11");
    if (Status s = check_size("decode_eac_unorm16", format, width, height, data, size); !s) return s;
    if (!values) return make_error("decode_eac_unorm16: no output buffer");
    const std::size_t channels = format == F::eac_rg11 ? 2 : 1;
    const std::uint32_t bx_count = (width + 3) / 4, by_count = (height + 3) / 4;
    const std::uint8_t* p = data;
    std::array<int, 16> ch[2];
    for (std::uint32_t by = 0; by < by_count; ++by) {
        for (std::uint32_t bx = 0; bx < bx_count; ++bx, p += 8 * channels) {
            for (std::size_t c = 0; c < channels; ++c) decode_eac11_block(load_be64(p + 8 * c), ch[c]);
            for (std::uint32_t y = 0; y < 4 && by * 4 + y < height; ++y)
                for (std::uint32_t x = 0; x < 4 && bx * 4 + x < width; ++x) {
                    std::uint16_t* out = values + (static_cast<std::size_t>(by * 4 + y) * width + bx * 4 + x) * channels;
                    for (std::size_t c = 0; c < channels; ++c) {
                        const int v = ch[c][x + 4 * y];
                        out[c] = static_cast<std::uint16_t>(v << 5 | v >> 6);
                    }
                }
        }
    }
    return {};
}

Result<std::vector<std::uint8_t>> encode_etc_rgba8(TextureFormat format, std::uint32_t width, std::uint32_t height,
                                                   const std::uint8_t* rgba) {
    if (!is_etc_colour(format))
        return make_error(std::string("encode_etc_rgba8: ") + format_name(format) +
                          " is not etc1, etc2_rgb, etc2_rgb_a1 or etc2_rgba");
    if (width < 1 || height < 1)
        return make_error(std::string("encode_etc_rgba8: ") + format_name(format) + ": image size " +
                          size_text(width, height) + " (each side must be at least 1)");
    if (!rgba) return make_error("encode_etc_rgba8: no pixels");
    const auto bytes = image_bytes(format, width, height);
    if (!bytes) return make_error(std::string("encode_etc_rgba8: image ") + size_text(width, height) + " is too large");
    return out_of_memory_is_an_error("encode_etc_rgba8", [&]() -> Result<std::vector<std::uint8_t>> {
        std::vector<std::uint8_t> out(static_cast<std::size_t>(*bytes));
        const std::uint32_t bx_count = (width + 3) / 4, by_count = (height + 3) / 4;
        std::uint8_t* p = out.data();
        Texels texels;
        std::array<int, 16> alpha{};
        for (std::uint32_t by = 0; by < by_count; ++by) {
            for (std::uint32_t bx = 0; bx < bx_count; ++bx) {
                for (std::uint32_t y = 0; y < 4; ++y)
                    for (std::uint32_t x = 0; x < 4; ++x) {
                        const std::uint32_t sx = std::min(bx * 4 + x, width - 1), sy = std::min(by * 4 + y, height - 1);
                        const std::uint8_t* in = rgba + (static_cast<std::size_t>(sy) * width + sx) * 4;
                        for (std::size_t c = 0; c < 4; ++c) texels[x + 4 * y][c] = in[c];
                        alpha[x + 4 * y] = in[3];
                    }
                if (format == F::etc2_rgba8) {
                    store_be64(p, encode_eac_block(alpha, false));
                    p += 8;
                }
                store_be64(p, encode_colour_block(texels, format));
                p += 8;
            }
        }
        return out;
    });
}

Result<std::vector<std::uint8_t>> encode_eac_unorm16(TextureFormat format, std::uint32_t width,
                                                     std::uint32_t height, const std::uint16_t* values) {
    if (!is_eac(format))
        return make_error(std::string("encode_eac_unorm16: ") + format_name(format) + " is not eac_r11 or eac_rg11");
    if (width < 1 || height < 1)
        return make_error(std::string("encode_eac_unorm16: ") + format_name(format) + ": image size " +
                          size_text(width, height) + " (each side must be at least 1)");
    if (!values) return make_error("encode_eac_unorm16: no values");
    const auto bytes = image_bytes(format, width, height);
    if (!bytes) return make_error(std::string("encode_eac_unorm16: image ") + size_text(width, height) + " is too large");
    return out_of_memory_is_an_error("encode_eac_unorm16", [&]() -> Result<std::vector<std::uint8_t>> {
        std::vector<std::uint8_t> out(static_cast<std::size_t>(*bytes));
        const std::size_t channels = format == F::eac_rg11 ? 2 : 1;
        const std::uint32_t bx_count = (width + 3) / 4, by_count = (height + 3) / 4;
        std::uint8_t* p = out.data();
        std::array<int, 16> block{};
        for (std::uint32_t by = 0; by < by_count; ++by) {
            for (std::uint32_t bx = 0; bx < bx_count; ++bx) {
                for (std::size_t c = 0; c < channels; ++c) {
                    for (std::uint32_t y = 0; y < 4; ++y)
                        for (std::uint32_t x = 0; x < 4; ++x) {
                            const std::uint32_t sx = std::min(bx * 4 + x, width - 1),
                                                sy = std::min(by * 4 + y, height - 1);
                            const unsigned v16 = values[(static_cast<std::size_t>(sy) * width + sx) * channels + c];
                            block[x + 4 * y] = static_cast<int>((v16 * 2047u + 32767u) / 65535u);
                        }
                    store_be64(p, encode_eac_block(block, true));
                    p += 8;
                }
            }
        }
        return out;
    });
}

}  // namespace px
