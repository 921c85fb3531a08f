#include "parallaxes/assets/image.h"

#include "parallaxes/core/files.h"
#include "parallaxes/core/limits.h"
#include "parallaxes/core/text.h"

#include <array>
#include <csetjmp>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <cctype>

// stb_image's allocations go through a per-decode budget (below): a file
// whose data expands past what its header declares (a deflate bomb in a
// small PNG) makes stb fail with "outofmem" instead of taking the machine's
// memory. stb is C: it reports a refused allocation, it never throws.
namespace px::detail {
void* stb_malloc(std::size_t size);
void* stb_realloc(void* p, std::size_t size);
void stb_free(void* p);
}  // namespace px::detail
#define STBI_MALLOC(size) px::detail::stb_malloc(size)
#define STBI_REALLOC(p, size) px::detail::stb_realloc(p, size)
#define STBI_FREE(p) px::detail::stb_free(p)
#define STBI_MAX_DIMENSIONS 4096  // = kMaxTextureSize (static_assert below)

// The one translation unit that compiles stb's implementations (Debian's
// libstb-dev ships headers only as far as CMake is concerned). stb's global
// flip flags (stbi_set_flip_vertically_on_load, stbi_flip_vertically_on_write)
// are never touched: they are process-wide state, so we flip explicitly below.
// stb decodes the PNG and TGA files of the scene format
// (docs/scene-format.md); JPEG goes to libjpeg-turbo (below). The other decoders stb carries (BMP, GIF, PSD, HDR, PIC, PNM)
// would only grow every host app's binary and the attack surface.
#define STBI_ONLY_PNG
#define STBI_ONLY_TGA
#define STBI_NO_LINEAR
#define STBI_NO_STDIO
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

static_assert(STBI_MAX_DIMENSIONS == px::kMaxTextureSize, "stb's own size limit is the library's");

// libjpeg reports errors through a callback that must not return: it
// longjmps back into the one C-style function below that called libjpeg.
// No C++ object lives in the frames it jumps across.
#ifndef PX_NO_JPEG
#include <jpeglib.h>
#endif

namespace px {

namespace detail {

namespace {

// Live bytes of the current decode on this thread, and its cap.
thread_local std::size_t t_live = 0;
thread_local std::size_t t_budget = std::numeric_limits<std::size_t>::max();
constexpr std::size_t kHeader = 16;  // keeps the block 16-byte aligned; holds its size

}  // namespace

void* stb_malloc(std::size_t size) {
    if (size > t_budget - t_live || size > std::numeric_limits<std::size_t>::max() - kHeader) return nullptr;
    auto* block = static_cast<unsigned char*>(std::malloc(size + kHeader));
    if (!block) return nullptr;
    std::memcpy(block, &size, sizeof size);
    t_live += size;
    return block + kHeader;
}

void* stb_realloc(void* p, std::size_t size) {
    if (!p) return stb_malloc(size);
    unsigned char* block = static_cast<unsigned char*>(p) - kHeader;
    std::size_t old = 0;
    std::memcpy(&old, block, sizeof old);
    if (size > old && size - old > t_budget - t_live) return nullptr;
    if (size > std::numeric_limits<std::size_t>::max() - kHeader) return nullptr;
    auto* grown = static_cast<unsigned char*>(std::realloc(block, size + kHeader));
    if (!grown) return nullptr;
    std::memcpy(grown, &size, sizeof size);
    t_live = t_live - old + size;
    return grown + kHeader;
}

void stb_free(void* p) {
    if (!p) return;
    unsigned char* block = static_cast<unsigned char*>(p) - kHeader;
    std::size_t size = 0;
    std::memcpy(&size, block, sizeof size);
    t_live -= size;
    std::free(block);
}

}  // namespace detail

namespace {

// The largest side this decode accepts (decode_image's max_side; at most
// kMaxTextureSize), for the header checks below.
thread_local int t_max_side = kMaxTextureSize;

class MaxSide {
public:
    explicit MaxSide(int side) { t_max_side = side; }
    ~MaxSide() { t_max_side = kMaxTextureSize; }
    MaxSide(const MaxSide&) = delete;
    MaxSide& operator=(const MaxSide&) = delete;
};

size_t row_bytes(int width, int channels) { return static_cast<size_t>(width) * channels; }

// Copies `height` rows of `stride` bytes from src to dst in reverse order:
// files are stored top row first, Image keeps the bottom row (v = 0) first.
void copy_rows_flipped(const std::uint8_t* src, std::uint8_t* dst, int height, size_t stride) {
    for (int y = 0; y < height; ++y)
        std::memcpy(dst + static_cast<size_t>(height - 1 - y) * stride,
                    src + static_cast<size_t>(y) * stride, stride);
}

// stbi_write_png_to_func callback: collects the encoded PNG in memory so that
// the file I/O (and its error reporting through errno) stays ours.
void append_bytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<std::uint8_t>*>(context);
    const auto* bytes = static_cast<const std::uint8_t*>(data);
    out->insert(out->end(), bytes, bytes + size);
}

struct StbiFree {
    void operator()(stbi_uc* p) const { stbi_image_free(p); }
};

// Caps what stb may hold while one decode runs on this thread.
class DecodeBudget {
public:
    explicit DecodeBudget(std::size_t bytes) { detail::t_budget = detail::t_live + bytes; }
    ~DecodeBudget() { detail::t_budget = std::numeric_limits<std::size_t>::max(); }
    DecodeBudget(const DecodeBudget&) = delete;
    DecodeBudget& operator=(const DecodeBudget&) = delete;
};

// stb's reason, or a plain one when it gave none readable (some of its
// paths leave a string that starts with NUL bytes).
std::string stb_reason() {
    const char* reason = stbi_failure_reason();
    if (!reason || reason[0] == '\0') return "corrupt or unsupported image data";
    const std::string text(reason);
    if (text == "outofmem")
        return "the image data expands past what its header declares (refused before it could exhaust memory)";
    for (const char c : text)
        if (static_cast<unsigned char>(c) < 0x20) return "corrupt or unsupported image data";
    return echo(text);
}

// --- PNG structure --------------------------------------------------------------
// PNG (ISO/IEC 15948): an 8-byte signature, then chunks of
// length (4 bytes, big-endian, < 2^31), type (4 letters), data, CRC-32 of
// type and data. IHDR comes first, PLTE before the first IDAT, IDATs in a
// row, IEND last. stb checks little of this and not the CRCs.

constexpr std::uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};

std::uint32_t be32(const std::uint8_t* p) {
    return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

void put_be32(std::uint8_t* p, std::uint32_t v) {
    p[0] = static_cast<std::uint8_t>(v >> 24);
    p[1] = static_cast<std::uint8_t>(v >> 16);
    p[2] = static_cast<std::uint8_t>(v >> 8);
    p[3] = static_cast<std::uint8_t>(v);
}

// CRC-32 as PNG defines it (polynomial 0xEDB88320, reflected).
std::uint32_t crc32(const std::uint8_t* data, std::size_t size) {
    static const std::array<std::uint32_t, 256> table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t n = 0; n < 256; ++n) {
            std::uint32_t c = n;
            for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[n] = c;
        }
        return t;
    }();
    std::uint32_t c = 0xFFFFFFFFu;
    for (std::size_t i = 0; i < size; ++i) c = table[(c ^ data[i]) & 0xFF] ^ (c >> 8);
    return c ^ 0xFFFFFFFFu;
}

struct PngLayout {
    std::uint32_t width = 0, height = 0;
    int bit_depth = 0, color_type = 0;
    std::size_t plte_offset = 0;  // of the chunk's length field; 0 when absent
    std::uint32_t plte_entries = 0;
    ImageInfo::Encoding encoding = ImageInfo::Encoding::none;
    std::string declared_by;
};

std::string chunk_name(const std::uint8_t* type) {
    std::string name;
    for (int i = 0; i < 4; ++i) {
        const auto c = static_cast<char>(type[i]);
        name += (std::isalpha(static_cast<unsigned char>(c)) ? std::string(1, c) : "?");
    }
    return name;
}

bool is_png(const std::uint8_t* bytes, std::size_t size) {
    return size >= 8 && std::memcmp(bytes, kPngSignature, 8) == 0;
}

Result<PngLayout> check_png(const std::uint8_t* bytes, std::size_t size) {
    PngLayout png;
    std::size_t at = 8;
    bool seen_ihdr = false, seen_idat = false, idat_ended = false, seen_iend = false;
    while (at < size && !seen_iend) {
        const std::string where = " at byte " + std::to_string(at);
        if (size - at < 12) return make_error("truncated chunk header" + where + " (the file ends before its IEND chunk)");
        const std::uint32_t length = be32(bytes + at);
        const std::uint8_t* type = bytes + at + 4;
        const std::string name = chunk_name(type);
        if (length > 0x7FFFFFFFu) return make_error("chunk '" + name + "'" + where + " declares an invalid length");
        if (length > size - at - 12)
            return make_error("chunk '" + name + "'" + where + " runs past the end of the file (truncated)");
        const std::uint8_t* data = type + 4;
        if (be32(data + length) != crc32(type, length + 4))
            return make_error("chunk '" + name + "'" + where + " has a bad CRC (the file is damaged)");
        if (!seen_ihdr && name != "IHDR") return make_error("the first chunk is '" + name + "', not IHDR");
        if (name == "IHDR") {
            if (seen_ihdr) return make_error("a second IHDR chunk" + where);
            if (length != 13) return make_error("IHDR is " + std::to_string(length) + " bytes, not 13");
            seen_ihdr = true;
            png.width = be32(data);
            png.height = be32(data + 4);
            png.bit_depth = data[8];
            png.color_type = data[9];
            const int d = png.bit_depth;
            bool valid = false;
            switch (png.color_type) {
                case 0: valid = d == 1 || d == 2 || d == 4 || d == 8 || d == 16; break;
                case 3: valid = d == 1 || d == 2 || d == 4 || d == 8; break;
                case 2: case 4: case 6: valid = d == 8 || d == 16; break;
                default: break;
            }
            if (!valid)
                return make_error("IHDR: bit depth " + std::to_string(d) + " with colour type " +
                                  std::to_string(png.color_type) + " is not a valid PNG combination");
            if (data[10] != 0 || data[11] != 0 || data[12] > 1)
                return make_error("IHDR: unknown compression, filter or interlace method");
            if (png.width == 0 || png.height == 0) return make_error("IHDR declares an empty image");
        } else if (name == "PLTE") {
            if (seen_idat) return make_error("PLTE" + where + " comes after the image data");
            if (png.plte_offset) return make_error("a second PLTE chunk" + where);
            if (length == 0 || length % 3 != 0 || length > 768)
                return make_error("PLTE is " + std::to_string(length) + " bytes: a palette holds 1 to 256 entries of 3 bytes");
            png.plte_offset = at;
            png.plte_entries = length / 3;
        } else if (name == "IDAT") {
            if (idat_ended) return make_error("IDAT chunks" + where + " are not consecutive");
            if (png.color_type == 3 && !png.plte_offset) return make_error("an indexed-colour image without a PLTE chunk");
            seen_idat = true;
        } else if (name == "IEND") {
            if (!seen_idat) return make_error("the file has no image data (IDAT) before IEND");
            seen_iend = true;
        } else if (name == "sRGB" || name == "iCCP") {
            // Either beats gAMA (PNG 11.3.2.5): an sRGB-capable reader uses them first.
            if (!seen_idat) {
                png.encoding = ImageInfo::Encoding::srgb;
                png.declared_by = name == "sRGB" ? "its sRGB chunk" : "its iCCP colour profile (read as sRGB)";
            }
        } else if (name == "gAMA") {
            if (!seen_idat && length == 4 && png.declared_by.rfind("its sRGB", 0) != 0 &&
                png.declared_by.rfind("its iCCP", 0) != 0) {
                const std::uint32_t g = be32(data);  // the encoding exponent times 100000
                const bool linear = g >= 95000 && g <= 105000;
                const bool srgb_like = g >= 40000 && g <= 50000;
                if (linear || srgb_like) {
                    png.encoding = linear ? ImageInfo::Encoding::linear : ImageInfo::Encoding::srgb;
                    png.declared_by = "its gAMA chunk (" + std::to_string(g) + " / 100000)";
                }
            }
        } else if ((type[0] & 0x20) == 0) {
            return make_error("unknown critical chunk '" + name + "'" + where);
        }
        if (seen_idat && name != "IDAT") idat_ended = true;
        at += 12 + static_cast<std::size_t>(length);
    }
    if (!seen_ihdr) return make_error("no IHDR chunk");
    if (!seen_iend) return make_error("the file ends before its IEND chunk (truncated)");
    return png;
}

// --- JPEG structure -------------------------------------------------------------
// JPEG (ITU T.81, Annex B): markers 0xFF xx; most carry a 2-byte length;
// entropy-coded data follows each SOS until the next marker that is not a
// restart (RSTn) or a stuffed 0xFF 0x00. Checked here: every segment lies
// inside the file, and every Huffman table (DHT) declares at most 256 codes,
// which Debian's stb_image 2.27 does not check before writing its tables
// (found by the image fuzz target: a write one past the code-size array).

bool named_tga(const std::string& name) {
    if (name.size() < 4) return false;
    std::string ext = name.substr(name.size() - 4);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".tga";
}

bool is_jpeg(const std::uint8_t* bytes, std::size_t size) {
    return size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
}

Status check_jpeg(const std::uint8_t* bytes, std::size_t size) {
    std::size_t at = 2;
    while (at + 1 < size) {
        const std::string where = " at byte " + std::to_string(at);
        if (bytes[at] != 0xFF) return make_error("expected a marker" + where);
        const std::uint8_t marker = bytes[at + 1];
        if (marker == 0xFF) {  // fill byte before a marker
            ++at;
            continue;
        }
        if (marker == 0xD9) return {};  // EOI
        if ((marker >= 0xD0 && marker <= 0xD7) || marker == 0x01) {
            at += 2;
            continue;
        }
        if (size - at < 4) return make_error("truncated segment" + where);
        const std::size_t length = (std::size_t{bytes[at + 2]} << 8) | bytes[at + 3];
        if (length < 2 || length > size - at - 2) return make_error("a segment" + where + " runs past the end of the file");
        const std::size_t end = at + 2 + length;
        if (marker == 0xC4) {
            for (std::size_t p = at + 4; p < end;) {
                if (end - p < 17) return make_error("a truncated Huffman table (DHT)" + where);
                std::size_t codes = 0;
                for (int i = 1; i <= 16; ++i) codes += bytes[p + i];
                if (codes > 256)
                    return make_error("a Huffman table (DHT)" + where + " declares " + std::to_string(codes) +
                                      " codes; at most 256 exist");
                if (codes > end - p - 17) return make_error("a Huffman table (DHT)" + where + " runs past its segment");
                p += 17 + codes;
            }
        }
        at = end;
        if (marker == 0xDA) {  // skip the entropy-coded data
            while (at + 1 < size &&
                   !(bytes[at] == 0xFF && bytes[at + 1] != 0x00 && !(bytes[at + 1] >= 0xD0 && bytes[at + 1] <= 0xD7)))
                ++at;
        }
    }
    return {};  // no EOI: stb decodes what is there, as most readers do
}

std::size_t decode_budget_bytes(int width, int height, std::size_t file_bytes);

#ifndef PX_NO_JPEG
// --- JPEG decoding (libjpeg-turbo) ------------------------------------------------

struct JpegContext {
    jpeg_decompress_struct info{};
    jpeg_error_mgr errors{};
    jpeg_progress_mgr progress{};
    std::jmp_buf jump{};
    char message[JMSG_LENGTH_MAX] = {0};
    bool created = false;
};

// A progressive JPEG may hold any number of scans, each a pass over the
// whole image: cap them, as libjpeg-turbo's documentation advises for
// untrusted input.
constexpr long kMaxJpegScans = 256;

extern "C" void jpeg_fail(j_common_ptr common) {
    auto* ctx = reinterpret_cast<JpegContext*>(common->client_data);
    (*common->err->format_message)(common, ctx->message);
    std::longjmp(ctx->jump, 1);
}

// libjpeg's warnings (level -1) say the data is corrupt ("premature end of
// data segment", "extraneous bytes"); it would go on and fill the rest with
// grey. A damaged texture is refused instead: never a silently wrong image.
// Trace messages (level >= 0) stay silent.
extern "C" void jpeg_on_message(j_common_ptr common, int level) {
    if (level < 0) jpeg_fail(common);
}

extern "C" void jpeg_progress(j_common_ptr common) {
    auto* d = reinterpret_cast<j_decompress_ptr>(common);
    if (d->input_scan_number > kMaxJpegScans) {
        auto* ctx = reinterpret_cast<JpegContext*>(common->client_data);
        std::snprintf(ctx->message, sizeof ctx->message, "more than %ld progressive scans", kMaxJpegScans);
        std::longjmp(ctx->jump, 1);
    }
}

// Reads the header and sets up the output colour space (grey for one
// channel, RGB otherwise). Returns false with ctx.message on an error.
bool jpeg_begin(JpegContext& ctx, const std::uint8_t* bytes, std::size_t size, bool grey, std::size_t memory) {
    ctx.info.err = jpeg_std_error(&ctx.errors);
    ctx.errors.error_exit = jpeg_fail;
    ctx.errors.emit_message = jpeg_on_message;
    ctx.info.client_data = &ctx;
    if (setjmp(ctx.jump)) return false;
    jpeg_create_decompress(&ctx.info);
    ctx.created = true;
    ctx.info.mem->max_memory_to_use = static_cast<long>(memory);
    ctx.progress.progress_monitor = jpeg_progress;
    ctx.info.progress = &ctx.progress;
    jpeg_mem_src(&ctx.info, bytes, static_cast<unsigned long>(size));
    jpeg_read_header(&ctx.info, TRUE);
    ctx.info.out_color_space = grey ? JCS_GRAYSCALE : JCS_RGB;
    return true;
}

bool jpeg_pixels(JpegContext& ctx, std::uint8_t* out, std::size_t stride) {
    if (setjmp(ctx.jump)) return false;
    jpeg_start_decompress(&ctx.info);
    while (ctx.info.output_scanline < ctx.info.output_height) {
        JSAMPROW row = out + static_cast<std::size_t>(ctx.info.output_scanline) * stride;
        jpeg_read_scanlines(&ctx.info, &row, 1);
    }
    jpeg_finish_decompress(&ctx.info);
    return true;
}

struct JpegGuard {
    JpegContext& ctx;
    ~JpegGuard() {
        if (ctx.created) jpeg_destroy_decompress(&ctx.info);
    }
};

Result<ImageInfo> jpeg_size_checked(JpegContext& ctx) {
    const JDIMENSION w = ctx.info.image_width, h = ctx.info.image_height;
    if (w < 1 || h < 1) return make_error("the header declares an empty image");
    if (w > static_cast<JDIMENSION>(t_max_side) || h > static_cast<JDIMENSION>(t_max_side))
        return make_error("the header declares " + std::to_string(w) + "x" + std::to_string(h) +
                          ", over the limit of " + std::to_string(t_max_side) + " texels per side");
    return ImageInfo{static_cast<int>(w), static_cast<int>(h)};
}

// Rows come back top first, `channels` each (grey or RGB expanded).
Result<std::vector<std::uint8_t>> decode_jpeg(const std::uint8_t* bytes, std::size_t size, int channels,
                                              ImageInfo& info) {
    auto ctx = std::make_unique<JpegContext>();
    JpegGuard guard{*ctx};
    const bool grey = channels <= 2;
    if (!jpeg_begin(*ctx, bytes, size, grey, decode_budget_bytes(kMaxTextureSize, kMaxTextureSize, size)))
        return make_error(std::string("cannot decode JPEG: ") + ctx->message);
    Result<ImageInfo> declared = jpeg_size_checked(*ctx);
    if (!declared) return declared.error();
    info = *declared;
    const int decoded_channels = grey ? 1 : 3;
    std::vector<std::uint8_t> decoded(static_cast<std::size_t>(info.width) * info.height * decoded_channels);
    if (!jpeg_pixels(*ctx, decoded.data(), static_cast<std::size_t>(info.width) * decoded_channels))
        return make_error(std::string("cannot decode JPEG: ") + ctx->message);
    if (decoded_channels == channels) return decoded;
    std::vector<std::uint8_t> out(static_cast<std::size_t>(info.width) * info.height * channels);
    const std::size_t texels = static_cast<std::size_t>(info.width) * info.height;
    for (std::size_t i = 0; i < texels; ++i) {
        const std::uint8_t* s = &decoded[i * decoded_channels];
        std::uint8_t* d = &out[i * channels];
        if (channels == 2) {
            d[0] = s[0];
            d[1] = 255;
        } else {  // 4: RGB plus opaque alpha
            d[0] = s[0];
            d[1] = s[1];
            d[2] = s[2];
            d[3] = 255;
        }
    }
    return out;
}

Result<ImageInfo> jpeg_info(const std::uint8_t* bytes, std::size_t size) {
    auto ctx = std::make_unique<JpegContext>();
    JpegGuard guard{*ctx};
    if (!jpeg_begin(*ctx, bytes, size, false, std::size_t{1} << 20))
        return make_error(std::string("cannot read the JPEG header: ") + ctx->message);
    return jpeg_size_checked(*ctx);
}
#else
// A build without libjpeg (the web build, web/README.md): JPEG files are
// refused by name; the page hands the library PNG instead.
const char* const kNoJpeg = "JPEG is not in this build (built without libjpeg: the web build); use PNG or TGA";

Result<std::vector<std::uint8_t>> decode_jpeg(const std::uint8_t*, std::size_t, int, ImageInfo&) {
    return make_error(kNoJpeg);
}

Result<ImageInfo> jpeg_info(const std::uint8_t*, std::size_t) { return make_error(kNoJpeg); }
#endif  // PX_NO_JPEG

// The decoder's cap for an image of the declared size: its output at up to
// 16 bits and 4 channels, twice over for the conversions, the inflated rows
// (which stb grows by doubling), and the compressed bytes it gathers.
std::size_t decode_budget_bytes(int width, int height, std::size_t file_bytes) {
    const std::size_t texels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    return texels * 8 * 4 + 2 * file_bytes + (std::size_t{1} << 20);
}

Result<ImageInfo> header_info(const std::uint8_t* bytes, std::size_t size, const PngLayout* png) {
    ImageInfo info;
    if (png) {
        if (png->width > static_cast<std::uint32_t>(t_max_side) ||
            png->height > static_cast<std::uint32_t>(t_max_side))
            return make_error("the header declares " + std::to_string(png->width) + "x" + std::to_string(png->height) +
                              ", over the limit of " + std::to_string(t_max_side) + " texels per side");
        info.width = static_cast<int>(png->width);
        info.height = static_cast<int>(png->height);
        info.encoding = png->encoding;
        info.declared_by = png->declared_by;
        return info;
    }
    if (size > static_cast<std::size_t>(std::numeric_limits<int>::max())) return make_error("file too large");
    int channels = 0;
    DecodeBudget budget(std::size_t{1} << 20);
    if (!stbi_info_from_memory(bytes, static_cast<int>(size), &info.width, &info.height, &channels))
        return make_error("not a PNG, JPEG or TGA image (" + stb_reason() + ")");
    if (info.width < 1 || info.height < 1) return make_error("the header declares an empty image");
    if (info.width > t_max_side || info.height > t_max_side)
        return make_error("the header declares " + std::to_string(info.width) + "x" + std::to_string(info.height) +
                          ", over the limit of " + std::to_string(t_max_side) + " texels per side");
    return info;
}

// Decodes with stb under the budget; rows come back top first.
Result<std::unique_ptr<stbi_uc, StbiFree>> stb_decode(const std::uint8_t* bytes, std::size_t size,
                                                      const ImageInfo& info, int channels) {
    DecodeBudget budget(decode_budget_bytes(info.width, info.height, size));
    int w = 0, h = 0, file_channels = 0;
    std::unique_ptr<stbi_uc, StbiFree> data(
        stbi_load_from_memory(bytes, static_cast<int>(size), &w, &h, &file_channels, channels));
    if (!data) return make_error("cannot decode image: " + stb_reason());
    if (w != info.width || h != info.height)
        return make_error("decoded " + std::to_string(w) + "x" + std::to_string(h) + ", but the header declares " +
                          std::to_string(info.width) + "x" + std::to_string(info.height));
    return data;
}

// A copy of the PNG with its PLTE padded to 256 entries of `fill`, CRC
// recomputed; stb then reads only initialised palette entries.
std::vector<std::uint8_t> with_full_palette(const std::uint8_t* bytes, std::size_t size, const PngLayout& png,
                                            std::uint8_t fill) {
    const std::size_t old_length = png.plte_entries * 3;
    std::vector<std::uint8_t> out;
    out.reserve(size + 768);
    out.insert(out.end(), bytes, bytes + png.plte_offset);
    std::uint8_t header[8];
    put_be32(header, 768);
    std::memcpy(header + 4, "PLTE", 4);
    out.insert(out.end(), header, header + 8);
    const std::uint8_t* entries = bytes + png.plte_offset + 8;
    out.insert(out.end(), entries, entries + old_length);
    out.insert(out.end(), 768 - old_length, fill);
    std::uint8_t crc[4];
    put_be32(crc, crc32(out.data() + png.plte_offset + 4, 768 + 4));
    out.insert(out.end(), crc, crc + 4);
    const std::size_t rest = png.plte_offset + 12 + old_length;
    out.insert(out.end(), bytes + rest, bytes + size);
    return out;
}

}  // namespace

namespace {

enum class Format { png, jpeg, tga };

// What every reader learns before it decodes: the format, a PNG's layout,
// and the declared size, after the size, structure and header checks.
struct Inspected {
    Format format = Format::tga;
    std::optional<PngLayout> png;
    ImageInfo info;
};

Result<Inspected> inspect(const std::uint8_t* bytes, std::size_t size, const std::string& name) {
    if (size > kMaxImageFileBytes)
        return make_error("the image is larger than the limit of " + std::to_string(kMaxImageFileBytes >> 20) + " MiB");
    if (size == 0) return make_error("the image file is empty");
    Inspected in;
    if (is_png(bytes, size)) {
        Result<PngLayout> layout = check_png(bytes, size);
        if (!layout) return make_error("not a valid PNG: " + layout.error().message);
        in.format = Format::png;
        in.png = *layout;
    } else if (is_jpeg(bytes, size)) {
        if (Status jpeg = check_jpeg(bytes, size); !jpeg) return make_error("not a valid JPEG: " + jpeg.error().message);
        in.format = Format::jpeg;
        Result<ImageInfo> info = jpeg_info(bytes, size);
        if (!info) return info.error();
        in.info = *info;
        return in;
    } else if (!named_tga(name)) {
        // TGA has no signature: stb would take almost any bytes for one and
        // decode noise. So a file is read as TGA only when it says it is one.
        return make_error("not a PNG or JPEG file (no signature), and not named *.tga");
    }
    Result<ImageInfo> info = header_info(bytes, size, in.png ? &*in.png : nullptr);
    if (!info) return info.error();
    in.info = *info;
    return in;
}

// An Image from decoded rows, top row first.
Image from_rows_top_down(const std::uint8_t* rows, const ImageInfo& info, int channels) {
    Image image;
    image.width = info.width;
    image.height = info.height;
    image.channels = channels;
    const size_t stride = row_bytes(image.width, channels);
    image.pixels.resize(stride * static_cast<size_t>(image.height));
    copy_rows_flipped(rows, image.pixels.data(), image.height, stride);
    return image;
}

// stb's decode of a PNG or TGA. A short palette: stb reads an out-of-range
// index's entry from memory it never wrote, so the PNG is decoded again with
// its palette padded two ways; pixels that differ use an index past the
// file's PLTE.
Result<Image> decode_with_stb(const std::uint8_t* bytes, std::size_t size, const Inspected& in, int channels) {
    const std::optional<PngLayout>& png = in.png;
    if (!(png && png->color_type == 3 && png->plte_entries < (1u << png->bit_depth))) {
        Result<std::unique_ptr<stbi_uc, StbiFree>> data = stb_decode(bytes, size, in.info, channels);
        if (!data) return data.error();
        return from_rows_top_down(data->get(), in.info, channels);
    }
    const std::size_t count = static_cast<std::size_t>(in.info.width) * in.info.height * channels;
    std::unique_ptr<stbi_uc, StbiFree> padded[2];
    for (int k = 0; k < 2; ++k) {
        const std::vector<std::uint8_t> copy = with_full_palette(bytes, size, *png, k == 0 ? 0x00 : 0xFF);
        Result<std::unique_ptr<stbi_uc, StbiFree>> d = stb_decode(copy.data(), copy.size(), in.info, channels);
        if (!d) return d.error();
        padded[k] = std::move(*d);
    }
    if (std::memcmp(padded[0].get(), padded[1].get(), count) != 0)
        return make_error("pixels use palette indices past the " + std::to_string(png->plte_entries) +
                          " entries of its PLTE chunk");
    return from_rows_top_down(padded[0].get(), in.info, channels);
}

}  // namespace

Result<Image> decode_image(const std::uint8_t* bytes, std::size_t size, const std::string& name, int channels,
                           int max_side) {
    const std::string who = echo_path(name);
    if (max_side < 1 || max_side > kMaxTextureSize)
        return make_error(who + ": max_side must be within 1.." + std::to_string(kMaxTextureSize) + ", got " +
                          std::to_string(max_side));
    if (channels < 1 || channels > 4)
        return make_error(who + ": cannot load image: channels must be 1..4, got " + std::to_string(channels));
    const MaxSide side(max_side);
    Result<Inspected> in = inspect(bytes, size, name);
    if (!in) return with_context(who, in.error());
    if (in->format == Format::jpeg) {
        ImageInfo info;
        Result<std::vector<std::uint8_t>> rows = decode_jpeg(bytes, size, channels, info);
        if (!rows) return with_context(who, rows.error());
        return from_rows_top_down(rows->data(), info, channels);
    }
    Result<Image> image = decode_with_stb(bytes, size, *in, channels);
    if (!image) return with_context(who, image.error());
    return image;
}

Result<Image> load_image(const std::string& path, int channels) {
    Result<std::vector<std::uint8_t>> bytes = read_file_bounded(path, kMaxImageFileBytes, "image");
    if (!bytes) return bytes.error();
    return decode_image(bytes->data(), bytes->size(), path, channels);
}

Result<ImageInfo> read_image_info(const std::string& path) {
    Result<std::vector<std::uint8_t>> bytes = read_file_bounded(path, kMaxImageFileBytes, "image");
    if (!bytes) return bytes.error();
    Result<Inspected> in = inspect(bytes->data(), bytes->size(), path);
    if (!in) return with_context(echo_path(path), in.error());
    return in->info;
}

Status write_png(const std::string& path, const Image& image) {
    if (image.width <= 0 || image.height <= 0)
        return make_error(path + ": cannot write PNG: empty image (" + std::to_string(image.width) +
                          "x" + std::to_string(image.height) + ")");
    if (image.channels < 1 || image.channels > 4)
        return make_error(path + ": cannot write PNG: channels must be 1..4, got " +
                          std::to_string(image.channels));
    const size_t stride = row_bytes(image.width, image.channels);
    if (image.pixels.size() != stride * static_cast<size_t>(image.height))
        return make_error(path + ": cannot write PNG: pixel buffer holds " +
                          std::to_string(image.pixels.size()) + " bytes, expected " +
                          std::to_string(stride * static_cast<size_t>(image.height)));
    if (stride > static_cast<size_t>(std::numeric_limits<int>::max()))
        return make_error(path + ": cannot write PNG: rows too wide");

    // PNG rows go top first.
    std::vector<std::uint8_t> top_down(image.pixels.size());
    copy_rows_flipped(image.pixels.data(), top_down.data(), image.height, stride);

    std::vector<std::uint8_t> encoded;
    if (!stbi_write_png_to_func(append_bytes, &encoded, image.width, image.height, image.channels,
                                top_down.data(), static_cast<int>(stride)))
        return make_error(path + ": cannot write PNG: encoding failed");

    Status written = write_file_atomically(path, encoded.data(), encoded.size());
    if (!written) return make_error("cannot write PNG: " + written.error().message);
    return {};
}

}  // namespace px
