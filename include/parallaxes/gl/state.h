// The host's GL state, saved and given back. The renderer draws into a
// context it does not own, so every entry point that changes GL state
// (loading a scene, drawing it, reading debug outputs, making framebuffers)
// holds a SavedGlState for its whole body: the snapshot is taken on entry
// and restored on every return, error paths included.
//
// What it covers is one table (state.cpp, listed by gl_state_entry_names):
// everything the library sets, and the state that would change what the
// library draws if the host had left it set. Bindings (framebuffers,
// renderbuffer, program, buffers, the host's vertex array, the 2D texture
// and sampler on every unit the library binds and on whichever unit the host
// left active), pixel storage, raster, depth, blend, colour, stencil,
// dither and coverage state, and on the ES 2.0 path the attribute slots the
// library points. Not covered, because the library never changes them: the
// current generic vertex attribute values, uniform buffer and transform
// feedback bindings, line width, hints, and textures on units it neither
// binds nor finds active.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "parallaxes/core/caps.h"
#include "parallaxes/gl/gl.h"

namespace px {

// Texture units and vertex attribute slots the library uses (shaders/interface.h;
// renderer.cpp checks at compile time that these cover its tables). Eight
// attribute slots: the minimum GL_MAX_VERTEX_ATTRIBS of ES 2.0.
inline constexpr int kLibraryTextureUnits = 4;
inline constexpr int kLibraryAttributeSlots = 8;

// The state table (gl/state.cpp): one row per piece of GL state the
// library touches, with how it is read, written back, set aside for a
// draw and (for the test) set to a value other than GL's default. What the
// renderer saves and restores, what its draws set aside and what
// tests/gpu_host_state_tests.cpp checks all come from it.
enum class GlStateScope {
    all,          // every OpenGL ES context
    es3_context,  // state an ES 3.x context has (vertex arrays, samplers, pixel buffers, ...)
    // An ES 3.x context other than WebGL 2, which has primitive restart
    // always on and refuses it as a capability (WebGL 2.0 section 5.18).
    es3_native,
    es2_context,  // an ES 2.0 context's (its single framebuffer binding)
    es2_path,     // where the library points attribute slots itself (ES 2.0 draws, emulate_es2 too)
};
enum class GlStateRepeat {
    once,
    per_texture_unit,    // each unit the library binds (kLibraryTextureUnits), and the host's active one
    per_attribute_slot,  // each slot the library points (kLibraryAttributeSlots)
    host_active_unit,    // the active texture unit itself
};

// One row of the table as the context holds it now.
struct GlStateValue {
    using Values = std::array<std::int64_t, 8>;
    std::string_view name;  // "depth func", "texture 2d", ... (the table's own text: no copy per save)
    int index = -1;     // the unit or slot; -1: not repeated
    size_t entry = 0;   // the row
    Values values{};    // what glGet read (a float as its bit pattern)
    bool operator==(const GlStateValue& o) const { return name == o.name && index == o.index && values == o.values; }
};

// Every row in scope for this context. Leaves the context as it was.
std::vector<GlStateValue> read_gl_state(const Caps& caps);
// The names of the table's rows, in restore order.
std::vector<std::string> gl_state_entry_names();

// Objects a test makes for set_gl_state_probe to bind.
struct GlStateProbe {
    static constexpr int kActiveUnit = kLibraryTextureUnits + 1;  // the host's active unit: past the library's
    static constexpr size_t kTextures = 8, kSamplers = 8;
    GLuint program = 0, vertex_array = 0, renderbuffer = 0, draw_framebuffer = 0, read_framebuffer = 0;
    GLuint buffers[5] = {0, 0, 0, 0, 0};  // array, array (bound last), element, pack, unpack
    GLuint textures[kTextures] = {};
    GLuint samplers[kSamplers] = {};
};
// Sets every row in scope to a value other than GL's default (the tests'
// "host state"), the active texture unit to kActiveUnit.
void set_gl_state_probe(const Caps& caps, const GlStateProbe& objects);

class SavedGlState {
public:
    explicit SavedGlState(const Caps& caps);
    ~SavedGlState();
    SavedGlState(const SavedGlState&) = delete;
    SavedGlState& operator=(const SavedGlState&) = delete;

    struct Snapshot;

private:
    std::unique_ptr<Snapshot> saved_;
};

// Sets the state every draw of the library assumes, whatever the host left
// (the table's set-aside column: scissor, stencil, blend, colour mask,
// depth test LESS with writes, back-face culling, sampler objects, ...).
// Call inside a SavedGlState.
void set_aside_host_state(const Caps& caps);

// Sets what the library's uploads need and a host may have changed: no
// pixel unpack buffer, tight rows (alignment 1, no row length or skips).
// Call inside a SavedGlState.
void set_unpack_defaults(const Caps& caps);
// The same for glReadPixels: no pixel pack buffer, alignment 1, no skips.
void set_pack_defaults(const Caps& caps);

}  // namespace px
