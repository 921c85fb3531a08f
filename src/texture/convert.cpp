#include "parallaxes/texture/convert.h"

#include "parallaxes/assets/color.h"

#include <algorithm>
#include <cmath>

#include "parallaxes/core/numeric.h"
#include "parallaxes/texture/codecs.h"

namespace px {

namespace {

using F = TextureFormat;

// A 2x box filter to the next level (max(1, w / 2)); odd sides fold their
// last texel into the last output texel, so every texel counts.
template <typename T, typename Acc>
std::vector<T> downsample(const std::vector<T>& src, std::uint32_t w, std::uint32_t h, int channels,
                          std::uint32_t nw, std::uint32_t nh) {
    std::vector<T> out(static_cast<std::size_t>(nw) * nh * channels);
    for (std::uint32_t y = 0; y < nh; ++y) {
        const std::uint32_t y0 = h == 1 ? 0 : 2 * y, y1 = h == 1 ? 0 : (y + 1 == nh ? h - 1 : 2 * y + 1);
        for (std::uint32_t x = 0; x < nw; ++x) {
            const std::uint32_t x0 = w == 1 ? 0 : 2 * x, x1 = w == 1 ? 0 : (x + 1 == nw ? w - 1 : 2 * x + 1);
            for (int c = 0; c < channels; ++c) {
                Acc sum = 0;
                int n = 0;
                for (std::uint32_t yy = y0; yy <= y1; ++yy)
                    for (std::uint32_t xx = x0; xx <= x1; ++xx) {
                        sum += src[(static_cast<std::size_t>(yy) * w + xx) * channels + c];
                        ++n;
                    }
                out[(static_cast<std::size_t>(y) * nw + x) * channels + c] =
                    static_cast<T>((sum + static_cast<Acc>(n / 2)) / static_cast<Acc>(n));
            }
        }
    }
    return out;
}

Status check_slot(TextureFormat format, std::uint32_t w, std::uint32_t h) {
    if (format_info(format).family == FormatFamily::pvrtc && !(is_power_of_two(w) && is_power_of_two(h)))
        return make_error(std::string(format_name(format)) + " needs power-of-two sizes; this texture is " +
                          std::to_string(w) + "x" + std::to_string(h));
    return {};
}

// The encoders write the top row first, as the field's tools do (and say so
// in the container: texture_data.h RowOrder). Images and height fields
// here keep row 0 at the bottom (v = 0), so their rows are reversed first
// (core/numeric.h reverse_rows).

// Lays out a chain and fills each level from `encode_level(level, w, h)`.
template <typename EncodeLevel>
Result<TextureData> build_chain(TextureFormat format, std::uint32_t w, std::uint32_t h, bool mipmaps,
                                EncodeLevel&& encode_level) {
    Status ok = check_slot(format, w, h);
    if (!ok) return ok.error();
    const int levels = mipmaps ? full_mip_count(w, h) : 1;
    Result<TextureData> t = allocate_texture(format, w, h, levels, 1, 1, std::uint64_t{1} << 31);
    if (!t) return t.error();
    t->container = ContainerKind::image;
    t->rows = RowOrder::top_first;
    t->rows_source = "written top row first";
    for (int i = 0; i < levels; ++i) {
        const TextureLevel& l = t->levels[static_cast<size_t>(i)];
        Result<std::vector<std::uint8_t>> bytes = encode_level(i, l.width, l.height);
        if (!bytes) return with_context("level " + std::to_string(i), bytes.error());
        if (bytes->size() != l.image_bytes)
            return make_error("level " + std::to_string(i) + ": the encoder gave " + std::to_string(bytes->size()) +
                              " bytes, not " + std::to_string(l.image_bytes));
        std::copy(bytes->begin(), bytes->end(), t->bytes.begin() + static_cast<std::ptrdiff_t>(l.offset));
    }
    return t;
}

}  // namespace

std::vector<std::string> asset_variant_names() { return {"raw", "etc1", "etc2", "astc", "astc_WxH", "pvrtc", "bc"}; }

Result<AssetFormats> asset_formats(const std::string& variant) {
    AssetFormats a;
    a.variant = variant;
    if (variant == "raw") return a;
    if (variant == "etc1") {
        a.height = a.normal = a.albedo = F::etc1_rgb8;
        return a;
    }
    if (variant == "etc2") {
        a.height = F::eac_r11;
        a.normal = F::eac_rg11;
        a.albedo = F::etc2_rgb8;
        return a;
    }
    if (variant == "pvrtc") {
        a.height = a.normal = a.albedo = F::pvrtc1_rgb_4bpp;
        return a;
    }
    if (variant == "bc") {
        a.height = F::bc4;
        a.normal = F::bc5;
        a.albedo = F::bc1_rgb;
        return a;
    }
    const std::string astc = variant == "astc" ? "astc_4x4" : variant;
    if (astc.rfind("astc_", 0) == 0) {
        Result<TextureFormat> f = parse_format(astc);
        if (f && format_info(*f).family == FormatFamily::astc) {
            a.height = a.normal = a.albedo = *f;
            return a;
        }
    }
    std::string names;
    for (const std::string& n : asset_variant_names()) names += (names.empty() ? "" : ", ") + n;
    return make_error("unknown texture variant '" + variant.substr(0, 64) + "' (known: " + names +
                      "; astc_WxH is any ASTC block size, e.g. astc_6x6)");
}

Result<std::vector<std::uint8_t>> encode_image(TextureFormat format, std::uint32_t w, std::uint32_t h,
                                               const std::uint8_t* rgba) {
    const FormatInfo& f = format_info(format);
    const std::size_t n = static_cast<std::size_t>(w) * h;
    switch (f.family) {
    case FormatFamily::uncompressed: {
        std::vector<std::uint8_t> out(n * static_cast<std::size_t>(f.channels));
        for (std::size_t i = 0; i < n; ++i)
            for (int c = 0; c < f.channels; ++c) out[i * f.channels + c] = rgba[i * 4 + c];
        return out;
    }
    case FormatFamily::etc1:
    case FormatFamily::etc2: return encode_etc_rgba8(format, w, h, rgba);
    case FormatFamily::astc: return encode_astc_rgba8(format, w, h, rgba);
    case FormatFamily::pvrtc: return encode_pvrtc_rgba8(format, w, h, rgba);
    case FormatFamily::s3tc: return encode_bc_rgba8(format, w, h, rgba);
    case FormatFamily::eac:
    case FormatFamily::rgtc: {
        std::vector<std::uint16_t> v(n * static_cast<std::size_t>(f.channels));
        for (std::size_t i = 0; i < n; ++i)
            for (int c = 0; c < f.channels; ++c) v[i * f.channels + c] = static_cast<std::uint16_t>(rgba[i * 4 + c] * 257u);
        return encode_image_unorm16(format, w, h, f.channels, v.data());
    }
    }
    return make_error("encode: unhandled format");
}

Result<std::vector<std::uint8_t>> encode_image_unorm16(TextureFormat format, std::uint32_t w, std::uint32_t h,
                                                       int channels, const std::uint16_t* values) {
    const FormatInfo& f = format_info(format);
    const std::size_t n = static_cast<std::size_t>(w) * h;
    if (channels < 1 || channels > 2) return make_error("encode: unorm16 input has 1 or 2 channels");
    if (f.family == FormatFamily::eac || f.family == FormatFamily::rgtc) {
        std::vector<std::uint16_t> v(n * static_cast<std::size_t>(f.channels));
        for (std::size_t i = 0; i < n; ++i)
            for (int c = 0; c < f.channels; ++c)
                v[i * f.channels + c] = values[i * channels + std::min(c, channels - 1)];
        return f.family == FormatFamily::eac ? encode_eac_unorm16(format, w, h, v.data())
                                             : encode_bc_unorm16(format, w, h, v.data());
    }
    // Everything else from 8 bits: one channel becomes grey (height in
    // colour formats), two become R, G with B = 0.
    std::vector<std::uint8_t> rgba(n * 4);
    for (std::size_t i = 0; i < n; ++i) {
        const auto to8 = [](std::uint16_t v) { return static_cast<std::uint8_t>((v * 255u + 32767u) / 65535u); };
        const std::uint8_t r = to8(values[i * channels]);
        const std::uint8_t g = channels > 1 ? to8(values[i * channels + 1]) : r;
        const std::uint8_t b = channels > 1 ? 0 : r;
        rgba[i * 4 + 0] = r;
        rgba[i * 4 + 1] = g;
        rgba[i * 4 + 2] = b;
        rgba[i * 4 + 3] = 255;
    }
    return encode_image(format, w, h, rgba.data());
}

Result<TextureData> encode_height_texture(const HeightField& field, TextureFormat format, bool mipmaps) {
    if (field.width < 1 || field.height < 1) return make_error("encode: empty height field");
    const std::uint32_t w = static_cast<std::uint32_t>(field.width), h = static_cast<std::uint32_t>(field.height);
    // Levels are filtered at 16 bits: an 11-bit format keeps what averaging gains.
    std::vector<std::uint16_t> base(field.texels.size());
    for (std::size_t i = 0; i < base.size(); ++i) {
        const double v = field.texels[i];
        base[i] = !(v > 0.0) ? 0 : static_cast<std::uint16_t>(std::lround(std::min(v, 1.0) * 65535.0));
    }
    reverse_rows(base, w, h, 1);
    std::vector<std::uint16_t> level = base;
    std::uint32_t lw = w, lh = h;
    return build_chain(format, w, h, mipmaps, [&](int i, std::uint32_t nw, std::uint32_t nh) {
        if (i > 0) {
            level = downsample<std::uint16_t, std::uint64_t>(level, lw, lh, 1, nw, nh);
            lw = nw;
            lh = nh;
        }
        return encode_image_unorm16(format, nw, nh, 1, level.data());
    });
}

Result<TextureData> encode_normal_texture(const Image& normal, TextureFormat format, bool mipmaps) {
    if (format_info(format).channels < 2)
        return make_error(std::string("a normal map needs two or more channels; ") + format_name(format) + " has one");
    if (normal.width < 1 || normal.height < 1 || normal.channels != 4) return make_error("encode: normal map must be RGBA8");
    const std::uint32_t w = static_cast<std::uint32_t>(normal.width), h = static_cast<std::uint32_t>(normal.height);
    std::vector<std::uint8_t> level = normal.pixels;
    reverse_rows(level, w, h, 4);
    std::uint32_t lw = w, lh = h;
    const bool two = format_info(format).channels == 2;
    return build_chain(format, w, h, mipmaps, [&](int i, std::uint32_t nw, std::uint32_t nh) {
        if (i > 0) {
            level = downsample<std::uint8_t, std::uint32_t>(level, lw, lh, 4, nw, nh);
            lw = nw;
            lh = nh;
            // Averaged normals are shorter: make each unit length again.
            for (std::size_t k = 0; k < level.size(); k += 4) {
                double x = level[k] / 127.5 - 1.0, y = level[k + 1] / 127.5 - 1.0, z = level[k + 2] / 127.5 - 1.0;
                const double len = std::sqrt(x * x + y * y + z * z);
                if (len > 1e-6) {
                    x /= len;
                    y /= len;
                    z /= len;
                }
                level[k] = to_unorm8(x * 0.5 + 0.5);
                level[k + 1] = to_unorm8(y * 0.5 + 0.5);
                level[k + 2] = to_unorm8(z * 0.5 + 0.5);
            }
        }
        std::vector<std::uint8_t> rgba = level;
        for (std::size_t k = 0; k < rgba.size(); k += 4) {
            if (two) rgba[k + 2] = 0;  // x, y only: z is reconstructed
            rgba[k + 3] = 255;
        }
        return encode_image(format, nw, nh, rgba.data());
    });
}

Result<TextureData> encode_color_texture(const Image& rgba, TextureFormat format, bool mipmaps, bool srgb) {
    if (rgba.width < 1 || rgba.height < 1 || rgba.channels != 4) return make_error("encode: colour image must be RGBA8");
    const std::uint32_t w = static_cast<std::uint32_t>(rgba.width), h = static_cast<std::uint32_t>(rgba.height);
    std::vector<std::uint8_t> level = rgba.pixels;
    reverse_rows(level, w, h, 4);
    std::uint32_t lw = w, lh = h;
    return build_chain(format, w, h, mipmaps, [&](int i, std::uint32_t nw, std::uint32_t nh) {
        if (i > 0 && srgb) {
            // sRGB colour: each level averages light, not code values.
            Image above;
            above.width = static_cast<int>(lw);
            above.height = static_cast<int>(lh);
            above.channels = 4;
            above.pixels = std::move(level);
            level = next_mip_level(above, true).pixels;
            lw = nw;
            lh = nh;
        } else if (i > 0) {
            level = downsample<std::uint8_t, std::uint32_t>(level, lw, lh, 4, nw, nh);
            lw = nw;
            lh = nh;
        }
        return encode_image(format, nw, nh, level.data());
    });
}

}  // namespace px
