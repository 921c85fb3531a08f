// astcenc's native .astc file (texture/containers.h read_astc).
#include <cstring>
#include <string>

#include "parallaxes/core/limits.h"
#include "parallaxes/texture/containers.h"
#include "container_shape.h"

namespace px {

namespace {

constexpr std::size_t kHeaderBytes = 16;

std::uint32_t rd24(const std::uint8_t* p) {
    return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
           static_cast<std::uint32_t>(p[2]) << 16;
}

std::string num(std::uint64_t v) { return std::to_string(v); }

}  // namespace

Result<TextureData> container_detail::read_astc(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes,
                                             TextureShape* header_only) {
    const std::string c = ".astc ";
    if (!bytes || size < kHeaderBytes)
        return make_error(c + "file of " + num(bytes ? size : 0) + " bytes is shorter than its 16-byte header");
    if (!(bytes[0] == 0x13 && bytes[1] == 0xAB && bytes[2] == 0xA1 && bytes[3] == 0x5C))
        return make_error(c + "magic is not 0x5CA1AB13");
    const std::uint32_t bx = bytes[4], by = bytes[5], bz = bytes[6];
    const std::uint32_t width = rd24(bytes + 7), height = rd24(bytes + 10), depth = rd24(bytes + 13);
    if (bz != 1 || depth != 1)
        return make_error(c + "block " + num(bx) + "x" + num(by) + "x" + num(bz) + ", depth " + num(depth) +
                          ": a 3D texture, which is not supported (block z and depth must be 1)");
    const FormatInfo* format = nullptr;
    for (const FormatInfo& f : all_formats())
        if (f.family == FormatFamily::astc && f.block_width == static_cast<int>(bx) &&
            f.block_height == static_cast<int>(by))
            format = &f;
    if (!format)
        return make_error(c + "block size " + num(bx) + "x" + num(by) +
                          " is not an ASTC 2D block size (4x4 to 12x12, as KHR_texture_compression_astc_ldr lists)");
    const std::uint32_t max = static_cast<std::uint32_t>(kMaxTextureSize);
    if (width == 0 || width > max) return make_error(c + "width " + num(width) + " is outside 1.." + num(max));
    if (height == 0 || height > max) return make_error(c + "height " + num(height) + " is outside 1.." + num(max));
    if (header_only) {
        *header_only = TextureShape{ContainerKind::astc, format->format, width, height, 1, 1, 1, 0};
        return TextureData{};
    }
    const std::optional<std::uint64_t> need = image_bytes(format->format, width, height);
    if (!need || *need > max_bytes)
        return make_error(c + "the texture needs more than the " + num(max_bytes) + " bytes allowed");
    if (size - kHeaderBytes != *need)
        return make_error(c + num(width) + "x" + num(height) + " " + format->name + " takes " + num(*need) +
                          " bytes of blocks; the file has " + num(size - kHeaderBytes) + " after its header");
    Result<TextureData> made = out_of_memory_is_an_error(c + "texture", [&] {
        return allocate_texture(format->format, width, height, 1, 1, 1, max_bytes);
    });
    if (!made) return make_error(c + made.error().message);
    TextureData t = std::move(made.value());
    t.container = ContainerKind::astc;
    t.rows = RowOrder::top_first;
    t.rows_source = ".astc declares none: top row first, as astcenc writes and decodes it";
    std::memcpy(t.bytes.data(), bytes + kHeaderBytes, t.bytes.size());
    return t;
}

Result<TextureData> read_astc(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes) {
    return container_detail::read_astc(bytes, size, max_bytes, nullptr);
}

}  // namespace px
