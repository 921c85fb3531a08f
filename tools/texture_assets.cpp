#include "texture_assets.h"

#include <cstdlib>
#include <filesystem>
#include <vector>

namespace px::tools {

Result<TempFolder> TempFolder::create() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && tmp[0] == '/' ? tmp : "/tmp") + "/parallax-textures-XXXXXX";
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    if (!mkdtemp(buffer.data())) return make_error("cannot make a temporary folder from '" + pattern + "'");
    return TempFolder(std::string(buffer.data()));
}

TempFolder::~TempFolder() {
    if (path_.empty()) return;
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

}  // namespace px::tools
