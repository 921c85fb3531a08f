// How often the expensive steps of the pipeline ran: validating a scene,
// building a material's images, building a mesh, planning an object for a
// frame. Tests and `parallax render --stats` read them to show that a scene is
// prepared once and planned once per object per frame (DESIGN.md). Counted
// process-wide (atomics): take a snapshot before and after, and subtract.
#pragma once

#include <cstdint>

namespace px {

struct PipelineCounters {
    std::uint64_t validations = 0;     // validate_scene
    std::uint64_t image_builds = 0;    // build_material_images (one material's textures)
    std::uint64_t mesh_builds = 0;     // build_object_mesh, make_displaced_plane
    std::uint64_t object_plans = 0;    // one object planned for one frame (ScenePlanner::plan)
    std::uint64_t programs_built = 0;  // GL programs made, compiled or from a stored binary
    std::uint64_t material_plans = 0;  // plan_variant: a named material's variant on a context

    PipelineCounters operator-(const PipelineCounters& before) const {
        return {validations - before.validations, image_builds - before.image_builds,
                mesh_builds - before.mesh_builds, object_plans - before.object_plans,
                programs_built - before.programs_built, material_plans - before.material_plans};
    }
};

// A snapshot of the counters now.
PipelineCounters pipeline_counters();

namespace counters {
enum class Step { validation, image_build, mesh_build, object_plan, program_build, material_plan };
// Called by the step itself.
void count(Step step, std::uint64_t n = 1);
}  // namespace counters

}  // namespace px
