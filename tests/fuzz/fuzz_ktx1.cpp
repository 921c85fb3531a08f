// libFuzzer target: bytes through the KTX 1.1 reader (texture/containers.h)
// with a 16 MB bound on the decoded texture. A successful read must have
// the layout texture_data.h describes (levels, extents, image sizes from the
// block arithmetic, bytes.size() their sum); an error must say something.
// A read that rewrites its result as its own writer would is read again and
// must give the same texture. Findings become tests in
// tests/unit_texture_containers.cpp.
#include <cstddef>
#include <cstdint>

#include "texture_invariants.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const px::Result<px::TextureData> texture = px::read_ktx1(data, size, px_fuzz::kFuzzMaxBytes);
    px_fuzz::check_texture(texture, px::ContainerKind::ktx1);
    px_fuzz::check_shape(data, size, texture);
    px_fuzz::check_round_trip(
        texture, [](const px::TextureData& t) { return px::write_ktx1(t); },
        [](const std::uint8_t* p, std::size_t n, std::uint64_t max) { return px::read_ktx1(p, n, max); });
    return 0;
}
