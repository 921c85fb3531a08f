#include "gl/program.h"

#include <cstdlib>
#include <sstream>
#include <vector>

#include "gl/errors.h"

namespace px {

Program::Program(ProgramHandle handle, std::string description)
    : handle_(std::move(handle)), description_(std::move(description)) {}

GLint Program::uniform(const char* name) const {
    auto it = uniforms_.find(name);
    if (it != uniforms_.end()) return it->second;
    const GLint location = glGetUniformLocation(handle_.get(), name);
    uniforms_.emplace(name, location);
    return location;
}

GLint Program::attribute(const char* name) const { return glGetAttribLocation(handle_.get(), name); }

namespace {

std::string shader_log(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(length > 1 ? length : 1), '\0');
    glGetShaderInfoLog(shader, length, nullptr, &log[0]);
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

std::string program_log(GLuint program) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(length > 1 ? length : 1), '\0');
    glGetProgramInfoLog(program, length, nullptr, &log[0]);
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

// The source lines a log refers to as "0:LINE" (Mesa, ANGLE and most ES drivers).
std::string quote_lines(const std::string& source, const std::string& log) {
    std::vector<std::string> lines;
    std::istringstream in(source);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    std::string out;
    size_t pos = 0;
    int quoted = 0;
    while ((pos = log.find("0:", pos)) != std::string::npos && quoted < 8) {
        pos += 2;
        char* end = nullptr;
        const long line = std::strtol(log.c_str() + pos, &end, 10);
        if (end == log.c_str() + pos || line < 1 || line > static_cast<long>(lines.size())) continue;
        out += "  " + std::to_string(line) + " | " + lines[static_cast<size_t>(line - 1)] + "\n";
        ++quoted;
    }
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

Result<std::unique_ptr<Program>> build_program(const AssembledSource& vertex, const AssembledSource& fragment,
                                               const std::string& description) {
    Result<ShaderHandle> vs = compile(GL_VERTEX_SHADER, vertex, description);
    if (!vs) return vs.error();
    Result<ShaderHandle> fs = compile(GL_FRAGMENT_SHADER, fragment, description);
    if (!fs) return fs.error();
    ProgramHandle program(glCreateProgram());
    glAttachShader(program.get(), vs->get());
    glAttachShader(program.get(), fs->get());
    // Fixed attribute slots so one vertex layout serves every variant.
    glBindAttribLocation(program.get(), 0, "a_position");
    glBindAttribLocation(program.get(), 1, "a_normal");
    glBindAttribLocation(program.get(), 2, "a_tangent");
    glBindAttribLocation(program.get(), 3, "a_uv");
    glLinkProgram(program.get());
    GLint ok = GL_FALSE;
    glGetProgramiv(program.get(), GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE)
        return make_error("variant '" + description + "' failed to link\n  defines: " + fragment.defines_summary +
                          "\n  driver log:\n" + program_log(program.get()));
    Status s = check_gl("building variant '" + description + "'");
    if (!s) return s.error();
    return std::make_unique<Program>(std::move(program), description);
}

Result<const Program*> ProgramCache::get(const VariantKey& key) {
    auto it = programs_.find(key.bits());
    if (it != programs_.end()) return static_cast<const Program*>(it->second.get());
    Result<VariantSources> sources = assemble_variant(key);
    if (!sources) return sources.error();
    Result<std::unique_ptr<Program>> program = build_program(sources->vertex, sources->fragment, key.describe());
    if (!program) return program.error();
    const Program* raw = program->get();
    programs_.emplace(key.bits(), std::move(*program));
    return raw;
}

void ProgramCache::abandon() {
    for (auto& entry : programs_) entry.second->abandon();
    programs_.clear();
}

}  // namespace px
