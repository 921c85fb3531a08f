#include "stability_precision.h"

namespace px::tools {

bool is_emulated_precision(const std::string& name) {
    return name == "fp32" || name == "fp16" || name == "lowp" || name == "nohighp";
}

profiling::RendererFactory make_renderer_factory(GetProcAddress get_proc_address) {
    return [get_proc_address](const std::string& precision, int /*variant_es*/) -> Result<RendererOptions> {
        RendererOptions o;
        o.get_proc_address = get_proc_address;
        if (precision == "native") return o;
        return make_error("precision '" + precision + "' is not built into this program yet");
    };
}

}  // namespace px::tools
