// Texture files by their identifier (texture/containers.h).
#include <cctype>
#include <cstring>
#include <optional>
#include <string>

#include "parallaxes/core/files.h"
#include "parallaxes/core/limits.h"
#include "parallaxes/core/text.h"
#include "parallaxes/texture/containers.h"
#include "container_shape.h"

namespace px {

namespace {

constexpr std::uint8_t kKtx1[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31, 0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
constexpr std::uint8_t kKtx2[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
constexpr std::uint8_t kPvr[4] = {0x50, 0x56, 0x52, 0x03};         // 0x03525650 little-endian
constexpr std::uint8_t kPvrSwapped[4] = {0x03, 0x52, 0x56, 0x50};  // the other byte order
constexpr std::uint8_t kAstc[4] = {0x13, 0xAB, 0xA1, 0x5C};         // 0x5CA1AB13 little-endian

bool starts_with(const std::uint8_t* bytes, std::size_t size, const std::uint8_t* id, std::size_t n) {
    return size >= n && std::memcmp(bytes, id, n) == 0;
}

// The first bytes as hex and as text: "AB 4B 54 58 ... (\"?KTX 12?..\")".
std::string describe_start(const std::uint8_t* bytes, std::size_t size) {
    if (size == 0) return "the data is empty";
    static const char* digits = "0123456789ABCDEF";
    const std::size_t n = size < 12 ? size : 12;
    std::string hex, text;
    for (std::size_t i = 0; i < n; ++i) {
        if (i) hex += ' ';
        hex += digits[bytes[i] >> 4];
        hex += digits[bytes[i] & 15];
        text += std::isprint(bytes[i]) ? static_cast<char>(bytes[i]) : '.';
    }
    std::string s = "the " + std::to_string(size) + "-byte data starts with " + hex + " (\"" + text + "\")";
    if (size >= 8 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0) s += ", a PNG image";
    else if (size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) s += ", a JPEG image";
    else if (size >= 4 && std::memcmp(bytes, "DDS ", 4) == 0) s += ", a DDS file";
    else if (size >= 6 && std::memcmp(bytes, "\xABKTX ", 5) == 0) s += ", a KTX identifier of an unknown version";
    else if (size >= 2 && bytes[0] == 's' && bytes[1] == 'B')
        s += ", a Basis Universal .basis file (transcode it first: `basisu -unpack file.basis` writes KTX 1.1 "
             "files of ETC1, ETC2, ASTC, BC1 to BC5 and PVRTC)";
    return s;
}

}  // namespace

ContainerKind sniff_container(const std::uint8_t* bytes, std::size_t size) {
    if (!bytes) return ContainerKind::image;
    if (starts_with(bytes, size, kKtx1, sizeof kKtx1)) return ContainerKind::ktx1;
    if (starts_with(bytes, size, kKtx2, sizeof kKtx2)) return ContainerKind::ktx2;
    // Either byte order: the reader refuses the other one by name.
    if (starts_with(bytes, size, kPvr, sizeof kPvr) || starts_with(bytes, size, kPvrSwapped, sizeof kPvrSwapped))
        return ContainerKind::pvr3;
    if (starts_with(bytes, size, kAstc, sizeof kAstc)) return ContainerKind::astc;
    return ContainerKind::image;
}

Result<TextureData> read_texture(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes) {
    if (!bytes) size = 0;
    switch (sniff_container(bytes, size)) {
    case ContainerKind::ktx1: return read_ktx1(bytes, size, max_bytes);
    case ContainerKind::ktx2: return read_ktx2(bytes, size, max_bytes);
    case ContainerKind::pvr3: return read_pvr3(bytes, size, max_bytes);
    case ContainerKind::astc: return read_astc(bytes, size, max_bytes);
    case ContainerKind::image: break;
    }
    return make_error("not a texture container: " + describe_start(bytes, size) +
                      "; the containers read are KTX 1.1 (\\xABKTX 11\\xBB), KTX 2.0 (\\xABKTX 20\\xBB), PVR v3 "
                      "(PVR\\x03) and astcenc's .astc (13 AB A1 5C)");
}

Result<TextureShape> read_texture_shape(const std::uint8_t* bytes, std::size_t size) {
    if (!bytes) size = 0;
    TextureShape shape;
    const auto header = [&](auto reader) -> Status {
        Result<TextureData> r = reader(bytes, size, 0, &shape);
        if (!r) return r.error();
        return {};
    };
    Status read;
    switch (sniff_container(bytes, size)) {
    case ContainerKind::ktx1: read = header(container_detail::read_ktx1); break;
    case ContainerKind::ktx2: read = header(container_detail::read_ktx2); break;
    case ContainerKind::pvr3: read = header(container_detail::read_pvr3); break;
    case ContainerKind::astc: read = header(container_detail::read_astc); break;
    case ContainerKind::image: return read_texture(bytes, size).error();  // its "not a texture container" error
    }
    if (!read) return read.error();
    // What it decodes to, from the block arithmetic: at most 4096 x 4096
    // x 16 bytes per level image, times at most 2048 layers x 6 faces x 13
    // levels, far inside 64 bits.
    for (std::uint32_t level = 0; level < shape.levels; ++level) {
        const std::optional<std::uint64_t> one = image_bytes(shape.format, mip_extent(shape.width, static_cast<int>(level)),
                                                            mip_extent(shape.height, static_cast<int>(level)));
        if (!one) return make_error(std::string(container_name(shape.container)) + ": level " + std::to_string(level) +
                                    " has no size in " + format_name(shape.format));
        shape.bytes += *one * shape.layers * shape.faces;
    }
    return shape;
}

Result<TextureShape> read_texture_file_shape(const std::string& path) {
    Result<std::vector<std::uint8_t>> head = read_file_prefix(path, kTextureHeaderBytes, "texture file");
    if (!head) return head.error();
    Result<TextureShape> shape = read_texture_shape(head->data(), head->size());
    if (!shape) return with_context(echo_path(path), shape.error());
    return shape;
}

Result<TextureData> read_texture_file(const std::string& path, std::uint64_t max_bytes) {
    // read_file_bounded checks for a regular file and the size before reading,
    // and names the path in its errors.
    Result<std::vector<std::uint8_t>> file = read_file_bounded(path, kMaxImageFileBytes, "texture file");
    if (!file) return file.error();
    Result<TextureData> t = read_texture(file->data(), file->size(), max_bytes);
    if (!t) return with_context(echo_path(path), t.error());
    return t;
}

}  // namespace px
