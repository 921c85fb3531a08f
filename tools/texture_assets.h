// Temporary folders for the commands that convert textures on the way.
#pragma once

#include <string>

#include "parallaxes/core/result.h"
#include "parallaxes/scene/scene_textures.h"

namespace px::tools {

// A fresh private folder under $TMPDIR (or /tmp) for converted textures,
// removed with everything in it when the value goes.
class TempFolder {
public:
    static Result<TempFolder> create();
    TempFolder(TempFolder&& o) noexcept : path_(std::move(o.path_)) { o.path_.clear(); }
    TempFolder& operator=(TempFolder&&) = delete;
    TempFolder(const TempFolder&) = delete;
    ~TempFolder();
    const std::string& path() const { return path_; }

private:
    explicit TempFolder(std::string path) : path_(std::move(path)) {}
    std::string path_;
};

}  // namespace px::tools
