#include "parallaxes/emulation/glslang_front.h"

#include <algorithm>
#include <limits>
#include <mutex>

#include <glslang/Public/ResourceLimits.h>

namespace px::emulation {

void initialize_glslang() {
    static std::once_flag once;
    std::call_once(once, [] { glslang::InitializeProcess(); });
}

std::unique_ptr<glslang::TShader> parse_es_source(const std::string& source, ShaderStage stage, const char* name,
                                                  std::string& log) {
    initialize_glslang();
    const EShLanguage language = stage == ShaderStage::vertex ? EShLangVertex : EShLangFragment;
    auto shader = std::make_unique<glslang::TShader>(language);
    const char* text = source.c_str();
    const int length = static_cast<int>(std::min<std::size_t>(source.size(), std::numeric_limits<int>::max()));
    if (name) shader->setStringsWithLengthsAndNames(&text, &length, &name, 1);
    else shader->setStringsWithLengths(&text, &length, 1);
    shader->setEnvInput(glslang::EShSourceGlsl, language, glslang::EShClientNone, 0);
    // Locations and bindings the source leaves out are assigned, so that a
    // program linked from it can be translated to SPIR-V.
    shader->setAutoMapLocations(true);
    shader->setAutoMapBindings(true);
    const bool parsed = shader->parse(GetDefaultResources(), 100, EEsProfile, false, false, EShMsgDefault);
    log = shader->getInfoLog();
    if (!parsed) return nullptr;
    return shader;
}

}  // namespace px::emulation
