#include "parallaxes/shaders/shader_source.h"

#include "parallaxes/shaders/conditional.h"
#include "parallaxes/shaders/interface.h"

#include <algorithm>
#include <cctype>
#include <iterator>
#include <map>
#include <set>
#include <sstream>

namespace px {

namespace {

const char* find_file(const std::string& path, const ShaderFiles* files) {
    if (files) {
        const auto found = files->find(path);
        return found == files->end() ? nullptr : found->second.c_str();
    }
    for (const EmbeddedShader& s : embedded_shaders())
        if (path == s.path) return s.text;
    return nullptr;
}

// `#include "x"` with optional spaces; returns the path or "" if the line is not an include.
bool parse_include(const std::string& line, std::string& path) {
    size_t i = line.find_first_not_of(" \t");
    if (i == std::string::npos || line.compare(i, 8, "#include") != 0) return false;
    const size_t open = line.find('"', i + 8);
    const size_t close = open == std::string::npos ? std::string::npos : line.find('"', open + 1);
    path = (open == std::string::npos || close == std::string::npos) ? "" : line.substr(open + 1, close - open - 1);
    return true;
}

// `origins`, when given, gets one entry per line written to `out`.
Status expand(const std::string& path, const std::string& includer, std::set<std::string>& seen,
              std::string& out, std::vector<LineOrigin>* origins, const ShaderFiles* files) {
    if (seen.count(path)) return {};  // each chunk once per source
    const char* text = find_file(path, files);
    if (!text)
        return make_error(includer + ": shader file '" + path + "' not found in shaders_es/" +
                          (!files && path.rfind("ladder/", 0) == 0
                               ? " (this build leaves out the optimisation ladder's profiling shaders: "
                                 "configure with -DPX_LADDER_SHADERS=ON; MinSizeRel's default is OFF)"
                               : ""));
    seen.insert(path);
    std::istringstream in(text);
    std::string line;
    int line_number = 0;
    while (std::getline(in, line)) {
        ++line_number;
        std::string included;
        if (parse_include(line, included)) {
            const std::string where = "shaders_es/" + path + ":" + std::to_string(line_number);
            if (included.empty()) return make_error(where + ": malformed #include (expected #include \"path\")");
            Status s = expand(included, where, seen, out, origins, files);
            if (!s) return s;
            continue;
        }
        out += line;
        out += '\n';
        if (origins) origins->push_back({"shaders_es/" + path, line_number});
    }
    return {};
}

std::string preamble(ShaderStage stage, int es_major) {
    std::string p;
    p += "#define PX_ES " + std::to_string(es_major) + "\n";
    if (stage == ShaderStage::vertex) {
        p += "precision highp float;\nprecision highp int;\n#define PX_HIGHP highp\n";
        p += es_major >= 3 ? "#define PX_ATTRIBUTE in\n#define PX_VARYING out\n"
                           : "#define PX_ATTRIBUTE attribute\n#define PX_VARYING varying\n";
        return p;
    }
    // Fragment: mediump by default; highp where the stage has it (ES 2.0
    // makes it optional: Mali-400-class GPUs have none), for uvs and depth.
    p += "precision mediump float;\nprecision mediump int;\n";
    if (es_major >= 3) {
        p += "#define PX_HIGHP highp\n#define PX_VARYING in\n";
        // highp: the debug outputs write hit uvs to a float target.
        p += "layout(location = 0) out highp vec4 px_frag_color;\n";
        p += "#define PX_FRAG_COLOR px_frag_color\n";
        // Depth only where the variant writes it: the resolved source then
        // names gl_FragDepth only in the variants that use it.
        p += "#ifdef PX_DEPTH_WRITE\n#define PX_FRAG_DEPTH gl_FragDepth\n#endif\n";
    } else {
        // PX_NO_FRAGMENT_HIGHP: draw as a GPU without fragment highp would.
        p += "#if defined(GL_FRAGMENT_PRECISION_HIGH) && !defined(PX_NO_FRAGMENT_HIGHP)\n#define PX_HIGHP highp\n"
             "#else\n#define PX_HIGHP mediump\n#endif\n";
        p += "#define PX_VARYING varying\n";
        p += "#define PX_FRAG_COLOR gl_FragColor\n";
        p += "#ifdef PX_DEPTH_WRITE\n#define PX_FRAG_DEPTH gl_FragDepthEXT\n#endif\n";
    }
    return p;
}

}  // namespace

Result<std::string> expand_includes(const std::string& entry_path) {
    std::set<std::string> seen;
    std::string out;
    Status s = expand(entry_path, "shader entry", seen, out, nullptr, nullptr);
    if (!s) return s.error();
    return out;
}

Result<AssembledSource> assemble_shader(const std::string& entry_path, ShaderStage stage, int es_major,
                                        const std::vector<std::string>& extensions,
                                        const std::vector<ShaderDefine>& defines, const ShaderFiles* files) {
    if (es_major != 2 && es_major != 3)
        return make_error("OpenGL ES " + std::to_string(es_major) + " is not supported (2 or 3)");
    std::set<std::string> seen;
    std::string body;
    std::vector<LineOrigin> body_origins;
    Status expanded = expand(entry_path, "shader entry", seen, body, &body_origins, files);
    if (!expanded) return expanded.error();

    AssembledSource a;
    // #version must be the very first line: some ES drivers reject anything,
    // even a comment, before it.
    std::string text = es_major >= 3 ? "#version 300 es\n" : "#version 100\n";
    for (const std::string& e : extensions) text += "#extension " + e + " : require\n";
    for (const ShaderDefine& d : defines) {
        text += "#define " + d.name + (d.value.empty() ? "" : " " + d.value) + "\n";
        if (!a.defines_summary.empty()) a.defines_summary += ' ';
        a.defines_summary += d.name + (d.value.empty() ? "" : "=" + d.value);
    }
    text += preamble(stage, es_major);
    text += "// ---- " + entry_path + "\n";
    // Errors name a line of shaders_es/ (or of the lines written above).
    const size_t prefix_lines = static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
    std::vector<LineOrigin> origins;
    origins.reserve(prefix_lines + body_origins.size());
    const std::string prefix_name = entry_path + " (version, defines, preamble)";
    for (size_t i = 0; i < prefix_lines; ++i) origins.push_back({prefix_name, static_cast<int>(i + 1)});
    origins.insert(origins.end(), std::make_move_iterator(body_origins.begin()),
                   std::make_move_iterator(body_origins.end()));
    text += body;
    // What the variant's defines decide is decided here, so the driver (and
    // any ShaderTransform) gets no code of an effect the variant does not
    // use; what only the driver knows (GL_FRAGMENT_PRECISION_HIGH) stays.
    Result<std::string> resolved = resolve_conditionals(text, entry_path, origins, &a.origins);
    if (!resolved) return resolved.error();
    a.text = std::move(*resolved);
    return a;
}

Result<VariantSources> assemble_variant(const VariantKey& key, const ShaderFiles* files) {
    const std::vector<ShaderDefine> defines = key.defines();
    Result<AssembledSource> vs = assemble_shader(key.vertex_entry(), ShaderStage::vertex, key.es_major,
                                                 key.extensions(ShaderStage::vertex), defines, files);
    if (!vs) return vs.error();
    Result<AssembledSource> fs = assemble_shader(key.fragment_entry(), ShaderStage::fragment, key.es_major,
                                                 key.extensions(ShaderStage::fragment), defines, files);
    if (!fs) return fs.error();
    // The declarations against the interface table that gl/program binds and
    // the renderer sets: a name it does not list fails here, without a context.
    for (const AssembledSource* stage : {&*vs, &*fs}) {
        Status declared = shader::check_declarations(
            stage->text, "variant '" + key.describe() + "' " + (stage == &*vs ? "vertex" : "fragment") + " stage");
        if (!declared) return declared.error();
    }
    return VariantSources{std::move(*vs), std::move(*fs)};
}

std::vector<long> shader_log_lines(const std::string& log, std::size_t limit) {
    std::vector<long> lines;
    for (std::size_t pos = log.find('0'); pos != std::string::npos && lines.size() < limit;
         pos = log.find('0', pos + 1)) {
        // "0:" or "0(" as a whole number: not the end of "10:" or "(0.5:".
        if (pos > 0 && (std::isdigit(static_cast<unsigned char>(log[pos - 1])) || log[pos - 1] == '.')) continue;
        if (pos + 2 >= log.size() || (log[pos + 1] != ':' && log[pos + 1] != '(')) continue;
        std::size_t end = pos + 2;
        long line = 0;
        while (end < log.size() && std::isdigit(static_cast<unsigned char>(log[end])) && line < 100000000)
            line = line * 10 + (log[end++] - '0');
        if (end == pos + 2 || line < 1) continue;
        if (log[pos + 1] == '(' && (end >= log.size() || log[end] != ')')) continue;
        if (std::find(lines.begin(), lines.end(), line) == lines.end()) lines.push_back(line);
    }
    return lines;
}

}  // namespace px
