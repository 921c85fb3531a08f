#include "parallaxes/core/counters.h"

#include <atomic>

namespace px {

namespace {
std::atomic<std::uint64_t> g_counts[6];
}

PipelineCounters pipeline_counters() {
    PipelineCounters c;
    c.validations = g_counts[0].load(std::memory_order_relaxed);
    c.image_builds = g_counts[1].load(std::memory_order_relaxed);
    c.mesh_builds = g_counts[2].load(std::memory_order_relaxed);
    c.object_plans = g_counts[3].load(std::memory_order_relaxed);
    c.programs_built = g_counts[4].load(std::memory_order_relaxed);
    c.material_plans = g_counts[5].load(std::memory_order_relaxed);
    return c;
}

void counters::count(Step step, std::uint64_t n) {
    g_counts[static_cast<int>(step)].fetch_add(n, std::memory_order_relaxed);
}

}  // namespace px
