#include "parallaxes/texture/decode.h"

#include <algorithm>
#include <string>

#include "parallaxes/texture/codecs.h"

namespace px {

namespace {

Status check_image(const TextureData& t, std::size_t level, std::uint32_t layer, std::uint32_t face) {
    if (level >= t.levels.size())
        return make_error("level " + std::to_string(level) + " of a texture with " + std::to_string(t.levels.size()) +
                          " levels");
    if (layer >= t.layers || face >= t.faces) return make_error("layer or face past the texture's");
    const TextureLevel& l = t.levels[level];
    const auto expected = image_bytes(t.format, l.width, l.height);
    if (!expected || *expected != l.image_bytes)
        return make_error(std::string("level ") + std::to_string(level) + " holds " + std::to_string(l.image_bytes) +
                          " bytes, not what a " + format_name(t.format) + " image of its size needs");
    const std::size_t images = static_cast<std::size_t>(t.layers) * t.faces;
    if (l.offset > t.bytes.size() || (t.bytes.size() - l.offset) / images < l.image_bytes)
        return make_error("level " + std::to_string(level) + " passes the end of the texture's data");
    return {};
}

}  // namespace

int height_bits(TextureFormat format) { return format_info(format).channel_bits; }

Result<Image> decode_rgba8(const TextureData& t, std::size_t level, std::uint32_t layer, std::uint32_t face) {
    Status ok = check_image(t, level, layer, face);
    if (!ok) return ok.error();
    const TextureLevel& l = t.levels[level];
    Image out;
    out.width = static_cast<int>(l.width);
    out.height = static_cast<int>(l.height);
    out.channels = 4;
    out.pixels.assign(static_cast<std::size_t>(l.width) * l.height * 4, 0);
    const std::uint8_t* data = t.image(level, layer, face);
    const FormatInfo& f = format_info(t.format);
    Status s;
    switch (f.family) {
    case FormatFamily::uncompressed: {
        const std::size_t n = static_cast<std::size_t>(l.width) * l.height;
        for (std::size_t i = 0; i < n; ++i) {
            std::uint8_t* o = &out.pixels[i * 4];
            const std::uint8_t* p = data + i * static_cast<std::size_t>(f.channels);
            o[0] = p[0];
            o[1] = f.channels > 1 ? p[1] : 0;
            o[2] = f.channels > 2 ? p[2] : 0;
            o[3] = f.channels > 3 ? p[3] : 255;
        }
        break;
    }
    case FormatFamily::etc1:
    case FormatFamily::etc2:
    case FormatFamily::eac:
        s = decode_etc_rgba8(t.format, l.width, l.height, data, l.image_bytes, out.pixels.data());
        break;
    case FormatFamily::astc:
        s = decode_astc_rgba8(t.format, l.width, l.height, data, l.image_bytes, out.pixels.data());
        break;
    case FormatFamily::pvrtc:
        s = decode_pvrtc_rgba8(t.format, l.width, l.height, data, l.image_bytes, out.pixels.data());
        break;
    case FormatFamily::s3tc:
    case FormatFamily::rgtc:
        s = decode_bc_rgba8(t.format, l.width, l.height, data, l.image_bytes, out.pixels.data());
        break;
    }
    if (!s) return s.error();
    return out;
}

Result<std::vector<std::uint16_t>> decode_unorm16(const TextureData& t, int channels, std::size_t level) {
    if (channels < 1 || channels > 2) return make_error("decode_unorm16: 1 or 2 channels");
    Status ok = check_image(t, level, 0, 0);
    if (!ok) return ok.error();
    const TextureLevel& l = t.levels[level];
    const std::size_t n = static_cast<std::size_t>(l.width) * l.height;
    std::vector<std::uint16_t> out(n * static_cast<std::size_t>(channels), 0);
    const FormatInfo& f = format_info(t.format);
    const std::uint8_t* data = t.image(level);
    auto take = [&](const std::uint16_t* values, int have) {
        for (std::size_t i = 0; i < n; ++i)
            for (int c = 0; c < channels; ++c)
                out[i * channels + c] = c < have ? values[i * static_cast<std::size_t>(have) + c] : 0;
    };
    if (t.format == TextureFormat::eac_r11 || t.format == TextureFormat::eac_rg11 || t.format == TextureFormat::bc4 ||
        t.format == TextureFormat::bc5) {
        const int have = f.channels;
        std::vector<std::uint16_t> all(n * static_cast<std::size_t>(have));
        Status s = f.family == FormatFamily::eac
                       ? decode_eac_unorm16(t.format, l.width, l.height, data, l.image_bytes, all.data())
                       : decode_bc_unorm16(t.format, l.width, l.height, data, l.image_bytes, all.data());
        if (!s) return s.error();
        take(all.data(), have);
        return out;
    }
    Result<Image> rgba = decode_rgba8(t, level);
    if (!rgba) return rgba.error();
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < channels; ++c)
            out[i * channels + c] = static_cast<std::uint16_t>(rgba->pixels[i * 4 + c] * 257u);
    return out;
}

Result<HeightField> height_field_from_texture(const TextureData& t, HeightConvention convention) {
    if (t.levels.empty()) return make_error("the texture has no levels");
    HeightField field;
    field.width = static_cast<int>(t.levels[0].width);
    field.height = static_cast<int>(t.levels[0].height);
    const std::size_t n = static_cast<std::size_t>(field.width) * field.height;
    field.texels.resize(n);
    if (height_bits(t.format) == 11) {
        Result<std::vector<std::uint16_t>> v = decode_unorm16(t, 1);
        if (!v) return v.error();
        for (std::size_t i = 0; i < n; ++i) {
            const float h = static_cast<float>((*v)[i] >> 5) / 2047.0f;  // the 11 bits back
            field.texels[i] = convention == HeightConvention::depth ? 1.0f - h : h;
        }
        return field;
    }
    Result<Image> rgba = decode_rgba8(t);
    if (!rgba) return rgba.error();
    for (std::size_t i = 0; i < n; ++i) {
        const float h = static_cast<float>(rgba->pixels[i * 4]) / 255.0f;
        field.texels[i] = convention == HeightConvention::depth ? 1.0f - h : h;
    }
    return field;
}

TextureData texture_from_image(const Image& image) {
    TextureData t;
    t.container = ContainerKind::image;
    static const TextureFormat by_channels[] = {TextureFormat::r8, TextureFormat::rg8, TextureFormat::rgb8,
                                                TextureFormat::rgba8};
    t.format = by_channels[std::clamp(image.channels, 1, 4) - 1];
    t.width = static_cast<std::uint32_t>(image.width);
    t.height = static_cast<std::uint32_t>(image.height);
    TextureLevel l;
    l.width = t.width;
    l.height = t.height;
    l.image_bytes = image.pixels.size();
    t.levels.push_back(l);
    t.bytes = image.pixels;
    return t;
}

}  // namespace px
