// Building GL programs from assembled sources, each with its typed interface
// (shaders/interface.h) resolved once at build time, and the per-context
// cache of programs by variant key.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include <glm/glm.hpp>

#include "parallaxes/core/result.h"
#include "parallaxes/effects/variant.h"
#include "parallaxes/gl/handles.h"
#include "parallaxes/gl/program_binary.h"
#include "parallaxes/shaders/interface.h"
#include "parallaxes/shaders/shader_source.h"

namespace px {

class Program {
public:
    GLuint id() const { return handle_.get(); }
    const std::string& description() const { return description_; }
    const VariantKey& key() const { return key_; }

    // The location resolved at build time; -1 only for a uniform that this
    // variant does not need (shader::needed), which setting then skips.
    GLint location(shader::Uniform u) const { return uniforms_[static_cast<std::size_t>(u)]; }
    GLint location(shader::Attribute a) const { return attributes_[static_cast<std::size_t>(a)]; }

    // Typed setters for the program in use (glUseProgram(id())): the slot's
    // GLSL type picks the overload, so a value of the wrong shape does not
    // compile. Arrays take `count` elements.
    void set(shader::UniformSlot<shader::Type::float1> s, float v) const;
    void set(shader::UniformSlot<shader::Type::float1> s, const float* v, int count) const;
    void set(shader::UniformSlot<shader::Type::vec2> s, const glm::vec2& v) const;
    void set(shader::UniformSlot<shader::Type::vec3> s, const glm::vec3& v) const;
    void set(shader::UniformSlot<shader::Type::vec3> s, const glm::vec3* v, int count) const;
    void set(shader::UniformSlot<shader::Type::vec4> s, const glm::vec4* v, int count) const;
    void set(shader::UniformSlot<shader::Type::mat2> s, const glm::mat2& v) const;
    void set(shader::UniformSlot<shader::Type::mat3> s, const glm::mat3& v) const;
    void set(shader::UniformSlot<shader::Type::mat4> s, const glm::mat4& v) const;
    void set(shader::UniformSlot<shader::Type::int1> s, int v) const;

    void abandon() { handle_.abandon(); }

private:
    friend Result<std::unique_ptr<Program>> build_program(const VariantSources&, const VariantKey&);
    friend class ProgramCache;
    Program() = default;
    // The checks and per-program state every linked program gets, whether
    // it was linked from source or loaded from a binary: uniform and
    // attribute locations (attributes at their bound slots), the interface
    // check both ways, and the sampler units (a binary, like a link, leaves
    // every uniform at 0: ES 3.0 section 2.12.3).
    static Result<std::unique_ptr<Program>> adopt(ProgramHandle program, const VariantKey& key,
                                                  const std::string& defines_summary);
    ProgramHandle handle_;
    std::string description_;
    VariantKey key_;
    std::array<GLint, shader::kUniformCount> uniforms_{};
    std::array<GLint, shader::kAttributeCount> attributes_{};
};

// Compiles and links one variant, binds the attribute slots and sampler units
// of shaders/interface.h and resolves every uniform. Errors hold the stage,
// the driver's log, the offending source lines and the variant's defines: a
// failed compile or link; a uniform or attribute the variant needs
// (shader::needed) and the program lacks; an active uniform the interface
// does not list, or one whose GLSL type or array size differs from it.
// Leaves the current program as it was.
Result<std::unique_ptr<Program>> build_program(const VariantSources& sources, const VariantKey& key);

// Rewrites an assembled source before it is compiled (RendererOptions::
// shader_transform): the precision emulation's hook, kept a plain callback so
// that gl/ and render/ link nothing of it. Returns the source to compile.
using ShaderTransform = std::function<Result<std::string>(const std::string& source, ShaderStage stage)>;

class ProgramCache {
public:
    ProgramCache() : ProgramCache(ShaderTransform{}) {}
    // Every program this cache builds compiles `transform`'s output (empty:
    // the sources as assembled). With a store and a context that has
    // program binaries (`support`), a program is first looked up in the
    // store under a key of its final sources and the driver, and every
    // fresh link is stored; an entry that fails any check is counted,
    // discarded and replaced (gl/program_binary.h).
    explicit ProgramCache(ShaderTransform transform, ProgramBinaryStore store = {},
                          ProgramBinarySupport support = {});
    // The program for a variant, built on first use.
    Result<const Program*> get(const VariantKey& key);
    size_t size() const { return programs_.size(); }
    void clear() { programs_.clear(); }
    // After a context loss: drop every program without calling GL.
    void abandon();
    const ProgramStats& stats() const { return stats_; }

private:
    // The program from the store's entry, or null (counted as rejected
    // when there was an entry).
    std::unique_ptr<Program> load_binary(const ProgramBinaryIdentity& id, const VariantKey& key,
                                         const std::string& defines_summary);
    void store_binary(const ProgramBinaryIdentity& id, GLuint program);

    ShaderTransform transform_;
    ProgramBinaryStore store_;
    ProgramBinarySupport support_;
    bool binaries_ = false;
    ProgramStats stats_;
    std::map<std::string, std::unique_ptr<Program>> programs_;  // by VariantKey::id()
};

}  // namespace px
