// Shared by the texture container fuzz targets: what a successful read must
// satisfy (texture/texture_data.h), trapping where it does not.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "parallaxes/core/limits.h"
#include "parallaxes/texture/containers.h"

namespace px_fuzz {

// Decoded bytes per input: small enough that the fuzzer runs many inputs,
// large enough for every check (a 4096 x 4096 header is refused here by
// the bound, not by a 64 MB allocation).
inline constexpr std::uint64_t kFuzzMaxBytes = std::uint64_t{16} << 20;

inline void check_texture(const px::Result<px::TextureData>& result, px::ContainerKind kind) {
    if (!result) {
        if (result.error().message.empty()) __builtin_trap();
        return;
    }
    const px::TextureData& t = result.value();
    const std::uint32_t max = static_cast<std::uint32_t>(px::kMaxTextureSize);
    if (t.container != kind || t.width < 1 || t.height < 1 || t.width > max || t.height > max) __builtin_trap();
    if (t.layers < 1 || (t.faces != 1 && t.faces != 6)) __builtin_trap();
    if (t.faces == 6 && t.width != t.height) __builtin_trap();
    if (t.levels.empty() || t.levels.size() > static_cast<std::size_t>(px::full_mip_count(t.width, t.height)))
        __builtin_trap();
    if ((kind == px::ContainerKind::ktx2) != !t.supercompression.empty()) __builtin_trap();
    std::uint64_t offset = 0;
    for (std::size_t i = 0; i < t.levels.size(); ++i) {
        const px::TextureLevel& l = t.levels[i];
        const auto one = px::image_bytes(t.format, l.width, l.height);
        if (l.width != px::mip_extent(t.width, static_cast<int>(i)) ||
            l.height != px::mip_extent(t.height, static_cast<int>(i)) || !one || *one != l.image_bytes ||
            l.offset != offset)
            __builtin_trap();
        offset += *one * t.layers * t.faces;
    }
    if (offset != t.bytes.size() || offset > kFuzzMaxBytes) __builtin_trap();
}

// A texture that was read is written by the container's own writer and read
// again: the writer must take it and the reader must give it back unchanged.
template <typename Write, typename Read>
void check_round_trip(const px::Result<px::TextureData>& result, Write write, Read read) {
    if (!result) return;
    const px::TextureData& t = result.value();
    const px::Result<std::vector<std::uint8_t>> file = write(t);
    if (!file) __builtin_trap();
    const px::Result<px::TextureData> again = read(file.value().data(), file.value().size(), kFuzzMaxBytes);
    if (!again) __builtin_trap();
    const px::TextureData& u = again.value();
    if (u.format != t.format || u.width != t.width || u.height != t.height || u.layers != t.layers ||
        u.faces != t.faces || u.levels.size() != t.levels.size() || u.bytes != t.bytes)
        __builtin_trap();
}

// The header alone (read_texture_shape, what scene checks look at before
// inflating anything) agrees with the full read: a header it refuses is
// refused by the full read too, and a texture read whole has the shape the
// header gave, from the first kTextureHeaderBytes alone.
inline void check_shape(const std::uint8_t* data, std::size_t size, const px::Result<px::TextureData>& result) {
    const px::Result<px::TextureShape> whole = px::read_texture_shape(data, size);
    const std::size_t head_size = size < px::kTextureHeaderBytes ? size : px::kTextureHeaderBytes;
    const px::Result<px::TextureShape> head = px::read_texture_shape(data, head_size);
    if (!whole && result) __builtin_trap();
    if (whole.ok() != head.ok()) __builtin_trap();
    if (!result) return;
    const px::TextureData& t = result.value();
    const px::TextureShape& s = whole.value();
    if (s.container != t.container || s.format != t.format || s.width != t.width || s.height != t.height ||
        s.layers != t.layers || s.faces != t.faces || s.levels != t.levels.size() || s.bytes != t.bytes.size())
        __builtin_trap();
}

}  // namespace px_fuzz
