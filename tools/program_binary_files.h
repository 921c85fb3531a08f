// The command line's program-binary store (gl/program_binary.h): one file
// per key in a folder. File I/O stays here, out of the library.
#pragma once

#include <cstddef>
#include <string>

#include "parallaxes/gl/program_binary.h"

namespace px::tools {

// An entry larger than this is not read (Mesa's llvmpipe binaries of our
// largest variants are well under 1 MiB).
inline constexpr std::size_t kMaxProgramBinaryEntryBytes = std::size_t{16} << 20;

// $XDG_CACHE_HOME/parallaxes/programs, else $HOME/.cache/parallaxes/programs;
// empty when neither is set. A relative XDG_CACHE_HOME is ignored, as the
// XDG Base Directory specification asks.
std::string default_program_cache_dir();

// Entries in `dir` as KEY.pxbin, written atomically (core/files.h) and read
// with a size cap. The folder is made mode 0700 and holds `key`: 16 random
// bytes (mode 0600, made on first use), the store's secret that every entry
// is authenticated with (ProgramBinaryStore::secret), so entries written by
// anyone who cannot read it are refused. Binaries are not used, with a
// warning, where the folder or the key is not this user's, or the folder is
// writable or the key readable by other users. An entry owned by another
// user is ignored (compiled afresh, then replaced). A missing entry is a
// miss; any other failure (unreadable entry, folder not writable) is a
// warning on stderr, the first of each kind only, and never fails the render.
ProgramBinaryStore file_program_store(const std::string& dir);

}  // namespace px::tools
