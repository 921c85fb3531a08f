// Draws a scene into a framebuffer of the current context. The renderer never
// creates or owns a context: the host app (or platform/ in headless runs)
// makes one current, then loads a scene and draws it into any framebuffer.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "effects/variant.h"
#include "gl/caps.h"
#include "planner/planner.h"
#include "gl/errors.h"
#include "gl/program.h"
#include "render/target.h"
#include "gl/texture.h"
#include "scene/material_images.h"
#include "scene/scene.h"

namespace px {

struct RendererOptions {
    // Entry points for extensions (KHR_debug); nullptr: no debug messages.
    GetProcAddress get_proc_address = nullptr;
    // OpenGL ES 2.0 only: draw as a GPU without fragment highp would (every
    // PX_HIGHP in the fragment stage is mediump, and the debug outputs use
    // their 11-bit packing), whatever this context has. For testing the
    // no-highp path on a context that has highp.
    bool emulate_no_fragment_highp = false;
    // An OpenGL ES 3.x context planned and drawn exactly as an ES 2.0 one
    // (GLSL ES 1.00 variants, the ES 2.0 uploads, draws and debug packing),
    // so that ES 2.0 variants can run through a transform that emits
    // GLSL ES 3.00 (the precision emulation). The host's ES 3.0 state is
    // saved and restored as ever. Combines with emulate_no_fragment_highp.
    bool emulate_es2 = false;
    // Applied to both assembled sources of every program before it is
    // compiled (gl/program.h ShaderTransform); empty: none. Uniform names
    // and types must survive it: the typed interface is checked as ever.
    ShaderTransform shader_transform;
    // The effect planner's cost table and calibrations (materials that
    // declare effects); default: the table built into the library.
    PlannerOptions planner;
    // Where program binaries are kept across runs (gl/program_binary.h):
    // on a context that has a binary format, each program is looked up
    // here (`load`) before compiling and stored (`store`) after a fresh
    // link. Empty: every program is compiled from source.
    ProgramBinaryStore program_binaries;
    // Applied to every object's planned variant before its program is built
    // and drawn (the debug passes keep their own output); empty: none. For
    // studies of shader forms that draw with the same inputs, such as the
    // optimisation ladder (VariantKey::ladder_step): the renderer binds
    // what the planned variant binds.
    std::function<VariantKey(const VariantKey&)> variant_transform;
    // Decode every texture file on the CPU and upload RGBA8, even where the
    // context samples its format (tests of the fallback path).
    bool force_texture_decode = false;
    // Draw as a context without GL_OES_texture_npot would (ES 2.0): every
    // non-power-of-two texture is resampled (tests of that path).
    bool emulate_no_texture_npot = false;
};

// What the renderer decided for one object: shown by `parallax render` and
// asserted by tests.
struct DrawReport {
    std::string object;
    std::string material;
    Technique requested = Technique::normal;
    VariantKey variant;
    std::vector<std::string> notes;  // why the variant differs from the request
    ObjectPlan plan;                 // the planner's whole answer: view, prediction, notes
};

class Renderer {
public:
    // Needs a current OpenGL ES 2.0 or 3.x context.
    static Result<std::unique_ptr<Renderer>> create(const RendererOptions& options = {});
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    const Caps& caps() const { return caps_; }

    // Uploads meshes and textures and builds the programs the scene needs.
    // Replaces any scene loaded before. Errors name the object or material.
    Status load(const SceneDesc& scene);
    // Draws the loaded scene into `target`. Every piece of GL state the
    // renderer changes is restored afterwards for the host app (the list is
    // in gl/state.h), and state the host left set that would change the
    // image (scissor, stencil, blend, colour mask, sampler objects, ...) is
    // set aside for the draw. `load` restores the host's state the same way.
    // `debug_output` (VariantKey::debug_output) draws what each shader
    // computed instead of colour; see render/surface_capture.h.
    // A target of another size than the plans were made for is planned
    // again first (the plan depends on texels per pixel).
    Status draw(const RenderTarget& target, std::uint8_t debug_output = 0);

    // Moving cameras: plans every object again for this camera and image
    // size, and draws from then on with that camera. Returns how many
    // objects changed variant. Cheap (no GL unless a new variant must be
    // compiled: call prepare() first to keep compiles out of the frame).
    Result<int> set_view(const CameraDesc& camera, int width, int height);
    // The plans for a view, without applying them.
    Result<std::vector<ObjectPlan>> plan_view(const CameraDesc& camera, int width, int height) const;
    // Compiles these variants now (e.g. every one a camera path will need).
    Status prepare(const std::vector<VariantKey>& keys);
    // The same for the plans of a camera path's frames (plan_view), and
    // draws each object once with each of its variants into `warm_target`
    // (its contents are undefined afterwards): drivers finish a program's
    // compile at its first draw, so no frame of the path pays for it.
    Status prepare(const std::vector<std::vector<ObjectPlan>>& frames, const RenderTarget& warm_target);

    const std::vector<DrawReport>& reports() const { return reports_; }
    // How each texture of the loaded scene reached the GPU (texture files:
    // direct upload or CPU decode; images: RGBA8), in load order.
    const std::vector<TextureUpload>& texture_uploads() const { return texture_uploads_; }
    // What was resampled at load and why (MaterialImages::notes), per material.
    const std::vector<std::string>& texture_notes() const { return texture_notes_; }
    // The options the exact reference must build its images with to see
    // the textures this context draws (scene/material_images.h).
    MaterialImageOptions material_image_options() const;
    size_t program_count() const;
    // How the loaded scene's programs were made (compiled, from binaries,
    // stored entries rejected); all zero before a load.
    ProgramStats program_stats() const;

    // Deletes every GL object (context still current).
    void release();
    // After a context loss: forgets every GL object without calling GL.
    void abandon();

    struct GpuScene;

private:
    Status load_checked(const SceneDesc& scene);
    Result<int> apply_plans(const CameraDesc& camera, int width, int height);
    Renderer() = default;
    Caps caps_;
    ShaderTransform shader_transform_;
    std::function<VariantKey(const VariantKey&)> variant_transform_;
    PlannerOptions planner_options_;
    ProgramBinaryStore program_binaries_;
    ProgramBinarySupport binary_support_;
    std::unique_ptr<GpuScene> scene_;
    std::vector<DrawReport> reports_;
    std::vector<TextureUpload> texture_uploads_;
    std::vector<std::string> texture_notes_;
    bool force_texture_decode_ = false;
};

}  // namespace px
