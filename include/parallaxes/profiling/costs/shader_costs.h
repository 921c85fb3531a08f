// Static shader costs read from what real compilers emit, never from a text
// count of the source (`parallax profile`, docs/profiling.md):
//  - glslang's SPIR-V for each stage of a variant: instruction classes,
//    the RelaxedPrecision (mediump/lowp) share, texture samples and which
//    are dependent reads, loops with their trip counts, and the shortest
//    and longest paths through the control flow;
//  - Mesa's NIR for the same variant (the text `ST_DEBUG=nir` prints as
//    llvmpipe links it; the tool captures it): ALU and texture
//    instructions, their 16-bit share, loops and branches as Mesa left them.
// GL-free: the SPIR-V side needs only the assembled sources.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/effects/variant.h"
#include "parallaxes/shaders/shader_source.h"

namespace px::profiling {

// Counts along one path (or the whole stage). Arithmetic is counted in
// scalar operations: a vec3 add is 3, a mat3 * vec3 is 9, as the scalar
// ALUs of current mobile GPUs (Mali Bifrost/Valhall, PowerVR Rogue) issue
// them; conversions and comparisons are arithmetic, register moves
// (composite construct/extract, shuffles, copies) are free.
struct OpCounts {
    double arithmetic = 0.0;      // scalar arithmetic operations
    double fp16 = 0.0;            // of those, on RelaxedPrecision (mediump/lowp) results
    double transcendental = 0.0;  // scalar sin/cos/exp/log/pow/sqrt/inversesqrt (and the one in normalize, length)
    double samples = 0.0;         // texture samples and fetches
    double branches = 0.0;        // conditional branches and discards
    OpCounts& operator+=(const OpCounts& o);
    OpCounts operator*(double k) const;
    // What a path search maximises or minimises: every operation counts 1.
    double weight() const { return arithmetic + transcendental + samples + branches; }
};

struct LoopCost {
    std::string where;        // "shaders_es/chunks/march.glsl:51"
    int trip_count = -1;      // from the loop's induction variable and constant bound; -1: not a counted loop
    int counted_trips = -1;   // what the longest path counts: trip_count, or a model's override for its file
    int depth = 1;            // 1: outermost
    bool has_samples = false; // texture reads inside it
};

struct SampleCost {
    std::string where;     // source line of the read
    bool dependent = false;  // its coordinates, or whether it runs at all, wait on another read's result
    std::vector<int> waits_on;  // indices of the reads it waits on (this stage's order)
    double repeats = 1.0;  // times it runs on the longest path (enclosing loops' trip counts)
};

struct StageCost {
    ShaderStage stage = ShaderStage::fragment;
    std::size_t spirv_words = 0;
    // Instructions by class, each counted once where it is written.
    int arithmetic_instructions = 0;
    int transcendental_instructions = 0;
    int texture_instructions = 0;
    int control_instructions = 0;
    int typed_results = 0;    // float/int results of arithmetic, transcendental and texture instructions
    int relaxed_results = 0;  // of those, decorated RelaxedPrecision (mediump or lowp in the source)
    int varying_components = 0;  // fragment: interpolated input components the stage reads
    int relaxed_varying_components = 0;  // of those, in inputs declared mediump or lowp (RelaxedPrecision)
    OpCounts total;     // every instruction once (loops not repeated)
    OpCounts shortest;  // the cheapest path: each branch its cheaper side, each loop left at its first exit
    OpCounts longest;   // the dearest path: each branch its dearer side, each loop run to its trip count
    bool unknown_trips = false;  // a loop without a constant trip count counted once on the longest path
    std::vector<LoopCost> loops;
    std::vector<SampleCost> samples;
    int dependent_samples = 0;
    // Texture results the longest path waits for one after another: the
    // longest chain of reads each needing the previous one's result, a
    // chain inside a loop counted once per iteration.
    double texture_round_trips = 0.0;
    // Waits in program order (each loop body once): how often an
    // instruction needs a texture result still in flight, on a GPU that
    // issues in the order written and waits for every read in flight at
    // once (the PowerVR whitepaper's "read, wait, math" count, 3.2.1).
    // Reads issued back to back share one wait.
    int in_order_waits = 0;
    // Cost of each source line ("shaders_es/chunks/march.glsl:54"), each
    // instruction once: for the changed lines of `profile --against`.
    std::map<std::string, OpCounts> by_line;
    double relaxed_share() const { return typed_results ? double(relaxed_results) / typed_results : 0.0; }
};

// glslang's SPIR-V for an assembled stage (GLSL ES 1.00 or 3.00 as it is,
// unoptimised, with line information). An error carries glslang's log.
Result<std::vector<std::uint32_t>> compile_spirv(const std::string& source, ShaderStage stage);

// Loops whose header is in a given file counted at a given trip count on
// the longest path (a cost model's loop_trips): file -> trips.
using TripOverrides = std::map<std::string, int>;

// The analysis of a module from compile_spirv. `origins` maps the source's
// lines to shaders_es/ files (AssembledSource::origins); empty: lines are
// named "source:N". Malformed words are an error, never a crash.
Result<StageCost> analyse_spirv(const std::vector<std::uint32_t>& words, ShaderStage stage,
                                const std::vector<LineOrigin>& origins = {}, const TripOverrides& trips = {});

// Both: compile and analyse one assembled stage.
Result<StageCost> stage_cost(const AssembledSource& source, ShaderStage stage, const TripOverrides& trips = {});

// --- Mesa's NIR ------------------------------------------------------------
struct NirCost {
    int alu = 0;          // ALU instructions (vector instructions count once, as NIR holds them)
    int alu_16bit = 0;    // of those, with a 16-bit destination
    int texture = 0;      // tex, txl, txd, txf, ... instructions
    int intrinsics = 0;   // loads of inputs and uniforms, stores of outputs, discards
    int loops = 0;        // loops Mesa left (llvmpipe unrolls counted loops of up to 32 iterations)
    int branches = 0;     // if statements
    int ssa_values = 0;   // SSA definitions
    double alu_16bit_share() const { return alu ? double(alu_16bit) / alu : 0.0; }
};

// The shaders in a NIR dump, in order: each begins at a "shader: MESA_SHADER_*"
// line. Stages other than vertex and fragment are skipped.
struct NirShader {
    ShaderStage stage = ShaderStage::fragment;
    std::string name;  // "GLSL3"
    NirCost cost;
};
Result<std::vector<NirShader>> parse_nir_dump(const std::string& text);

}  // namespace px::profiling
