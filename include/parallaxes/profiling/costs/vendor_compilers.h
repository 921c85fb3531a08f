// Vendor offline shader compilers for `parallax profile`: Arm's Mali Offline
// Compiler (malioc) and the PowerVR SDK's GLSL ES compilers
// (GLSLESCompiler_Rogue, ...). Each reports what one shader stage costs on
// its GPU family: registers, cycles per pipe, the bounding pipe. Neither tool
// ships with Debian, so they are looked for on PATH and the report says so
// when none is there. The parsers take the tools' printed reports; they never
// guess a figure: a report that lacks one the parser needs is an error naming
// it.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/effects/variant.h"

namespace px::profiling {

// One variant of a shader stage as a vendor compiler reports it: malioc's
// "Main" (or, for vertex shaders on GPUs with index-driven vertex shading,
// "Position" and "Varying", each compiled and reported separately).
struct VendorVariant {
    std::string name;              // "Main", "Position", "Varying"; "" for a tool without variants
    int work_registers = -1;       // -1: not reported (or N/A)
    int uniform_registers = -1;
    double fp16_percent = -1.0;    // 16-bit arithmetic share, -1: not reported (or N/A)
    bool stack_spilling = false;
    std::vector<std::string> pipes;        // column names as the tool names them
    std::vector<double> total, shortest, longest;  // per pipe (NaN where the tool prints N/A); empty: row absent
    std::string bound;             // the longest path's bounding pipe(s), "A", "V, T"; the total's where the
                                   // longest path is N/A; empty if absent
    std::string total_bound, shortest_bound, longest_bound;  // each row's own (empty for N/A)
    std::vector<std::string> notes; // per variant (e.g. "stack spill 8 bytes")
};

// One shader stage's figures from a vendor compiler: the primary variant's
// figures (malioc's Main, or Position where a vertex shader has no Main
// figures) in the base, every variant in `variants`, in the report's order.
struct VendorCycles : VendorVariant {
    std::string tool;              // "malioc 7.4.0" / "GLSLESCompiler_Rogue"
    std::string target;            // "Mali-G78 r1p1 (Valhall)", "Rogue"
    std::string shader_type;       // "OpenGL ES Fragment", "Vulkan Vertex", ... where the report says
    double cycles = -1.0;          // a single total cycle figure where the tool gives one (PowerVR), else -1
    std::vector<VendorVariant> variants;
};

// malioc's text report (malioc 6.x to 8.x; Midgard, Bifrost and Valhall
// tables; variant sections under '=' or '-' rules). A line of a variant
// section that looks like figures the parser does not know is refused,
// quoted, rather than read wrong.
Result<VendorCycles> parse_malioc_text(const std::string& output);
// malioc's `--format json` report. Pipes are given the text report's short
// names (arith_fma -> FMA, load_store -> LS, ...) so that both formats of
// one compile give the same figures.
Result<VendorCycles> parse_malioc_json(const std::string& output);
// The PowerVR compilers' profile output (stdout and the .prof file together).
Result<VendorCycles> parse_powervr_output(const std::string& output);

struct VendorTool {
    std::string name;   // "malioc", "GLSLESCompiler_Rogue"
    std::string path;   // absolute path found on PATH
};

// The vendor compilers found on $PATH (each candidate name checked with access(X_OK)); empty if none.
std::vector<VendorTool> find_vendor_tools();

// Writes `source` to a temporary file with the stage's extension (.vert/.frag), runs the tool on it
// (posix_spawn, stdout+stderr captured through a pipe, a wall-clock limit after which the child and
// anything it started are killed, output capped at 4 MiB), parses the output. Errors name the tool,
// its exit status and the first lines of its output. `es_major` 2 or 3 (the source's #version says
// it anyway). A file the tool writes (PowerVR's <out>.prof) is read only when it is a regular file,
// not through a symlink, at most 4 MiB. Every string in the result and the error has been through
// clean_tool_text.
Result<VendorCycles> run_vendor_tool(const VendorTool& tool, const std::string& source, ShaderStage stage,
                                     int es_major,
                                     std::chrono::milliseconds time_limit = std::chrono::seconds(60));

// The vendor tools over a whole `parallax profile` run: one time budget for
// all their runs together, and a tool that runs out of time once is not
// started again in that run (a hanging compiler would otherwise cost the
// limit once per variant). One run may take what is left of the budget, but
// at most half the whole budget, so that one hang leaves time for the others.
class VendorRun {
public:
    VendorRun(std::vector<VendorTool> tools, std::chrono::milliseconds budget);
    const std::vector<VendorTool>& tools() const { return tools_; }
    // run_vendor_tool within the budget. A tool that timed out before, or
    // that finds the budget spent, is not started: the error says so and
    // starts with "skipped:".
    Result<VendorCycles> run(const VendorTool& tool, const std::string& source, ShaderStage stage, int es_major);
    // One line per tool that was stopped or skipped, for the report; empty when none was.
    const std::vector<std::string>& notes() const { return notes_; }

private:
    std::vector<VendorTool> tools_;
    std::chrono::milliseconds budget_;
    std::chrono::steady_clock::duration used_{};
    std::vector<std::string> timed_out_;  // tool names
    std::vector<std::string> notes_;
    bool budget_noted_ = false;
};

// Text from a tool (its output, or a name or path it gave) made safe for a
// report: valid UTF-8 (each invalid byte becomes U+FFFD, so JSON can carry
// it), with terminal escape sequences and control characters removed except
// newline and tab (so that printing it cannot drive the terminal).
std::string clean_tool_text(const std::string& raw);

// One line for reports when no vendor tool is on PATH.
std::string vendor_tools_absent_line();  // "no vendor compiler on PATH (looked for malioc, GLSLESCompiler_...)"

}  // namespace px::profiling
