// 8-bit images in memory, and PNG/JPG/TGA files through stb_image.
// Row 0 is the bottom row (texture coordinate v = 0), as OpenGL uploads it;
// load_image and write_png flip so that files keep their usual top-down order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "parallaxes/core/limits.h"
#include "parallaxes/core/result.h"

namespace px {

struct Image {
    int width = 0;
    int height = 0;
    int channels = 4;                 // 1..4; textures are uploaded as RGBA
    std::vector<std::uint8_t> pixels; // width * height * channels, row 0 = bottom

    std::uint8_t* texel(int x, int y) { return &pixels[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * static_cast<size_t>(channels)]; }
    const std::uint8_t* texel(int x, int y) const {
        return &pixels[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * static_cast<size_t>(channels)];
    }
};

// What an image file's header declares, read without decoding its pixels.
struct ImageInfo {
    ImageInfo() = default;
    ImageInfo(int w, int h) : width(w), height(h) {}
    int width = 0;
    int height = 0;
    // The colour space a PNG declares (PNG 3rd edition, 11.3.2): an sRGB
    // chunk, or an iCCP profile (read as sRGB: the profiles packs embed are
    // sRGB's), is sRGB; gAMA alone says the encoding's exponent: 1/2.2 or
    // near it (45455) is sRGB's curve, 1.0 (100000) linear. `declared_by`
    // names the chunk ("sRGB chunk", "gAMA 1.0"); empty with `none`: JPEG
    // and TGA files, and PNGs without those chunks, declare nothing.
    enum class Encoding : std::uint8_t { none, srgb, linear } encoding = Encoding::none;
    std::string declared_by;
};

// Loads PNG, JPEG or TGA as `channels` channels. PNG and JPEG are known by
// their signatures; TGA has none, so only a file named *.tga is read as one
// (anything else is refused rather than decoded as noise). Before anything
// is decoded:
// the file must be a regular file of at most kMaxImageFileBytes, its header
// must declare at most kMaxTextureSize texels per side, and a PNG's chunk
// structure must be sound (IHDR first, valid depth and colour type, CRCs,
// PLTE sizes, IDAT, IEND). The decoder's memory is capped by what the header
// declares, so data that expands past it is refused. An indexed PNG whose
// pixels use palette entries its PLTE lacks is refused (the decoder would
// fill them with whatever memory held). Errors name the file and the reason.
Result<Image> load_image(const std::string& path, int channels = 4);

// The same from bytes in memory; `name` is what errors call them (and a
// name ending in .tga lets them be read as TGA). max_side (1..kMaxTextureSize)
// lowers the size limit, e.g. to a device's GL_MAX_TEXTURE_SIZE.
Result<Image> decode_image(const std::uint8_t* bytes, std::size_t size, const std::string& name, int channels = 4,
                           int max_side = kMaxTextureSize);

// The header's size, with the same file and header checks as load_image.
Result<ImageInfo> read_image_info(const std::string& path);

// Writes a PNG; errors name the file.
Status write_png(const std::string& path, const Image& image);

// A solid-colour image (used for albedo given as a colour).
Image make_solid_image(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b,
                       std::uint8_t a = 255);

}  // namespace px
