#include "texture_assets.h"

#include "parallaxes/core/interrupts.h"

namespace px::tools {

// Made and removed through the interrupt registry: SIGINT or SIGTERM while
// textures are converted removes the folder too (core/interrupts.h).
Result<TempFolder> TempFolder::create() {
    Result<std::string> path = interrupts::make_registered_folder("parallax-textures-");
    if (!path) return path.error();
    return TempFolder(std::move(*path));
}

TempFolder::~TempFolder() { interrupts::remove_registered_folder(path_); }

}  // namespace px::tools
