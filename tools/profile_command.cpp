// parallax profile [--variants PATTERN] [--es 2|3] [--format table|md|json] [--out DIR]
//                  [--compare A B] [--against REV] [--ladder] [--no-nir] [--no-time]
//                  [--vendor-timeout SECONDS]
// Static shader costs from glslang's SPIR-V and Mesa's NIR, the mobile cost
// model's estimate, vendor compilers' figures where one is on PATH, and the
// measured llvmpipe time on a bench scene (docs/profiling.md).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_common.h"
#include "parallaxes/profiling/reports/svg_plot.h"
#include "commands.h"
#include "profile_calibration.h"
#include "parallaxes/core/files.h"
#include "parallaxes/emulation/precision.h"
#include "parallaxes/shaders/shader_source.h"
#include "parallaxes/gl/gl.h"
#include "parallaxes/gl/program.h"
#include "parallaxes/platform/headless_context.h"
#include "parallaxes/profiling/measurement/bench.h"
#include "parallaxes/profiling/costs/cost_model.h"
#include "parallaxes/profiling/costs/model_calibration.h"
#include "parallaxes/profiling/costs/process.h"
#include "parallaxes/profiling/costs/shader_profile.h"
#include "parallaxes/profiling/reports/stability_catalogue.h"
#include "parallaxes/profiling/costs/vendor_compilers.h"
#include "parallaxes/render/offscreen_target.h"

namespace px::tools {

namespace {

struct ProfileArgs {
    std::string variants;  // glob or substring on variant names; empty: each technique's default variant
    int es = 3;
    std::string format = "table";
    std::string out;
    std::vector<std::string> compare;  // two patterns
    std::string against;               // a git revision
    bool ladder = false;
    bool no_nir = false;
    bool no_time = false;
    std::string model_file;
    std::string scene = "bricks";
    double angle = 60.0;
    std::string size = "256x256";
    int frames = 5;
    std::string doc;        // write docs/profiling.md from this run
    double vendor_timeout = 120.0;  // seconds for all vendor compiler runs together
    std::string gpu;                // --gpu: real GPU compilers ("mali-g57,adreno-630", "all", "list")
    double gpu_timeout = 20.0;      // seconds per variant for one real GPU compiler
    bool gpu_precision = false;     // --gpu-precision: each variant as written against every value highp
    std::string nir_child;  // internal: the child that prints NIR for these variants (ids, ';'-separated)
    std::string command;
    bool calibrate = false;    // the model against a real compiler (profile_calibration.h)
    CalibrationArgs calibration;
};

constexpr const char* kNirMarker = "@@parallax-nir-variant ";

// Each technique's variant as a bench material draws it by default.
std::vector<VariantKey> default_variants(int es) {
    std::vector<VariantKey> out;
    for (const TechniqueInfo& info : technique_table()) {
        if (info.min_es_major > es) continue;
        VariantKey k = default_variant(info, es);
        k.packed_height = true;  // the bench's procedural materials
        k.exact_view = TechniqueOptions{}.exact_view;
        out.push_back(k.canonical());
    }
    return out;
}

// Every variant a name may select: the catalogue's (the ladder's included)
// and each technique's default.
std::vector<VariantKey> all_variants(int es) {
    std::vector<VariantKey> all = enumerate_variants(es);
    for (const VariantKey& k : default_variants(es)) {
        bool known = false;
        for (const VariantKey& e : all) known |= e == k;
        if (!known) all.push_back(k);
    }
    return all;
}

bool matches(const std::string& pattern, const std::string& name) {
    if (pattern.find_first_of("*?") != std::string::npos) return profiling::glob_match(pattern, name);
    return name.find(pattern) != std::string::npos;
}

Result<std::vector<VariantKey>> select_variants(const std::string& pattern, int es) {
    if (pattern.empty()) return default_variants(es);
    if (Result<VariantKey> named = VariantKey::parse(pattern)) {
        if (named->es_major != es) return make_error("'" + pattern + "' is an OpenGL ES " + std::to_string(named->es_major) + ".0 variant: add --es " + std::to_string(named->es_major));
        return std::vector<VariantKey>{*named};
    }
    std::vector<VariantKey> out;
    for (const VariantKey& k : all_variants(es))
        if (matches(pattern, k.describe())) out.push_back(k);
    if (out.empty())
        return make_error("--variants '" + pattern + "' matches no OpenGL ES " + std::to_string(es) +
                          ".0 variant (names as `parallax profile --variants '*'` lists them, e.g. 'pom es3 samples<=32')");
    return out;
}

// Exactly one variant: an exact name, else a pattern that matches one.
Result<VariantKey> select_one(const std::string& pattern, int es) {
    // Any variant by its exact name, enumerated or not ("pom es3 samples<=64 ...").
    if (Result<VariantKey> named = VariantKey::parse(pattern)) {
        if (named->es_major != es) return make_error("'" + pattern + "' is an OpenGL ES " + std::to_string(named->es_major) + ".0 variant: add --es " + std::to_string(named->es_major));
        return *named;
    }
    const std::vector<VariantKey> all = all_variants(es);
    std::vector<VariantKey> found;
    for (const VariantKey& k : all)
        if (matches(pattern, k.describe())) found.push_back(k);
    if (found.size() == 1) return found[0];
    if (found.empty()) return make_error("--compare: '" + pattern + "' matches no variant");
    std::string names;
    for (std::size_t i = 0; i < found.size() && i < 6; ++i) names += "\n  " + found[i].describe();
    return make_error("--compare: '" + pattern + "' matches " + std::to_string(found.size()) +
                      " variants; give one exact name, e.g.:" + names);
}

// --- NIR: a child `parallax` prints it -------------------------------------

int run_nir_child(const ProfileArgs& a) {
    platform::ContextOptions options;
    options.es_major = a.es;
    auto context = platform::HeadlessContext::create(options);
    if (!context) return fail(context.error().message);
    std::stringstream list(a.nir_child);
    std::string item;
    while (std::getline(list, item, ';')) {
        const Result<VariantKey> key = VariantKey::parse(item);
        if (!key) return fail("--nir-child: " + key.error().message);
        Result<VariantSources> sources = assemble_variant(*key);
        if (!sources) return fail(sources.error().message);
        std::fprintf(stderr, "%s%s\n", kNirMarker, item.c_str());
        std::fflush(stderr);
        Result<std::unique_ptr<Program>> program = build_program(*sources, *key);
        if (!program) return fail(program.error().message);
    }
    return 0;
}

// NIR of each variant, from a child process with Mesa's debug output on.
Status capture_nir(std::vector<profiling::VariantProfile>& profiles, int es) {
    if (profiles.empty()) return {};
    std::string list;
    for (const profiling::VariantProfile& p : profiles) list += (list.empty() ? "" : ";") + p.key.id();
    std::error_code ec;
    const std::string self = std::filesystem::read_symlink("/proc/self/exe", ec).string();
    if (ec) return make_error("cannot find this program's path for the NIR capture: " + ec.message());
    profiling::ProcessOptions options;
    options.timeout_s = 600.0;
    options.max_output = 256u << 20;
    options.capture_stdout = false;
    // ST_DEBUG=nir prints the NIR Mesa hands its backend as each program
    // links; the cache off, or a cached program would print nothing.
    options.extra_env = {"ST_DEBUG=nir", "MESA_SHADER_CACHE_DISABLE=true"};
    Result<profiling::ProcessResult> run =
        profiling::run_process({self, "profile", "--es", std::to_string(es), "--nir-child", list}, options);
    if (!run) return run.error();
    if (run->timed_out) return make_error("the NIR capture did not finish within 600 s");
    if (run->truncated) return make_error("the NIR capture printed more than 256 MiB");
    if (run->exit_status != 0) {
        const std::size_t at = run->output.rfind("parallax: error:");
        return make_error("the NIR capture failed: " + (at == std::string::npos ? run->output.substr(0, 400) : run->output.substr(at)));
    }
    // Split at the markers; each section holds the variant's stages.
    std::map<std::string, std::string> sections;
    std::size_t at = run->output.find(kNirMarker);
    while (at != std::string::npos) {
        const std::size_t name_start = at + std::string(kNirMarker).size();
        const std::size_t name_end = run->output.find('\n', name_start);
        if (name_end == std::string::npos) break;
        const std::size_t next = run->output.find(kNirMarker, name_end);
        sections[run->output.substr(name_start, name_end - name_start)] =
            run->output.substr(name_end, next == std::string::npos ? std::string::npos : next - name_end);
        at = next;
    }
    for (profiling::VariantProfile& p : profiles) {
        const auto found = sections.find(p.key.id());
        if (found == sections.end()) {
            p.nir_note = "Mesa printed no NIR for this variant";
            continue;
        }
        Result<std::vector<profiling::NirShader>> shaders = profiling::parse_nir_dump(found->second);
        if (!shaders) {
            p.nir_note = shaders.error().message;
            continue;
        }
        for (const profiling::NirShader& s : *shaders) {
            if (s.stage == ShaderStage::vertex && !p.nir_vertex) p.nir_vertex = s.cost;
            if (s.stage == ShaderStage::fragment && !p.nir_fragment) p.nir_fragment = s.cost;
        }
    }
    return {};
}

// --- Vendor compilers ------------------------------------------------------

// Each tool on each variant's fragment stage, within the run's one time
// budget (a tool that runs out of time is not started again: VendorRun).
std::string run_vendor_tools(std::vector<profiling::VariantProfile>& profiles, profiling::VendorRun& vendor) {
    const std::vector<profiling::VendorTool>& tools = vendor.tools();
    if (tools.empty()) return profiling::vendor_tools_absent_line();
    std::string line;
    for (const profiling::VendorTool& t : tools) line += (line.empty() ? "" : ", ") + t.name + " (" + t.path + ")";
    const std::size_t notes_before = vendor.notes().size();
    for (profiling::VariantProfile& p : profiles) {
        Result<VariantSources> sources = assemble_variant(p.key);
        if (!sources) continue;
        for (const profiling::VendorTool& t : tools) {
            Result<profiling::VendorCycles> c = vendor.run(t, sources->fragment.text, ShaderStage::fragment, p.key.es_major);
            profiling::VendorFigures f;
            f.tool = t.name;
            if (!c) {
                const bool skipped = c.error().message.rfind("skipped:", 0) == 0;
                f.target = skipped ? c.error().message.substr(0, 200) : "failed: " + c.error().message.substr(0, 200);
                if (!skipped)  // a skip is said once, in the notes
                    std::fprintf(stderr, "parallax: warning: %s on %s: %s\n", t.name.c_str(), p.name.c_str(),
                                 c.error().message.c_str());
            } else {
                f.target = c->target;
                f.work_registers = c->work_registers;
                f.fp16_percent = c->fp16_percent;
                f.pipes = c->pipes;
                f.total = c->total;
                f.shortest = c->shortest;
                f.longest = c->longest;
                f.bound = c->bound;
                f.cycles = c->cycles;
            }
            p.vendor_fragment.push_back(f);
        }
    }
    for (std::size_t i = notes_before; i < vendor.notes().size(); ++i) {
        std::fprintf(stderr, "parallax: warning: %s\n", vendor.notes()[i].c_str());
        line += "; " + vendor.notes()[i];
    }
    // A tool's path comes from $PATH: printable, valid UTF-8, like what the tools print.
    return profiling::clean_tool_text(line);
}

// --- Real GPU compilers ----------------------------------------------------

// Every variant through each --gpu target's driver (one qemu run per target
// for all of them), into the profiles; one line per target for the report.
Result<std::vector<std::string>> run_gpu_compilers(std::vector<profiling::VariantProfile*> profiles, const ProfileArgs& a,
                                                   const std::vector<const ShaderFiles*>& files) {
    Result<std::vector<profiling::GpuTarget>> targets = profiling::parse_gpu_targets(a.gpu);
    if (!targets) return targets.error();
    Result<profiling::GpuCompilers> tools = profiling::find_gpu_compilers();
    if (!tools) return tools.error();
    std::vector<VariantKey> keys;
    for (const profiling::VariantProfile* p : profiles) keys.push_back(p->key);
    std::vector<std::string> lines;
    for (const profiling::GpuTarget& t : *targets) {
        if (a.es > t.es_max) {
            lines.push_back(t.gpu + ": " + t.driver + " runs OpenGL ES 2.0 only; not run on these ES " +
                            std::to_string(a.es) + ".0 variants");
            continue;
        }
        std::fprintf(stderr, "parallax: compiling %zu variant(s) with %s's compiler (%s, under qemu-aarch64)\n",
                     keys.size(), t.gpu.c_str(), t.driver.c_str());
        const auto start = std::chrono::steady_clock::now();
        Result<profiling::GpuRun> run = profiling::compile_variants_on_gpu(*tools, t, a.es, keys, files, a.gpu_timeout);
        if (!run) return run.error();
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        int failed = 0;
        for (size_t i = 0; i < profiles.size(); ++i) {
            profiling::GpuFigures f;
            f.target = t.name;
            f.gpu = t.gpu;
            f.program = run->programs[i];
            f.summary = profiling::summarise(t, f.program);
            if (!f.program.error.empty()) {
                ++failed;
                std::fprintf(stderr, "parallax: warning: %s on %s: %s\n", t.gpu.c_str(), profiles[i]->name.c_str(),
                             f.program.error.c_str());
            }
            profiles[i]->gpu.push_back(std::move(f));
        }
        char took[32];
        std::snprintf(took, sizeof took, "%.1f", seconds);
        lines.push_back(t.gpu + ": " + t.driver + " of " + run->context + ", " + std::to_string(keys.size() - failed) +
                        " of " + std::to_string(keys.size()) + " variant(s) compiled, " + took + " s");
    }
    return lines;
}

// --- Time and error on a bench scene ----------------------------------------

// Draws each variant the bench can draw (its technique and options on a
// bench material; the ladder's through the renderer's variant transform)
// and fills in its time and error. Returns the GL renderer string.
Result<std::string> measure(std::vector<profiling::VariantProfile>& profiles, const ProfileArgs& a, int width, int height) {
    platform::ContextOptions context_options;
    context_options.es_major = a.es;
    auto context = platform::HeadlessContext::create(context_options);
    if (!context) return context.error();
    auto target = OffscreenTarget::create(width, height);
    if (!target) return target.error();
    const std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    int done = 0;
    for (profiling::VariantProfile& p : profiles) {
        ++done;
        const VariantKey& k = p.key;
        const TechniqueInfo& info = technique_info(k.technique);
        // What a bench material can ask for: the rest of the key must come out as planned.
        if (k.debug_output || k.lod || k.depth_write || k.normal_rg || k.height_11bit || k.no_fragment_highp ||
            (((info.options & kOptHeight) != 0) && !k.packed_height) || !info.benched)
            continue;
        profiling::BenchOptions o;
        std::string scene = a.scene;
        if (k.shadow == ShadowMode::hard) scene = "bricks_shadowed";
        if (k.shadow == ShadowMode::soft) scene = "bricks_soft";
        o.scenes = {scene};
        o.techniques = {info.name};
        if (info.options & (kOptSamples | kOptSteps)) o.samples = {k.max_samples};
        o.angles = {a.angle};
        o.width = width;
        o.height = height;
        o.frames = a.frames;
        o.exact_view = k.ladder_step ? false : k.exact_view;
        if (k.shadow != ShadowMode::none) o.shadow_samples = {k.shadow_samples};
        const std::uint8_t step = k.ladder_step;
        if (step) o.renderer.variant_transform = [step](const VariantKey& planned) {
            VariantKey l = planned;
            l.ladder_step = step;
            return l;
        };
        Result<profiling::BenchRun> run =
            profiling::run_bench(o, target->target(), [&target]() { return target->read_pixels(); }, nullptr);
        if (!run) return with_context(p.name, run.error());
        show_progress("profile", done, static_cast<int>(profiles.size()), p.name);
        for (const profiling::BenchRow& row : run->rows) {
            if (row.variant != p.name) continue;  // drawn as another variant: not this one's time
            profiling::Measured m;
            m.scene = row.scene;
            m.angle_deg = row.angle_deg;
            m.ns_per_pixel = row.ns_per_pixel;
            m.ratio_to_normal = row.ratio_to_normal;
            m.uv_error_mean = row.uv_error_mean;
            m.uv_error_p95 = row.uv_error_p95;
            m.color_psnr_db = row.color_psnr_db;
            p.measured = m;
        }
    }
    return renderer;
}

// --- --against: the shaders of another commit ------------------------------

// git, with what its output must look like fixed on the command line, so
// that the user's or the repository's configuration can neither change what
// we parse nor run a program: no pager, names unquoted, no fsmonitor hook;
// diff_options() for every diff. The configuration itself is kept
// (GIT_CONFIG_GLOBAL=/dev/null and GIT_CONFIG_NOSYSTEM would drop it): it
// holds safe.directory, without which git refuses a checkout another user
// owns, and the repository's own .git/config is read whatever those say, so
// only options can make the calls immune.
Result<std::string> git(const std::vector<std::string>& args) {
    std::vector<std::string> argv = {"git", "--no-pager", "-c", "core.quotePath=false", "-c", "core.fsmonitor=false",
                                     "-c", "color.ui=never"};
    argv.insert(argv.end(), args.begin(), args.end());
    profiling::ProcessOptions o;
    o.capture_stderr = true;
    // Variables git reads that change a diff whatever its options say:
    // GIT_DIFF_OPTS overrides -U0 (context lines would count as changed),
    // GIT_EXTERNAL_DIFF names a program (--no-ext-diff also refuses it).
    o.remove_env = {"GIT_DIFF_OPTS", "GIT_EXTERNAL_DIFF", "GIT_PAGER", "PAGER"};
    o.timeout_s = 60.0;
    o.max_output = 64u << 20;
    Result<profiling::ProcessResult> r = profiling::run_process(argv, o);
    if (!r) return r.error();
    if (r->exit_status != 0 || r->timed_out) {
        std::string command;
        for (const std::string& s : argv) command += (command.empty() ? "" : " ") + s;
        return make_error("'" + command + "' failed: " + profiling::clean_tool_text(r->output.substr(0, 400)));
    }
    return r->output;
}

// Lines of shaders_es/ files that differ between REV and the working tree:
// file -> changed line numbers, on each side.
struct ChangedLines {
    std::map<std::string, std::set<int>> old_lines, new_lines;
};

// A diff git prints the same whatever the configuration says (diff.noprefix,
// diff.mnemonicPrefix, diff.external, diff.relative, diff.interHunkContext,
// color.diff, textconv drivers, rename detection): "a/" and "b/" names,
// every changed line in a hunk of its own run, nothing run but git.
const std::vector<std::string> kDiffOptions = {"--no-ext-diff", "--no-textconv", "--no-color", "--no-renames",
                                               "--no-relative", "--src-prefix=a/", "--dst-prefix=b/",
                                               "--inter-hunk-context=0", "-U0"};

// The file a "--- a/NAME" or "+++ b/NAME" line names; "" for /dev/null.
std::string diff_file(const std::string& line, const char* prefix) {
    std::string name = line.substr(4);
    if (name.rfind(prefix, 0) != 0) return "";
    name = name.substr(2);
    if (!name.empty() && name.back() == '\t') name.pop_back();  // git ends a name holding a space with a tab
    return name;
}

Result<ChangedLines> changed_lines(const std::string& rev) {
    std::vector<std::string> args = {"diff"};
    args.insert(args.end(), kDiffOptions.begin(), kDiffOptions.end());
    args.insert(args.end(), {rev, "--", "shaders_es"});
    Result<std::string> diff = git(args);
    if (!diff) return diff.error();
    ChangedLines c;
    std::istringstream in(*diff);
    std::string line, old_file, new_file;
    while (std::getline(in, line)) {
        if (line.rfind("--- ", 0) == 0) old_file = diff_file(line, "a/");
        else if (line.rfind("+++ ", 0) == 0) new_file = diff_file(line, "b/");
        else if (line.rfind("@@ ", 0) == 0) {
            int a = 0, b = 1, cc = 0, d = 1;
            const std::size_t minus = line.find('-'), plus = line.find('+');
            if (minus == std::string::npos || plus == std::string::npos) continue;
            if (std::sscanf(line.c_str() + minus + 1, "%d,%d", &a, &b) < 1) continue;
            if (line.find(',', minus) > line.find(' ', minus)) b = 1;
            if (std::sscanf(line.c_str() + plus + 1, "%d,%d", &cc, &d) < 1) continue;
            if (line.find(',', plus) > line.find(' ', plus)) d = 1;
            for (int i = 0; i < b && i < 100000; ++i) c.old_lines[old_file].insert(a + i);
            for (int i = 0; i < d && i < 100000; ++i) c.new_lines[new_file].insert(cc + i);
        }
    }
    return c;
}

Result<ShaderFiles> shader_files_at(const std::string& rev) {
    // -z: names as they are, whatever core.quotePath; cat-file: the blob's
    // bytes, never through a textconv driver.
    Result<std::string> names = git({"ls-tree", "-r", "-z", "--name-only", rev, "--", "shaders_es"});
    if (!names) return names.error();
    ShaderFiles files;
    std::istringstream in(*names);
    std::string path;
    while (std::getline(in, path, '\0')) {
        if (path.rfind("shaders_es/", 0) != 0) continue;
        Result<std::string> text = git({"cat-file", "blob", rev + ":" + path});
        if (!text) return text.error();
        files[path.substr(11)] = *text;
    }
    if (files.empty()) return make_error("--against " + rev + ": that commit has no shaders_es/ folder");
    return files;
}

profiling::OpCounts lines_cost(const profiling::StageCost& s, const std::map<std::string, std::set<int>>& lines) {
    profiling::OpCounts sum;
    for (const auto& [where, cost] : s.by_line) {
        const std::size_t colon = where.rfind(':');
        if (colon == std::string::npos) continue;
        const auto file = lines.find(where.substr(0, colon));
        if (file == lines.end()) continue;
        if (file->second.count(std::atoi(where.c_str() + colon + 1))) sum += cost;
    }
    return sum;
}

std::string ops_text(const profiling::OpCounts& c) {
    char b[160];
    std::snprintf(b, sizeof b, "%.0f ops, %.0f transc., %.0f reads", c.arithmetic, c.transcendental, c.samples);
    return b;
}

int run_against(const ProfileArgs& a, const std::vector<VariantKey>& keys, const profiling::CostModel& model,
                profiling::ReportFormat format, const profiling::ReportContext& context) {
    // A revision, never an option: git would take "--output=FILE" as one.
    if (a.against.empty() || a.against[0] == '-' || a.against.find_first_of(" \t\n") != std::string::npos)
        return fail("--against: '" + a.against + "' is not a revision");
    Result<std::string> commit = git({"rev-parse", "--verify", "--quiet", "--end-of-options", a.against + "^{commit}"});
    if (!commit) return fail("--against: '" + a.against + "' is not a commit of the git repository here (run it in a checkout)");
    Result<ShaderFiles> old_files = shader_files_at(a.against);
    if (!old_files) return fail(old_files.error().message);
    Result<ChangedLines> changed = changed_lines(a.against);
    if (!changed) return fail(changed.error().message);
    // The working tree's files against what this program carries.
    for (const EmbeddedShader& s : embedded_shaders()) {
        std::ifstream file(std::string("shaders_es/") + s.path, std::ios::binary);
        std::stringstream text;
        text << file.rdbuf();
        if (file && text.str() != s.text)
            std::fprintf(stderr, "parallax: warning: shaders_es/%s differs from the shaders this program was built "
                                 "with: rebuild for the changed lines to match\n", s.path);
    }
    // Both builds of every variant first, so that --gpu compiles them in one go.
    std::ostringstream out;
    std::vector<profiling::VariantProfile> nows, thens;
    for (const VariantKey& key : keys) {
        Result<profiling::VariantProfile> now = profiling::profile_variant(key, model);
        if (!now) return fail(now.error().message);
        Result<profiling::VariantProfile> then = profiling::profile_variant(key, model, &*old_files);
        if (!then) {
            out << key.describe() << ": not built at " << a.against << ": " << then.error().message << "\n\n";
            continue;
        }
        then->name = key.describe() + " @ " + a.against;
        nows.push_back(std::move(*now));
        thens.push_back(std::move(*then));
    }
    profiling::ReportContext with_gpu = context;
    if (!a.gpu.empty()) {
        std::vector<profiling::VariantProfile*> all;
        std::vector<const ShaderFiles*> files;
        for (size_t i = 0; i < nows.size(); ++i) {
            all.push_back(&thens[i]);
            files.push_back(&*old_files);
            all.push_back(&nows[i]);
            files.push_back(nullptr);
        }
        Result<std::vector<std::string>> gpu = run_gpu_compilers(all, a, files);
        if (!gpu) return fail(gpu.error().message);
        with_gpu.gpu_lines = *gpu;
    }
    for (size_t i = 0; i < nows.size(); ++i) {
        const profiling::VariantProfile& now = nows[i];
        const profiling::VariantProfile& then = thens[i];
        out << profiling::compare_report(then, now, format, with_gpu);
        if (format != profiling::ReportFormat::json) {
            const profiling::OpCounts added = lines_cost(now.fragment, changed->new_lines);
            const profiling::OpCounts removed = lines_cost(then.fragment, changed->old_lines);
            const profiling::OpCounts added_v = lines_cost(now.vertex, changed->new_lines);
            const profiling::OpCounts removed_v = lines_cost(then.vertex, changed->old_lines);
            out << (format == profiling::ReportFormat::markdown ? "\n- " : "")
                << "Changed lines, fragment stage: " << ops_text(removed) << " before, " << ops_text(added) << " now\n"
                << (format == profiling::ReportFormat::markdown ? "- " : "")
                << "Changed lines, vertex stage: " << ops_text(removed_v) << " before, " << ops_text(added_v) << " now\n\n";
        }
    }
    std::fputs(out.str().c_str(), stdout);
    return 0;
}

// Through a temporary file renamed over the target (core/files.h): a
// symlink planted at an output name is replaced, never followed, and a full
// disk leaves the previous file, not a truncated one.
Status write_file(const std::string& path, const std::string& text) { return write_file_atomically(path, text); }

// Counts, NIR, vendor figures and (unless --no-time) measurements for keys.
Result<std::vector<profiling::VariantProfile>> profile_all(const std::vector<VariantKey>& keys, const ProfileArgs& a,
                                                           const profiling::CostModel& model, int width, int height,
                                                           profiling::ReportContext& context, profiling::VendorRun& vendor) {
    std::vector<profiling::VariantProfile> profiles;
    for (const VariantKey& k : keys) {
        Result<profiling::VariantProfile> p = profiling::profile_variant(k, model);
        if (!p) return p.error();
        profiles.push_back(std::move(*p));
    }
    context.vendor_line = run_vendor_tools(profiles, vendor);
    if (!a.gpu.empty()) {
        std::vector<profiling::VariantProfile*> all;
        for (profiling::VariantProfile& p : profiles) all.push_back(&p);
        Result<std::vector<std::string>> gpu = run_gpu_compilers(all, a, {});
        if (!gpu) return gpu.error();
        context.gpu_lines = *gpu;
    }
    if (!a.no_nir) {
        Status nir = capture_nir(profiles, a.es);
        if (!nir) return nir.error();
    }
    if (!a.no_time) {
        Result<std::string> renderer = measure(profiles, a, width, height);
        if (!renderer) return renderer.error();
        context.renderer = *renderer + ", " + a.scene + " at " + std::to_string(static_cast<int>(a.angle)) + " degrees, " +
                           a.size + ", median of " + std::to_string(a.frames) + " frames";
    }
    return profiles;
}

std::vector<VariantKey> ladder_keys(int es) {
    std::vector<VariantKey> keys;
    VariantKey base;
    base.technique = Technique::offset_limited;
    base.es_major = static_cast<std::uint8_t>(es);
    base.packed_height = true;  // the bench's procedural materials
    for (int step = 1; step <= kLadderSteps; ++step) {
        VariantKey k = base;
        k.ladder_step = static_cast<std::uint8_t>(step);
        keys.push_back(k.canonical());
    }
    VariantKey shipped = base;
    shipped.exact_view = TechniqueOptions{}.exact_view;
    keys.push_back(shipped.canonical());
    return keys;
}

// docs/profiling.md: every table from one run, the command beside it.
// The pictures beside the doc: the ladder's model cycles and measured time
// per step, and each default variant's model against its measurement.
std::string ladder_svg(const std::vector<profiling::VariantProfile>& steps) {
    profiling::PlotSeries model{"model cycles", "#1f77b4", {}, {}, {}, true};
    profiling::PlotSeries measured{"llvmpipe time", "#d62728", {}, {}, {}, true};
    profiling::PlotOptions o;
    const double model0 = steps.empty() ? 0.0 : steps.front().fragment_longest.total;
    const double time0 = steps.empty() || !steps.front().measured ? 0.0 : steps.front().measured->ns_per_pixel;
    for (size_t i = 0; i < steps.size(); ++i) {
        const profiling::VariantProfile& p = steps[i];
        const int step = ladder_step_info(p.key.ladder_step).step;
        o.x_categories.push_back(step ? std::to_string(step) : "shipped");
        model.x.push_back(static_cast<double>(i + 1));
        model.y.push_back(model0 > 0.0 ? p.fragment_longest.total / model0 : std::nan(""));
        measured.x.push_back(static_cast<double>(i + 1));
        measured.y.push_back(time0 > 0.0 && p.measured ? p.measured->ns_per_pixel / time0 : std::nan(""));
        model.labels.push_back(ladder_step_info(p.key.ladder_step).name);
    }
    o.title = "The PowerVR optimisation ladder";
    o.subtitle = "fragment cost per step relative to step 1: the model's longest path and llvmpipe's time per pixel";
    o.x_label = "step (docs/profiling.md's ladder table names each)";
    o.y_label = "relative to step 1";
    o.width = 900;
    return profiling::svg_plot({model, measured}, o);
}

std::string agreement_svg(const std::vector<profiling::VariantProfile>& profiles, int es) {
    const profiling::VariantProfile* base = nullptr;
    for (const profiling::VariantProfile& p : profiles)
        if (p.key.technique == Technique::normal && p.measured) base = &p;
    profiling::PlotSeries points{"default variants, ES " + std::to_string(es) + ".0", "#2ca02c", {}, {}, {}, false};
    for (const profiling::VariantProfile& p : profiles) {
        if (!base || !p.measured || &p == base || base->fragment_longest.total <= 0.0) continue;
        points.x.push_back(p.fragment_longest.total / base->fragment_longest.total);
        points.y.push_back(p.measured->ratio_to_normal);
        points.labels.push_back(technique_name(p.key.technique));
    }
    profiling::PlotOptions o;
    o.title = "Cost model against llvmpipe, OpenGL ES " + std::to_string(es) + ".0";
    o.subtitle = "each technique's default variant, relative to normal mapping";
    o.x_label = "model: longest-path cycles / normal mapping's";
    o.y_label = "measured: frame time / normal mapping's";
    o.log_x = o.log_y = true;
    o.equality = true;
    o.band = 2.0;
    return profiling::svg_plot({points}, o);
}

// Writes a picture beside the doc; its name for the doc's link.
Result<std::string> write_beside(const std::string& doc, const std::string& name, const std::string& svg) {
    const std::filesystem::path path = std::filesystem::path(doc).parent_path() / name;
    Status w = write_file(path.string(), svg);
    if (!w) return w.error();
    return name;
}

profiling::ReportContext doc_context(const ProfileArgs& a, const profiling::CostModel& model) {
    profiling::ReportContext context;
    context.model = &model;
    context.command = a.command;
    return context;
}

std::string doc_intro(const std::string& command) {
    std::ostringstream doc;
    doc << "# Shader cost profiling\n\n"
        << "What each shader variant costs, read from what real compilers emit (never from a text count of the "
           "source), turned into estimated cycles on a mobile-class GPU by a stated model, beside the time measured on "
           "this machine's llvmpipe. Generated by `" << command << "`; every number below comes from that run.\n\n"
        << "- **SPIR-V** (glslang, unoptimised, the variant's GLSL ES 1.00 or 3.00 source as the driver gets it): "
           "instruction classes in scalar operations (a vec3 add is 3), the share on RelaxedPrecision (mediump, lowp) "
           "results, texture reads and which wait on another read (through data and control flow), loops with the "
           "trip counts of their induction variables, the shortest and longest paths, the dependent-read chain "
           "(round trips) and the waits in program order.\n"
        << "- **NIR** (Mesa 22.3's, captured from a child `parallax` with `ST_DEBUG=nir` as llvmpipe links each "
           "program): ALU and texture instructions, the 16-bit ALU share, loops left after Mesa's unrolling.\n"
        << "- **Model**: the counts turned into cycles per thread on each pipe (A arithmetic, T texture, V "
           "varyings) plus exposed texture latency, with rates fitted to what Arm's Mali Offline Compiler reports "
           "for real shaders on a Mali-G78 (\"The cost model against a real compiler\" below: the fit and how it "
           "does on shaders held out of it); its structure and the rates the fit cannot reach come from "
           "profiling/costs/cost_model.json (parameters and assumptions listed at the end; `--model FILE` takes another).\n"
        << "- **Vendor compilers**: Arm's malioc or a PowerVR GLSLESCompiler, when on PATH, run on the same sources; "
           "their cycles appear in the vendor column (the longest path's; where the tool prints N/A there, loops it "
           "cannot bound, the total instruction cycles, marked). The malioc parser reads text and JSON reports of "
           "malioc 6.x to 8.x, every variant of a shader separately (a vertex shader's Position and Varying), and "
           "was checked on real reports from public sources (tests/data/vendor/real/SOURCES.md); a line of figures "
           "it does not know is refused, quoted. PowerVR's profile parser has no public real output to check against.\n"
        << "- **Measured**: llvmpipe, the bench scene's plane, median frame time per covered pixel and the "
           "interleaved ratio to normal mapping; hit-uv error against the exact reference.\n\n";
    return doc.str();
}

Status doc_defaults(std::ostringstream& doc, const ProfileArgs& a, const profiling::CostModel& model, int width,
                    int height, profiling::VendorRun& vendor) {
    const profiling::ReportFormat md = profiling::ReportFormat::markdown;
    for (int es : {3, 2}) {
        ProfileArgs e = a;
        e.es = es;
        profiling::ReportContext context = doc_context(a, model);
        Result<std::vector<profiling::VariantProfile>> profiles = profile_all(default_variants(es), e, model, width, height, context, vendor);
        if (!profiles) return profiles.error();
        doc << "## Each technique's default variant, OpenGL ES " << es << ".0\n\n"
            << profiling::profile_report(*profiles, md, context) << "\n";
        std::string normal_name;
        for (const profiling::VariantProfile& p : *profiles)
            if (p.key.technique == Technique::normal) normal_name = p.name;
        Result<std::string> picture =
            write_beside(a.doc, "profiling_model_es" + std::to_string(es) + ".svg", agreement_svg(*profiles, es));
        if (!picture) return picture.error();
        doc << "### Model against measurement (ES " << es << ".0)\n\n"
            << profiling::agreement_report(*profiles, normal_name, md) << "\n"
            << "![model against measurement, ES " << es << ".0](" << *picture << ")\n\n";
        if (es == 3)
            doc << "Where the two part, it is mostly loops: the model's longest path runs every loop to its budget "
                   "(PX_MAX_SAMPLES; maxmip's 4096 steps, which no fragment walks), while the shaders' dynamic sample "
                   "count and early exits stop most fragments sooner. llvmpipe is also not a mobile GPU: a CPU "
                   "rasteriser with 8-wide SIMD, loops of up to 32 iterations unrolled, no texture latency to hide, "
                   "and a frame time that carries the vertex stage and per-draw costs, which pull every ratio "
                   "towards 1.\n\n";
    }
    return {};
}

Status doc_ladder(std::ostringstream& doc, const ProfileArgs& a, const profiling::CostModel& model, int width,
                  int height, profiling::VendorRun& vendor) {
    profiling::ReportContext context = doc_context(a, model);
    Result<std::vector<profiling::VariantProfile>> ladder = profile_all(ladder_keys(3), a, model, width, height, context, vendor);
    if (!ladder) return ladder.error();
    Result<std::string> picture = write_beside(a.doc, "profiling_ladder.svg", ladder_svg(*ladder));
    if (!picture) return picture.error();
    doc << "## The PowerVR optimisation ladder\n\n"
        << "The Parallax Bumpmapping whitepaper's offset-limited shader as its baseline, then each step it took, "
           "in its order (shaders_es/ladder/; `parallax profile --ladder`). FS cycles are the model's longest "
           "path; d cycles the change from the step before; waits the texture waits in program order; the time "
           "and error are measured on the bench scene like the variants above.\n\n"
        << profiling::ladder_report(*ladder, profiling::ReportFormat::markdown, context) << "\n"
        << "![the ladder: model cycles and measured time per step](" << *picture << ")\n\n";
    return {};
}

Status doc_comparison(std::ostringstream& doc, const ProfileArgs& a, const profiling::CostModel& model, int width,
                      int height, profiling::VendorRun& vendor) {
    profiling::ReportContext context = doc_context(a, model);
    Result<VariantKey> pom32 = VariantKey::parse("pom es3 samples<=32 exact-view packed");
    Result<VariantKey> pom64 = VariantKey::parse("pom es3 samples<=64 exact-view packed");
    if (!pom32 || !pom64) return make_error("internal: the comparison's variants");
    Result<std::vector<profiling::VariantProfile>> pair = profile_all({*pom32, *pom64}, a, model, width, height, context, vendor);
    if (!pair) return pair.error();
    doc << "## A comparison: POM at 32 and 64 samples\n\n"
        << "`parallax profile --compare 'pom es3 samples<=32 exact-view packed' 'pom es3 samples<=64 exact-view "
           "packed'`, from the same run:\n\n"
        << profiling::compare_report((*pair)[0], (*pair)[1], profiling::ReportFormat::markdown, context) << "\n"
        << "`--against REV` prints the same table for each selected variant between the shaders_es/ of a commit "
           "and this program's, with the cost of the changed lines on each side.\n\n";
    return {};
}

int run_doc(const ProfileArgs& a, const profiling::CostModel& model, int width, int height, profiling::VendorRun& vendor) {
    std::error_code ec;
    const std::filesystem::path parent = std::filesystem::path(a.doc).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    std::ostringstream doc;
    doc << doc_intro(a.command);
    for (auto section : {&doc_defaults, &doc_ladder, &doc_comparison}) {
        Status s = section(doc, a, model, width, height, vendor);
        if (!s) return fail(s.error().message);
    }
    if (Status s = doc_calibration(doc, a.doc); !s) return fail(s.error().message);
    doc << "## " << profiling::model_section(model, profiling::ReportFormat::markdown).substr(4) << "\n";
    Status w = write_file(a.doc, doc.str());
    if (!w) return fail(w.error().message);
    std::fprintf(stderr, "wrote %s\n", a.doc.c_str());
    return 0;
}

// --make-calibration-set with --gpu: the selected variants' fragment shaders
// and one real compiler's per-pipe cycles of them, as a calibration set that
// --calibrate --calibration-set fits the cost model to (half fits, half is
// held out). Panfrost's pipes are named as the model's: Bifrost's arith,
// texture, vary, ldst as A, T, V, LS; Valhall's A is the busiest of fma, cvt
// and sfu, as malioc's A column is.
Result<std::vector<VariantKey>> profile_keys(const ProfileArgs& a);

// --gpu-precision: each selected variant compiled twice by each Bifrost or
// Valhall GPU's compiler, with its own precision qualifiers and with every
// value declared highp. Both are the precision emulator's re-emission of
// the same source (identity and fp32: include/parallaxes/emulation/precision.h),
// so that only the qualifiers differ between them.
int run_gpu_precision(const ProfileArgs& a) {
    const auto fixed = [](double v, int digits) {
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
        return std::string(buffer);
    };
    Result<std::vector<profiling::GpuTarget>> targets = profiling::parse_gpu_targets(a.gpu);
    if (!targets) return fail(targets.error().message);
    std::vector<profiling::GpuTarget> listed;
    for (const profiling::GpuTarget& t : *targets)
        if (!t.listing_env.empty()) listed.push_back(t);
    if (listed.empty())
        return fail("--gpu-precision: the 16-bit share is read from Bifrost's and Valhall's instruction listings: name "
                    "mali-g52 or mali-g57 in --gpu");
    Result<profiling::GpuCompilers> tools = profiling::find_gpu_compilers();
    if (!tools) return fail(tools.error().message);
    Result<std::vector<VariantKey>> keys = profile_keys(a);
    if (!keys) return fail(keys.error().message);
    std::vector<profiling::ShaderPair> pairs;
    for (const VariantKey& k : *keys) {
        Result<VariantSources> sources = assemble_variant(k);
        if (!sources) return fail(k.describe() + ": " + sources.error().message);
        for (emulation::PrecisionProfile profile : {emulation::PrecisionProfile::identity, emulation::PrecisionProfile::fp32}) {
            Result<std::string> v = emulation::emulate_precision(sources->vertex.text, ShaderStage::vertex, profile);
            Result<std::string> f = emulation::emulate_precision(sources->fragment.text, ShaderStage::fragment, profile);
            if (!v) return fail(k.describe() + " (vertex, " + emulation::profile_name(profile) + "): " + v.error().message);
            if (!f) return fail(k.describe() + " (fragment, " + emulation::profile_name(profile) + "): " + f.error().message);
            pairs.push_back({*v, *f});
        }
    }
    std::vector<std::vector<std::string>> rows;
    std::vector<std::string> lines;
    for (const profiling::GpuTarget& t : listed) {
        std::fprintf(stderr, "parallax: compiling %zu variant(s) twice with %s's compiler (%s, under qemu-aarch64)\n",
                     keys->size(), t.gpu.c_str(), t.driver.c_str());
        // The re-emitted sources are GLSL ES 3.00 whatever the variant's version.
        Result<profiling::GpuRun> run = profiling::compile_on_gpu(*tools, t, 3, pairs, a.gpu_timeout);
        if (!run) return fail(run.error().message);
        lines.push_back(t.gpu + ": " + t.driver + " of " + run->context);
        const auto cell = [&fixed](const profiling::GpuSummary& m, const std::string& error) -> std::vector<std::string> {
            if (!error.empty() && m.instructions < 0.0) return {"failed: " + error.substr(0, 60), "", ""};
            return {m.narrow_share >= 0.0 ? fixed(100.0 * m.narrow_share, 0) + " % (" + std::to_string(m.conversions) + ")" : "-",
                    m.cycles >= 0.0 ? fixed(m.cycles, 2) : "-", m.threads >= 0.0 ? fixed(m.threads, 0) : "-"};
        };
        for (size_t i = 0; i < keys->size(); ++i) {
            const profiling::GpuProgram& as_written = run->programs[2 * i];
            const profiling::GpuProgram& highp = run->programs[2 * i + 1];
            const profiling::GpuSummary m = profiling::summarise(t, as_written), h = profiling::summarise(t, highp);
            std::vector<std::string> row = {(*keys)[i].describe(), t.gpu};
            for (const std::string& c : cell(m, as_written.error)) row.push_back(c);
            for (const std::string& c : cell(h, highp.error)) row.push_back(c);
            row.push_back(m.cycles > 0.0 && h.cycles > 0.0 ? fixed(h.cycles / m.cycles, 2) : "-");
            rows.push_back(std::move(row));
        }
    }
    std::printf("command    %s\n", a.command.c_str());
    for (const std::string& l : lines) std::printf("compiler   %s\n", l.c_str());
    std::fputs(profiling::render_table({"variant", "GPU", "as written: 16-bit (cvt)", "cycles", "threads",
                                        "all highp: 16-bit (cvt)", "cycles", "threads", "highp / as written"},
                                       rows, profiling::ReportFormat::table)
                   .c_str(),
               stdout);
    std::printf("16-bit: the share of the fragment shader's arithmetic and data-movement instructions that compute in "
                "16 bits (type .f16, .v2f16, .i16, ...) against 32, counted from the compiler's last instruction "
                "listing (BIFROST_MESA_DEBUG=shaders); in brackets the conversions between widths. Both columns compile "
                "the precision emulator's re-emission of the variant: identity (its own qualifiers) and fp32 (every "
                "value highp), so only the qualifiers differ. cycles and threads as the compiler's statistics line.\n");
    return 0;
}

int run_gpu_calibration_set(const ProfileArgs& a) {
    Result<std::vector<profiling::GpuTarget>> targets = profiling::parse_gpu_targets(a.gpu);
    if (!targets) return fail(targets.error().message);
    if (targets->size() != 1 || targets->front().pipes.empty())
        return fail("--make-calibration-set with --gpu: name one GPU whose compiler estimates cycles per pipe "
                    "(mali-g52, mali-g57)");
    const profiling::GpuTarget& t = targets->front();
    if (const std::string unwritable = check_output_file(a.calibration.make_set); !unwritable.empty())
        return fail("--make-calibration-set: " + unwritable);
    Result<std::vector<VariantKey>> keys = profile_keys(a);
    if (!keys) return fail(keys.error().message);
    Result<profiling::GpuCompilers> tools = profiling::find_gpu_compilers();
    if (!tools) return fail(tools.error().message);
    std::fprintf(stderr, "parallax: compiling %zu variant(s) with %s's compiler (%s, under qemu-aarch64)\n", keys->size(),
                 t.gpu.c_str(), t.driver.c_str());
    Result<profiling::GpuRun> run = profiling::compile_variants_on_gpu(*tools, t, a.es, *keys, {}, a.gpu_timeout);
    if (!run) return fail(run.error().message);
    profiling::CalibrationSet set;
    set.gpu = t.gpu;
    set.compiler = t.driver + " (" + run->context + ")";
    set.source = "this project's shader variants (parallax shaders), compiled by " + t.driver +
                 " under qemu-aarch64 with drm-shim (tools/cross/make_gpu_compilers.sh)";
    set.made_by = a.command;
    int left_out = 0;
    for (size_t i = 0; i < keys->size(); ++i) {
        const profiling::GpuStage* f = run->programs[i].fragment();
        const std::string name = (*keys)[i].describe() + ".frag";
        if (!f) {
            std::fprintf(stderr, "parallax: %s: %s; left out\n", name.c_str(), run->programs[i].error.c_str());
            ++left_out;
            continue;
        }
        // A debug output's shader writes what the search found, and the
        // compiler drops the shading it no longer needs, which the analysis
        // of glslang's unoptimised SPIR-V still counts: left out.
        if ((*keys)[i].debug_output) {
            ++left_out;
            continue;
        }
        // The compiler's figures count a loop it kept once; the analysis
        // counts every trip: only fully unrolled (or loop-free) shaders compare.
        if (const double loops = f->figure("loops").value_or(0.0); loops > 0.0) {
            std::fprintf(stderr, "parallax: %s: the compiler kept %g loop(s) (its cycles count one pass); left out\n",
                         name.c_str(), loops);
            ++left_out;
            continue;
        }
        profiling::VendorCycles figures;
        figures.tool = set.compiler;
        figures.target = t.gpu;
        const auto get = [&](const char* words) { return f->figure(words).value_or(0.0); };
        const bool valhall = f->figure("fma").has_value();
        const double arith = valhall ? std::max({get("fma"), get("cvt"), get("sfu")}) : get("arith");
        figures.pipes = {"A", "LS", "V", "T"};
        figures.total = {arith, get(valhall ? "ls" : "ldst"), get(valhall ? "v" : "vary"), get(valhall ? "t" : "texture")};
        Result<VariantSources> sources = assemble_variant((*keys)[i]);
        if (!sources) return fail(name + ": " + sources.error().message);
        Result<profiling::CalibrationShader> entry =
            profiling::calibration_entry(name, sources->fragment.text, ShaderStage::fragment, figures);
        if (!entry) return fail(entry.error().message);
        set.shaders.push_back(std::move(*entry));
    }
    if (set.shaders.empty()) return fail("--make-calibration-set: no variant compiled with " + t.gpu);
    if (Status w = write_file_atomically(a.calibration.make_set, profiling::calibration_set_json(set)); !w)
        return fail(w.error().message);
    std::fprintf(stderr, "wrote %s: %zu fragment shaders (%d left out), %s on %s\n", a.calibration.make_set.c_str(),
                 set.shaders.size(), left_out, set.compiler.c_str(), set.gpu.c_str());
    return 0;
}

// --calibrate and --make-calibration-set (profile_calibration.h); -1 where
// neither was asked for. Their options are refused without them.
int run_calibration_modes(const ProfileArgs& a) {
    if (!a.gpu.empty() && !a.calibration.make_set.empty()) return run_gpu_calibration_set(a);
    if (a.calibrate || !a.calibration.make_set.empty()) {
        if (a.calibrate && !a.calibration.make_set.empty())
            return fail("--calibrate and --make-calibration-set: one at a time (make the set, then calibrate on it)");
        CalibrationArgs c = a.calibration;
        c.model_file = a.model_file;
        c.format = a.format;
        c.command = a.command;
        return a.calibrate ? run_calibrate(c) : run_make_calibration_set(c);
    }
    if (!a.calibration.model_out.empty()) return fail("--model-out goes with --calibrate");
    if (!a.calibration.shaders.empty() || !a.calibration.reports.empty() || !a.calibration.source.empty())
        return fail("--shaders, --reports and --set-source go with --make-calibration-set");
    return -1;
}

// Every option checked, and where the reports go, before anything is
// compiled or timed.
Status check_profile_args(const ProfileArgs& a, int& width, int& height) {
    if (!parse_size(a.size, width, height, 2048)) return make_error("--size: '" + a.size + "' is not WIDTHxHEIGHT within 1..2048");
    if (a.frames < 1 || a.frames > 1000) return make_error("--frames: must be within 1..1000");
    if (!(a.vendor_timeout > 0.0 && a.vendor_timeout <= 86400.0))
        return make_error("--vendor-timeout: must be within (0, 86400] seconds");
    if (!(a.angle >= 0.0 && a.angle < 90.0)) return make_error("--angle: must be within [0, 90) degrees");
    if (!a.out.empty())
        if (const std::string unwritable = check_output_folder(a.out); !unwritable.empty()) return make_error("--out: " + unwritable);
    if (!a.doc.empty())
        if (const std::string unwritable = check_output_file(a.doc); !unwritable.empty()) return make_error("--doc: " + unwritable);
    return {};
}

// The model the reports use: the carried, calibrated one; --model's file as
// written; or, with --calibration-set, that set's fit of the base (--model's
// file, or the carried base).
Result<profiling::CostModel> load_cost_model(const std::string& file, const std::string& set_file) {
    if (!set_file.empty()) return model_fitted_to(set_file, file);
    if (file.empty()) return profiling::default_cost_model();
    Result<std::vector<std::uint8_t>> bytes = read_file_bounded(file, 1u << 20, "cost model");
    if (!bytes) return bytes.error();
    return profiling::parse_cost_model(std::string(bytes->begin(), bytes->end()), file);
}

// The variants asked for: the ladder's steps, the two compared, or those matching --variants.
Result<std::vector<VariantKey>> profile_keys(const ProfileArgs& a) {
    if (a.ladder) return ladder_keys(a.es);
    if (a.compare.empty()) return select_variants(a.variants, a.es);
    if (a.compare.size() != 2) return make_error("--compare takes two variants: --compare A B");
    std::vector<VariantKey> keys;
    for (const std::string& pattern : a.compare) {
        Result<VariantKey> k = select_one(pattern, a.es);
        if (!k) return k.error();
        keys.push_back(*k);
    }
    return keys;
}

// The ladder's, the comparison's or the profile's report in one format.
std::string profile_text(const ProfileArgs& a, const std::vector<profiling::VariantProfile>& profiles,
                         profiling::ReportFormat format, const profiling::ReportContext& context) {
    std::string text = a.ladder              ? profiling::ladder_report(profiles, format, context)
                       : !a.compare.empty() ? profiling::compare_report(profiles[0], profiles[1], format, context)
                                            : profiling::profile_report(profiles, format, context);
    if (format != profiling::ReportFormat::json) text += "\n" + profiling::model_section(*context.model, format);
    return text;
}

// --out: the report as Markdown and JSON.
Status write_profile_outputs(const ProfileArgs& a, const std::vector<profiling::VariantProfile>& profiles,
                             const profiling::ReportContext& context) {
    std::error_code ec;
    std::filesystem::create_directories(a.out, ec);
    if (ec) return make_error("cannot create '" + a.out + "': " + ec.message());
    const std::string stem = a.out + "/" + (a.ladder ? "ladder" : !a.compare.empty() ? "compare" : "profile");
    for (profiling::ReportFormat f : {profiling::ReportFormat::markdown, profiling::ReportFormat::json}) {
        Status w = write_file(stem + (f == profiling::ReportFormat::json ? ".json" : ".md"), profile_text(a, profiles, f, context));
        if (!w) return w;
    }
    std::fprintf(stderr, "wrote %s.md and %s.json\n", stem.c_str(), stem.c_str());
    return {};
}

int run_profile(ProfileArgs a) {
    if (!a.nir_child.empty()) return run_nir_child(a);
    if (a.gpu == "list") {
        std::fputs(profiling::gpu_targets_text().c_str(), stdout);
        return 0;
    }
    if (!a.gpu.empty()) {
        // Every name checked, and each GPU against the ES version, before any work.
        Result<std::vector<profiling::GpuTarget>> targets = profiling::parse_gpu_targets(a.gpu);
        if (!targets) return fail(targets.error().message);
        for (const profiling::GpuTarget& t : *targets)
            if (a.es > t.es_max && a.doc.empty())  // --doc profiles ES 2.0 variants too
                return fail("--gpu " + t.name + ": " + t.gpu + " (" + t.driver +
                            ") runs OpenGL ES 2.0 only: profile its variants with --es 2");
        if (!(a.gpu_timeout > 0.0 && a.gpu_timeout <= 3600.0))
            return fail("--gpu-timeout: must be within (0, 3600] seconds");
    }
    if (a.gpu_precision) {
        if (a.gpu.empty()) return fail("--gpu-precision needs --gpu mali-g52 and/or mali-g57");
        return run_gpu_precision(a);
    }
    if (const int calibration = run_calibration_modes(a); calibration >= 0) return calibration;
    Result<profiling::ReportFormat> format = profiling::parse_report_format(a.format);
    if (!format) return fail("--format: " + format.error().message);
    int width = 0, height = 0;
    if (Status s = check_profile_args(a, width, height); !s) return fail(s.error().message);
    Result<profiling::CostModel> model = load_cost_model(a.model_file, a.calibration.set_file);
    if (!model) return fail(model.error().message);
    // One time budget for every vendor compiler run of this command.
    profiling::VendorRun vendor(profiling::find_vendor_tools(),
                                std::chrono::milliseconds(static_cast<long long>(a.vendor_timeout * 1000.0)));
    if (!a.doc.empty()) return run_doc(a, *model, width, height, vendor);
    profiling::ReportContext context;
    context.command = a.command;
    context.model = &*model;
    Result<std::vector<VariantKey>> keys = profile_keys(a);
    if (!keys) return fail(keys.error().message);
    if (!a.against.empty()) return run_against(a, *keys, *model, *format, context);
    Result<std::vector<profiling::VariantProfile>> profiles = profile_all(*keys, a, *model, width, height, context, vendor);
    if (!profiles) return fail(profiles.error().message);
    std::fputs(profile_text(a, *profiles, *format, context).c_str(), stdout);
    if (!a.out.empty())
        if (Status s = write_profile_outputs(a, *profiles, context); !s) return fail(s.error().message);
    return 0;
}

}  // namespace

void add_profile_command(CLI::App& app, int argc, char** argv) {
    auto args = std::make_shared<ProfileArgs>();
    for (int i = 0; i < argc; ++i) {
        std::string word = i == 0 ? "parallax" : argv[i];
        if (word.find_first_of(" \t'\"") != std::string::npos) word = "'" + word + "'";  // as a shell would need it
        args->command += (i ? " " : "") + word;
    }
    CLI::App* cmd = app.add_subcommand("profile", "Static shader costs (glslang SPIR-V, Mesa NIR, a mobile cost model) "
                                                  "beside measured time");
    cmd->add_option("--variants", args->variants,
                    "Variants whose names match (substring, or glob with * ?); default: each technique's default variant");
    cmd->add_option("--es", args->es, "OpenGL ES major version: 2 or 3")->check(CLI::IsMember({2, 3}))->capture_default_str();
    cmd->add_option("--format", args->format, "table, md or json")->capture_default_str();
    cmd->add_option("--out", args->out, "Also write the report as Markdown and JSON into this folder");
    cmd->add_option("--compare", args->compare, "Two variants (exact names or patterns matching one each): per-metric deltas")
        ->expected(2);
    cmd->add_option("--against", args->against,
                    "A git revision: the selected variants built from its shaders_es/ against this program's");
    cmd->add_flag("--ladder", args->ladder, "The PowerVR whitepaper's optimisation ladder, step by step");
    cmd->add_flag("--no-nir", args->no_nir, "Skip Mesa's NIR (a child process with ST_DEBUG=nir)");
    cmd->add_flag("--no-time", args->no_time, "Skip the llvmpipe timing and error measurement");
    cmd->add_option("--model", args->model_file, "A cost model file (the shape of profiling/costs/cost_model.json)");
    cmd->add_option("--scene", args->scene, "Bench scene the variants are timed on")->capture_default_str();
    cmd->add_option("--angle", args->angle, "View angle of the timing, degrees off the normal")->capture_default_str();
    cmd->add_option("--size", args->size, "Timing target size")->capture_default_str();
    cmd->add_option("--frames", args->frames, "Timed frames per variant (median)")->capture_default_str();
    cmd->add_option("--vendor-timeout", args->vendor_timeout,
                    "Seconds for all vendor compiler runs together (one run gets at most half); a compiler that runs "
                    "out of time is not started again")
        ->capture_default_str();
    cmd->add_option("--gpu", args->gpu,
                    "Real mobile GPU compilers (Mesa's arm64 drivers under qemu-aarch64; "
                    "tools/cross/make_gpu_compilers.sh): comma-separated names, 'all', or 'list'");
    cmd->add_flag("--gpu-precision", args->gpu_precision,
                  "With --gpu (Bifrost, Valhall): each variant compiled as written and with every value highp: the "
                  "share of 16-bit instructions, conversions and cycles of both");
    cmd->add_option("--gpu-timeout", args->gpu_timeout,
                    "Seconds a real GPU compiler may take per variant (under emulation) before it is given up")
        ->capture_default_str();
    cmd->add_option("--doc", args->doc, "Write the profiling document (docs/profiling.md) from one run");
    cmd->add_flag("--calibrate", args->calibrate,
                  "The cost model fitted to a real compiler's figures (the carried Mali-G78 set): weights, and how "
                  "the fit does on the shaders held out of it");
    cmd->add_option("--calibration-set", args->calibration.set_file,
                    "A calibration set file (profiling/costs/calibration/): with --calibrate, the fit on it; otherwise "
                    "the reports use the model fitted to it (another GPU class)");
    cmd->add_option("--model-out", args->calibration.model_out,
                    "With --calibrate: write the fitted model (the base is --model, or profiling/costs/cost_model.json)");
    cmd->add_option("--make-calibration-set", args->calibration.make_set,
                    "Write a calibration set: each shader of --shaders counted, beside its report in --reports");
    cmd->add_option("--shaders", args->calibration.shaders, "With --make-calibration-set: a folder of .frag and .vert sources");
    cmd->add_option("--reports", args->calibration.reports,
                    "With --make-calibration-set: a folder of malioc reports, NAME.txt or NAME.json (or in frag/)");
    cmd->add_option("--set-source", args->calibration.source,
                    "With --make-calibration-set: where the shaders and reports came from (kept in the set)");
    cmd->add_option("--nir-child", args->nir_child, "internal")->group("");
    cmd->callback([args]() { set_exit_status(run_profile(*args)); });
}

}  // namespace px::tools
