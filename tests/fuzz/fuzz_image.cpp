// libFuzzer target: bytes through the image decoder (PNG, JPEG, TGA), with
// the file and header checks and the decoder's memory cap. A decoded image
// must have the size its header declared, within the limits. Findings
// become tests in tests/unit_hostile.cpp.
#include <cstddef>
#include <cstdint>

#include "parallaxes/assets/image.h"
#include "parallaxes/core/limits.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // One channel count per input, chosen by its first byte, so each
    // conversion path sees the same structures.
    const int channels = size > 0 ? 1 + data[0] % 4 : 4;
    // TGA has no signature: it is read only from files named *.tga.
    const char* name = size > 0 && (data[0] & 4) ? "fuzz.tga" : "fuzz.png";
    // Images up to 256 per side: the checks and decoders are the same, and
    // the fuzzer runs far more inputs than at 4096 (each a 64 MB decode).
    constexpr int kSide = 256;
    px::Result<px::Image> image = px::decode_image(data, size, name, channels, kSide);
    if (image) {
        if (image->width < 1 || image->height < 1 || image->width > kSide ||
            image->height > kSide || image->channels != channels ||
            image->pixels.size() != static_cast<std::size_t>(image->width) * image->height * channels)
            __builtin_trap();
    }
    return 0;
}
