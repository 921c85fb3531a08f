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
};

// Counts one line of a Bifrost or Valhall instruction listing
// ("r3 = FMA.v2f16 r1.h00, ...", "*    r2 = FMA.f32 ..."); lines that are
// not an instruction with a destination are left alone.
void count_listing_line(const std::string& line, GpuStage& stage);
GpuSummary summarise(const GpuTarget& target, const GpuProgram& program);

// A fragment's cycles per pixel from the compiler's static estimate
// `cycles` (one pass of each loop it kept: `loops`): the estimate itself
// where it kept none; where it kept one, the estimate times the loop
// iterations the shader counted at that pixel (`counted`: the work counters
// ran; at least one pass), an upper bound, since the code outside the loop
// is counted each time; -1 where a loop was kept and nothing was counted.
double cycles_per_pixel(double cycles, double loops, bool counted, double iterations);

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
// (PX_MAX_LIGHTS) set to the scene's light count, for a per-pixel cost: a
// compiler that keeps the lights loop (one whose body holds a shadow march)
// counts one pass of it, which a cost per pixel must not take for a search's
// loop and multiply by the search's iterations.
Result<GpuRun> compile_variants_on_gpu(const GpuCompilers& tools, const GpuTarget& target, int es_major,
                                       const std::vector<VariantKey>& keys,
                                       const std::vector<const ShaderFiles*>& files = {},
                                       double seconds_per_program = 60.0, int lights = 0);

// What a cost per pixel needs of each variant: its figures compiled for the
// scene's light count (`lights`: the lights loop's bound, PX_MAX_LIGHTS, set
// to it), and the shipped program's (bound kMaxLights) beside them. The
// shipped program is what `profile --gpu` reports; for a scene with fewer
// lights it is not what runs: a compiler that unrolls its lights loop counts
// every light's code in its estimate, and one that keeps it keeps the live
// values across it (maxmip spills 4:37 on Mali-G57, all 41 of its loads and
// stores outside the walk's loop; with the bound at one light it spills
// none: docs/gpu-compilers.md). So a cost per pixel is of the program
// specialised to the scene's lights, and a kept loop in it is a search's.
struct GpuCost {
    GpuSummary scene;    // compiled with PX_MAX_LIGHTS = the scene's light count
    GpuSummary shipped;  // as shipped (PX_MAX_LIGHTS = kMaxLights)
    std::string error;   // either compile's
};
Result<std::vector<GpuCost>> gpu_costs_of_variants(const GpuCompilers& tools, const GpuTarget& target, int es_major,
                                                   const std::vector<VariantKey>& keys, int lights,
                                                   double seconds_per_program = 60.0, std::string* context = nullptr);

// `source` with its lights loop bound (the "#define PX_MAX_LIGHTS" line the
// variant's defines put there) set to `lights`. Error: no such line.
Result<std::string> with_light_bound(const std::string& source, int lights);

}  // namespace px::profiling
