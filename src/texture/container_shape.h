// Inside texture/: the container readers with a stop after the header.
// With `shape` non-null each fills it once the header's fields are checked
// (exactly as the full read checks them) and returns an empty TextureData,
// reading nothing past the header (texture_file.cpp's read_texture_shape).
#pragma once

#include "parallaxes/texture/containers.h"

namespace px::container_detail {

Result<TextureData> read_ktx1(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes, TextureShape* header_only);
Result<TextureData> read_ktx2(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes, TextureShape* header_only);
Result<TextureData> read_pvr3(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes, TextureShape* header_only);
Result<TextureData> read_astc(const std::uint8_t* bytes, std::size_t size, std::uint64_t max_bytes, TextureShape* header_only);

}  // namespace px::container_detail
