#include "assets/image.h"

#include "core/files.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>

// The one translation unit that compiles stb's implementations (Debian's
// libstb-dev ships headers only as far as CMake is concerned). stb's global
// flip flags (stbi_set_flip_vertically_on_load, stbi_flip_vertically_on_write)
// are never touched: they are process-wide state, so we flip explicitly below.
// The formats the scene format documents (docs/scene-format.md): PNG, JPEG
// and TGA. The other decoders stb carries (BMP, GIF, PSD, HDR, PIC, PNM)
// would only grow every host app's binary and the attack surface.
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_ONLY_TGA
#define STBI_NO_LINEAR
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace px {

namespace {

size_t row_bytes(int width, int channels) { return static_cast<size_t>(width) * channels; }

// Copies `height` rows of `stride` bytes from src to dst in reverse order:
// files are stored top row first, Image keeps the bottom row (v = 0) first.
void copy_rows_flipped(const std::uint8_t* src, std::uint8_t* dst, int height, size_t stride) {
    for (int y = 0; y < height; ++y)
        std::memcpy(dst + static_cast<size_t>(height - 1 - y) * stride,
                    src + static_cast<size_t>(y) * stride, stride);
}

std::string errno_text(int err) { return err != 0 ? std::string(std::strerror(err)) : "unknown error"; }

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

struct StbiFree {
    void operator()(stbi_uc* p) const { stbi_image_free(p); }
};

// stbi_write_png_to_func callback: collects the encoded PNG in memory so that
// the file I/O (and its error reporting through errno) stays ours.
void append_bytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<std::uint8_t>*>(context);
    const auto* bytes = static_cast<const std::uint8_t*>(data);
    out->insert(out->end(), bytes, bytes + size);
}

}  // namespace

Result<Image> load_image(const std::string& path, int channels) {
    if (channels < 1 || channels > 4)
        return make_error(path + ": cannot load image: channels must be 1..4, got " +
                          std::to_string(channels));

    // Open the file ourselves: errno then says why (missing, permissions),
    // where stb would only report "can't fopen".
    errno = 0;
    FilePtr file(std::fopen(path.c_str(), "rb"));
    if (!file) return make_error(path + ": cannot open image: " + errno_text(errno));

    int width = 0, height = 0, file_channels = 0;
    std::unique_ptr<stbi_uc, StbiFree> data(
        stbi_load_from_file(file.get(), &width, &height, &file_channels, channels));
    if (!data) {
        // stbi_failure_reason is thread-local in C++11 builds of stb_image (STBI_THREAD_LOCAL).
        const char* reason = stbi_failure_reason();
        return make_error(path + ": cannot decode image: " + (reason ? reason : "unknown reason"));
    }

    Image image;
    image.width = width;
    image.height = height;
    image.channels = channels;
    const size_t stride = row_bytes(width, channels);
    image.pixels.resize(stride * static_cast<size_t>(height));
    copy_rows_flipped(data.get(), image.pixels.data(), height, stride);
    return image;
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

Image make_solid_image(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b,
                       std::uint8_t a) {
    Image image;
    image.width = width > 0 ? width : 0;
    image.height = height > 0 ? height : 0;
    image.channels = 4;
    const std::uint8_t rgba[4] = {r, g, b, a};
    image.pixels.resize(row_bytes(image.width, 4) * static_cast<size_t>(image.height));
    for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = rgba[i % 4];
    return image;
}

}  // namespace px
