#include "stability_precision.h"
#include "draw_surface.h"

#include "parallaxes/emulation/precision.h"

namespace px::tools {

bool is_emulated_precision(const std::string& name) {
    return name == "fp32" || name == "fp16" || name == "lowp" || name == "nohighp" || name == "lowp_all";
}

profiling::RendererFactory make_renderer_factory(GetProcAddress get_proc_address) {
    return [get_proc_address](const std::string& precision, int variant_es) -> Result<RendererOptions> {
        RendererOptions o = program_renderer_options(get_proc_address);
        if (precision == "native") return o;
        Result<emulation::PrecisionProfile> profile = emulation::parse_profile(precision);
        if (!profile) return profile.error();
        const emulation::PrecisionProfile p = *profile;
        o.shader_transform = [p](const std::string& source, ShaderStage stage) {
            return emulation::emulate_precision(source, stage, p);
        };
        // ES 2.0 variants run on this ES 3.0 context as on ES 2.0; without
        // fragment highp they also take the source's own fallback (PX_HIGHP
        // is mediump there, the debug outputs use their 11-bit packing).
        o.emulate_es2 = variant_es == 2;
        o.emulate_no_fragment_highp = p == emulation::PrecisionProfile::nohighp;
        return o;
    };
}

}  // namespace px::tools
