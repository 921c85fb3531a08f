// glslang's SPIR-V for an assembled stage (shader_costs.h: compile_spirv),
// through the program's one glslang set-up (emulation/glslang_front.h).
#include "parallaxes/profiling/costs/shader_costs.h"

#include <memory>

#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include "parallaxes/emulation/glslang_front.h"

namespace px::profiling {

Result<std::vector<std::uint32_t>> compile_spirv(const std::string& source, ShaderStage stage) {
    // The program's one glslang set-up (emulation/glslang_front.h); the
    // module is the front end's plain translation, which is what is counted.
    const EShLanguage language = stage == ShaderStage::vertex ? EShLangVertex : EShLangFragment;
    std::string log;
    std::unique_ptr<glslang::TShader> shader = emulation::parse_es_source(source, stage, "source", log);
    if (!shader) return make_error("glslang: " + log);
    glslang::TProgram program;
    program.addShader(shader.get());
    if (!program.link(EShMsgDefault)) return make_error(std::string("glslang link: ") + program.getInfoLog());
    std::vector<unsigned int> words;
    spv::SpvBuildLogger logger;
    glslang::SpvOptions options;
    options.generateDebugInfo = true;  // OpLine: the cost of each source line
    options.disableOptimizer = true;
    glslang::GlslangToSpv(*program.getIntermediate(language), words, &logger, &options);
    if (words.size() < 5) return make_error("glslang produced no SPIR-V: " + logger.getAllMessages());
    // Without a target environment glslang leaves the version word 0; the
    // module is SPIR-V 1.0 in every other respect.
    words[1] = 0x00010000u;
    return std::vector<std::uint32_t>(words.begin(), words.end());
}

}  // namespace px::profiling
