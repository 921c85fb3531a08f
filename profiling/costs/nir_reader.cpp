// Mesa's NIR as `ST_DEBUG=nir` prints it (shader_costs.h: parse_nir_dump).
#include "parallaxes/profiling/costs/shader_costs.h"

#include <sstream>
#include <string>

namespace px::profiling {

Result<std::vector<NirShader>> parse_nir_dump(const std::string& text) {
    std::vector<NirShader> shaders;
    std::istringstream in(text);
    std::string line;
    bool inside = false;  // a vertex or fragment shader's body
    while (std::getline(in, line)) {
        if (line.rfind("shader: MESA_SHADER_", 0) == 0) {
            const std::string stage = line.substr(20);
            inside = stage == "VERTEX" || stage == "FRAGMENT";
            if (inside) {
                shaders.emplace_back();
                shaders.back().stage = stage == "VERTEX" ? ShaderStage::vertex : ShaderStage::fragment;
            }
            continue;
        }
        if (!inside) continue;
        NirShader& s = shaders.back();
        if (line.rfind("name: ", 0) == 0) {
            s.name = line.substr(6);
            continue;
        }
        std::size_t start = line.find_first_not_of(" \t");
        if (start == std::string::npos) continue;
        const std::string body = line.substr(start);
        if (body.rfind("loop {", 0) == 0) {
            ++s.cost.loops;
            continue;
        }
        if (body.rfind("if ", 0) == 0 && body.back() == '{') {
            ++s.cost.branches;
            continue;
        }
        // "vec4 16 ssa_48 = (float16)txl ssa_47 (coord), ..." and
        // "vec1 32 ssa_44 = fmul ssa_39, ssa_480"; intrinsics without a
        // destination start with "intrinsic".
        if (body.rfind("intrinsic ", 0) == 0) {
            ++s.cost.intrinsics;
            continue;
        }
        if (body.rfind("vec", 0) != 0 && body.rfind("1 ", 0) != 0) continue;
        std::istringstream words(body);
        std::string size, bits, name, equals, op;
        words >> size >> bits >> name >> equals >> op;
        if (equals != "=" || name.rfind("ssa_", 0) != 0) continue;
        ++s.cost.ssa_values;
        if (op.size() > 2 && op[0] == '(') {
            const std::size_t close = op.find(')');
            op = close == std::string::npos ? op : op.substr(close + 1);
        }
        if (op == "intrinsic") {
            ++s.cost.intrinsics;
        } else if (op == "tex" || op == "txb" || op == "txl" || op == "txd" || op == "txf" || op == "txf_ms" ||
                   op == "txs" || op == "lod" || op == "tg4" || op == "query_levels" || op == "texture_samples" ||
                   op == "samples_identical" || op == "tex_prefetch" || op == "fragment_fetch_amd" ||
                   op == "fragment_mask_fetch_amd") {
            ++s.cost.texture;
        } else if (op == "load_const" || op == "undefined" || op == "phi" || op == "deref_var" ||
                   op == "deref_array" || op == "deref_struct" || op == "deref_cast" || op == "parallel_copy") {
            // not ALU work
        } else {
            ++s.cost.alu;
            if (bits == "16") ++s.cost.alu_16bit;
        }
    }
    if (shaders.empty()) return make_error("the NIR dump holds no vertex or fragment shader ('shader: MESA_SHADER_' lines)");
    return shaders;
}

}  // namespace px::profiling
