#include "parallaxes/gl/program_binary.h"

#include <algorithm>
#include <cstdio>
#include <initializer_list>
#include <limits>

#include "parallaxes/shaders/interface.h"

namespace px {

namespace {

constexpr std::uint8_t kMagic[4] = {'P', 'X', 'P', 'B'};
constexpr std::uint64_t kFnv64Prime = 0x100000001b3ull;

std::string gl_string(GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? reinterpret_cast<const char*>(s) : "";
}

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_u64(std::vector<std::uint8_t>& out, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
std::uint64_t get_le(const std::uint8_t* p, int bytes) {
    std::uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}

std::string hex(std::uint64_t v) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

}  // namespace

std::uint64_t fnv1a64(const void* bytes, std::size_t size, std::uint64_t state) {
    const auto* p = static_cast<const std::uint8_t*>(bytes);
    for (std::size_t i = 0; i < size; ++i) state = (state ^ p[i]) * kFnv64Prime;
    return state;
}

ProgramBinarySupport query_program_binary_support(const Caps& caps, GetProcAddress get_proc) {
    ProgramBinarySupport s;
    s.core = caps.context_es3();
    if (s.core) {
        s.get_binary = glGetProgramBinary;
        s.program_binary = glProgramBinary;
    } else {
        if (!caps.has("GL_OES_get_program_binary")) {
            s.unavailable_reason = "this OpenGL ES 2.0 context lacks GL_OES_get_program_binary";
            return s;
        }
        if (!get_proc) {
            s.unavailable_reason = "GL_OES_get_program_binary needs RendererOptions::get_proc_address";
            return s;
        }
        s.get_binary = reinterpret_cast<PFNGLGETPROGRAMBINARYOESPROC>(get_proc("glGetProgramBinaryOES"));
        s.program_binary = reinterpret_cast<PFNGLPROGRAMBINARYOESPROC>(get_proc("glProgramBinaryOES"));
        if (!s.get_binary || !s.program_binary) {
            s.unavailable_reason = "get_proc_address found no glGetProgramBinaryOES/glProgramBinaryOES";
            return s;
        }
    }
    GLint count = 0;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &count);
    if (!check_gl("glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS)") || count <= 0 || count > 64) {
        s.unavailable_reason = "the context offers no program binary format (GL_NUM_PROGRAM_BINARY_FORMATS is " +
                               std::to_string(count) + "; Mesa offers none with MESA_SHADER_CACHE_DISABLE set)";
        return s;
    }
    std::vector<GLint> formats(static_cast<size_t>(count), 0);
    glGetIntegerv(GL_PROGRAM_BINARY_FORMATS, formats.data());
    if (!check_gl("glGetIntegerv(GL_PROGRAM_BINARY_FORMATS)")) {
        s.unavailable_reason = "glGetIntegerv(GL_PROGRAM_BINARY_FORMATS) failed";
        return s;
    }
    for (GLint f : formats) s.formats.push_back(static_cast<GLenum>(f));
    std::sort(s.formats.begin(), s.formats.end());
    s.context_identity = gl_string(GL_VENDOR) + "\n" + gl_string(GL_RENDERER) + "\n" + gl_string(GL_VERSION) +
                         "\nformats";
    for (GLenum f : s.formats) s.context_identity += " " + std::to_string(f);
    s.available = true;
    return s;
}

ProgramBinaryIdentity program_binary_identity(const std::string& context_identity, const std::string& vertex,
                                              const std::string& fragment) {
    std::string bindings;
    for (const shader::AttributeInfo& a : shader::attributes())
        bindings += std::string(a.name) + "=" + std::to_string(a.slot) + ";";
    const std::string version = "parallaxes program binary " + std::to_string(kProgramBinaryEntryVersion);
    // Each part with its length first, so no two different sets of parts
    // hash the same bytes.
    const std::initializer_list<const std::string*> parts = {&version, &context_identity, &bindings, &vertex,
                                                             &fragment};
    const auto hash = [&](std::uint64_t state) {
        for (const std::string* part : parts) {
            const std::uint64_t length = part->size();
            state = fnv1a64(&length, sizeof length, state);
            state = fnv1a64(part->data(), part->size(), state);
        }
        return state;
    };
    static const char kCheckTag[] = "identity check";
    ProgramBinaryIdentity id;
    id.key = hex(hash(kFnv64Offset));
    id.check = hash(fnv1a64(kCheckTag, sizeof kCheckTag - 1));
    return id;
}

namespace {

// The entry's authentication: SipHash-2-4 of header bytes 0..15, the
// identity check and the payload.
std::uint64_t entry_mac(const SipKey& secret, const std::uint8_t* head16, std::uint64_t identity_check,
                        const std::uint8_t* payload, std::size_t size) {
    std::vector<std::uint8_t> message(head16, head16 + 16);
    message.reserve(24 + size);
    put_u64(message, identity_check);
    message.insert(message.end(), payload, payload + size);
    return siphash24(secret, message.data(), message.size());
}

}  // namespace

std::vector<std::uint8_t> encode_program_binary_entry(std::uint64_t identity_check, GLenum format,
                                                      const std::vector<std::uint8_t>& payload, const SipKey& secret) {
    std::vector<std::uint8_t> out(kMagic, kMagic + 4);
    out.reserve(kProgramBinaryHeaderSize + payload.size());
    put_u32(out, kProgramBinaryEntryVersion);
    put_u32(out, static_cast<std::uint32_t>(format));
    put_u32(out, static_cast<std::uint32_t>(payload.size()));
    put_u64(out, entry_mac(secret, out.data(), identity_check, payload.data(), payload.size()));
    put_u64(out, identity_check);
    out.insert(out.end(), payload.begin(), payload.end());
    return out;
}

Result<ProgramBinaryPayload> decode_program_binary_entry(const std::vector<std::uint8_t>& bytes,
                                                         std::uint64_t identity_check,
                                                         const std::vector<GLenum>& formats, const SipKey& secret) {
    if (bytes.size() < kProgramBinaryHeaderSize)
        return make_error("entry of " + std::to_string(bytes.size()) + " bytes is shorter than its " +
                          std::to_string(kProgramBinaryHeaderSize) + "-byte header");
    const std::uint8_t* p = bytes.data();
    if (!std::equal(kMagic, kMagic + 4, p)) return make_error("entry does not start with the magic 'PXPB'");
    const std::uint64_t version = get_le(p + 4, 4);
    if (version != kProgramBinaryEntryVersion)
        return make_error("entry version " + std::to_string(version) + ", expected " +
                          std::to_string(kProgramBinaryEntryVersion));
    const std::uint64_t length = get_le(p + kProgramBinaryLengthOffset, 4);
    const std::size_t available = bytes.size() - kProgramBinaryHeaderSize;
    if (length != available)
        return make_error("entry header gives a payload of " + std::to_string(length) + " bytes, the entry holds " +
                          std::to_string(available) + (length > available ? " (truncated)" : ""));
    if (length == 0) return make_error("entry has an empty payload");
    const std::uint8_t* payload = p + kProgramBinaryHeaderSize;
    // Which program it claims to be for first (a plain mismatch is the
    // common case: sources changed), then whether the header, that claim
    // and the payload were written together by someone holding the secret.
    const std::uint64_t claimed = get_le(p + 24, 8);
    if (claimed != identity_check)
        return make_error("entry was made for another program (sources, driver or bindings differ)");
    if (entry_mac(secret, p, claimed, payload, available) != get_le(p + 16, 8))
        return make_error("entry fails its authentication (damaged, or not written with this store's secret)");
    const GLenum format = static_cast<GLenum>(get_le(p + 8, 4));
    if (std::find(formats.begin(), formats.end(), format) == formats.end())
        return make_error("entry's binary format " + std::to_string(format) + " is not one this context offers");
    return ProgramBinaryPayload{format, payload, available};
}

void set_binary_retrievable(const ProgramBinarySupport& support, GLuint program) {
    // ES 3.0 section 2.12.3: without the hint a driver may not keep the
    // binary. GL_OES_get_program_binary has no such parameter.
    if (support.available && support.core) glProgramParameteri(program, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
}

Result<std::vector<std::uint8_t>> read_program_binary(const ProgramBinarySupport& support, GLuint program,
                                                      GLenum& format) {
    if (!support.available) return make_error("program binaries are unavailable: " + support.unavailable_reason);
    GLint length = 0;
    glGetProgramiv(program, GL_PROGRAM_BINARY_LENGTH, &length);
    Status s = check_gl("glGetProgramiv(GL_PROGRAM_BINARY_LENGTH)");
    if (!s) return s.error();
    if (length <= 0) return make_error("the driver gives a program binary length of " + std::to_string(length));
    if (static_cast<std::uint64_t>(length) > std::numeric_limits<std::uint32_t>::max() - kProgramBinaryHeaderSize)
        return make_error("the driver's program binary is too large to store");
    std::vector<std::uint8_t> bytes(static_cast<size_t>(length));
    GLsizei written = 0;
    format = GL_NONE;
    support.get_binary(program, length, &written, &format, bytes.data());
    s = check_gl("glGetProgramBinary");
    if (!s) return s.error();
    if (written <= 0 || written > length)
        return make_error("glGetProgramBinary wrote " + std::to_string(written) + " bytes");
    bytes.resize(static_cast<size_t>(written));
    return bytes;
}

Result<ProgramHandle> program_from_binary(const ProgramBinarySupport& support, const ProgramBinaryPayload& payload) {
    if (!support.available) return make_error("program binaries are unavailable: " + support.unavailable_reason);
    if (payload.size > static_cast<std::size_t>(std::numeric_limits<GLsizei>::max()))
        return make_error("binary of " + std::to_string(payload.size) + " bytes is too large for glProgramBinary");
    ProgramHandle program(glCreateProgram());
    // A binary carries the bindings it was linked with (they are part of the
    // identity); bound here too so that the program object's own state
    // agrees, and build_program's slot check verifies the outcome.
    for (const shader::AttributeInfo& a : shader::attributes())
        glBindAttribLocation(program.get(), static_cast<GLuint>(a.slot), a.name);
    support.program_binary(program.get(), payload.format, payload.data, static_cast<GLsizei>(payload.size));
    Status s = check_gl("glProgramBinary");
    if (!s) return s.error();
    GLint ok = GL_FALSE;
    glGetProgramiv(program.get(), GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = program_info_log(program.get());
        return make_error("the driver refused the binary (GL_LINK_STATUS false)" +
                          (log.empty() ? std::string() : ": " + log));
    }
    return program;
}

}  // namespace px
