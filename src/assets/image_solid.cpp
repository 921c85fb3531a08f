// make_solid_image, apart from the file readers and writers of image.cpp:
// a renderer that reads no files links it without stb_image or libjpeg.
#include "parallaxes/assets/image.h"

namespace px {

Image make_solid_image(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b, std::uint8_t a) {
    Image image;
    image.width = width > 0 ? width : 0;
    image.height = height > 0 ? height : 0;
    image.channels = 4;
    const std::uint8_t rgba[4] = {r, g, b, a};
    image.pixels.resize(static_cast<size_t>(image.width) * 4 * static_cast<size_t>(image.height));
    for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = rgba[i % 4];
    return image;
}

}  // namespace px
