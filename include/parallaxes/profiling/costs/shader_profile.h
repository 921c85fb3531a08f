// One variant's profile for `parallax profile`: its static costs from
// glslang's SPIR-V (both stages), the cost model's estimate, what Mesa's NIR
// and any vendor compiler said, and what was measured; and the report
// writers (text table, Markdown, JSON) and comparisons. GL-free: what needs
// a context (NIR, timing) is measured by the tool and filled in here.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "parallaxes/effects/variant.h"
#include "parallaxes/profiling/costs/cost_model.h"
#include "parallaxes/profiling/costs/gpu_compilers.h"
#include "parallaxes/profiling/costs/shader_costs.h"
#include "parallaxes/shaders/shader_source.h"

namespace px::profiling {

struct VendorFigures {  // a vendor compiler's figures for one stage, as reported
    std::string tool;
    std::string target;
    int work_registers = -1;
    double fp16_percent = -1.0;
    std::vector<std::string> pipes;
    std::vector<double> total, shortest, longest;  // NaN where the tool prints N/A
    std::string bound;     // the longest path's; the total's where the longest is N/A
    double cycles = -1.0;  // a single figure where the tool gives one
};

struct GpuFigures {  // one real GPU compiler's statistics for a variant (profile --gpu)
    std::string target;   // GpuTarget::name, "mali-g57"
    std::string gpu;      // "Mali-G57 (Valhall)"
    GpuProgram program;   // every stage the driver compiled, in its own words; or the error
    GpuSummary summary;
};

struct Measured {
    std::string scene;     // bench scene and angle the variant was drawn on
    double angle_deg = 0.0;
    double ns_per_pixel = 0.0;     // llvmpipe, median frame / pixels drawn
    double ratio_to_normal = 0.0;  // median of interleaved per-round ratios to normal mapping
    double uv_error_mean = 0.0;    // texels, against the exact reference
    double uv_error_p95 = 0.0;
    double color_psnr_db = 0.0;
};

struct VariantProfile {
    VariantKey key;
    std::string name;  // key.describe()
    StageCost vertex, fragment;
    PipeCycles fragment_shortest, fragment_longest, vertex_longest;
    std::optional<NirCost> nir_vertex, nir_fragment;
    std::string nir_note;  // why NIR is absent, when it is
    std::vector<VendorFigures> vendor_fragment;
    std::vector<GpuFigures> gpu;  // one per --gpu target
    std::optional<Measured> measured;
};

// Assembles the variant (from `files`, or the embedded shaders when null)
// and counts both stages.
Result<VariantProfile> profile_variant(const VariantKey& key, const CostModel& model, const ShaderFiles* files = nullptr);

enum class ReportFormat { table, markdown, json };
Result<ReportFormat> parse_report_format(const std::string& name);
// A table as text (aligned columns, the first left-aligned) or Markdown.
std::string render_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                         ReportFormat format);

struct ReportContext {
    std::string command;        // how the report was made
    std::string renderer;       // GL_RENDERER of the timing and NIR context, empty when none
    std::string vendor_line;    // "no vendor compiler on PATH (...)" or the tools used
    std::vector<std::string> gpu_lines;  // per --gpu target: what the driver's context said, and how it ran
    const CostModel* model = nullptr;
};

// The per-variant table: the columns mobile developers read in the vendors'
// offline compilers (work registers where known, 16-bit share, cycles per
// pipe, shortest and longest path), then the SPIR-V counts, NIR, time.
std::string profile_report(const std::vector<VariantProfile>& profiles, ReportFormat format, const ReportContext& context);

// Per-metric deltas between two profiles (B - A, and B / A).
std::string compare_report(const VariantProfile& a, const VariantProfile& b, ReportFormat format,
                           const ReportContext& context);

// The optimisation ladder: one row per step (profiles in step order, the
// shipped shader last), each with its change in static cost, estimated
// cycles, measured time and the image error against the exact reference.
std::string ladder_report(const std::vector<VariantProfile>& steps, ReportFormat format, const ReportContext& context);

// Model against measurement: for each measured variant, its estimated
// cycles relative to `baseline`'s (normal mapping's variant) beside its
// measured time relative to normal mapping (BenchRow::ratio_to_normal), and a sentence naming where they agree within a factor of 2
// and where they part.
std::string agreement_report(const std::vector<VariantProfile>& profiles, const std::string& baseline, ReportFormat format);

// The real GPU compilers' figures (profile --gpu): one row per variant and
// GPU; empty when no profile has any.
std::string gpu_report(const std::vector<VariantProfile>& profiles, ReportFormat format);

// The cost model's parameters and assumptions, for reports.
std::string model_section(const CostModel& model, ReportFormat format);

}  // namespace px::profiling
