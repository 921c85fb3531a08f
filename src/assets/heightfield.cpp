#include "parallaxes/assets/heightfield.h"
#include "parallaxes/core/text.h"

#include "parallaxes/core/limits.h"
#include "parallaxes/core/numeric.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace px {

namespace {


// Formats a float for error messages without trailing noise ("0.3", not "0.300000").
std::string num(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

// --- 5x7 bitmap font ---------------------------------------------------------
// Rows are listed top first, as read; '#' is a raised pixel. Drawn for this
// project (classic 5x7 LCD-style shapes).
struct Glyph {
    char c;
    std::array<const char*, 7> rows;
};

constexpr int kGlyphW = 5;
constexpr int kGlyphH = 7;
constexpr int kGlyphAdvance = kGlyphW + 1;  // one blank column between glyphs

constexpr Glyph kFont[] = {
    {' ', {".....", ".....", ".....", ".....", ".....", ".....", "....."}},
    {'A', {".###.", "#...#", "#...#", "#####", "#...#", "#...#", "#...#"}},
    {'B', {"####.", "#...#", "#...#", "####.", "#...#", "#...#", "####."}},
    {'C', {".###.", "#...#", "#....", "#....", "#....", "#...#", ".###."}},
    {'D', {"####.", "#...#", "#...#", "#...#", "#...#", "#...#", "####."}},
    {'E', {"#####", "#....", "#....", "####.", "#....", "#....", "#####"}},
    {'F', {"#####", "#....", "#....", "####.", "#....", "#....", "#...."}},
    {'G', {".###.", "#...#", "#....", "#.###", "#...#", "#...#", ".####"}},
    {'H', {"#...#", "#...#", "#...#", "#####", "#...#", "#...#", "#...#"}},
    {'I', {".###.", "..#..", "..#..", "..#..", "..#..", "..#..", ".###."}},
    {'J', {"..###", "...#.", "...#.", "...#.", "...#.", "#..#.", ".##.."}},
    {'K', {"#...#", "#..#.", "#.#..", "##...", "#.#..", "#..#.", "#...#"}},
    {'L', {"#....", "#....", "#....", "#....", "#....", "#....", "#####"}},
    {'M', {"#...#", "##.##", "#.#.#", "#.#.#", "#...#", "#...#", "#...#"}},
    {'N', {"#...#", "#...#", "##..#", "#.#.#", "#..##", "#...#", "#...#"}},
    {'O', {".###.", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."}},
    {'P', {"####.", "#...#", "#...#", "####.", "#....", "#....", "#...."}},
    {'Q', {".###.", "#...#", "#...#", "#...#", "#.#.#", "#..#.", ".##.#"}},
    {'R', {"####.", "#...#", "#...#", "####.", "#.#..", "#..#.", "#...#"}},
    {'S', {".####", "#....", "#....", ".###.", "....#", "....#", "####."}},
    {'T', {"#####", "..#..", "..#..", "..#..", "..#..", "..#..", "..#.."}},
    {'U', {"#...#", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."}},
    {'V', {"#...#", "#...#", "#...#", "#...#", "#...#", ".#.#.", "..#.."}},
    {'W', {"#...#", "#...#", "#...#", "#.#.#", "#.#.#", "#.#.#", ".#.#."}},
    {'X', {"#...#", "#...#", ".#.#.", "..#..", ".#.#.", "#...#", "#...#"}},
    {'Y', {"#...#", "#...#", ".#.#.", "..#..", "..#..", "..#..", "..#.."}},
    {'Z', {"#####", "....#", "...#.", "..#..", ".#...", "#....", "#####"}},
    {'0', {".###.", "#...#", "#..##", "#.#.#", "##..#", "#...#", ".###."}},
    {'1', {"..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###."}},
    {'2', {".###.", "#...#", "....#", "...#.", "..#..", ".#...", "#####"}},
    {'3', {"#####", "...#.", "..#..", "...#.", "....#", "#...#", ".###."}},
    {'4', {"...#.", "..##.", ".#.#.", "#..#.", "#####", "...#.", "...#."}},
    {'5', {"#####", "#....", "####.", "....#", "....#", "#...#", ".###."}},
    {'6', {"..##.", ".#...", "#....", "####.", "#...#", "#...#", ".###."}},
    {'7', {"#####", "....#", "...#.", "..#..", ".#...", ".#...", ".#..."}},
    {'8', {".###.", "#...#", "#...#", ".###.", "#...#", "#...#", ".###."}},
    {'9', {".###.", "#...#", "#...#", ".####", "....#", "...#.", ".##.."}},
};

// Compile-time check that every row is exactly 5 of '#' / '.'.
constexpr bool font_well_formed() {
    for (const Glyph& g : kFont)
        for (const char* row : g.rows) {
            int n = 0;
            for (; row[n] != '\0'; ++n)
                if (row[n] != '#' && row[n] != '.') return false;
            if (n != kGlyphW) return false;
        }
    return true;
}
static_assert(font_well_formed(), "5x7 font rows must be 5 characters of '#' or '.'");

const Glyph* find_glyph(char c) {
    for (const Glyph& g : kFont)
        if (g.c == c) return &g;
    return nullptr;
}

std::string describe_char(char c) {
    const auto uc = static_cast<unsigned char>(c);
    if (uc >= 0x20 && uc < 0x7f) return std::string("'") + c + "'";
    char buf[16];
    std::snprintf(buf, sizeof buf, "byte 0x%02x", uc);
    return buf;
}

// --- Procedural field definitions ---------------------------------------------

std::string field_prefix(const FieldSpec& spec) {
    return std::string("field '") + field_kind_name(spec.kind) + "': ";
}

// Distance from x to the nearest multiple of `period`.
double distance_to_grid(double x, double period) {
    const double t = x / period;
    return std::abs(t - std::round(t)) * period;
}

// count: at least 1 and at most the size (bricks, lines, hemispheres, cones).
Status check_count(const FieldSpec& spec, const std::string& pre) {
    if (spec.count < 1)
        return make_error(pre + "count must be ≥ 1, got " + std::to_string(spec.count));
    if (spec.count > spec.size)
        return make_error(pre + "count must be ≤ size (" + std::to_string(spec.size) +
                          "), got " + std::to_string(spec.count));
    return {};
}

Status check_bricks(const FieldSpec& spec, const std::string& pre) {
    if (Status s = check_count(spec, pre); !s) return s;
    // Rows alternate offset / not offset; an odd count would put two
    // unshifted rows next to each other across the tile edge.
    if (spec.count % 2 != 0)
        return make_error(pre + "count (rows) must be even so the running bond continues "
                                "across the tile edge, got " +
                          std::to_string(spec.count));
    // Joint (mortar) plus a bevel of mortar/2 on each side must leave a
    // flat top: 2 * mortar < row height = 1 / count.
    const double limit = 0.5 / spec.count;
    if (!(spec.mortar > 0.0f && spec.mortar < limit))
        return make_error(pre + "mortar must be in (0, " + num(limit) +
                          ") (joint plus bevels under the row height), got " +
                          num(spec.mortar));
    return {};
}

Status check_text(const FieldSpec& spec, const std::string& pre) {
    if (spec.text.empty()) return make_error(pre + "text must not be empty");
    if (spec.text.size() > static_cast<size_t>(kMaxFieldTextLength))
        return make_error(pre + "text must be at most " + std::to_string(kMaxFieldTextLength) +
                          " characters, got " + std::to_string(spec.text.size()));
    for (size_t i = 0; i < spec.text.size(); ++i) {
        const char c = spec.text[i];
        if (!find_glyph(c)) {
            std::string hint = (c >= 'a' && c <= 'z') ? " (letters must be upper case)" : "";
            return make_error(pre + "no glyph for character " + describe_char(c) +
                              " at position " + std::to_string(i) +
                              "; the 5x7 font has A-Z, 0-9 and space" + hint);
        }
    }
    return {};
}

Status check_lines(const FieldSpec& spec, const std::string& pre) {
    if (Status s = check_count(spec, pre); !s) return s;
    if (spec.line_width < 1)
        return make_error(pre + "line_width must be ≥ 1, got " + std::to_string(spec.line_width));
    // At least one ground texel between neighbours, or lines merge.
    // In 64 bits: count and line_width are each at most INT_MAX here.
    if (const long long span = static_cast<long long>(spec.count) * (static_cast<long long>(spec.line_width) + 1);
        span > spec.size)
        return make_error(pre + "count * (line_width + 1) must be ≤ size so lines stay "
                                "apart, got " +
                          std::to_string(spec.count) + " * " +
                          std::to_string(static_cast<long long>(spec.line_width) + 1) + " > " +
                          std::to_string(spec.size));
    return {};
}

Status check_sine(const FieldSpec& spec, const std::string& pre) {
    // Whole periods per tile, or the tile would not repeat seamlessly;
    // at most size/2 (Nyquist), or the samples alias.
    const double f = spec.frequency;
    if (!(f >= 1.0 && f == std::floor(f)))
        return make_error(pre + "frequency must be a whole number ≥ 1 (periods per tile), got " +
                          num(f));
    if (f > spec.size / 2.0)
        return make_error(pre + "frequency must be ≤ size/2 (" + num(spec.size / 2.0) +
                          ") or it aliases, got " + num(f));
    return {};
}

}  // namespace

Status validate_field_spec(const FieldSpec& spec) {
    const std::string pre = field_prefix(spec);
    if (spec.size < 1 || spec.size > kMaxTextureSize)
        return make_error(pre + "size must be in 1.." + std::to_string(kMaxTextureSize) + ", got " +
                          std::to_string(spec.size));
    switch (spec.kind) {
        case FieldKind::flat:
            // Written as !(in range) so NaN is rejected too.
            if (!(spec.level >= 0.0f && spec.level <= 1.0f))
                return make_error(pre + "level must be in [0, 1], got " + num(spec.level));
            break;
        case FieldKind::bricks: return check_bricks(spec, pre);
        case FieldKind::text: return check_text(spec, pre);
        case FieldKind::lines: return check_lines(spec, pre);
        case FieldKind::hemispheres:
        case FieldKind::cones: return check_count(spec, pre);
        case FieldKind::sine: return check_sine(spec, pre);
        case FieldKind::spike:
            break;
        case FieldKind::pit:
            if (!(spec.radius > 0.0f && spec.radius < 0.5f))
                return make_error(pre + "radius must be in (0, 0.5), got " + num(spec.radius));
            break;
    }
    return {};
}

namespace {

// Running-bond bricks: rows of height 1/count, two bricks of width 1/2 per
// row, odd rows shifted by half a brick. `d` is the distance to the nearest
// brick edge line (joint centre line); a joint is mortar wide, half on each
// side, and a bevel ramps from 0 to 1 over mortar/2 beyond it.
double bricks_height(double u, double v, int rows, double mortar) {
    const double row_h = 1.0 / rows;
    const long long row = static_cast<long long>(std::floor(v * rows));
    const double shift = (row % 2 != 0) ? 0.25 : 0.0;
    const double d = std::min(distance_to_grid(v, row_h), distance_to_grid(u + shift, 0.5));
    const double half_joint = 0.5 * mortar;
    const double bevel = 0.5 * mortar;
    return std::clamp((d - half_joint) / bevel, 0.0, 1.0);
}

// Distance from (u, v) to the centre of its cell in a count x count grid,
// in cell units.
double cell_radius(double u, double v, int count) {
    const double cu = u * count - std::floor(u * count) - 0.5;
    const double cv = v * count - std::floor(v * count) - 0.5;
    return std::sqrt(cu * cu + cv * cv);
}

constexpr double kBumpRadius = 0.45;  // of a cell

double hemisphere_height(double u, double v, int count) {
    const double q = cell_radius(u, v, count) / kBumpRadius;
    return q < 1.0 ? std::sqrt(1.0 - q * q) : 0.0;
}

double cone_height(double u, double v, int count) {
    const double q = cell_radius(u, v, count) / kBumpRadius;
    return q < 1.0 ? 1.0 - q : 0.0;
}

// Text layout: glyph cells of s x s tile units, 5 per glyph plus one blank
// column between glyphs. s fills 80% of the tile width, unless the 7 rows
// would then exceed 80% of its height (short strings). Centred in the tile.
struct TextLayout {
    double cell = 0.0;
    double x0 = 0.0, y0 = 0.0;  // bottom-left of the text block in uv
    int columns = 0;
};

TextLayout layout_text(const std::string& text) {
    TextLayout l;
    l.columns = static_cast<int>(text.size()) * kGlyphAdvance - 1;
    l.cell = std::min(0.8 / l.columns, 0.8 / kGlyphH);
    l.x0 = 0.5 - 0.5 * l.columns * l.cell;
    l.y0 = 0.5 - 0.5 * kGlyphH * l.cell;
    return l;
}

double text_height(double u, double v, const std::string& text, const TextLayout& l) {
    const double gx = std::floor((u - l.x0) / l.cell);
    const double gy = std::floor((v - l.y0) / l.cell);
    if (gx < 0 || gx >= l.columns || gy < 0 || gy >= kGlyphH) return 0.0;
    const int col = static_cast<int>(gx);
    if (col % kGlyphAdvance == kGlyphW) return 0.0;  // spacing column
    const Glyph* g = find_glyph(text[static_cast<size_t>(col / kGlyphAdvance)]);
    // Font rows are top first; v grows upwards, so v's cell row 0 is the bottom row.
    const char* row = g->rows[static_cast<size_t>(kGlyphH - 1 - static_cast<int>(gy))];
    return row[col % kGlyphAdvance] == '#' ? 1.0 : 0.0;
}

// Fills every texel with h((x + 0.5) / size, (y + 0.5) / size).
// (A template rather than std::function so the per-texel call inlines: up to 8192^2 texels.)
template <typename F>
HeightField sample_field(int size, const F& h) {
    HeightField f;
    f.width = size;
    f.height = size;
    f.texels.resize(static_cast<size_t>(size) * size);
    for (int y = 0; y < size; ++y) {
        const double v = (y + 0.5) / size;
        for (int x = 0; x < size; ++x) {
            const double u = (x + 0.5) / size;
            f.ref(x, y) = static_cast<float>(h(u, v));
        }
    }
    return f;
}

struct KindName {
    FieldKind kind;
    const char* name;
};

constexpr KindName kKindNames[] = {
    {FieldKind::flat, "flat"},     {FieldKind::bricks, "bricks"},
    {FieldKind::text, "text"},     {FieldKind::lines, "lines"},
    {FieldKind::hemispheres, "hemispheres"}, {FieldKind::cones, "cones"},
    {FieldKind::sine, "sine"},     {FieldKind::spike, "spike"},
    {FieldKind::pit, "pit"},
};

}  // namespace

// --- HeightField ----------------------------------------------------------------

float HeightField::at(int x, int y) const {
    return texels[static_cast<size_t>(wrap_index(y, height)) * width + wrap_index(x, width)];
}

double HeightField::sample_bilinear(double u, double v) const {
    if (width <= 0 || height <= 0) return 0.0;
    // GL_LINEAR (ES 3.0 spec, 3.8.10): coordinates in texel space minus 0.5
    // put texel centres on integers; i0 = floor, weight = fraction, and
    // GL_REPEAT wraps i0 and i0 + 1 independently.
    const BilinearTaps b = bilinear_taps(u, v, width, height);
    const auto t = [&](int x, int y) {
        return static_cast<double>(texels[static_cast<size_t>(y) * width + x]);
    };
    return (1 - b.ax) * (1 - b.ay) * t(b.x0, b.y0) + b.ax * (1 - b.ay) * t(b.x1, b.y0) +
           (1 - b.ax) * b.ay * t(b.x0, b.y1) + b.ax * b.ay * t(b.x1, b.y1);
}

HeightField height_field_from_image(const Image& image, HeightConvention convention) {
    HeightField f;
    f.width = image.width;
    f.height = image.height;
    f.texels.resize(static_cast<size_t>(image.width) * image.height);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const float value = image.texel(x, y)[0] / 255.0f;  // red, or the only channel
            f.ref(x, y) = convention == HeightConvention::depth ? 1.0f - value : value;
        }
    return f;
}

// --- Names --------------------------------------------------------------------------

const char* field_kind_name(FieldKind kind) {
    for (const KindName& k : kKindNames)
        if (k.kind == kind) return k.name;
    return "unknown";
}

std::vector<std::string> field_kind_names() {
    std::vector<std::string> names;
    for (const KindName& k : kKindNames) names.emplace_back(k.name);
    return names;
}

Result<FieldKind> parse_field_kind(const std::string& name) {
    std::string known;
    for (const KindName& k : kKindNames) {
        if (name == k.name) return k.kind;
        if (!known.empty()) known += ", ";
        known += k.name;
    }
    return make_error("unknown field kind '" + echo(name) + "' (known: " + known + ")");
}

// --- Procedural fields -----------------------------------------------------------

Result<HeightField> make_height_field(const FieldSpec& spec) {
    if (Status s = validate_field_spec(spec); !s) return s.error();
    const int n = spec.size;
    switch (spec.kind) {
        case FieldKind::flat: {
            const double level = spec.level;
            return sample_field(n, [&](double, double) { return level; });
        }
        case FieldKind::bricks: {
            const int rows = spec.count;
            const double mortar = spec.mortar;
            return sample_field(n, [&](double u, double v) { return bricks_height(u, v, rows, mortar); });
        }
        case FieldKind::text: {
            const TextLayout layout = layout_text(spec.text);
            return sample_field(n, [&](double u, double v) { return text_height(u, v, spec.text, layout); });
        }
        case FieldKind::lines: {
            // Defined on the texel grid (widths are in texels): line i starts at
            // the texel nearest the centre of its period, minus half its width.
            // validate() guarantees a gap of at least one texel, wrap included.
            HeightField f = sample_field(n, [](double, double) { return 0.0; });
            const double period = static_cast<double>(n) / spec.count;
            for (int i = 0; i < spec.count; ++i) {
                const int start = static_cast<int>(std::floor((i + 0.5) * period)) - spec.line_width / 2;
                for (int k = 0; k < spec.line_width; ++k) {
                    const int x = wrap_index(start + k, n);
                    for (int y = 0; y < n; ++y) f.ref(x, y) = 1.0f;
                }
            }
            return f;
        }
        case FieldKind::hemispheres: {
            const int count = spec.count;
            return sample_field(n, [&](double u, double v) { return hemisphere_height(u, v, count); });
        }
        case FieldKind::cones: {
            const int count = spec.count;
            return sample_field(n, [&](double u, double v) { return cone_height(u, v, count); });
        }
        case FieldKind::sine: {
            const double f = spec.frequency;
            return sample_field(n, [&](double u, double v) {
                return 0.5 + 0.5 * std::sin(2.0 * kPi<double> * f * u) * std::sin(2.0 * kPi<double> * f * v);
            });
        }
        case FieldKind::spike: {
            // A single texel by definition (the smallest feature the texture holds).
            HeightField f = sample_field(n, [](double, double) { return 0.0; });
            f.ref(n / 2, n / 2) = 1.0f;
            return f;
        }
        case FieldKind::pit: {
            const double r = spec.radius;
            return sample_field(n, [&](double u, double v) {
                return (std::abs(u - 0.5) < r && std::abs(v - 0.5) < r) ? 0.0 : 1.0;
            });
        }
    }
    return make_error(field_prefix(spec) + "unhandled field kind");
}

// --- Derived images ------------------------------------------------------------------

Image derive_normal_map(const HeightField& field, float height_scale, bool pack_height) {
    Image img;
    img.width = field.width;
    img.height = field.height;
    img.channels = 4;
    img.pixels.resize(static_cast<size_t>(field.width) * field.height * 4);
    // Heights h in [0, 1] stand for h * height_scale tile units; one texel is
    // 1/w of the tile in u (1/h in v), so a central difference over two texels
    // gives dH/du = (h(x+1) - h(x-1)) / 2 * w * height_scale. The surface
    // z = H(u, v) has normal (-dH/du, -dH/dv, 1), normalised: tangent space
    // with +x = +u, +y = +v (OpenGL-style, "green up"), +z out of the surface.
    const double sx = 0.5 * field.width * static_cast<double>(height_scale);
    const double sy = 0.5 * field.height * static_cast<double>(height_scale);
    for (int y = 0; y < field.height; ++y)
        for (int x = 0; x < field.width; ++x) {
            const double dhdu = (static_cast<double>(field.at(x + 1, y)) - field.at(x - 1, y)) * sx;
            const double dhdv = (static_cast<double>(field.at(x, y + 1)) - field.at(x, y - 1)) * sy;
            const double len = std::sqrt(dhdu * dhdu + dhdv * dhdv + 1.0);
            std::uint8_t* p = img.texel(x, y);
            p[0] = to_unorm8(-dhdu / len * 0.5 + 0.5);
            p[1] = to_unorm8(-dhdv / len * 0.5 + 0.5);
            p[2] = to_unorm8(1.0 / len * 0.5 + 0.5);
            p[3] = pack_height ? to_unorm8(field.at(x, y)) : std::uint8_t{255};
        }
    return img;
}

namespace {

// A fixed integer hash of a texel (lowbias32 on the packed coordinates) in [-1, 1].
double texel_noise(std::uint32_t x, std::uint32_t y) {
    std::uint32_t h = x * 0x9E3779B1u ^ (y + 0x7F4A7C15u) * 0x85EBCA77u;
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    h *= 0x846CA68Bu;
    h ^= h >> 16;
    return static_cast<double>(h) / 2147483647.5 - 1.0;
}

// Value noise over `cell`-texel cells, wrapping with the field (smoothstep
// blend of the corner hashes): blotches that tile as the texture does.
double cell_noise(int x, int y, int width, int height, int cell) {
    const int cx = std::max(1, width / cell), cy = std::max(1, height / cell);
    const double fx = (x + 0.5) * cx / width, fy = (y + 0.5) * cy / height;
    const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
    auto smooth = [](double t) { return t * t * (3.0 - 2.0 * t); };
    const double sx = smooth(fx - x0), sy = smooth(fy - y0);
    auto corner = [&](int i, int j) {
        return texel_noise(static_cast<std::uint32_t>(((i % cx) + cx) % cx) + 0x10000u,
                           static_cast<std::uint32_t>(((j % cy) + cy) % cy) + 0x20000u);
    };
    const double a = corner(x0, y0) + (corner(x0 + 1, y0) - corner(x0, y0)) * sx;
    const double b = corner(x0, y0 + 1) + (corner(x0 + 1, y0 + 1) - corner(x0, y0 + 1)) * sx;
    return a + (b - a) * sy;
}

}  // namespace

Image ramp_image(const HeightField& field, const HeightRamp& ramp) {
    Image img;
    img.width = field.width;
    img.height = field.height;
    img.channels = 4;
    img.pixels.resize(static_cast<size_t>(field.width) * field.height * 4);
    for (int y = 0; y < field.height; ++y)
        for (int x = 0; x < field.width; ++x) {
            const double h = std::clamp(static_cast<double>(field.at(x, y)), 0.0, 1.0);
            const double n = ramp.grain == 0.0f ? 0.0
                                                : 0.5 * texel_noise(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y)) +
                                                      0.5 * cell_noise(x, y, field.width, field.height, 8);
            const double shade = 1.0 + static_cast<double>(ramp.grain) * n;
            std::uint8_t* p = img.texel(x, y);
            for (int c = 0; c < 3; ++c)
                p[c] = to_unorm8(std::clamp((ramp.low[c] + (ramp.high[c] - ramp.low[c]) * h) * shade, 0.0, 1.0));
            p[3] = 255;
        }
    return img;
}

Image height_image(const HeightField& field) {
    // R, G and B hold the height, alpha is 255 (opaque, so the file views as grey).
    return ramp_image(field, HeightRamp{});
}

HeightField quantized_8bit(const HeightField& field) {
    HeightField q = field;
    for (float& h : q.texels) h = static_cast<float>(to_unorm8(h)) / 255.0f;
    return q;
}

}  // namespace px
