// PVR v3 reader and writer (texture/containers.h), after Imagination's
// "PowerVR Texture Container File Format" 3.0: a 52-byte little-endian
// header (version 0x03525650, flags, a 64-bit pixel format, colour space,
// channel type, height, width, depth, surfaces, faces, MIP map count,
// metadata size), the metadata, then for each MIP level, for each surface
// (array layer), for each face, the image's depth slices. That order is
// TextureData's (per level: layer-major, faces within a layer), so the
// image data is copied as one block once every size has been checked.
#include <cstring>
#include <string>

#include "parallaxes/core/limits.h"
#include "parallaxes/texture/containers.h"
#include "container_shape.h"

namespace px {

namespace {

constexpr std::size_t kHeaderBytes = 52;
constexpr std::uint32_t kVersion = 0x03525650u;         // "PVR\x03"
constexpr std::uint32_t kVersionSwapped = 0x50565203u;  // the same, other endianness
constexpr std::uint32_t kMaxLayers = kMaxTextureLayers;

std::uint32_t rd32(const std::uint8_t* p) {
    return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
           static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}
void put32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
std::string num(std::uint64_t v) { return std::to_string(v); }
std::string hex(std::uint64_t v) { return hex_code(v); }

// The PVR v3 pixel format of an uncompressed format: channel letters in the
// low four bytes, bits per channel in the high four.
std::uint64_t pvr_pixel_format(const FormatInfo& f) {
    if (f.compressed()) return f.pvr_format;
    static const char letters[4] = {'r', 'g', 'b', 'a'};
    std::uint64_t v = 0;
    for (int i = 0; i < f.channels; ++i) {
        v |= static_cast<std::uint64_t>(static_cast<unsigned char>(letters[i])) << (8 * i);
        v |= std::uint64_t{8} << (32 + 8 * i);
    }
    return v;
}

}  // namespace

Result<TextureData> container_detail::read_pvr3(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes,
                                             TextureShape* header_only) {
    const std::string c = "PVR v3 ";
    if (size < kHeaderBytes)
        return make_error(c + "header: the file has " + num(size) + " bytes, fewer than the 52-byte header");
    const std::uint32_t version = rd32(bytes);
    if (version == kVersionSwapped)
        return make_error(c + "version 0x50565203: the file was written in the other (big-endian) byte order, "
                          "which is not supported");
    if (version != kVersion)
        return make_error(c + "version " + hex(version) + " is not 0x03525650 (\"PVR\\x03\")");
    const std::uint64_t pixel_format =
        static_cast<std::uint64_t>(rd32(bytes + 8)) | static_cast<std::uint64_t>(rd32(bytes + 12)) << 32;
    const std::uint32_t colour_space = rd32(bytes + 16), channel_type = rd32(bytes + 20), height = rd32(bytes + 24),
                        width = rd32(bytes + 28), depth = rd32(bytes + 32), surfaces = rd32(bytes + 36),
                        faces = rd32(bytes + 40), mip_count = rd32(bytes + 44), meta_size = rd32(bytes + 48);
    if (colour_space != 0 && colour_space != 1)
        return make_error(c + "colour space " + num(colour_space) + " is not 0 (linear) or 1 (sRGB)");
    // 0xFFFFFFFF is the format table's "no PVR code" marker (bc1_rgba has
    // it), not a pixel format: format_from_pvr would match it.
    if (pixel_format == 0xFFFFFFFFu)
        return make_error(c + "pixel format 4294967295 is not a supported texture format");
    const Result<TextureFormat> fmt = format_from_pvr(pixel_format, channel_type);
    if (!fmt) return make_error(c + fmt.error().message);
    const TextureFormat format = *fmt;
    const std::uint32_t max = static_cast<std::uint32_t>(kMaxTextureSize);
    if (width == 0 || width > max) return make_error(c + "width " + num(width) + " is outside 1.." + num(max));
    if (height == 0 || height > max) return make_error(c + "height " + num(height) + " is outside 1.." + num(max));
    if (depth > 1) return make_error(c + "depth " + num(depth) + ": a 3D texture, which is not supported (must be 1)");
    if (surfaces == 0 || surfaces > kMaxLayers)
        return make_error(c + "numSurfaces " + num(surfaces) + " is outside 1.." + num(kMaxLayers));
    if (faces != 1 && faces != 6) return make_error(c + "numFaces " + num(faces) + " (must be 1 or 6)");
    if (faces == 6 && width != height)
        return make_error(c + "numFaces 6 with a " + num(width) + "x" + num(height) +
                          " base: cube map faces must be square");
    const int chain = full_mip_count(width, height);
    if (mip_count == 0) return make_error(c + "MIPMapCount 0 (must be at least 1, the base level)");
    if (mip_count > static_cast<std::uint32_t>(chain))
        return make_error(c + "MIPMapCount " + num(mip_count) + " is more than the " +
                          num(static_cast<std::uint64_t>(chain)) + " levels of a " + num(width) + "x" + num(height) +
                          " texture's full chain");
    if (header_only) {
        *header_only = TextureShape{ContainerKind::pvr3, format, width, height, surfaces, faces, mip_count, 0};
        return TextureData{};
    }
    if (meta_size > size - kHeaderBytes)
        return make_error(c + "metaDataSize " + num(meta_size) + " passes the end of the " + num(size) +
                          "-byte file (" + num(size - kHeaderBytes) + " bytes follow the header)");
    // Metadata: blocks of FourCC, key, dataSize, data. Orientation is FourCC
    // "PVR" 3, key 3, three bytes (x, y, z): y nonzero means y increases
    // upwards (bottom row first). Without it, PVRTexToolCLI's default: top
    // row first (x right, y down).
    RowOrder rows = RowOrder::top_first;
    std::string rows_source = "no PVR v3 orientation metadata: top row first, the PVRTexTool default";
    for (std::uint64_t m = kHeaderBytes, end = kHeaderBytes + std::uint64_t{meta_size}; m < end;) {
        const std::string at = c + "metadata block at byte " + num(m);
        if (end - m < 12) return make_error(at + ": its 12-byte header passes the end of the metadata");
        const std::uint32_t fourcc = rd32(bytes + m), key = rd32(bytes + m + 4), data_size = rd32(bytes + m + 8);
        if (data_size > end - m - 12)
            return make_error(at + ": dataSize " + num(data_size) + " passes the end of the " + num(meta_size) +
                              "-byte metadata");
        if (fourcc == kVersion && key == 3) {
            if (data_size < 2) return make_error(at + ": orientation data of " + num(data_size) + " bytes (must be 3)");
            const bool up = bytes[m + 12 + 1] != 0;
            rows = up ? RowOrder::bottom_first : RowOrder::top_first;
            rows_source = std::string("PVR v3 orientation metadata (y ") + (up ? "up" : "down") + ")";
        }
        m += 12 + std::uint64_t{data_size};
    }
    std::uint64_t pos = kHeaderBytes + std::uint64_t{meta_size};
    const std::uint64_t images = std::uint64_t{surfaces} * faces;
    const std::uint64_t data_start = pos;
    for (std::uint32_t i = 0; i < mip_count; ++i) {
        const std::uint32_t w = mip_extent(width, static_cast<int>(i)), h = mip_extent(height, static_cast<int>(i));
        const std::uint64_t level = *image_bytes(format, w, h) * images;
        if (pos - data_start + level > max_bytes)
            return make_error(c + "the texture needs " + num(pos - data_start + level) + "+ bytes, more than the " +
                              num(max_bytes) + " allowed");
        if (level > size - pos)
            return make_error(c + "MIP level [" + num(i) + "] (" + num(w) + "x" + num(h) + " " + format_name(format) +
                              ", " + num(level) + " bytes at byte " + num(pos) + ") passes the end of the " +
                              num(size) + "-byte file");
        pos += level;
    }
    if (pos != size)
        return make_error(c + "the file has " + num(size - pos) + " bytes after the last MIP level (at byte " +
                          num(pos) + " of " + num(size) + ")");
    Result<TextureData> made = out_of_memory_is_an_error(c + "texture", [&] {
        return allocate_texture(format, width, height, static_cast<int>(mip_count), surfaces, faces, max_bytes);
    });
    if (!made) return make_error(c + made.error().message);
    TextureData t = std::move(made.value());
    t.container = ContainerKind::pvr3;
    t.rows = rows;
    t.rows_source = rows_source;
    t.srgb = colour_space == 1;
    if (t.srgb) t.color_space_source = "PVR v3 colour space 1 (sRGB)";
    if (t.bytes.size() != pos - data_start) return make_error(c + "internal: level sizes disagree");
    std::memcpy(t.bytes.data(), bytes + data_start, t.bytes.size());
    return t;
}

Result<std::vector<std::uint8_t>> write_pvr3(const TextureData& t) {
    const std::string c = "PVR v3 ";
    const FormatInfo& info = format_info(t.format);
    if (info.compressed() && info.pvr_format == 0xFFFFFFFFu)
        return make_error(c + "writer: " + info.name + " has no PVR v3 pixel format");
    Status layout = check_texture_layout(t);
    if (!layout) return make_error(c + "writer: " + layout.error().message);
    return out_of_memory_is_an_error(c + "writer", [&]() -> Result<std::vector<std::uint8_t>> {
        std::vector<std::uint8_t> out;
        out.reserve(kHeaderBytes + t.bytes.size());
        const std::uint64_t pf = pvr_pixel_format(info);
        put32(out, kVersion);
        put32(out, 0);  // flags
        put32(out, static_cast<std::uint32_t>(pf));
        put32(out, static_cast<std::uint32_t>(pf >> 32));
        put32(out, t.srgb ? 1 : 0);  // colour space: linear or sRGB
        put32(out, 0);  // channel type: unsigned byte, normalised
        put32(out, t.height);
        put32(out, t.width);
        put32(out, 1);  // depth
        put32(out, t.layers);
        put32(out, t.faces);
        put32(out, static_cast<std::uint32_t>(t.levels.size()));
        // Orientation metadata: x right, y down or up, z in.
        put32(out, 15);
        put32(out, kVersion);
        put32(out, 3);
        put32(out, 3);
        out.push_back(0);
        out.push_back(t.rows == RowOrder::bottom_first ? 2 : 0);
        out.push_back(0);
        out.insert(out.end(), t.bytes.begin(), t.bytes.end());
        return out;
    });
}

Result<TextureData> read_pvr3(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes) {
    return container_detail::read_pvr3(bytes, size, max_bytes, nullptr);
}

}  // namespace px
