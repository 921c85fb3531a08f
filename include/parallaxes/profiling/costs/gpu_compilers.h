// Real mobile GPU compilers for `parallax profile --gpu`: Mesa's own drivers
// for Mali (Panfrost: Midgard, Bifrost, Valhall), Adreno (Freedreno's ir3),
// the Raspberry Pi 4's V3D and Mali-400/450 (Lima), as Debian's arm64 Mesa
// builds them, run on this machine under qemu-aarch64 with one of Mesa's
// drm-shim "noop" libraries preloaded so that the driver loads with no
// device. A small arm64 program (tools/gpu/shader_probe.c) compiles and
// draws each program, and the driver prints its statistics (shader-db
// lines, or ir3's disassembly summary); pixels are meaningless.
// tools/cross/make_gpu_compilers.sh makes the sysroot, shims and program.
//
// The figures are the compiler's own, under its own words ("inst", "cycles",
// "arith", "threads", "spills:fills"); nothing is estimated here except the
// bound pipe, which is the pipe whose cycles equal the compiler's cycle
// figure (Bifrost, Valhall). A loop the compiler did not unroll counts once.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/effects/variant.h"
#include "parallaxes/shaders/shader_source.h"

namespace px::profiling {

// One GPU that --gpu names.
struct GpuTarget {
    std::string name;     // what --gpu takes: "mali-g57"
    std::string gpu;      // "Mali-G57 (Valhall)"
    std::string driver;   // "Panfrost"
    std::string shim;     // lib<shim>_noop_drm_shim.so
    std::vector<std::string> env;  // the shim's GPU and the driver's statistics switch
    int es_max = 3;       // Lima: OpenGL ES 2.0 only
    bool ir3 = false;     // statistics from ir3's disassembly (Adreno), not shader-db lines
    std::vector<std::string> pipes;  // per-pipe cycle figures, in the compiler's words ("arith", "texture", ...)
    std::string renderer;  // what GL_RENDERER must hold when that driver loaded: "Mali-G57", "FD630"
    // The switch that also prints the compiler's instruction listing
    // (Bifrost, Valhall: BIFROST_MESA_DEBUG=shaderdb,shaders), from which
    // each fragment stage's 16-bit share is counted; "" where not read.
    std::string listing_env;
};

// Every GPU --gpu knows, in --gpu list's order.
const std::vector<GpuTarget>& gpu_targets();
// "mali-g52,adreno-630" (names case-insensitive; "all" for every one). An
// unknown name is an error listing the known ones.
Result<std::vector<GpuTarget>> parse_gpu_targets(const std::string& names);
// --gpu list: one line per GPU (name, GPU, driver, ES versions).
std::string gpu_targets_text();

struct GpuFigure {
    std::string words;  // the compiler's words for the figure: "inst", "cycles", "sstall", "(ss)"
    double value = 0.0;
};

// One stage as one driver compiled it (a stage may be compiled more than
// once: Panfrost's position and varying halves of a vertex shader, V3D's and
// Freedreno's binning vertex shader).
struct GpuStage {
    std::string stage;  // the driver's name for it: "MESA_SHADER_FRAGMENT", "FRAG", "VERTEX_BIN", ...
    bool fragment = false;
    std::string line;   // the statistics line(s) as the driver printed them
    std::vector<GpuFigure> figures;
    int spills = -1, fills = -1;  // -1: not reported
    // From the compiler's last instruction listing of the stage (Bifrost,
    // Valhall; -1 where none was read): arithmetic and data-movement
    // instructions by the width they compute in, as their type suffix says
    // (".f16", ".v2f16", ".i16", ".v4i8", ...: narrow; ".f32", ".i32", ...:
    // 32-bit), and the conversions between widths ("F16_TO_F32", ...).
    // Loads, stores, texture, blending and branches are left out.
    int narrow_ops = -1, wide_ops = -1, conversions = -1;
    // From the same listing's blocks: the share of its instructions inside
    // a loop the compiler kept (a block whose predecessor is listed at or
    // after it closes a loop over the blocks between); 0 with none kept.
    double loop_share = -1.0;
    // The figure named `words`, if the compiler printed it.
    std::optional<double> figure(const std::string& words) const;
};

struct GpuProgram {
    std::vector<GpuStage> stages;  // in the order printed
    std::string error;             // compile, link or draw error, or why there are no figures
    const GpuStage* fragment() const;  // the first fragment stage, null if none
};

// What a target says about one program, summarised for reports.
struct GpuSummary {
    double instructions = -1.0;  // "inst" / "instr" of the fragment stage
    double cycles = -1.0;        // the compiler's cycle estimate per fragment (Bifrost, Valhall)
    std::string bound;           // the pipe(s) whose cycles equal it
    double threads = -1.0;       // threads per core (Panfrost, V3D)
    double registers = -1.0;     // registers (Midgard "registers", V3D "max-temps", ir3 "full")
    int spills = -1, fills = -1;
    double loops = -1.0;         // loops left after the compiler's unrolling
    double vertex_instructions = -1.0;  // all vertex stages together
    // The fragment stage's narrow share, narrow / (narrow + 32-bit), and its
    // conversions (GpuStage; -1 where not listed).
    double narrow_share = -1.0;
    int conversions = -1;
    double loop_share = -1.0;  // GpuStage::loop_share of the fragment stage
};

// Counts one line of a Bifrost or Valhall instruction listing
// ("r3 = FMA.v2f16 r1.h00, ...", "*    r2 = FMA.f32 ..."); lines that are
// not an instruction with a destination are left alone.
void count_listing_line(const std::string& line, GpuStage& stage);
GpuSummary summarise(const GpuTarget& target, const GpuProgram& program);

// A fragment's cycles per pixel from the compiler's static estimate
// `cycles` (one pass of each loop it kept: `loops`): the estimate itself
// where it kept none. Where it kept one, with the loop iterations the shader
// counted (`counted`: the work counters ran; at least one pass) and
// `loop_share` (GpuStage::loop_share, 0..1) known: the estimate with the
// loop's share of it taken once per pass, cycles x ((1 - share) + share x
// passes), which takes a loop instruction to cost what the program's average
// one does; without the share: the estimate times the passes, an upper bound
// (the code outside the loop counted each pass). -1 where a loop was kept
// and nothing was counted.
double cycles_per_pixel(double cycles, double loops, bool counted, double iterations, double loop_share = -1.0);

struct GpuRun {
    std::string context;              // GL_RENDERER | GL_VERSION the probe got
    std::vector<GpuProgram> programs;  // one per program given, in order
};

// Reads shader_probe's output (its markers, and the driver's lines between
// them) for `programs` programs. A program without its end marker gets an
// error saying so; lines that look like statistics but do not parse are
// an error quoting them.
Result<GpuRun> parse_probe_output(const GpuTarget& target, const std::string& output, std::size_t programs);

// Where make_gpu_compilers.sh put its files: $PX_GPU_COMPILERS, or
// ~/.cache/parallaxes/gpu-compilers. A missing piece is an error naming the
// command that makes it.
struct GpuCompilers {
    std::string dir, sysroot, qemu;
};
Result<GpuCompilers> find_gpu_compilers();

struct ShaderPair {
    std::string vertex, fragment;  // full sources
};

// Compiles every pair with `target`'s driver (qemu-aarch64, the shim
// preloaded, Mesa's shader caches off), up to 16 pairs a run, each run
// limited to 20 s plus `seconds_per_program` per pair: a program the
// compiler does not finish (the limit passes, or the driver crashes) is
// marked so and the next run starts after it; after two such in a row the
// rest are skipped.
Result<GpuRun> compile_on_gpu(const GpuCompilers& tools, const GpuTarget& target, int es_major,
                              const std::vector<ShaderPair>& pairs, double seconds_per_program = 60.0);

// The same for variants: each assembled (from `files[i]` where given and
// not null, else the embedded shaders) and compiled, in order.
// `lights` (1 to kMaxLights; 0: as shipped): the lights loop's bound
// (PX_MAX_LIGHTS) set to the scene's light count. `search_steps` (empty, or
// one per key; 0: as the key says): the search loop's bound (PX_MAX_SAMPLES)
// set to that many steps, the search truncated where a pixel's search ends.
Result<GpuRun> compile_variants_on_gpu(const GpuCompilers& tools, const GpuTarget& target, int es_major,
                                       const std::vector<VariantKey>& keys,
                                       const std::vector<const ShaderFiles*>& files = {},
                                       double seconds_per_program = 60.0, int lights = 0,
                                       const std::vector<int>& search_steps = {});

// `source` with the value of its "#define NAME VALUE" line (one the
// variant's defines put there) set to `value`. Error: no such line.
Result<std::string> with_define(const std::string& source, const std::string& name, int value);

// What a pixel of a scene costs on a GPU, from its compiler: one variant as
// a scene draws it.
//
// A compiler's static estimate sums every instruction of the program once:
// every step of an unrolled search, though a pixel's search ends at its
// crossing, and one pass of a loop it kept. And the shipped program bounds
// its lights loop at kMaxLights: a compiler that unrolls the loop counts
// every light's code, and one that keeps it keeps live values across it
// (maxmip spills 4:37 on Mali-G57, all 41 of its loads and stores outside
// the walk's loop, and none with the bound at one light: docs/gpu-compilers.md).
// So the cost of a pixel is the estimate for the variant compiled for the
// scene's light count with its search truncated to the steps the pixel's
// search took (`steps`, from the shader's own work counters; 0 for a
// variant without a search): what that pixel runs. Where the compiler still
// keeps a loop there (a search of many steps, a long shadow march), the
// loop's share of the instruction listing (GpuStage::loop_share) is taken
// once per pass (cycles_per_pixel), the passes being the larger of the
// search's steps and the shadow ray's samples (the listing does not say
// which loop was kept; a soft march runs all its samples, a hard one at
// most that many).
struct GpuPixelCost {
    VariantKey key;
    int steps = 0;
};
// The steps a pixel's search is truncated to: the counted `iterations`
// rounded up, within 1 and the key's bound; 0 for a variant without a
// search or where nothing was counted (`counted` false, or NaN).
int pixel_search_steps(const VariantKey& key, bool counted, double iterations);
struct GpuCost {
    GpuSummary variant;  // the variant compiled for the scene's lights (search as the key says)
    GpuSummary pixel;    // truncated to the pixel's steps (= variant where steps is 0)
    double cycles_per_pixel = -1.0;  // -1: no estimate
    std::string error;   // either compile's
};
// Both compiles for each request, in one or two runs of the compiler.
// `lights`: the scene's light count (1 to kMaxLights).
Result<std::vector<GpuCost>> gpu_pixel_costs(const GpuCompilers& tools, const GpuTarget& target, int es_major,
                                             const std::vector<GpuPixelCost>& requests, int lights,
                                             std::string* context = nullptr, double seconds_per_program = 60.0);

}  // namespace px::profiling
