// Building GL programs from assembled sources, and the per-context cache of
// programs by variant key.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>

#include "core/result.h"
#include "effects/variant.h"
#include "shaders/shader_source.h"
#include "gl/handles.h"

namespace px {

class Program {
public:
    Program(ProgramHandle handle, std::string description);
    GLuint id() const { return handle_.get(); }
    const std::string& description() const { return description_; }
    // -1 when the program has no such active uniform (the compiler may drop
    // unused ones); setting -1 is a no-op in GL.
    GLint uniform(const char* name) const;
    GLint attribute(const char* name) const;
    void abandon() { handle_.abandon(); }

private:
    ProgramHandle handle_;
    std::string description_;
    mutable std::unordered_map<std::string, GLint> uniforms_;
};

// Compiles and links one vertex + fragment pair. On failure the error holds
// the stage, the driver's log, the offending source lines and the defines.
Result<std::unique_ptr<Program>> build_program(const AssembledSource& vertex, const AssembledSource& fragment,
                                               const std::string& description);


class ProgramCache {
public:
    // The program for a variant, built on first use.
    Result<const Program*> get(const VariantKey& key);
    size_t size() const { return programs_.size(); }
    void clear() { programs_.clear(); }
    // After a context loss: drop every program without calling GL.
    void abandon();

private:
    std::map<std::uint64_t, std::unique_ptr<Program>> programs_;
};

}  // namespace px
