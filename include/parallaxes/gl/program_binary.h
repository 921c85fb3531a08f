// Program binaries kept across runs behind two host callbacks (bgfx's
// CallbackI::cacheRead/cacheWrite): the library never touches files; the host
// (or tools/ for the command line) decides where entries live. ProgramCache
// (gl/program.h) asks for an entry before compiling and hands one over after
// every fresh link; everything here validates an entry before the driver
// sees it, and a bad one is only ever discarded and rebuilt.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "parallaxes/core/caps.h"
#include "parallaxes/core/result.h"
#include "parallaxes/core/siphash.h"
#include "parallaxes/gl/errors.h"
#include "parallaxes/gl/gl.h"
#include "parallaxes/gl/handles.h"

namespace px {

// The host's storage. `load` returns the bytes last stored under `key`, or
// nullopt when it has none; `store` keeps them (a failure is the host's to
// report: the render goes on either way). Keys are 16 lowercase hex digits,
// safe as file names. Either may be empty: no lookups, or no writes.
struct ProgramBinaryStore {
    std::function<std::optional<std::vector<std::uint8_t>>(const std::string& key)> load;
    std::function<void(const std::string& key, const std::vector<std::uint8_t>& bytes)> store;
    // The host's secret: every entry carries a SipHash-2-4 of its header,
    // identity and payload under it, so an entry made or altered by anyone
    // without it (another user, a shared CI cache) is refused before the
    // driver sees it. Keep it where only the user can read it (the command
    // line keeps a random one, mode 0600, in its cache folder). All zero:
    // entries are still checked for damage, but anyone who can write the
    // store can forge one.
    SipKey secret{};
    bool enabled() const { return load || store; }
};

// What a ProgramCache did, for the host and `parallax render`.
struct ProgramStats {
    int compiled = 0;     // compiled and linked from source
    int from_binary = 0;  // loaded from a stored entry
    int rejected = 0;     // stored entries discarded (each then compiled and stored afresh)
    std::string last_rejection;  // why the last one was discarded
    // Why the last freshly linked program's binary could not be read back
    // for the store (the program itself is fine); empty: none failed.
    std::string store_problem;
    // Empty while binaries are in use; otherwise why not (no store given,
    // no binary formats on this context, ...).
    std::string binaries_off;
};

// Whether and how the current context saves and restores program binaries:
// OpenGL ES 3.0 core (glGetProgramBinary) or, on ES 2.0,
// GL_OES_get_program_binary through the host's loader. Both need
// GL_NUM_PROGRAM_BINARY_FORMATS > 0: Mesa lists the extension even when it
// offers no format (MESA_SHADER_CACHE_DISABLE=true).
struct ProgramBinarySupport {
    bool available = false;
    std::string unavailable_reason;  // when !available
    bool core = false;               // ES 3.0 entry points (GL_PROGRAM_BINARY_RETRIEVABLE_HINT exists)
    std::vector<GLenum> formats;     // GL_PROGRAM_BINARY_FORMATS
    // GL_RENDERER, GL_VERSION and the formats: what a binary is valid for.
    std::string context_identity;
    PFNGLGETPROGRAMBINARYOESPROC get_binary = nullptr;
    PFNGLPROGRAMBINARYOESPROC program_binary = nullptr;
};

// Queries the current context (the ES 2.0 entry points through `get_proc`).
ProgramBinarySupport query_program_binary_support(const Caps& caps, GetProcAddress get_proc);

// Bump when the entry layout, the identity's contents or anything a binary
// silently depends on (the attribute bindings' meaning) changes: it is part
// of every key and of the header, so old entries are missed, not misread.
inline constexpr std::uint32_t kProgramBinaryEntryVersion = 2;

// The entry's header, little-endian, before the driver's payload:
//   offset  0  4 bytes  magic "PXPB"
//   offset  4  u32      kProgramBinaryEntryVersion
//   offset  8  u32      the GL binary format (glGetProgramBinary's)
//   offset 12  u32      payload length in bytes
//   offset 16  u64      SipHash-2-4 under the store's secret of bytes 0..15,
//                       the identity check and the payload (one
//                       authenticates the header, the program it is for and
//                       the driver's bytes together)
//   offset 24  u64      the program's identity check (below)
inline constexpr std::size_t kProgramBinaryHeaderSize = 32;
inline constexpr std::size_t kProgramBinaryLengthOffset = 12;

// 64-bit FNV-1a, continuing from `state`.
inline constexpr std::uint64_t kFnv64Offset = 0xcbf29ce484222325ull;
std::uint64_t fnv1a64(const void* bytes, std::size_t size, std::uint64_t state = kFnv64Offset);

// A program's key and identity check: both hash the entry version, the
// context identity, the attribute bindings and both final sources (after the
// shader transform). The check starts from another offset basis, so an entry
// that lands under a colliding key still fails it.
struct ProgramBinaryIdentity {
    std::string key;          // 16 lowercase hex digits
    std::uint64_t check = 0;  // stored in the header, compared on load
};
ProgramBinaryIdentity program_binary_identity(const std::string& context_identity, const std::string& vertex,
                                              const std::string& fragment);

std::vector<std::uint8_t> encode_program_binary_entry(std::uint64_t identity_check, GLenum format,
                                                      const std::vector<std::uint8_t>& payload,
                                                      const SipKey& secret = SipKey{});

// The payload of a valid entry (pointing into `bytes`).
struct ProgramBinaryPayload {
    GLenum format = GL_NONE;
    const std::uint8_t* data = nullptr;
    std::size_t size = 0;
};
// Refuses, saying why: a short or truncated entry, another magic or entry
// version, a length that disagrees with the bytes, an entry that fails its
// authentication under `secret` (damaged, made without the secret, or one
// program's payload under another's header), an entry made for another
// program (identity check) or a format this context lacks.
Result<ProgramBinaryPayload> decode_program_binary_entry(const std::vector<std::uint8_t>& bytes,
                                                         std::uint64_t identity_check,
                                                         const std::vector<GLenum>& formats,
                                                         const SipKey& secret = SipKey{});

// The linked program's binary (link it after set_binary_retrievable on ES
// 3.0); `format` receives its format.
Result<std::vector<std::uint8_t>> read_program_binary(const ProgramBinarySupport& support, GLuint program,
                                                      GLenum& format);
// Before glLinkProgram: ask the driver to keep the binary retrievable (ES 3.0).
void set_binary_retrievable(const ProgramBinarySupport& support, GLuint program);

// A new program object with the interface's attribute bindings, loaded from a
// binary. Fails on a GL error or GL_LINK_STATUS false, with the driver's log.
Result<ProgramHandle> program_from_binary(const ProgramBinarySupport& support, const ProgramBinaryPayload& payload);

}  // namespace px
