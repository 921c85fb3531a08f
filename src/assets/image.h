// 8-bit images in memory, and PNG/JPG/TGA files through stb_image.
// Row 0 is the bottom row (texture coordinate v = 0), as OpenGL uploads it;
// load_image and write_png flip so that files keep their usual top-down order.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"

namespace px {

struct Image {
    int width = 0;
    int height = 0;
    int channels = 4;                 // 1..4; textures are uploaded as RGBA
    std::vector<std::uint8_t> pixels; // width * height * channels, row 0 = bottom

    std::uint8_t* texel(int x, int y) { return &pixels[(static_cast<size_t>(y) * width + x) * channels]; }
    const std::uint8_t* texel(int x, int y) const {
        return &pixels[(static_cast<size_t>(y) * width + x) * channels];
    }
};

// Loads PNG, JPG or TGA (whatever stb_image reads) as `channels` channels.
// Errors name the file and stb's reason.
Result<Image> load_image(const std::string& path, int channels = 4);

// Writes a PNG; errors name the file.
Status write_png(const std::string& path, const Image& image);

// A solid-colour image (used for albedo given as a colour).
Image make_solid_image(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b,
                       std::uint8_t a = 255);

}  // namespace px
