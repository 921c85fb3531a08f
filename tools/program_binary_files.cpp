#include "program_binary_files.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <system_error>

#include "parallaxes/core/files.h"
#include "parallaxes/core/text.h"

namespace px::tools {

namespace {

// Keys come from the library as 16 hex digits; anything else is never
// turned into a path.
bool valid_key(const std::string& key) {
    if (key.size() != 16) return false;
    for (char c : key)
        if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
    return true;
}

struct Warnings {
    bool read = false;
    bool write = false;
};

void warn(bool& shown, const std::string& message) {
    if (shown) return;
    shown = true;
    std::fprintf(stderr, "parallax: warning: program binary cache: %s (further such warnings not shown)\n",
                 message.c_str());
}

}  // namespace

std::string default_program_cache_dir() {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    if (xdg && xdg[0] == '/') return std::string(xdg) + "/parallaxes/programs";
    const char* home = std::getenv("HOME");
    if (home && home[0] != '\0') return std::string(home) + "/.cache/parallaxes/programs";
    return {};
}

ProgramBinaryStore file_program_store(const std::string& dir) {
    auto warnings = std::make_shared<Warnings>();
    ProgramBinaryStore store;
    store.load = [dir, warnings](const std::string& key) -> std::optional<std::vector<std::uint8_t>> {
        if (!valid_key(key)) return std::nullopt;
        const std::string path = dir + "/" + key + ".pxbin";
        std::error_code ec;
        const std::filesystem::file_status status = std::filesystem::symlink_status(path, ec);
        if (status.type() == std::filesystem::file_type::not_found) return std::nullopt;  // a miss, not a problem
        Result<std::vector<std::uint8_t>> bytes =
            read_file_bounded(path, kMaxProgramBinaryEntryBytes, "program binary entry");
        if (!bytes) {
            warn(warnings->read, bytes.error().message + "; compiling from source");
            return std::nullopt;
        }
        return std::move(*bytes);
    };
    store.store = [dir, warnings](const std::string& key, const std::vector<std::uint8_t>& bytes) {
        if (!valid_key(key)) return;
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec) {
            warn(warnings->write, "cannot create folder '" + echo_path(dir) + "': " + ec.message());
            return;
        }
        Status written = write_file_atomically(dir + "/" + key + ".pxbin", bytes.data(), bytes.size());
        if (!written) warn(warnings->write, written.error().message);
    };
    return store;
}

}  // namespace px::tools
