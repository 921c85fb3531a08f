// Texture containers: KTX 1.1, KTX 2.0 (no or Zstandard supercompression)
// and PVR v3, read into TextureData and written from it (texture/ktx.cpp,
// texture/pvr.cpp, texture/texture_file.cpp).
//
// Readers validate every header field before any allocation or read: the
// identifier, endianness, format codes, extents (1..kMaxTextureSize; 2D
// textures only: depth 0 or 1), level counts (0 means "generate" in KTX and
// is refused: levels are used as given), layers and faces, key/value data
// lengths, level sizes and offsets against the file's size and against the
// format's block arithmetic, all with overflow-checked 64-bit arithmetic, and
// the total against max_bytes. Errors name the container and the field
// ("KTX 2.0 level index [2].byteOffset 81920 + byteLength 4096 passes the end
// of the 65536-byte file"); the caller prefixes the file name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/texture/texture_data.h"

namespace px {

// Default bound on the decoded bytes of one texture file (all levels,
// layers and faces): a 4096 x 4096 RGBA8 image with its mip chain is 89 MB.
inline constexpr std::uint64_t kMaxTextureFileBytes = std::uint64_t{128} << 20;

Result<TextureData> read_ktx1(const std::uint8_t* bytes, std::size_t size,
                              std::uint64_t max_bytes = kMaxTextureFileBytes);
Result<TextureData> read_ktx2(const std::uint8_t* bytes, std::size_t size,
                              std::uint64_t max_bytes = kMaxTextureFileBytes);
Result<TextureData> read_pvr3(const std::uint8_t* bytes, std::size_t size,
                              std::uint64_t max_bytes = kMaxTextureFileBytes);
// astcenc's .astc file: magic 0x5CA1AB13, block size (2D: z = 1), 24-bit
// extents, then the blocks row by row, one level. It declares no
// orientation: read top row first, as astcenc writes it from a PNG and
// shows it decoded.
Result<TextureData> read_astc(const std::uint8_t* bytes, std::size_t size,
                              std::uint64_t max_bytes = kMaxTextureFileBytes);

// Which container the bytes start with (KTX 1.1, KTX 2.0 or PVR v3
// identifier), or nullopt-like ContainerKind::image for anything else.
ContainerKind sniff_container(const std::uint8_t* bytes, std::size_t size);
// Any of the four by its identifier; errors for anything else.
Result<TextureData> read_texture(const std::uint8_t* bytes, std::size_t size,
                                 std::uint64_t max_bytes = kMaxTextureFileBytes);
// Reads a file (a regular file of at most kMaxImageFileBytes); errors are
// prefixed with the path.
Result<TextureData> read_texture_file(const std::string& path, std::uint64_t max_bytes = kMaxTextureFileBytes);

// What a container's header says, read before anything is allocated or
// inflated: enough to refuse a texture of the wrong kind (an array, a cube
// map) or size before reading its data. `bytes` is what it decodes to (every
// level, layer and face), from the format's block arithmetic (TextureShape,
// texture_data.h).
// The header fields are checked as the full readers check them (the same
// errors); nothing past the header is read, so the first
// kTextureHeaderBytes of a file are enough.
inline constexpr std::size_t kTextureHeaderBytes = 128;
Result<TextureShape> read_texture_shape(const std::uint8_t* bytes, std::size_t size);
// Reads only the file's first kTextureHeaderBytes; errors name the path.
Result<TextureShape> read_texture_file_shape(const std::string& path);

// Writers: little-endian, the data as `texture.rows` says and declared so:
// KTX 1.1 KTXorientation "S=r,T=d" (top row first) or "S=r,T=u"; KTX 2.0 "rd"
// or "ru", with a basic data format descriptor and optional zstd
// supercompression (level 1..22); PVR v3 with its orientation metadata (y
// down or up). texture/convert.h's encoders make top-first data.
Result<std::vector<std::uint8_t>> write_ktx1(const TextureData& texture);
Result<std::vector<std::uint8_t>> write_ktx2(const TextureData& texture, int zstd_level = 0);
Result<std::vector<std::uint8_t>> write_pvr3(const TextureData& texture);

}  // namespace px
