// The host's GL state, saved and given back. The renderer draws into a
// context it does not own, so every entry point that changes GL state
// (loading a scene, drawing it, reading debug outputs, making framebuffers)
// holds a SavedGlState for its whole body: the snapshot is taken on entry
// and restored on every return, error paths included.
//
// What it covers is everything the library sets, and the state that would
// change what the library draws if the host had left it set:
//   bindings   framebuffer (draw and read on ES 3.0), renderbuffer, program,
//              array and element array buffer, vertex array object (ES 3.0),
//              pixel pack and unpack buffers (ES 3.0), the active texture unit
//              and, on each unit the library uses, the 2D texture and (ES 3.0)
//              the sampler object
//   pixels     pack and unpack alignment; on ES 3.0 row length, skip rows,
//              skip pixels, image height, skip images
//   raster     viewport, scissor test and box, cull face on/off and mode,
//              front face, polygon offset fill, rasterizer discard (ES 3.0)
//   fragment   depth test, function, mask and range, clear depth, blend on/off,
//              functions, equations and colour, colour mask, clear colour,
//              stencil test, functions, ops and write masks (front and back),
//              dither, sample coverage and alpha to coverage, primitive
//              restart with the fixed index (ES 3.0)
//   vertex     ES 2.0: per attribute slot the library uses, enabled, size,
//              type, normalised, stride, pointer and buffer. ES 3.0 draws
//              through VAOs of the library's own, so the host's VAO is
//              never written, only bound again.
// Not covered, because the library never changes them: the current generic
// vertex attribute values, uniform buffer and transform feedback bindings,
// line width, hints, and textures on units it does not use.
#pragma once

#include <array>
#include <memory>

#include "parallaxes/core/caps.h"
#include "parallaxes/gl/gl.h"

namespace px {

// Texture units and vertex attribute slots the library uses (shaders/interface.h;
// renderer.cpp checks at compile time that these cover its tables). Eight
// attribute slots: the minimum GL_MAX_VERTEX_ATTRIBS of ES 2.0.
inline constexpr int kLibraryTextureUnits = 4;
inline constexpr int kLibraryAttributeSlots = 8;

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

// Sets what the library's uploads need and a host may have changed: no
// pixel unpack buffer, tight rows (alignment 1, no row length or skips).
// Call inside a SavedGlState.
void set_unpack_defaults(const Caps& caps);
// The same for glReadPixels: no pixel pack buffer, alignment 1, no skips.
void set_pack_defaults(const Caps& caps);

}  // namespace px
