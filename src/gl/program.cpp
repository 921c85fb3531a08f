#include "parallaxes/gl/program.h"
#include "parallaxes/core/counters.h"

#include <cstdlib>
#include <optional>
#include <sstream>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "parallaxes/gl/errors.h"

namespace px {

namespace {

std::string shader_log(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(length > 1 ? length : 1), '\0');
    glGetShaderInfoLog(shader, length, nullptr, &log[0]);
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

// The source lines the log points at, quoted (shader_log_lines: Mesa's and
// most ES drivers' "0:LINE", NVIDIA's "0(LINE)").
std::string quote_lines(const std::string& source, const std::string& log) {
    std::vector<std::string> lines;
    std::istringstream in(source);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    std::string out;
    for (long line : shader_log_lines(log))
        if (line <= static_cast<long>(lines.size()))
            out += "  " + std::to_string(line) + " | " + lines[static_cast<size_t>(line - 1)] + "\n";
    return out;
}

Result<ShaderHandle> compile(GLenum stage, const AssembledSource& source, const std::string& description) {
    ShaderHandle shader(glCreateShader(stage));
    const char* text = source.text.c_str();
    glShaderSource(shader.get(), 1, &text, nullptr);
    glCompileShader(shader.get());
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.get(), GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = shader_log(shader.get());
        return make_error(std::string(stage == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                          " shader of variant '" + description + "' failed to compile\n  defines: " +
                          source.defines_summary + "\n  driver log:\n" + log + quote_lines(source.text, log));
    }
    return shader;
}

}  // namespace

namespace {

GLenum gl_type(shader::Type t) {
    switch (t) {
        case shader::Type::float1: return GL_FLOAT;
        case shader::Type::vec2: return GL_FLOAT_VEC2;
        case shader::Type::vec3: return GL_FLOAT_VEC3;
        case shader::Type::vec4: return GL_FLOAT_VEC4;
        case shader::Type::mat2: return GL_FLOAT_MAT2;
        case shader::Type::mat3: return GL_FLOAT_MAT3;
        case shader::Type::mat4: return GL_FLOAT_MAT4;
        case shader::Type::int1: return GL_INT;
        case shader::Type::sampler2d: return GL_SAMPLER_2D;
    }
    return GL_NONE;
}

// Checks the linked program against the interface table, both ways.
Status check_interface(GLuint program, const std::string& what) {
    GLint count = 0, longest = 0;
    glGetProgramiv(program, GL_ACTIVE_UNIFORMS, &count);
    glGetProgramiv(program, GL_ACTIVE_UNIFORM_MAX_LENGTH, &longest);
    std::vector<char> buffer(static_cast<size_t>(longest > 0 ? longest : 1) + 1, '\0');
    for (GLint i = 0; i < count; ++i) {
        GLsizei length = 0;
        GLint size = 0;
        GLenum type = GL_NONE;
        glGetActiveUniform(program, static_cast<GLuint>(i), static_cast<GLsizei>(buffer.size()), &length, &size,
                           &type, buffer.data());
        std::string name(buffer.data(), static_cast<size_t>(length));
        // Arrays are reported as "u_name[0]".
        const size_t bracket = name.find('[');
        if (bracket != std::string::npos) name.resize(bracket);
        // Built-in uniforms (gl_DepthRange) may be listed as active too.
        if (name.rfind("gl_", 0) == 0) continue;
        const shader::UniformInfo* found = nullptr;
        for (const shader::UniformInfo& u : shader::uniforms())
            if (name == u.name) found = &u;
        if (!found)
            return make_error(what + ": the shader has uniform '" + name +
                              "', which include/parallaxes/shaders/interface.h does not list, so the renderer never sets it");
        if (gl_type(found->type) != type || size > found->array_size)
            return make_error(what + ": uniform '" + name + "' is declared with another type or array size than "
                              "include/parallaxes/shaders/interface.h gives (" + shader::type_name(found->type) +
                              (found->array_size > 1 ? "[" + std::to_string(found->array_size) + "]" : "") + ")");
    }
    return {};
}

}  // namespace

namespace {

// Compiles and links a variant's sources at the interface's attribute slots;
// with `binaries`, asks the driver to keep the binary for the store.
Result<ProgramHandle> link_sources(const VariantSources& sources, const std::string& description,
                                   const ProgramBinarySupport* binaries) {
    Result<ShaderHandle> vs = compile(GL_VERTEX_SHADER, sources.vertex, description);
    if (!vs) return vs.error();
    Result<ShaderHandle> fs = compile(GL_FRAGMENT_SHADER, sources.fragment, description);
    if (!fs) return fs.error();
    ProgramHandle program(glCreateProgram());
    glAttachShader(program.get(), vs->get());
    glAttachShader(program.get(), fs->get());
    // Fixed attribute slots from the interface table, so one vertex layout
    // serves every variant.
    for (const shader::AttributeInfo& a : shader::attributes())
        glBindAttribLocation(program.get(), static_cast<GLuint>(a.slot), a.name);
    if (binaries) set_binary_retrievable(*binaries, program.get());
    glLinkProgram(program.get());
    GLint ok = GL_FALSE;
    glGetProgramiv(program.get(), GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE)
        return make_error("variant '" + description + "' failed to link\n  defines: " +
                          sources.fragment.defines_summary + "\n  driver log:\n" + program_info_log(program.get()));
    return program;
}

}  // namespace

Result<std::unique_ptr<Program>> Program::adopt(ProgramHandle program, const VariantKey& key,
                                                const std::string& defines_summary) {
    const std::string description = key.describe();
    const std::string what = "variant '" + description + "'\n  defines: " + defines_summary + "\n ";
    std::unique_ptr<Program> p(new Program());
    p->description_ = description;
    p->key_ = key;
    for (const shader::UniformInfo& u : shader::uniforms()) {
        const GLint location = glGetUniformLocation(program.get(), u.name);
        if (location < 0 && shader::needed(u.id, key))
            return make_error(what + " needs uniform '" + std::string(u.name) +
                              "' (include/parallaxes/shaders/interface.h), and the linked program has no active uniform of that "
                              "name: a misspelt or unused declaration in shaders_es/");
        p->uniforms_[static_cast<std::size_t>(u.id)] = location;
    }
    for (const shader::AttributeInfo& a : shader::attributes()) {
        const GLint location = glGetAttribLocation(program.get(), a.name);
        if (location < 0 && shader::needed(a.id, key))
            return make_error(what + " needs attribute '" + std::string(a.name) +
                              "' (include/parallaxes/shaders/interface.h), and the linked program has no active attribute of that "
                              "name");
        if (location >= 0 && location != a.slot)
            return make_error(what + " attribute '" + std::string(a.name) + "' linked at slot " +
                              std::to_string(location) + ", not at its bound slot " + std::to_string(a.slot));
        p->attributes_[static_cast<std::size_t>(a.id)] = location;
    }
    Status interface = check_interface(program.get(), "variant '" + description + "'");
    if (!interface) return interface.error();

    // Sampler units are per program state: set them once, here.
    GLint previous = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &previous);
    glUseProgram(program.get());
    for (const shader::SamplerInfo& s : shader::samplers()) {
        const GLint location = p->uniforms_[static_cast<std::size_t>(s.uniform)];
        if (location >= 0) glUniform1i(location, s.unit);
    }
    // (A previous program the host deleted while current is gone now.)
    glUseProgram(previous != 0 && glIsProgram(static_cast<GLuint>(previous)) ? static_cast<GLuint>(previous) : 0);
    Status s = check_gl("building variant '" + description + "'");
    if (!s) return s.error();
    p->handle_ = std::move(program);
    return p;
}

Result<std::unique_ptr<Program>> build_program(const VariantSources& sources, const VariantKey& key) {
    Result<ProgramHandle> program = link_sources(sources, key.describe(), nullptr);
    if (!program) return program.error();
    return Program::adopt(std::move(*program), key, sources.fragment.defines_summary);
}

#define PX_LOCATION(slot) const GLint l = location(slot.id); if (l < 0) return
void Program::set(shader::UniformSlot<shader::Type::float1> s, float v) const { PX_LOCATION(s); glUniform1f(l, v); }
void Program::set(shader::UniformSlot<shader::Type::float1> s, const float* v, int count) const {
    PX_LOCATION(s);
    glUniform1fv(l, count, v);
}
void Program::set(shader::UniformSlot<shader::Type::vec2> s, const glm::vec2& v) const {
    PX_LOCATION(s);
    glUniform2f(l, v.x, v.y);
}
void Program::set(shader::UniformSlot<shader::Type::vec3> s, const glm::vec3& v) const {
    PX_LOCATION(s);
    glUniform3fv(l, 1, glm::value_ptr(v));
}
void Program::set(shader::UniformSlot<shader::Type::vec3> s, const glm::vec3* v, int count) const {
    PX_LOCATION(s);
    glUniform3fv(l, count, glm::value_ptr(v[0]));
}
void Program::set(shader::UniformSlot<shader::Type::vec4> s, const glm::vec4* v, int count) const {
    PX_LOCATION(s);
    glUniform4fv(l, count, glm::value_ptr(v[0]));
}
void Program::set(shader::UniformSlot<shader::Type::mat2> s, const glm::mat2& v) const {
    PX_LOCATION(s);
    glUniformMatrix2fv(l, 1, GL_FALSE, glm::value_ptr(v));
}
void Program::set(shader::UniformSlot<shader::Type::mat3> s, const glm::mat3& v) const {
    PX_LOCATION(s);
    glUniformMatrix3fv(l, 1, GL_FALSE, glm::value_ptr(v));
}
void Program::set(shader::UniformSlot<shader::Type::mat4> s, const glm::mat4& v) const {
    PX_LOCATION(s);
    glUniformMatrix4fv(l, 1, GL_FALSE, glm::value_ptr(v));
}
void Program::set(shader::UniformSlot<shader::Type::int1> s, int v) const { PX_LOCATION(s); glUniform1i(l, v); }
#undef PX_LOCATION

ProgramCache::ProgramCache(ShaderTransform transform, ProgramBinaryStore store, ProgramBinarySupport support)
    : transform_(std::move(transform)), store_(std::move(store)), support_(std::move(support)) {
    if (!store_.enabled())
        stats_.binaries_off = "no program binary store";
    else if (!support_.available)
        stats_.binaries_off = support_.unavailable_reason.empty() ? "program binaries unavailable"
                                                                  : support_.unavailable_reason;
    else
        binaries_ = true;
}

Result<const Program*> ProgramCache::get(const VariantKey& key) {
    const std::string key_id = key.id();
    auto it = programs_.find(key_id);
    if (it != programs_.end()) return static_cast<const Program*>(it->second.get());
    Result<VariantSources> sources = assemble_variant(key);
    if (!sources) return sources.error();
    if (transform_) {
        for (auto [stage, source] : {std::pair{ShaderStage::vertex, &sources->vertex},
                                     std::pair{ShaderStage::fragment, &sources->fragment}}) {
            Result<std::string> rewritten = transform_(source->text, stage);
            if (!rewritten)
                return make_error("variant '" + key.describe() + "' " +
                                  (stage == ShaderStage::vertex ? "vertex" : "fragment") +
                                  " stage: the shader transform failed: " + rewritten.error().message);
            source->text = std::move(*rewritten);
        }
    }
    const std::string& defines = sources->fragment.defines_summary;
    std::optional<ProgramBinaryIdentity> id;
    if (binaries_) {
        // Keyed by the sources as compiled, after the transform.
        id = program_binary_identity(support_.context_identity, sources->vertex.text, sources->fragment.text);
        if (std::unique_ptr<Program> loaded = load_binary(*id, key, defines)) {
            ++stats_.from_binary;
            counters::count(counters::Step::program_build);
            const Program* raw = loaded.get();
            programs_.emplace(key_id, std::move(loaded));
            return raw;
        }
    }
    Result<ProgramHandle> linked = link_sources(*sources, key.describe(), binaries_ ? &support_ : nullptr);
    if (!linked) return linked.error();
    Result<std::unique_ptr<Program>> program = Program::adopt(std::move(*linked), key, defines);
    if (!program) return program.error();
    ++stats_.compiled;
    counters::count(counters::Step::program_build);
    if (id) store_binary(*id, (*program)->id());
    const Program* raw = program->get();
    programs_.emplace(key_id, std::move(*program));
    return raw;
}

std::unique_ptr<Program> ProgramCache::load_binary(const ProgramBinaryIdentity& id, const VariantKey& key,
                                                   const std::string& defines_summary) {
    if (!store_.load) return nullptr;
    const std::optional<std::vector<std::uint8_t>> bytes = store_.load(id.key);
    if (!bytes) return nullptr;
    // Whatever is wrong with an entry, the program is compiled from source
    // and a fresh entry stored in its place: a bad entry costs one compile.
    const auto reject = [&](const std::string& why) {
        ++stats_.rejected;
        stats_.last_rejection = "entry " + id.key + " (variant '" + key.describe() + "'): " + why;
        return nullptr;
    };
    Result<ProgramBinaryPayload> payload = decode_program_binary_entry(*bytes, id.check, support_.formats, store_.secret);
    if (!payload) return reject(payload.error().message);
    Result<ProgramHandle> program = program_from_binary(support_, *payload);
    if (!program) return reject(program.error().message);
    // The same checks as a program linked from source: a binary that loads
    // but does not match the typed interface is never used.
    Result<std::unique_ptr<Program>> adopted = Program::adopt(std::move(*program), key, defines_summary);
    if (!adopted) return reject("the loaded program fails the interface check: " + adopted.error().message);
    return std::move(*adopted);
}

void ProgramCache::store_binary(const ProgramBinaryIdentity& id, GLuint program) {
    if (!store_.store) return;
    GLenum format = GL_NONE;
    Result<std::vector<std::uint8_t>> payload = read_program_binary(support_, program, format);
    if (!payload) {
        stats_.store_problem = payload.error().message;
        return;
    }
    store_.store(id.key, encode_program_binary_entry(id.check, format, *payload, store_.secret));
}

void ProgramCache::abandon() {
    for (auto& entry : programs_) entry.second->abandon();
    programs_.clear();
}

}  // namespace px
