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
};
GpuSummary summarise(const GpuTarget& target, const GpuProgram& program);

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
Result<GpuRun> compile_variants_on_gpu(const GpuCompilers& tools, const GpuTarget& target, int es_major,
                                       const std::vector<VariantKey>& keys,
                                       const std::vector<const ShaderFiles*>& files = {},
                                       double seconds_per_program = 60.0);

}  // namespace px::profiling
