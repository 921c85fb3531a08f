// Writing an output file safely, one implementation for every writer (PNG
// images, benchmark reports): the bytes go to a temporary file created
// exclusively beside the target (never one that exists, a planted symlink
// included), which is then renamed over it. Readers never see a partial
// file, and a failure leaves the previous file intact and removes the
// temporary. A character device or named pipe (`-o /dev/null`, `-o
// /dev/stdout`, a FIFO), directly or where a link leads, is written into
// as it is instead; a block device or socket is refused.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"

namespace px {

// Errors name the path and the system's reason: the folder is missing or not
// writable, the disk is full, the target is write-protected (an existing
// file we may not write is refused, not silently replaced) or a folder.
Status write_file_atomically(const std::string& path, const void* bytes, std::size_t size);
inline Status write_file_atomically(const std::string& path, const std::string& text) {
    return write_file_atomically(path, text.data(), text.size());
}

// The first max_bytes bytes of a regular file (all of it if shorter),
// refused as read_file_bounded refuses (missing, folder, FIFO, device), with
// no limit on the file's size: what a header is read from.
Result<std::vector<std::uint8_t>> read_file_prefix(const std::string& path, std::size_t max_bytes,
                                                   const std::string& what);

// Reads a whole regular file of at most max_bytes. Refused, naming the path
// and `what` ("scene file", "image"): a missing or unreadable file, a folder,
// a FIFO or device (which could block or never end), a file over the limit
// (checked before anything is allocated for it, and again while reading, in
// case it grows).
Result<std::vector<std::uint8_t>> read_file_bounded(const std::string& path, std::size_t max_bytes,
                                                    const std::string& what);

}  // namespace px
