#include "parallaxes/profiling/costs/gpu_compilers.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "parallaxes/core/files.h"
#include "parallaxes/core/interrupts.h"
#include "parallaxes/core/limits.h"
#include "parallaxes/profiling/costs/process.h"
#include "parallaxes/profiling/costs/vendor_compilers.h"

// The lines these parsers read, as Mesa 22.3.6's drivers print them (real
// output of each is kept in tests/data/gpu/, with the command that made it):
//   Panfrost (Bifrost, Valhall, Midgard) and Lima, shader-db:
//     SHADER-DB: MESA_SHADER_FRAGMENT shader: 297 inst, 207 tuples, 42 clauses,
//       8.416667 cycles, 8.416667 arith, 0.500000 texture, 0.875000 vary,
//       0.000000 ldst, 187 quadwords, 2 threads, 8 preloads, 0 loops, 0:0 spills:fills
//   V3D, shader-db:
//     SHADER-DB-GLSL3 - MESA_SHADER_FRAGMENT shader: 289 inst, 4 threads, 0 loops,
//       44 uniforms, 26 max-temps, 0:0 spills:fills, 7 sfu-stalls, 296 inst-and-stalls, 22 nops
//   Freedreno ir3 (IR3_SHADER_DEBUG=disasm), after each shader's disassembly:
//     MESA: info: ; FRAG prog 6/1: 453 instr, 221 nops, 232 non-nops, 25 mov, 14 cov, 576 dwords
//     MESA: info: ; FRAG prog 6/1: 31 last-baryf, 0 half, 6 full, 12 constlen
//     MESA: info: ; FRAG prog 6/1: 234 cat0, 39 cat1, ..., 0 cat7,
//     MESA: info: ; FRAG prog 6/1: 163 sstall, 19 (ss), 61 systall, 2 (sy), 0 loops
// Each statistics line is a list of "<number> <words>" items separated by
// commas, and "<spills>:<fills> spills:fills".

namespace px::profiling {

namespace {

constexpr double kStartSeconds = 20.0;  // qemu and the driver starting, per run (2 to 3 s measured)

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string trim(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t\r");
    if (a == std::string::npos) return "";
    return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> parts;
    std::string part;
    std::istringstream in(s);
    while (std::getline(in, part, sep)) parts.push_back(part);
    return parts;
}

// "297 inst" -> {inst, 297}; "0:0 spills:fills" -> spills and fills.
Status read_items(const std::string& list, GpuStage& stage) {
    for (const std::string& raw : split(list, ',')) {
        const std::string item = trim(raw);
        if (item.empty()) continue;
        const size_t space = item.find(' ');
        if (space == std::string::npos) return make_error("statistics item '" + item + "' has no figure and name");
        const std::string number = item.substr(0, space), words = trim(item.substr(space + 1));
        if (words == "spills:fills") {
            int spills = 0, fills = 0;
            char colon = 0;
            std::istringstream in(number);
            if (!(in >> spills >> colon >> fills) || colon != ':' || spills < 0 || fills < 0)
                return make_error("statistics item '" + item + "' is not spills:fills");
            stage.spills = spills;
            stage.fills = fills;
            continue;
        }
        char* end = nullptr;
        const double value = std::strtod(number.c_str(), &end);
        if (end == number.c_str() || *end != '\0' || !std::isfinite(value) || value < 0.0)
            return make_error("statistics item '" + item + "' does not start with a figure");
        stage.figures.push_back({words, value});
    }
    return {};
}

// A shader-db line: "SHADER-DB...: MESA_SHADER_<STAGE> shader: <items>".
Result<std::optional<GpuStage>> shaderdb_line(const std::string& line) {
    if (line.rfind("SHADER-DB", 0) != 0) return std::optional<GpuStage>();
    const size_t at = line.find("MESA_SHADER_");
    const size_t colon = line.find(" shader: ", at == std::string::npos ? 0 : at);
    if (at == std::string::npos || colon == std::string::npos)
        return make_error("a shader-db line without its stage: '" + line.substr(0, 160) + "'");
    GpuStage stage;
    stage.stage = line.substr(at, colon - at);
    stage.fragment = stage.stage == "MESA_SHADER_FRAGMENT";
    stage.line = line;
    if (Status s = read_items(line.substr(colon + 9), stage); !s) return s.error();
    return std::optional<GpuStage>(std::move(stage));
}

// ir3: "MESA: info: ; FRAG prog 6/1: <items>" (several lines per shader).
bool ir3_line(const std::string& line, std::string& key, std::string& stage, std::string& items) {
    const size_t semi = line.find("; ");
    if (semi == std::string::npos) return false;
    const std::string rest = line.substr(semi + 2);
    const size_t prog = rest.find(" prog ");
    const size_t colon = rest.find(": ");
    if (prog == std::string::npos || colon == std::string::npos || prog > colon) return false;
    stage = rest.substr(0, prog);
    if (stage.empty() || stage.find(' ') != std::string::npos) return false;
    key = rest.substr(0, colon);
    items = rest.substr(colon + 2);
    return true;
}

// Mesa's own shaders (blits and clears, translated from TGSI: "TTN") may be
// compiled during a program's draw: their figures are not the program's.
bool internal_shader(const std::string& name) { return name.rfind("TTN", 0) == 0; }

// The block structure of one instruction listing ("blockN {" ... "} -> S
// from P Q"): instructions per block, and the loops (a predecessor listed at
// or after its successor closes one over the blocks between them).
struct ListingBlocks {
    std::vector<int> order;
    std::map<int, int> instructions;
    std::map<int, std::vector<int>> predecessors;
    int current = -1;

    static bool is_instruction(const std::string& raw) {
        std::string l = trim(raw);
        while (!l.empty() && (l[0] == '*' || l[0] == '+' || l[0] == ' ' || l[0] == '\t')) l.erase(0, 1);
        if (l.empty() || l.rfind("NOP", 0) == 0) return false;
        const size_t equals = l.find(" = ");
        if (equals != std::string::npos) {
            const size_t at = l.find_first_not_of(' ', equals + 3);
            return at != std::string::npos && l[at] >= 'A' && l[at] <= 'Z';
        }
        return l[0] >= 'A' && l[0] <= 'Z' && l.size() > 1 && ((l[1] >= 'A' && l[1] <= 'Z') || l[1] == '_');
    }

    void line(const std::string& l) {
        if (l.rfind("block", 0) == 0 && l.size() > 7 && l.compare(l.size() - 2, 2, " {") == 0) {
            current = std::atoi(l.c_str() + 5);
            order.push_back(current);
            return;
        }
        if (current >= 0 && !l.empty() && l[0] == '}') {
            const size_t from = l.find(" from ");
            if (from != std::string::npos) {
                std::istringstream words(l.substr(from + 6));
                std::string w;
                while (words >> w)
                    if (w.rfind("block", 0) == 0) predecessors[current].push_back(std::atoi(w.c_str() + 5));
            }
            current = -1;
            return;
        }
        if (current >= 0 && is_instruction(l)) ++instructions[current];
    }

    // The share of the listing's instructions inside a loop; -1 if it has none.
    double loop_share() const {
        double total = 0.0, looped = 0.0;
        std::map<int, size_t> index;
        for (size_t i = 0; i < order.size(); ++i) index.emplace(order[i], i);
        std::vector<bool> in_loop(order.size(), false);
        for (size_t i = 0; i < order.size(); ++i) {
            auto p = predecessors.find(order[i]);
            if (p == predecessors.end()) continue;
            for (int pred : p->second) {
                auto at = index.find(pred);
                if (at == index.end() || at->second < i) continue;
                for (size_t k = i; k <= at->second; ++k) in_loop[k] = true;
            }
        }
        for (size_t i = 0; i < order.size(); ++i) {
            auto n = instructions.find(order[i]);
            const double count = n == instructions.end() ? 0.0 : n->second;
            total += count;
            if (in_loop[i]) looped += count;
        }
        return total > 0.0 ? looped / total : -1.0;
    }
};

Status read_program_lines(const GpuTarget& target, const std::vector<std::string>& lines, GpuProgram& program) {
    std::string current_key;
    bool internal = false;
    // The listing (BIFROST_MESA_DEBUG=shaders): the compiler prints the
    // fragment shader's IR several times ("block0 {" starts each: after
    // lowering, after register allocation, after scheduling), then its
    // statistics line; the last listing is what runs.
    bool in_fragment = false;
    std::optional<GpuStage> listing, listed;
    ListingBlocks blocks;
    for (const std::string& raw : lines) {
        const std::string line = clean_tool_text(raw);
        if (!target.listing_env.empty()) {
            if (line.rfind("shader: MESA_SHADER_", 0) == 0) {
                in_fragment = trim(line) == "shader: MESA_SHADER_FRAGMENT" && !listed.has_value();
                continue;
            }
            if (in_fragment) {
                if (trim(line) == "block0 {") {
                    GpuStage fresh;
                    fresh.narrow_ops = fresh.wide_ops = fresh.conversions = 0;
                    listing = fresh;
                    blocks = ListingBlocks{};
                    blocks.line(trim(line));
                } else if (listing) {
                    count_listing_line(line, *listing);
                    blocks.line(line);
                }
            }
        }
        if (target.ir3) {
            // "Native code for unnamed FRAG shader GLSL3 with sha1 ...:" names the shader that follows.
            const size_t native = line.find("Native code for ");
            const size_t shader = line.find(" shader ", native);
            if (native != std::string::npos && shader != std::string::npos) {
                internal = internal_shader(line.substr(shader + 8));
                continue;
            }
            std::string key, stage, items;
            if (internal || !ir3_line(line, key, stage, items)) continue;
            if (key != current_key) {
                GpuStage s;
                s.stage = stage;
                s.fragment = stage == "FRAG";
                program.stages.push_back(std::move(s));
                current_key = key;
            }
            GpuStage& s = program.stages.back();
            s.line += (s.line.empty() ? "" : "\n") + line.substr(line.find("; "));
            if (Status st = read_items(items, s); !st) return st;
            continue;
        }
        // V3D names the shader: "SHADER-DB-GLSL3 - MESA_SHADER_...".
        if (line.rfind("SHADER-DB-", 0) == 0 && internal_shader(line.substr(10))) continue;
        Result<std::optional<GpuStage>> stage = shaderdb_line(line);
        if (!stage) return stage.error();
        if (*stage) {
            if ((*stage)->fragment && in_fragment && listing) {
                (*stage)->narrow_ops = listing->narrow_ops;
                (*stage)->wide_ops = listing->wide_ops;
                (*stage)->conversions = listing->conversions;
                (*stage)->loop_share = blocks.loop_share();
                if ((*stage)->loop_share < 0.0) (*stage)->loop_share = 0.0;
                listed = listing;
            }
            if ((*stage)->fragment) in_fragment = false;
            program.stages.push_back(std::move(**stage));
        }
    }
    return {};
}

std::string shell_word(const std::string& s) {
    if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-./=:,+") ==
                          std::string::npos)
        return s;
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

}  // namespace

void count_listing_line(const std::string& line, GpuStage& stage) {
    const size_t equals = line.find(" = ");
    if (equals == std::string::npos) return;
    size_t at = equals + 3;
    while (at < line.size() && line[at] == ' ') ++at;
    size_t end = at;
    while (end < line.size() && line[end] != ' ' && line[end] != '\t') ++end;
    const std::string word = line.substr(at, end - at);
    const size_t dot = word.find('.');
    const std::string opcode = word.substr(0, dot);
    if (opcode.empty() || !(opcode[0] >= 'A' && opcode[0] <= 'Z') ||
        opcode.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") != std::string::npos)
        return;
    for (const char* skipped : {"LD_", "ST_", "STORE", "LOAD", "TEX", "VAR_TEX", "LEA_", "BLEND", "ATEST", "ZS_EMIT",
                                "BRANCH", "JUMP", "DISCARD", "BARRIER", "COLLECT", "SPLIT", "PHI", "NOP"})
        if (opcode.rfind(skipped, 0) == 0) return;
    if (stage.narrow_ops < 0) stage.narrow_ops = stage.wide_ops = stage.conversions = 0;
    if (opcode.find("_TO_") != std::string::npos) {
        ++stage.conversions;
        return;
    }
    bool narrow = false, wide = false;
    for (size_t from = dot; from != std::string::npos && from < word.size();) {
        const size_t next = word.find('.', from + 1);
        const std::string mod = word.substr(from + 1, next == std::string::npos ? std::string::npos : next - from - 1);
        for (const char* n : {"f16", "v2f16", "i16", "v2i16", "u16", "v2u16", "s16", "v2s16", "v4i8", "v4u8", "v4s8", "i8", "u8", "s8"})
            narrow = narrow || mod == n;
        for (const char* w : {"f32", "i32", "u32", "s32"}) wide = wide || mod == w;
        from = next;
    }
    if (narrow) ++stage.narrow_ops;
    else if (wide) ++stage.wide_ops;
}

const std::vector<GpuTarget>& gpu_targets() {
    static const std::vector<GpuTarget> targets = {
        {"mali-g52", "Mali-G52 (Bifrost)", "Panfrost", "panfrost", {"PAN_GPU_ID=0x7212", "BIFROST_MESA_DEBUG=shaderdb"}, 3,
         false, {"arith", "texture", "vary", "ldst"}, "Mali-G52", "BIFROST_MESA_DEBUG=shaderdb,shaders"},
        {"mali-g57", "Mali-G57 (Valhall)", "Panfrost", "panfrost", {"PAN_GPU_ID=0x9093", "BIFROST_MESA_DEBUG=shaderdb"}, 3,
         false, {"fma", "cvt", "sfu", "v", "t", "ls"}, "Mali-G57", "BIFROST_MESA_DEBUG=shaderdb,shaders"},
        {"mali-t860", "Mali-T860 (Midgard)", "Panfrost", "panfrost", {"PAN_GPU_ID=0x860", "MIDGARD_MESA_DEBUG=shaderdb"}, 3,
         false, {}, "Mali-T860", ""},
        {"adreno-630", "Adreno 630", "Freedreno (ir3)", "freedreno", {"FD_GPU_ID=630", "FD_MESA_DEBUG=serialc", "IR3_SHADER_DEBUG=disasm"}, 3, true, {}, "FD630", ""},
        {"v3d-4.2", "VideoCore VI, V3D 4.2 (Raspberry Pi 4)", "V3D", "v3d", {"V3D_DEBUG=shaderdb"}, 3, false, {}, "V3D 4.2", ""},
        {"mali-450", "Mali-450 (Utgard)", "Lima", "lima", {"LIMA_DEBUG=shaderdb"}, 2, false, {}, "Mali450", ""},
    };
    return targets;
}

std::string gpu_targets_text() {
    std::ostringstream s;
    s << "GPUs for --gpu (Mesa's arm64 drivers under qemu-aarch64 with drm-shim; tools/cross/make_gpu_compilers.sh):\n";
    for (const GpuTarget& t : gpu_targets())
        s << "  " << t.name << std::string(t.name.size() < 12 ? 12 - t.name.size() : 1, ' ') << t.gpu << ", " << t.driver
          << ", OpenGL ES " << (t.es_max >= 3 ? "2.0 and 3.0" : "2.0 only") << "\n";
    return s.str();
}

Result<std::vector<GpuTarget>> parse_gpu_targets(const std::string& names) {
    std::vector<GpuTarget> chosen;
    std::string known;
    for (const GpuTarget& t : gpu_targets()) known += (known.empty() ? "" : ", ") + t.name;
    for (const std::string& raw : split(names, ',')) {
        const std::string name = lower(trim(raw));
        if (name.empty()) continue;
        if (name == "all") return gpu_targets();
        auto it = std::find_if(gpu_targets().begin(), gpu_targets().end(), [&](const GpuTarget& t) { return t.name == name; });
        if (it == gpu_targets().end())
            return make_error("--gpu: no GPU named '" + trim(raw).substr(0, 60) + "' (known: " + known + ", all; --gpu list)");
        if (std::none_of(chosen.begin(), chosen.end(), [&](const GpuTarget& t) { return t.name == name; }))
            chosen.push_back(*it);
    }
    if (chosen.empty()) return make_error("--gpu: no GPU named (known: " + known + ", all)");
    return chosen;
}

std::optional<double> GpuStage::figure(const std::string& words) const {
    for (const GpuFigure& f : figures)
        if (f.words == words) return f.value;
    return std::nullopt;
}

const GpuStage* GpuProgram::fragment() const {
    for (const GpuStage& s : stages)
        if (s.fragment) return &s;
    return nullptr;
}

GpuSummary summarise(const GpuTarget& target, const GpuProgram& program) {
    GpuSummary sum;
    for (const GpuStage& s : program.stages) {
        if (s.fragment) continue;
        const std::optional<double> n = s.figure(target.ir3 ? "instr" : "inst");
        if (n) sum.vertex_instructions = std::max(0.0, sum.vertex_instructions) + *n;
    }
    const GpuStage* f = program.fragment();
    if (!f) return sum;
    const auto get = [&](const char* words) { return f->figure(words).value_or(-1.0); };
    sum.instructions = get(target.ir3 ? "instr" : "inst");
    sum.cycles = get("cycles");
    sum.threads = get("threads");
    sum.registers = target.ir3 ? get("full") : std::max(get("registers"), get("max-temps"));
    sum.loops = get("loops");
    sum.spills = f->spills;
    sum.fills = f->fills;
    sum.loop_share = f->loop_share;
    if (f->narrow_ops >= 0 && f->narrow_ops + f->wide_ops > 0) {
        sum.narrow_share = static_cast<double>(f->narrow_ops) / static_cast<double>(f->narrow_ops + f->wide_ops);
        sum.conversions = f->conversions;
    }
    if (sum.cycles >= 0.0)
        for (const std::string& pipe : target.pipes) {
            const std::optional<double> c = f->figure(pipe);
            if (c && std::fabs(*c - sum.cycles) <= 1e-6 * std::max(1.0, sum.cycles))
                sum.bound += (sum.bound.empty() ? "" : ", ") + pipe;
        }
    return sum;
}

Result<GpuRun> parse_probe_output(const GpuTarget& target, const std::string& output, std::size_t programs) {
    GpuRun run;
    run.programs.resize(programs);
    std::vector<std::vector<std::string>> lines(programs);
    std::vector<bool> ended(programs, false);
    long current = -1;
    std::istringstream in(output);
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("px-probe ", 0) == 0) {
            std::istringstream words(line.substr(9));
            std::string what;
            words >> what;
            if (what == "context") {
                run.context = clean_tool_text(trim(line.substr(17)));
            } else if (what == "no-context") {
                return make_error("the " + target.driver + " driver gave no context: " + clean_tool_text(line.substr(20)));
            } else if (what == "begin" || what == "end") {
                long n = -1;
                words >> n;
                if (n < 0 || static_cast<std::size_t>(n) >= programs)
                    return make_error("shader probe output names program " + std::to_string(n) + " of " +
                                      std::to_string(programs));
                if (what == "begin") {
                    current = n;
                    continue;
                }
                std::string status;
                words >> status;
                ended[n] = true;
                if (status != "ok") {
                    std::string rest;
                    std::getline(words, rest);
                    run.programs[n].error = clean_tool_text(trim(rest)).substr(0, 400);
                }
                current = -1;
            }
            continue;
        }
        if (current >= 0) lines[current].push_back(line);
    }
    for (std::size_t i = 0; i < programs; ++i) {
        if (Status s = read_program_lines(target, lines[i], run.programs[i]); !s)
            return make_error(target.gpu + ", program " + std::to_string(i) + ": " + s.error().message);
        if (!ended[i] && run.programs[i].error.empty()) run.programs[i].error = "the probe did not finish this program";
        if (ended[i] && run.programs[i].error.empty() && !run.programs[i].fragment())
            run.programs[i].error = "the driver printed no fragment statistics";
    }
    return run;
}

Result<GpuCompilers> find_gpu_compilers() {
    const char* env = std::getenv("PX_GPU_COMPILERS");
    const char* home = std::getenv("HOME");
    GpuCompilers t;
    t.dir = env && env[0] ? env : std::string(home ? home : "") + "/.cache/parallaxes/gpu-compilers";
    const std::string make = "tools/cross/make_gpu_compilers.sh";
    std::error_code ec;
    if (!std::filesystem::is_regular_file(t.dir + "/.complete", ec) ||
        !std::filesystem::is_regular_file(t.dir + "/shader_probe", ec))
        return make_error("--gpu: no GPU compilers in " + t.dir + " (make them with `" + make +
                          "`: Debian's arm64 Mesa, its drm-shim and a probe, about 2 minutes; PX_GPU_COMPILERS "
                          "names another folder)");
    std::ifstream manifest(t.dir + "/MANIFEST");
    std::string line;
    while (std::getline(manifest, line))
        if (line.rfind("sysroot ", 0) == 0) t.sysroot = trim(line.substr(8));
    if (t.sysroot.empty() || !std::filesystem::is_regular_file(t.sysroot + "/.complete", ec))
        return make_error("--gpu: the arm64 sysroot named in " + t.dir + "/MANIFEST is gone (run `" + make + "` again)");
    for (const GpuTarget& g : gpu_targets())
        if (!std::filesystem::is_regular_file(t.dir + "/lib" + g.shim + "_noop_drm_shim.so", ec))
            return make_error("--gpu: " + t.dir + " has no lib" + g.shim + "_noop_drm_shim.so (run `" + make + "` again)");
    t.qemu = "qemu-aarch64";
    return t;
}

Result<GpuRun> compile_on_gpu(const GpuCompilers& tools, const GpuTarget& target, int es_major,
                              const std::vector<ShaderPair>& pairs, double seconds_per_program) {
    if (es_major > target.es_max)
        return make_error(target.gpu + " (" + target.driver + ") runs OpenGL ES 2.0 only: its figures need --es 2");
    Result<interrupts::TempFolder> folder = interrupts::TempFolder::create("parallax-gpu-");
    if (!folder) return folder.error();
    std::vector<std::string> files;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const std::string base = folder->path() + "/p" + std::to_string(i);
        if (Status s = write_file_atomically(base + ".vert", pairs[i].vertex); !s) return s.error();
        if (Status s = write_file_atomically(base + ".frag", pairs[i].fragment); !s) return s.error();
        files.push_back(base + ".vert");
        files.push_back(base + ".frag");
    }
    // Up to 16 programs a run (each run costs 2 to 3 s of start-up under
    // qemu). A program the compiler does not finish (a hang, past the run's
    // limit, or a crash) is marked and the next run starts after it; after
    // two such in a row the rest are not started.
    constexpr std::size_t kBatch = 16;
    GpuRun all;
    all.programs.resize(pairs.size());
    int stuck_in_a_row = 0;
    std::size_t next = 0;
    while (next < pairs.size()) {
        if (stuck_in_a_row >= 2) {
            for (std::size_t i = next; i < pairs.size(); ++i)
                all.programs[i].error = "skipped: the compiler did not finish the two variants before it";
            break;
        }
        const std::size_t count = std::min(kBatch, pairs.size() - next);
        std::vector<std::string> argv = {tools.qemu, "-L", tools.sysroot, "-E",
                                         "LD_PRELOAD=" + tools.dir + "/lib" + target.shim + "_noop_drm_shim.so",
                                         "-E", "MESA_SHADER_CACHE_DISABLE=true", "-E", "MESA_GLSL_CACHE_DISABLE=true"};
        // qemu's -E splits its value at commas: the listing switch
        // ("shaderdb,shaders") reaches the program through qemu's own
        // environment instead, which it passes on, in place of the
        // statistics switch of the same name.
        const std::string listing_name = target.listing_env.substr(0, target.listing_env.find('='));
        for (const std::string& e : target.env) {
            if (!listing_name.empty() && e.rfind(listing_name + "=", 0) == 0) continue;
            argv.push_back("-E");
            argv.push_back(e);
        }
        argv.push_back(tools.dir + "/shader_probe");
        argv.push_back(std::to_string(es_major));
        argv.insert(argv.end(), files.begin() + static_cast<long>(2 * next),
                    files.begin() + static_cast<long>(2 * (next + count)));
        ProcessOptions options;
        options.timeout_s = kStartSeconds + seconds_per_program * static_cast<double>(count);
        options.max_output = 64u << 20;  // ir3's disassembly is long
        options.remove_env = {"LD_PRELOAD"};
        if (!target.listing_env.empty()) options.extra_env.push_back(target.listing_env);
        Result<ProcessResult> r = run_process(argv, options);
        if (!r) return make_error(target.gpu + ": cannot run qemu-aarch64: " + r.error().message);
        Result<GpuRun> part = parse_probe_output(target, r->output, count);
        if (!part) return part.error();
        if (all.context.empty()) all.context = part->context;
        if (!part->context.empty() && part->context.find(target.renderer) == std::string::npos)
            return make_error(target.gpu + ": the driver that loaded is '" + part->context + "', not " + target.renderer +
                              "'s (is " + tools.dir + "/lib" + target.shim +
                              "_noop_drm_shim.so the right shim? tools/cross/make_gpu_compilers.sh makes it)");
        if (part->context.empty() && !r->timed_out) {
            std::string command;
            for (const std::string& word : argv) command += (command.empty() ? "" : " ") + shell_word(word);
            return make_error(target.gpu + ": the shader probe ended (" +
                              (r->signal ? "signal " + std::to_string(r->signal) : "exit " + std::to_string(r->exit_status)) +
                              ") before it had a context; run by hand: " + command.substr(0, 700));
        }
        std::size_t done = 0;
        while (done < count && part->programs[done].error != "the probe did not finish this program") {
            all.programs[next + done] = part->programs[done];
            stuck_in_a_row = 0;
            ++done;
        }
        if (done == count) {
            next += count;
            continue;
        }
        GpuProgram& stuck = all.programs[next + done];
        stuck.error = r->timed_out ? "the compiler did not finish it: the run's limit of " +
                                         std::to_string(static_cast<int>(options.timeout_s)) + " s passed"
                                   : "the driver ended the run on it (" +
                                         (r->signal ? "signal " + std::to_string(r->signal)
                                                    : "exit " + std::to_string(r->exit_status)) +
                                         ")";
        ++stuck_in_a_row;
        next += done + 1;
    }
    return all;
}

Result<GpuRun> compile_variants_on_gpu(const GpuCompilers& tools, const GpuTarget& target, int es_major,
                                       const std::vector<VariantKey>& keys, const std::vector<const ShaderFiles*>& files,
                                       double seconds_per_program, int lights, const std::vector<int>& search_steps) {
    if (lights < 0 || lights > kMaxLights)
        return make_error("lights: " + std::to_string(lights) + " is outside 0.." + std::to_string(kMaxLights));
    if (!search_steps.empty() && search_steps.size() != keys.size())
        return make_error("search_steps: " + std::to_string(search_steps.size()) + " for " + std::to_string(keys.size()) +
                          " variants");
    std::vector<ShaderPair> pairs;
    for (std::size_t i = 0; i < keys.size(); ++i) {
        Result<VariantSources> sources = assemble_variant(keys[i], i < files.size() ? files[i] : nullptr);
        if (!sources) return with_context(keys[i].describe(), sources.error());
        ShaderPair pair{sources->vertex.text, sources->fragment.text};
        const int steps = search_steps.empty() ? 0 : search_steps[i];
        for (std::string* text : {&pair.vertex, &pair.fragment}) {
            const bool fragment = text == &pair.fragment;
            if (lights > 0) {
                Result<std::string> t = with_define(*text, "PX_MAX_LIGHTS", lights);
                if (!t) return with_context(keys[i].describe() + (fragment ? " (fragment)" : " (vertex)"), t.error());
                *text = std::move(*t);
            }
            if (steps > 0 && fragment) {
                Result<std::string> t = with_define(*text, "PX_MAX_SAMPLES", steps);
                if (!t) return with_context(keys[i].describe() + " (fragment)", t.error());
                *text = std::move(*t);
            }
        }
        pairs.push_back(std::move(pair));
    }
    return compile_on_gpu(tools, target, es_major, pairs, seconds_per_program);
}

Result<std::string> with_define(const std::string& source, const std::string& name, int value) {
    const std::string head = "#define " + name + " ";
    std::size_t at = source.rfind(head, 0) == 0 ? 0 : source.find("\n" + head);
    if (at == std::string::npos) return make_error("no '#define " + name + "' line to set");
    if (source[at] == '\n') ++at;
    const std::size_t end = source.find('\n', at);
    std::string out = source;
    out.replace(at, (end == std::string::npos ? source.size() : end) - at, head + std::to_string(value));
    return out;
}

int pixel_search_steps(const VariantKey& key, bool counted, double iterations) {
    if (!(technique_info(key.technique).options & (kOptSamples | kOptSteps)) || !counted || !(iterations >= 0.0)) return 0;
    const int bound = std::max(1, static_cast<int>(key.max_samples));
    return static_cast<int>(std::clamp(std::ceil(iterations), 1.0, static_cast<double>(bound)));
}

Result<std::vector<GpuCost>> gpu_pixel_costs(const GpuCompilers& tools, const GpuTarget& target, int es_major,
                                             const std::vector<GpuPixelCost>& requests, int lights,
                                             std::string* context, double seconds_per_program) {
    if (lights < 1 || lights > kMaxLights)
        return make_error("lights: " + std::to_string(lights) + " is outside 1.." + std::to_string(kMaxLights));
    // Every distinct variant once, and every distinct truncation once.
    std::vector<VariantKey> keys, truncated_keys;
    std::vector<int> steps;
    std::vector<std::size_t> variant_of(requests.size()), truncation_of(requests.size(), SIZE_MAX);
    for (std::size_t i = 0; i < requests.size(); ++i) {
        const VariantKey& k = requests[i].key;
        auto at = std::find_if(keys.begin(), keys.end(), [&](const VariantKey& x) { return x.id() == k.id(); });
        variant_of[i] = static_cast<std::size_t>(at - keys.begin());
        if (at == keys.end()) keys.push_back(k);
        const int n = requests[i].steps;
        if (n <= 0) continue;
        std::size_t j = 0;
        while (j < truncated_keys.size() && !(truncated_keys[j].id() == k.id() && steps[j] == n)) ++j;
        if (j == truncated_keys.size()) {
            truncated_keys.push_back(k);
            steps.push_back(n);
        }
        truncation_of[i] = j;
    }
    std::vector<VariantKey> all = keys;
    all.insert(all.end(), truncated_keys.begin(), truncated_keys.end());
    std::vector<int> all_steps(keys.size(), 0);
    all_steps.insert(all_steps.end(), steps.begin(), steps.end());
    Result<GpuRun> run = compile_variants_on_gpu(tools, target, es_major, all, {}, seconds_per_program, lights, all_steps);
    if (!run) return run.error();
    if (context) *context = run->context;
    std::vector<GpuCost> out(requests.size());
    for (std::size_t i = 0; i < requests.size(); ++i) {
        const GpuProgram& whole = run->programs[variant_of[i]];
        const GpuProgram& cut =
            truncation_of[i] == SIZE_MAX ? whole : run->programs[keys.size() + truncation_of[i]];
        out[i].variant = summarise(target, whole);
        out[i].pixel = summarise(target, cut);
        out[i].error = !whole.error.empty() ? whole.error : cut.error;
        // A loop the compiler still keeps is taken to run the larger of the
        // search's steps and the shadow ray's samples (a soft march runs all
        // of them, a hard one at most that many): the listing does not say
        // which loop it kept.
        const VariantKey& k = requests[i].key;
        const int passes = std::max({1, requests[i].steps, k.shadow != ShadowMode::none ? static_cast<int>(k.shadow_samples) : 0});
        out[i].cycles_per_pixel = cycles_per_pixel(out[i].pixel.cycles, out[i].pixel.loops, true,
                                                   static_cast<double>(passes), out[i].pixel.loop_share);
    }
    return out;
}

double cycles_per_pixel(double cycles, double loops, bool counted, double iterations, double loop_share) {
    if (!(cycles >= 0.0)) return -1.0;
    if (!(loops > 0.0)) return cycles;
    if (!counted || !(iterations >= 0.0)) return -1.0;
    const double passes = std::max(1.0, iterations);
    if (loop_share >= 0.0 && loop_share <= 1.0) return cycles * ((1.0 - loop_share) + loop_share * passes);
    return cycles * passes;
}

}  // namespace px::profiling
