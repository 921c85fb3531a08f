// Temporary folders for the commands that convert textures on the way:
// core/interrupts.h's, so that SIGINT, SIGTERM or SIGHUP removes them too.
#pragma once

#include <string>

#include "parallaxes/core/interrupts.h"
#include "parallaxes/core/result.h"
#include "parallaxes/scene/scene_textures.h"

namespace px::tools {

using TempFolder = interrupts::TempFolder;

// A fresh private folder $TMPDIR/parallax-textures-XXXXXX (or under /tmp),
// removed with everything in it when the value goes or the program is
// interrupted.
inline Result<TempFolder> make_texture_folder() { return TempFolder::create("parallax-textures-"); }

}  // namespace px::tools
