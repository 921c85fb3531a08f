// SipHash-2-4 (Aumasson and Bernstein, "SipHash: a fast short-input PRF",
// 2012): a keyed 64-bit hash that whoever lacks the 128-bit key cannot
// compute. The program-binary cache authenticates its entries with it
// (gl/program_binary.h): a checksum alone can be recomputed by anyone who
// can write the cache.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace px {

using SipKey = std::array<std::uint8_t, 16>;

// SipHash-2-4 of `size` bytes under `key`.
std::uint64_t siphash24(const SipKey& key, const void* data, std::size_t size);

}  // namespace px
