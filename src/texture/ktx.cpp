// KTX 1.1 and KTX 2.0 readers and writers (texture/containers.h).
//
// KTX 1.1 (Khronos, "KTX File Format Specification" 1.1): a 12-byte
// identifier, thirteen uint32 header fields, the key/value data, then per
// mip level a uint32 imageSize followed by the level's images (for a
// non-array cube map imageSize is one face's size and each face is padded
// to 4 bytes; otherwise it covers every layer and face), then mipPadding
// to 4 bytes. Uncompressed rows are padded to 4 bytes (GL_UNPACK_ALIGNMENT
// 4): the reader strips that padding, the writer adds it, so TextureData
// always holds tightly packed rows.
//
// KTX 2.0 (Khronos, "KTX File Format Specification" 2.0): identifier,
// nine uint32 fields, the index (DFD, key/value data, supercompression
// global data), the level index (level 0 = base first; the data in the file
// is stored smallest level first), and the level data, uncompressed or
// Zstandard-compressed per level.
//
// Every size and offset is checked in 64-bit arithmetic that cannot wrap
// (`fits`) against the file's size and against the block arithmetic before
// anything is allocated.
#ifndef PX_NO_ZSTD
#include <zstd.h>
#else
#include <cstddef>
// A build without libzstd (the web build): supercompressed KTX 2.0 files are
// refused with this message, uncompressed ones read as ever.
namespace {
constexpr std::size_t kNoZstd = ~std::size_t{0};
std::size_t ZSTD_decompress(void*, std::size_t, const void*, std::size_t) { return kNoZstd; }
std::size_t ZSTD_compressBound(std::size_t n) { return n; }
std::size_t ZSTD_compress(void*, std::size_t, const void*, std::size_t, int) { return kNoZstd; }
bool ZSTD_isError(std::size_t code) { return code == kNoZstd; }
const char* ZSTD_getErrorName(std::size_t) { return "Zstandard is not in this build (built without libzstd: the web build)"; }
}  // namespace
#endif

#include <algorithm>
#include <cctype>
#include <cstring>
#include <string>

#include "parallaxes/core/limits.h"
#include "parallaxes/core/text.h"
#include "parallaxes/texture/codecs.h"
#include "parallaxes/texture/containers.h"
#include "container_shape.h"

namespace px {

namespace {

constexpr std::uint8_t kKtx1Identifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31,
                                              0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
constexpr std::uint8_t kKtx2Identifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32,
                                              0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
constexpr std::size_t kKtx1HeaderBytes = 64;
constexpr std::size_t kKtx2HeaderBytes = 80;  // header and index, before the level index
constexpr std::uint32_t kMaxLayers = kMaxTextureLayers;

std::uint32_t rd32(const std::uint8_t* p) {
    return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
           static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}
std::uint64_t rd64(const std::uint8_t* p) {
    return static_cast<std::uint64_t>(rd32(p)) | static_cast<std::uint64_t>(rd32(p + 4)) << 32;
}
void put32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void set32(std::vector<std::uint8_t>& out, std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
}
void set64(std::vector<std::uint8_t>& out, std::size_t at, std::uint64_t v) {
    set32(out, at, static_cast<std::uint32_t>(v));
    set32(out, at + 4, static_cast<std::uint32_t>(v >> 32));
}
void pad_to(std::vector<std::uint8_t>& out, std::size_t alignment) {
    while (out.size() % alignment) out.push_back(0);
}

// [offset, offset + length) lies inside `size` bytes, without wrapping.
bool fits(std::uint64_t offset, std::uint64_t length, std::uint64_t size) {
    return length <= size && offset <= size - length;
}
std::uint64_t align4(std::uint64_t v) { return (v + 3) & ~std::uint64_t{3}; }

std::string num(std::uint64_t v) { return std::to_string(v); }
std::string hex(std::uint64_t v) { return hex_code(v); }

std::string shape(TextureFormat format, std::uint32_t w, std::uint32_t h, std::uint32_t layers,
                  std::uint32_t faces) {
    std::string s = num(w) + "x" + num(h) + " " + format_name(format);
    if (layers > 1) s += " x " + num(layers) + " layers";
    if (faces > 1) s += " x " + num(faces) + " faces";
    return s;
}

// Extents, layers, faces and levels as a header gives them, named by the
// container's field names. Leaves the layer count (0 -> 1) in `layers`.
struct ShapeFields {
    const char* width;
    const char* height;
    const char* depth;
    const char* layers;
    const char* faces;
    const char* levels;
};

Status check_shape(const std::string& c, const ShapeFields& n, std::uint32_t w, std::uint32_t h, std::uint32_t d,
                   std::uint32_t& layers, std::uint32_t faces, std::uint32_t levels) {
    const std::uint32_t max = static_cast<std::uint32_t>(kMaxTextureSize);
    if (w == 0 || w > max)
        return make_error(c + n.width + " " + num(w) + " is outside 1.." + num(max));
    if (h == 0)
        return make_error(c + n.height + " 0: a 1D texture, which is not supported (must be 1.." + num(max) + ")");
    if (h > max) return make_error(c + n.height + " " + num(h) + " is outside 1.." + num(max));
    if (d > 1) return make_error(c + n.depth + " " + num(d) + ": a 3D texture, which is not supported (must be 0 or 1)");
    if (layers > kMaxLayers)
        return make_error(c + n.layers + " " + num(layers) + " is more than the " + num(kMaxLayers) + " supported");
    if (layers == 0) layers = 1;
    if (faces != 1 && faces != 6) return make_error(c + n.faces + " " + num(faces) + " (must be 1 or 6)");
    if (faces == 6 && w != h)
        return make_error(c + n.faces + " 6 with a " + num(w) + "x" + num(h) + " base: cube map faces must be square");
    if (levels == 0)
        return make_error(c + n.levels + " 0 asks for the mip chain to be generated, which is not supported "
                          "(levels are used as the file gives them)");
    const int chain = full_mip_count(w, h);
    if (levels > static_cast<std::uint32_t>(chain))
        return make_error(c + n.levels + " " + num(levels) + " is more than the " + num(static_cast<std::uint64_t>(chain)) +
                          " levels of a " + num(w) + "x" + num(h) + " texture's full chain");
    return {};
}

// A writer's input: the layout texture_data.h describes, exactly.
Status check_writable(const TextureData& t, const std::string& c) {
    Status layout = check_texture_layout(t);
    if (!layout) return make_error(c + "writer: " + layout.error().message);
    return {};
}

// The row order a KTXorientation value declares: KTX 1.1 "S=r,T=d" (T=u:
// bottom row first; an R= part for 3D textures may follow), KTX 2.0 "rd"
// ("ru"; a third letter for 3D). Errors name the value.
Result<RowOrder> orientation_rows(const std::string& c, const std::string& value, bool ktx2) {
    const std::string shown = "KTXorientation \"" + echo(value) + "\"";
    char t = 0;
    if (ktx2) {
        if (value.size() >= 2 && (value[0] == 'r' || value[0] == 'l')) t = value[1];
    } else {
        const std::size_t at = value.find("T=");
        if (at != std::string::npos && at + 2 < value.size()) t = value[at + 2];
    }
    if (t == 'd') return RowOrder::top_first;
    if (t == 'u') return RowOrder::bottom_first;
    return make_error(c + shown + " is not an orientation this reader knows (" +
                      (ktx2 ? "\"rd\" or \"ru\"" : "\"S=r,T=d\" or \"S=r,T=u\"") + ")");
}

bool same_key(const char* text, std::size_t length, const char* key) {
    if (std::strlen(key) != length) return false;
    for (std::size_t i = 0; i < length; ++i)
        if (std::tolower(static_cast<unsigned char>(text[i])) != std::tolower(static_cast<unsigned char>(key[i])))
            return false;
    return true;
}

// One key/value block (KTX 1.1 and 2.0 lay it out alike: a uint32 length,
// the NUL-terminated key and the value, padding to 4). KTXorientation, in
// any case (PVRTexToolCLI writes "KTXOrientation"), sets `rows`.
Status read_key_values(const std::string& c, const std::uint8_t* kv, std::uint64_t length, std::uint64_t base,
                       bool ktx2, RowOrder& rows, std::string& rows_source) {
    std::uint64_t pos = 0;
    for (std::uint64_t index = 0; pos < length; ++index) {
        const std::string at = c + "key/value pair [" + num(index) + "] at byte " + num(base + pos);
        if (length - pos < 4)
            return make_error(at + ": its 4-byte keyAndValueByteSize passes the end of the " + num(length) +
                              "-byte key/value data");
        const std::uint64_t n = rd32(kv + pos);
        pos += 4;
        if (n > length - pos)
            return make_error(at + ": keyAndValueByteSize " + num(n) + " passes the end of the " + num(length) +
                              "-byte key/value data (" + num(length - pos) + " bytes left)");
        const char* text = reinterpret_cast<const char*>(kv + pos);
        const void* nul = std::memchr(text, 0, static_cast<std::size_t>(n));
        if (!nul) return make_error(at + ": the key has no NUL terminator within its " + num(n) + " bytes");
        const std::size_t key_len = static_cast<std::size_t>(static_cast<const char*>(nul) - text);
        if (same_key(text, key_len, "KTXorientation")) {
            std::string value(text + key_len + 1, static_cast<std::size_t>(n) - key_len - 1);
            while (!value.empty() && value.back() == '\0') value.pop_back();
            Result<RowOrder> r = orientation_rows(at + ": ", value, ktx2);
            if (!r) return r.error();
            rows = *r;
            rows_source = std::string(text, key_len) + " \"" + echo(value) + "\"";
        }
        // Padding to 4; the last pair's padding may be cut by the block end.
        pos = std::min(length, align4(pos + n));
    }
    return {};
}

std::vector<std::uint8_t> key_value(const std::string& key, const std::string& value) {
    std::vector<std::uint8_t> out;
    const std::uint32_t n = static_cast<std::uint32_t>(key.size() + 1 + value.size() + 1);
    put32(out, n);
    out.insert(out.end(), key.begin(), key.end());
    out.push_back(0);
    out.insert(out.end(), value.begin(), value.end());
    out.push_back(0);
    pad_to(out, 4);
    return out;
}

// KTX 1.1 bytes of one image in the file: compressed as the block
// arithmetic says, uncompressed with each row padded to 4 bytes.
std::uint64_t ktx1_file_image_bytes(TextureFormat format, std::uint32_t w, std::uint32_t h) {
    const FormatInfo& f = format_info(format);
    if (f.compressed()) return image_bytes(format, w, h).value_or(0);
    return align4(std::uint64_t{w} * static_cast<std::uint64_t>(f.block_bytes)) * h;
}

std::uint32_t gl_base_internal_format(const FormatInfo& f) {
    if (!f.compressed()) return f.gl_format;
    switch (f.channels) {
    case 1: return glenum::kRed;
    case 2: return glenum::kRg;
    case 3: return glenum::kRgb;
    default: return glenum::kRgba;
    }
}

}  // namespace

// ---------------------------------------------------------------- KTX 1.1

Result<TextureData> container_detail::read_ktx1(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes,
                                             TextureShape* header_only) {
    const std::string c = "KTX 1.1 ";
    if (size < kKtx1HeaderBytes)
        return make_error(c + "header: the file has " + num(size) + " bytes, fewer than the 64-byte header");
    if (std::memcmp(bytes, kKtx1Identifier, sizeof kKtx1Identifier) != 0)
        return make_error(c + "identifier: the file does not start with \"\\xABKTX 11\\xBB\\r\\n\\x1A\\n\"");
    const std::uint32_t endianness = rd32(bytes + 12);
    if (endianness == 0x01020304u)
        return make_error(c + "endianness 0x01020304: a big-endian file, which is not supported (convert it to "
                          "little-endian, 0x04030201)");
    if (endianness != 0x04030201u)
        return make_error(c + "endianness " + hex(endianness) + " is neither 0x04030201 (little-endian) nor "
                          "0x01020304 (big-endian)");
    const std::uint32_t gl_type = rd32(bytes + 16), gl_type_size = rd32(bytes + 20), gl_format = rd32(bytes + 24),
                        gl_internal = rd32(bytes + 28), width = rd32(bytes + 36), height = rd32(bytes + 40),
                        depth = rd32(bytes + 44), faces = rd32(bytes + 52), level_count = rd32(bytes + 56),
                        kv_bytes = rd32(bytes + 60);
    std::uint32_t layers = rd32(bytes + 48);
    // An sRGB internal format: the linear format of the same bits, sampled
    // through its sRGB twin (ES 2.0's unsized GL_SRGB(_ALPHA)_EXT are their
    // own glFormat too).
    const std::uint32_t linear_internal = linear_gl_of_srgb(gl_internal);
    const std::string srgb_source =
        linear_internal ? "glInternalFormat " + hex(gl_internal) + " (" + srgb_gl_name(gl_internal) + ")" : std::string();
    const std::uint32_t read_format =
        linear_internal && gl_format == gl_internal ? linear_internal
        : linear_internal && gl_format == 0x8C42 ? glenum::kRgba  // GL_SRGB_ALPHA_EXT as glFormat
        : linear_internal && gl_format == 0x8C40 ? glenum::kRgb
                                                 : gl_format;
    const Result<TextureFormat> fmt =
        format_from_gl(linear_internal ? linear_internal : gl_internal, read_format, gl_type);
    if (!fmt) return make_error(c + fmt.error().message);
    const TextureFormat format = *fmt;
    const FormatInfo& info = format_info(format);
    if (info.compressed()) {
        if (gl_type != 0)
            return make_error(c + "glType " + hex(gl_type) + " with the compressed glInternalFormat " +
                              hex(gl_internal) + " (must be 0)");
        if (gl_format != 0)
            return make_error(c + "glFormat " + hex(gl_format) + " with the compressed glInternalFormat " +
                              hex(gl_internal) + " (must be 0)");
        if (gl_type_size > 1) return make_error(c + "glTypeSize " + num(gl_type_size) + " (must be 1)");
    } else if (gl_type_size != 1) {
        return make_error(c + "glTypeSize " + num(gl_type_size) + " with glType GL_UNSIGNED_BYTE (must be 1)");
    }
    const bool plain_cube = faces == 6 && layers == 0;  // imageSize is one face's
    const ShapeFields names{"pixelWidth",  "pixelHeight",    "pixelDepth",
                            "numberOfArrayElements", "numberOfFaces", "numberOfMipmapLevels"};
    if (Status s = check_shape(c, names, width, height, depth, layers, faces, level_count); !s) return s.error();
    if (header_only) {
        *header_only = TextureShape{ContainerKind::ktx1, format, width, height, layers, faces, level_count, 0};
        return TextureData{};
    }
    if (kv_bytes > size - kKtx1HeaderBytes)
        return make_error(c + "bytesOfKeyValueData " + num(kv_bytes) + " passes the end of the " + num(size) +
                          "-byte file (" + num(size - kKtx1HeaderBytes) + " bytes follow the header)");
    // Without the key: top row first, as astcenc and basisu write (and their
    // decoders show) KTX 1.1 files that declare nothing.
    RowOrder rows = RowOrder::top_first;
    std::string rows_source = "no KTXorientation: top row first, as astcenc and basisu write";
    if (Status s = read_key_values(c, bytes + kKtx1HeaderBytes, kv_bytes, kKtx1HeaderBytes, false, rows, rows_source); !s)
        return s.error();

    // Walk the levels: sizes against the block arithmetic, data against the
    // file's end; remember where each level's first image starts.
    std::uint64_t pos = kKtx1HeaderBytes + std::uint64_t{kv_bytes};
    std::uint64_t total = 0;
    const std::uint64_t images = std::uint64_t{layers} * faces;
    std::vector<std::uint64_t> starts;
    std::vector<std::uint64_t> stored_sizes;  // one image as stored: `one`, or fewer PVRTC blocks
    std::vector<std::string> notes;
    for (std::uint32_t i = 0; i < level_count; ++i) {
        const std::uint32_t w = mip_extent(width, static_cast<int>(i)), h = mip_extent(height, static_cast<int>(i));
        const std::string at = c + "level [" + num(i) + "] (" + shape(format, w, h, layers, faces) + ")";
        const std::uint64_t one = ktx1_file_image_bytes(format, w, h);
        total += *image_bytes(format, w, h) * images;
        if (total > max_bytes)
            return make_error(c + "the texture needs " + num(total) + "+ bytes, more than the " + num(max_bytes) +
                              " allowed");
        if (!fits(pos, 4, size))
            return make_error(at + " imageSize at byte " + num(pos) + " passes the end of the " + num(size) +
                              "-byte file");
        const std::uint64_t image_size = rd32(bytes + pos);
        std::uint64_t stored = one;
        std::uint64_t expected = plain_cube ? one : one * images;
        // A PVRTC1 level under 2 x 2 blocks stored with only the blocks it
        // covers (basisu): accepted, and repeated to the size GL takes.
        if (image_size != expected && info.family == FormatFamily::pvrtc) {
            const std::uint64_t few = pvrtc_stored_bytes(format, w, h);
            if (few != one && image_size == (plain_cube ? few : few * images)) {
                stored = few;
                expected = image_size;
                notes.push_back("level [" + num(i) + "] " + num(w) + "x" + num(h) + ": " + num(few / 8) +
                                " stored PVRTC block(s), repeated to the " + num(one / 8) +
                                " that IMG_texture_compression_pvrtc sizes a level at (at least 2x2 blocks); "
                                "decoding wraps, so the texels are the same");
            }
        }
        if (image_size != expected) {
            std::string why;
            if (info.family == FormatFamily::pvrtc)
                why = " (PVRTC1 levels take at least 2x2 blocks, " + num(one) + " bytes here, or exactly the " +
                      num(pvrtc_stored_bytes(format, w, h)) + " bytes of the blocks the level covers)";
            return make_error(at + " imageSize " + num(image_size) + " does not match the " + num(expected) +
                              " bytes the format's block arithmetic gives" +
                              (plain_cube ? std::string(" for one face") : std::string()) + why);
        }
        pos += 4;
        starts.push_back(pos);
        stored_sizes.push_back(stored);
        const std::uint64_t data = plain_cube ? align4(stored) * 6 : align4(expected);  // cube and mip padding
        if (!fits(pos, data, size))
            return make_error(at + " data of " + num(data) + " bytes at byte " + num(pos) + " passes the end of the " +
                              num(size) + "-byte file");
        pos += data;
    }
    if (pos != size)
        return make_error(c + "the file has " + num(size - pos) + " bytes after the last level (at byte " + num(pos) +
                          " of " + num(size) + ")");

    Result<TextureData> made = out_of_memory_is_an_error(c + "texture", [&] {
        return allocate_texture(format, width, height, static_cast<int>(level_count), layers, faces, max_bytes);
    });
    if (!made) return make_error(c + made.error().message);
    TextureData t = std::move(made.value());
    t.container = ContainerKind::ktx1;
    t.rows = rows;
    t.rows_source = rows_source;
    t.srgb = linear_internal != 0;
    t.color_space_source = srgb_source;
    t.notes = std::move(notes);
    const std::size_t tight_row_unit = static_cast<std::size_t>(info.block_bytes);
    for (std::size_t i = 0; i < t.levels.size(); ++i) {
        const TextureLevel& l = t.levels[i];
        const std::uint64_t one = stored_sizes[i];
        const std::uint64_t stride = plain_cube ? align4(one) : one;
        for (std::uint64_t k = 0; k < images; ++k) {
            const std::uint8_t* src = bytes + starts[i] + k * stride;
            std::uint8_t* dst = t.bytes.data() + l.offset + k * l.image_bytes;
            if (info.family == FormatFamily::pvrtc && one != l.image_bytes) {
                const std::vector<std::uint8_t> padded = pvrtc_pad_level(format, l.width, l.height, src);
                std::memcpy(dst, padded.data(), l.image_bytes);
            } else if (info.compressed()) {
                std::memcpy(dst, src, l.image_bytes);
            } else {
                const std::size_t row = l.width * tight_row_unit;
                const std::size_t file_row = static_cast<std::size_t>(align4(row));
                for (std::uint32_t y = 0; y < l.height; ++y)
                    std::memcpy(dst + y * row, src + y * file_row, row);
            }
        }
    }
    return t;
}

Result<std::vector<std::uint8_t>> write_ktx1(const TextureData& t) {
    const std::string c = "KTX 1.1 ";
    if (Status s = check_writable(t, c); !s) return s.error();
    const FormatInfo& info = format_info(t.format);
    if (t.srgb && srgb_gl_of_linear(info.gl_internal_format) == 0)
        return make_error(c + "writer: " + info.name + " has no sRGB glInternalFormat");
    return out_of_memory_is_an_error(c + "writer", [&]() -> Result<std::vector<std::uint8_t>> {
        std::vector<std::uint8_t> out(kKtx1Identifier, kKtx1Identifier + sizeof kKtx1Identifier);
        const std::vector<std::uint8_t> kv =
            key_value("KTXorientation", t.rows == RowOrder::top_first ? "S=r,T=d" : "S=r,T=u");
        put32(out, 0x04030201u);
        put32(out, info.compressed() ? 0 : glenum::kUnsignedByte);
        put32(out, 1);
        put32(out, info.compressed() ? 0 : info.gl_format);
        put32(out, t.srgb ? srgb_gl_of_linear(info.gl_internal_format) : info.gl_internal_format);
        put32(out, gl_base_internal_format(info));
        put32(out, t.width);
        put32(out, t.height);
        put32(out, 0);
        put32(out, t.layers > 1 ? t.layers : 0);
        put32(out, t.faces);
        put32(out, static_cast<std::uint32_t>(t.levels.size()));
        put32(out, static_cast<std::uint32_t>(kv.size()));
        out.insert(out.end(), kv.begin(), kv.end());
        const bool plain_cube = t.faces == 6 && t.layers == 1;
        const std::size_t images = static_cast<std::size_t>(t.layers) * t.faces;
        for (std::size_t i = 0; i < t.levels.size(); ++i) {
            const TextureLevel& l = t.levels[i];
            const std::uint64_t one = ktx1_file_image_bytes(t.format, l.width, l.height);
            put32(out, static_cast<std::uint32_t>(plain_cube ? one : one * images));
            for (std::size_t k = 0; k < images; ++k) {
                const std::uint8_t* src = t.bytes.data() + l.offset + k * l.image_bytes;
                if (info.compressed()) {
                    out.insert(out.end(), src, src + l.image_bytes);
                } else {
                    const std::size_t row = l.width * static_cast<std::size_t>(info.block_bytes);
                    for (std::uint32_t y = 0; y < l.height; ++y) {
                        out.insert(out.end(), src + y * row, src + (y + 1) * row);
                        pad_to(out, 4);  // rows padded to 4 (the header is 4-aligned)
                    }
                }
                if (plain_cube) pad_to(out, 4);  // cubePadding
            }
            pad_to(out, 4);  // mipPadding
        }
        return out;
    });
}

// ---------------------------------------------------------------- KTX 2.0

namespace {

constexpr std::uint32_t kSchemeNone = 0, kSchemeBasisLz = 1, kSchemeZstd = 2, kSchemeZlib = 3;

struct DfdSample {
    std::uint32_t bit_offset;
    std::uint32_t bit_length;  // bits
    std::uint32_t channel;
    std::uint32_t lower;
    std::uint32_t upper;
};

// A basic data format descriptor block (Khronos Data Format Specification
// 1.3, section 5): colour model, BT.709 primaries, linear or sRGB transfer, the
// texel block's dimensions, bytesPlane0 (0 when supercompressed), and one
// sample per channel (uncompressed) or per compressed sub-block.
std::vector<std::uint8_t> basic_dfd(const FormatInfo& f, bool supercompressed, bool srgb) {
    std::uint32_t model = 1;  // KHR_DF_MODEL_RGBSDA
    std::vector<DfdSample> samples;
    const std::uint32_t all = 0xFFFFFFFFu;
    switch (f.family) {
    case FormatFamily::uncompressed: {
        static const std::uint32_t ids[4] = {0, 1, 2, 15};  // R, G, B, A
        for (int i = 0; i < f.channels; ++i)
            samples.push_back({8u * static_cast<std::uint32_t>(i), 8, ids[i], 0, 255});
        break;
    }
    case FormatFamily::etc1:
        model = 160;
        samples.push_back({0, 64, 0, 0, all});
        break;
    case FormatFamily::etc2:
        model = 161;
        if (f.format == TextureFormat::etc2_rgba8) samples.push_back({0, 64, 15, 0, all});
        samples.push_back({f.format == TextureFormat::etc2_rgba8 ? 64u : 0u, 64, 2, 0, all});
        break;
    case FormatFamily::eac:
        model = 161;
        samples.push_back({0, 64, 0, 0, all});
        if (f.channels == 2) samples.push_back({64, 64, 1, 0, all});
        break;
    case FormatFamily::astc:
        model = 162;
        samples.push_back({0, 128, 0, 0, all});
        break;
    case FormatFamily::pvrtc:
        model = 164;
        samples.push_back({0, 64, 0, 0, all});
        break;
    case FormatFamily::s3tc:
        if (f.format == TextureFormat::bc1_rgb || f.format == TextureFormat::bc1_rgba) {
            model = 128;
            samples.push_back({0, 64, f.format == TextureFormat::bc1_rgba ? 1u : 0u, 0, all});
        } else {
            model = f.format == TextureFormat::bc2 ? 129 : 130;
            samples.push_back({0, 64, 15, 0, all});
            samples.push_back({64, 64, 0, 0, all});
        }
        break;
    case FormatFamily::rgtc:
        model = f.channels == 1 ? 131 : 132;
        samples.push_back({0, 64, 0, 0, all});
        if (f.channels == 2) samples.push_back({64, 64, 1, 0, all});
        break;
    }
    const std::uint32_t block_size = 24 + 16 * static_cast<std::uint32_t>(samples.size());
    std::vector<std::uint8_t> out;
    put32(out, 4 + block_size);                     // dfdTotalSize
    put32(out, 0);                                  // vendorId 0 (Khronos), descriptorType 0 (basic)
    put32(out, 2u | block_size << 16);              // versionNumber 2 (1.3), descriptorBlockSize
    put32(out, model | 1u << 8 | (srgb ? 2u : 1u) << 16);  // colorModel, BT.709 primaries, linear or sRGB, flags 0
    put32(out, static_cast<std::uint32_t>(f.block_width - 1) | static_cast<std::uint32_t>(f.block_height - 1) << 8);
    put32(out, supercompressed ? 0u : static_cast<std::uint32_t>(f.block_bytes));  // bytesPlane0..3
    put32(out, 0);                                  // bytesPlane4..7
    for (const DfdSample& s : samples) {
        put32(out, s.bit_offset | (s.bit_length - 1) << 16 | s.channel << 24);
        put32(out, 0);  // sample position
        put32(out, s.lower);
        put32(out, s.upper);
    }
    return out;
}

std::size_t level_alignment(const FormatInfo& f) {
    // lcm(texel block bytes, 4)
    const std::size_t b = static_cast<std::size_t>(f.block_bytes);
    std::size_t a = b;
    while (a % 4) a += b;
    return a;
}

}  // namespace

Result<TextureData> container_detail::read_ktx2(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes,
                                             TextureShape* header_only) {
    const std::string c = "KTX 2.0 ";
    if (size < kKtx2HeaderBytes)
        return make_error(c + "header: the file has " + num(size) + " bytes, fewer than the 80-byte header and index");
    if (std::memcmp(bytes, kKtx2Identifier, sizeof kKtx2Identifier) != 0)
        return make_error(c + "identifier: the file does not start with \"\\xABKTX 20\\xBB\\r\\n\\x1A\\n\"");
    const std::uint32_t vk_format = rd32(bytes + 12), type_size = rd32(bytes + 16), width = rd32(bytes + 20),
                        height = rd32(bytes + 24), depth = rd32(bytes + 28), faces = rd32(bytes + 36),
                        level_count = rd32(bytes + 40), scheme = rd32(bytes + 44);
    std::uint32_t layers = rd32(bytes + 32);
    // An sRGB vkFormat: the linear format of the same bits, sampled as sRGB.
    const std::uint32_t linear_vk = linear_vk_of_srgb(vk_format);
    const Result<TextureFormat> fmt = format_from_vk(linear_vk ? linear_vk : vk_format);
    if (!fmt) return make_error(c + fmt.error().message);
    const TextureFormat format = *fmt;
    if (type_size != 1)
        return make_error(c + "typeSize " + num(type_size) + " with vkFormat " + num(vk_format) + " (must be 1)");
    const ShapeFields names{"pixelWidth", "pixelHeight", "pixelDepth", "layerCount", "faceCount", "levelCount"};
    if (Status s = check_shape(c, names, width, height, depth, layers, faces, level_count); !s) return s.error();
    if (scheme == kSchemeBasisLz)
        return make_error(c + "supercompressionScheme 1 (BasisLZ) is not supported (only none and Zstandard are)");
    if (scheme == kSchemeZlib)
        return make_error(c + "supercompressionScheme 3 (ZLIB) is not supported (only none and Zstandard are)");
    if (scheme != kSchemeNone && scheme != kSchemeZstd)
        return make_error(c + "supercompressionScheme " + num(scheme) +
                          " is not a known scheme (only 0, none, and 2, Zstandard, are supported)");
    if (header_only) {
        *header_only = TextureShape{ContainerKind::ktx2, format, width, height, layers, faces, level_count, 0};
        return TextureData{};
    }

    const std::string file = "the " + num(size) + "-byte file";
    const std::uint32_t dfd_offset = rd32(bytes + 48), dfd_length = rd32(bytes + 52), kvd_offset = rd32(bytes + 56),
                        kvd_length = rd32(bytes + 60);
    const std::uint64_t sgd_offset = rd64(bytes + 64), sgd_length = rd64(bytes + 72);
    const std::uint64_t index_bytes = std::uint64_t{24} * level_count;
    if (!fits(kKtx2HeaderBytes, index_bytes, size))
        return make_error(c + "level index of " + num(level_count) + " entries (" + num(index_bytes) +
                          " bytes at byte 80) passes the end of " + file);
    if (!fits(dfd_offset, dfd_length, size))
        return make_error(c + "dfdByteOffset " + num(dfd_offset) + " + dfdByteLength " + num(dfd_length) +
                          " passes the end of " + file);
    if (dfd_length < 4)
        return make_error(c + "dfdByteLength " + num(dfd_length) + " is too short for a data format descriptor");
    if (rd32(bytes + dfd_offset) != dfd_length)
        return make_error(c + "dfdTotalSize " + num(rd32(bytes + dfd_offset)) + " differs from dfdByteLength " +
                          num(dfd_length));
    if (!fits(kvd_offset, kvd_length, size))
        return make_error(c + "kvdByteOffset " + num(kvd_offset) + " + kvdByteLength " + num(kvd_length) +
                          " passes the end of " + file);
    // Without the key: "rd", the KTX 2.0 specification's default.
    RowOrder rows = RowOrder::top_first;
    std::string rows_source = "no KTXorientation: \"rd\", the KTX 2.0 default";
    if (Status s = read_key_values(c, bytes + kvd_offset, kvd_length, kvd_offset, true, rows, rows_source); !s)
        return s.error();
    if (!fits(sgd_offset, sgd_length, size))
        return make_error(c + "sgdByteOffset " + num(sgd_offset) + " + sgdByteLength " + num(sgd_length) +
                          " passes the end of " + file);

    const std::uint64_t images = std::uint64_t{layers} * faces;
    std::uint64_t total = 0;
    for (std::uint32_t i = 0; i < level_count; ++i) {
        const std::uint8_t* e = bytes + kKtx2HeaderBytes + 24 * std::size_t{i};
        const std::uint64_t offset = rd64(e), length = rd64(e + 8), uncompressed = rd64(e + 16);
        const std::uint32_t w = mip_extent(width, static_cast<int>(i)), h = mip_extent(height, static_cast<int>(i));
        const std::uint64_t expected = *image_bytes(format, w, h) * images;
        const std::string at = c + "level index [" + num(i) + "]";
        const std::string what = " bytes a " + shape(format, w, h, layers, faces) + " level has";
        total += expected;
        if (total > max_bytes)
            return make_error(c + "the texture needs " + num(total) + "+ bytes, more than the " + num(max_bytes) +
                              " allowed");
        if (!fits(offset, length, size))
            return make_error(at + ".byteOffset " + num(offset) + " + byteLength " + num(length) +
                              " passes the end of " + file);
        if (scheme == kSchemeNone) {
            if (length != expected)
                return make_error(at + ".byteLength " + num(length) + " does not match the " + num(expected) + what);
            if (uncompressed != length)
                return make_error(at + ".uncompressedByteLength " + num(uncompressed) + " differs from byteLength " +
                                  num(length) + " with no supercompression");
        } else if (uncompressed != expected) {
            return make_error(at + ".uncompressedByteLength " + num(uncompressed) + " does not match the " +
                              num(expected) + what);
        }
    }

    Result<TextureData> made = out_of_memory_is_an_error(c + "texture", [&] {
        return allocate_texture(format, width, height, static_cast<int>(level_count), layers, faces, max_bytes);
    });
    if (!made) return make_error(c + made.error().message);
    TextureData t = std::move(made.value());
    t.container = ContainerKind::ktx2;
    t.supercompression = scheme == kSchemeZstd ? "zstd" : "none";
    t.rows = rows;
    t.rows_source = rows_source;
    // The vkFormat, or the DFD's transfer function (byte 10 of the basic
    // block, after its 8-byte header and the total size: KHR_DF_TRANSFER_SRGB
    // is 2), which the specification requires to agree with it.
    const std::uint32_t transfer = dfd_length >= 4 + 12 ? bytes[dfd_offset + 4 + 10] : 0;
    // (A format with no sRGB form, EAC or BC4/5, is data whatever the DFD says.)
    t.srgb = linear_vk != 0 || (transfer == 2 && srgb_vk_of_linear(format_info(format).vk_format) != 0);
    t.color_space_source = linear_vk ? "vkFormat " + num(vk_format) + " (an sRGB format)"
                           : t.srgb ? std::string("the data format descriptor's transfer function 2 (sRGB)")
                                           : std::string();
    for (std::size_t i = 0; i < t.levels.size(); ++i) {
        const std::uint8_t* e = bytes + kKtx2HeaderBytes + 24 * i;
        const std::uint64_t offset = rd64(e), length = rd64(e + 8);
        // Fits: the levels' sum was checked against the allocation of t.bytes.
        const std::size_t expected = static_cast<std::size_t>(t.levels[i].image_bytes * images);
        std::uint8_t* dst = t.bytes.data() + t.levels[i].offset;
        if (scheme == kSchemeNone) {
            std::memcpy(dst, bytes + offset, expected);
            continue;
        }
        const std::size_t got =
            ZSTD_decompress(dst, expected, bytes + offset, static_cast<std::size_t>(length));
        if (ZSTD_isError(got))
            return make_error(c + "level [" + num(i) + "] Zstandard data (" + num(length) + " bytes at byte " +
                              num(offset) + ") does not decompress to its " + num(expected) +
                              " bytes: " + ZSTD_getErrorName(got));
        if (got != expected)
            return make_error(c + "level [" + num(i) + "] Zstandard data decompresses to " + num(got) +
                              " bytes, not its uncompressedByteLength " + num(expected));
    }
    return t;
}

Result<std::vector<std::uint8_t>> write_ktx2(const TextureData& t, int zstd_level) {
    const std::string c = "KTX 2.0 ";
    if (Status s = check_writable(t, c); !s) return s.error();
    const FormatInfo& info = format_info(t.format);
    if (t.srgb && srgb_vk_of_linear(info.vk_format) == 0)
        return make_error(c + "writer: " + info.name + " has no sRGB vkFormat");
    if (info.vk_format == 0)
        return make_error(c + "writer: " + info.name + " has no vkFormat (Vulkan defines no such format)");
    if (zstd_level < 0 || zstd_level > 22)
        return make_error(c + "writer: Zstandard level " + std::to_string(zstd_level) + " (0: none, or 1..22)");
    const bool zstd = zstd_level > 0;
    return out_of_memory_is_an_error(c + "writer", [&]() -> Result<std::vector<std::uint8_t>> {
        const std::size_t n = t.levels.size();
        std::vector<std::uint8_t> out(kKtx2Identifier, kKtx2Identifier + sizeof kKtx2Identifier);
        put32(out, t.srgb ? srgb_vk_of_linear(info.vk_format) : info.vk_format);
        put32(out, 1);  // typeSize
        put32(out, t.width);
        put32(out, t.height);
        put32(out, 0);  // pixelDepth
        put32(out, t.layers > 1 ? t.layers : 0);
        put32(out, t.faces);
        put32(out, static_cast<std::uint32_t>(n));
        put32(out, zstd ? kSchemeZstd : kSchemeNone);
        out.resize(kKtx2HeaderBytes + 24 * n, 0);  // index and level index, filled below
        const std::vector<std::uint8_t> dfd = basic_dfd(info, zstd, t.srgb);
        const std::size_t dfd_offset = out.size();
        out.insert(out.end(), dfd.begin(), dfd.end());
        const std::vector<std::uint8_t> kv = key_value("KTXorientation", t.rows == RowOrder::top_first ? "rd" : "ru");
        const std::size_t kvd_offset = out.size();
        out.insert(out.end(), kv.begin(), kv.end());
        set32(out, 48, static_cast<std::uint32_t>(dfd_offset));
        set32(out, 52, static_cast<std::uint32_t>(dfd.size()));
        set32(out, 56, static_cast<std::uint32_t>(kvd_offset));
        set32(out, 60, static_cast<std::uint32_t>(kv.size()));
        // sgd: none (offset and length 0).
        const std::size_t images = static_cast<std::size_t>(t.layers) * t.faces;
        const std::size_t alignment = zstd ? 1 : level_alignment(info);
        for (std::size_t k = n; k-- > 0;) {  // smallest level first
            const TextureLevel& l = t.levels[k];
            const std::size_t length = l.image_bytes * images;
            const std::uint8_t* src = t.bytes.data() + l.offset;
            pad_to(out, alignment);
            const std::size_t offset = out.size();
            if (zstd) {
                std::vector<std::uint8_t> packed(ZSTD_compressBound(length));
                const std::size_t got = ZSTD_compress(packed.data(), packed.size(), src, length, zstd_level);
                if (ZSTD_isError(got))
                    return make_error(c + "writer: level " + num(k) + ": Zstandard: " + ZSTD_getErrorName(got));
                out.insert(out.end(), packed.begin(), packed.begin() + static_cast<std::ptrdiff_t>(got));
            } else {
                out.insert(out.end(), src, src + length);
            }
            const std::size_t e = kKtx2HeaderBytes + 24 * k;
            set64(out, e, offset);
            set64(out, e + 8, out.size() - offset);
            set64(out, e + 16, length);
        }
        return out;
    });
}

Result<TextureData> read_ktx1(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes) {
    return container_detail::read_ktx1(bytes, size, max_bytes, nullptr);
}

Result<TextureData> read_ktx2(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes) {
    return container_detail::read_ktx2(bytes, size, max_bytes, nullptr);
}

}  // namespace px
