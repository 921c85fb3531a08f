// Draws a prepared scene into a framebuffer of the current context, as part of
// the host's own frame. The renderer never creates or owns a context: the
// host app (or platform/ in headless runs) makes one current, loads a scene
// once, then each frame calls draw() with its own camera, viewport, object
// transforms and depth buffer, between its own draws.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"
#include "parallaxes/effects/variant.h"
#include "parallaxes/gl/caps.h"
#include "parallaxes/planner/planner.h"
#include "parallaxes/gl/errors.h"
#include "parallaxes/gl/program.h"
#include "parallaxes/render/target.h"
#include "parallaxes/gl/texture.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/scene/prepared_scene.h"
#include "parallaxes/scene/scene.h"

namespace px {

// Texture files for the renderer: the readers that prepare them
// (scene/material_images.h) and the upload that hands them to GL as they
// are, or decoded where the context cannot sample their format.
struct TextureFileSupport {
    const TextureFileReaders* readers = nullptr;
    Result<Texture> (*upload)(const TextureData& data, const Caps& caps, const std::string& what, bool mipmaps,
                              bool force_decode, TextureUpload* report, DecodeLevel decode, bool srgb) = nullptr;
};

// Every file the library reads (render/texture_files.cpp): set
// RendererOptions::texture_files to it where scenes name files.
const TextureFileSupport* texture_files();

struct RendererOptions {
    // Entry points for extensions (KHR_debug); nullptr: no debug messages.
    // The driver's messages reach the library's errors through a KHR_debug
    // callback it installs only where the host has none (a host's callback
    // and its user parameter are never replaced), and takes out again when
    // the renderer is destroyed with its context current.
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
    // Debug draws (draw(target, debug_output)) of searching techniques show
    // each pixel's loop iterations and texture fetches in place of the hit
    // uv (VariantKey::count_work; include/parallaxes/profiling/measurement/work.h reads them).
    bool count_work = false;
    // Float debug draws (debug output 1, ES 3.0) of height-reading techniques
    // show the ray each pixel's trace was handed instead of its hit
    // (VariantKey::capture_ray): SurfaceSample uv = the fragment's uv,
    // height and visibility = the parallax vector (uv shift per unit of
    // normalised height). What the bench's "own ray" error is measured from.
    bool capture_ray = false;
    // The effect planner, for scenes whose materials declare effects:
    // px::effect_planner (parallaxes/planner/planner.h, ParallaxES::planner).
    // Null (the default): materials must name their technique, and a scene
    // that declares effects is refused at load with a message saying so; the
    // renderer then links none of the planner, its cost table or its JSON
    // parser.
    EffectPlannerFactory effect_planner = nullptr;
    // How scene files are read and uploaded (images, KTX 1.1, KTX 2.0 and
    // PVR v3 containers, the CPU decoders): px::texture_files(). Null (the
    // default): textures are procedural or colours, a scene that names a
    // file is refused at load naming the file, and the renderer links no
    // image or container reader, codec, libjpeg, libzstd or libastcenc.
    const TextureFileSupport* texture_files = nullptr;
    // The effect planner's cost table and calibrations; default: the table
    // built into the library.
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
    // Save every piece of GL state the library touches before each call and
    // restore it after (gl/state.h has the list). A host that sets its own
    // state before each of its draws may turn this off: the library then
    // leaves behind what its draw set (its program, textures on units 0-3,
    // buffers, vertex array and attributes 0-3, viewport, depth test, depth
    // mask and function, cull face, front face, blend and scissor off, and
    // the framebuffer binding). docs/host-integration.md has the measured saving.
    bool preserve_host_state = true;
    // Names the context that is current (e.g. eglGetCurrentContext); the
    // renderer records it at create() and refuses every later call made
    // while another context (or none) is current, with an error instead of
    // a driver crash. Empty: looked up through get_proc_address
    // ("eglGetCurrentContext"); where neither is given the renderer cannot
    // tell contexts apart, and the host must keep the renderer's context
    // current (or share objects with it) whenever it calls the renderer.
    std::function<const void*()> current_context;
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

// A rectangle of the target in pixels, from its lower left corner (as glViewport).
struct Viewport {
    int x = 0, y = 0;
    int width = 0, height = 0;  // 0 x 0: the whole target
};

// One frame as the host draws it (planned and drawn by Renderer::draw).
struct HostFrame {
    HostFrame() = default;
    explicit HostFrame(const RenderTarget& t) : target(t) {}

    RenderTarget target;       // the framebuffer the host draws into, and its size in pixels
    Viewport viewport;         // where in it the scene is drawn; empty: the whole target
    glm::mat4 view{1.0f};      // the host's camera: view and projection matrices
    glm::mat4 projection{1.0f};
    // Each object's model transform this frame, in scene order; empty: the
    // transforms of the scene description.
    std::vector<glm::mat4> models;
    // By default nothing is cleared: the scene is depth-tested against the
    // host's depth buffer and drawn over its colour. Clears stay inside
    // the viewport; colour is cleared to the scene's background.
    bool clear_color = false;
    bool clear_depth = false;
    std::uint8_t debug_output = 0;  // VariantKey::debug_output (render/surface_capture.h)
    // What the target's colour holds: lighting is computed in linear light,
    // and the shader encodes it for an sRGB display (srgb_encoded, the
    // default: an ordinary RGBA8 window or texture that a display shows as
    // it is), writes it linear (linear: a host that post-processes in linear
    // light, e.g. into a float target), or writes it linear into a
    // framebuffer that encodes on write (srgb_framebuffer: an
    // GL_SRGB8_ALPHA8 attachment, or an EGL surface with
    // EGL_GL_COLORSPACE_SRGB). Debug outputs are data and never encoded.
    enum class TargetColor : std::uint8_t { srgb_encoded, linear, srgb_framebuffer };
    TargetColor target_color = TargetColor::srgb_encoded;

    // A camera description as view and projection matrices, for this
    // viewport of the target (empty: the whole target; its aspect ratio).
    static HostFrame from_camera(const CameraDesc& camera, const RenderTarget& target, const Viewport& viewport = {});
};

// How the library reached the current frame: counts since create().
struct RendererStats {
    std::uint64_t frames = 0;         // draw() calls that drew
    std::uint64_t plans = 0;          // frames the objects were planned for (the others reused a plan)
    std::uint64_t objects_drawn = 0;
};

class Renderer {
public:
    // Needs a current OpenGL ES 2.0 or 3.x context.
    static Result<std::unique_ptr<Renderer>> create(const RendererOptions& options = {});
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    const Caps& caps() const { return caps_; }

    // How scenes must be prepared for this context (texture sizes it can
    // sample): pass to prepare_scene, or let load(SceneDesc) do it.
    PrepareOptions prepare_options() const;
    // Uploads a prepared scene's meshes and textures, and builds the programs
    // of the materials that name their technique (so that a shader error
    // surfaces here); variants the planner picks per frame are built at the
    // frame that first draws them. Replaces any scene loaded before. Errors
    // name the object or material. The prepared scene is shared, not copied:
    // the exact reference and the benchmark read the same one.
    Status load(std::shared_ptr<const PreparedScene> scene);
    // prepare_scene(scene, prepare_options()), then load.
    Status load(const SceneDesc& scene);
    // Replaces one material (by name) of the loaded scene: only its textures
    // (and meshes displaced from it) are built and uploaded again. On error
    // the loaded scene is unchanged.
    Status replace_material(const MaterialDesc& material);
    // The loaded scene (null before a load).
    const std::shared_ptr<const PreparedScene>& prepared() const { return prepared_; }

    // Plans and draws the loaded scene as part of the host's frame: into
    // frame.target's framebuffer, inside frame.viewport, with the host's
    // view, projection and object transforms, depth-tested (GL_LESS)
    // against the host's depth buffer, with depth written (corrected where
    // the plan writes gl_FragDepth). Nothing is cleared unless asked. The
    // objects are planned again only when the frame's camera, viewport
    // size or transforms changed. Every piece of GL state the renderer
    // changes is restored afterwards (gl/state.h has the list) unless
    // RendererOptions::preserve_host_state is off, and state the host left
    // set that would change the image (scissor, stencil, blend, colour
    // mask, sampler objects, ...) is set aside for the draw.
    Status draw(const HostFrame& frame);
    // What `parallax render` draws: scene_frame(target, debug_output).
    Status draw(const RenderTarget& target, std::uint8_t debug_output = 0);
    // The whole target seen from the camera of the last set_view (at first,
    // the scene's), cleared to the scene's background first.
    HostFrame scene_frame(const RenderTarget& target, std::uint8_t debug_output = 0) const;

    // Moving cameras for draw(target): plans every object again for this
    // camera and image size, and draws from then on with that camera.
    // Returns how many objects changed variant. Cheap (no GL unless a new variant must be
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
    const RendererStats& stats() const { return stats_; }
    // How the loaded scene's programs were made (compiled, from binaries,
    // stored entries rejected); all zero before a load.
    ProgramStats program_stats() const;

    // Deletes every GL object (its context current: with another current,
    // it forgets them instead, as abandon(), rather than delete another
    // context's objects of the same names).
    void release();
    // After a context loss: forgets every GL object without calling GL.
    void abandon();

    struct GpuScene;

private:
    Status load_checked(std::shared_ptr<const PreparedScene> scene);
    Result<int> apply_plans(const PlanView& view);
    // The effect planner where the renderer has one, else the named-technique
    // planner (planner/object_plan.h): the one place an object is planned.
    Result<std::unique_ptr<FramePlanner>> make_planner(const std::shared_ptr<const PreparedScene>& scene,
                                                       std::vector<MaterialRelief> reliefs) const;
    Status check_context(const char* what) const;
    Status draw_checked(const HostFrame& frame);
    Renderer() = default;
    std::shared_ptr<const PreparedScene> prepared_;
    std::function<const void*()> current_context_;
    const void* context_ = nullptr;  // the context create() ran in (when current_context_ can tell)
    bool preserve_host_state_ = true;
    RendererStats stats_;
    Caps caps_;
    ShaderTransform shader_transform_;
    bool count_work_ = false;
    bool capture_ray_ = false;
    std::function<VariantKey(const VariantKey&)> variant_transform_;
    PlannerOptions planner_options_;
    EffectPlannerFactory effect_planner_ = nullptr;
    const TextureFileSupport* texture_files_ = nullptr;
    ProgramBinaryStore program_binaries_;
    ProgramBinarySupport binary_support_;
    std::unique_ptr<GpuScene> scene_;
    std::vector<DrawReport> reports_;
    std::vector<TextureUpload> texture_uploads_;
    std::vector<std::string> texture_notes_;
    bool force_texture_decode_ = false;
    GetProcAddress get_proc_address_ = nullptr;
    bool owns_debug_callback_ = false;  // the context's KHR_debug callback is the library's
};

}  // namespace px
