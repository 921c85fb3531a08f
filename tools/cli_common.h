// Helpers every subcommand shares: the error line and WIDTHxHEIGHT sizes.
#pragma once

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include "parallaxes/core/counters.h"

namespace px::tools {

// Prints "parallax: error: MESSAGE" and returns the exit status 1.
inline int fail(const std::string& message) {
    std::fprintf(stderr, "parallax: error: %s\n", message.c_str());
    return 1;
}

// Before a long run writes into `dir`: the folder made, and a file created
// and removed in it, so that a folder that cannot be written (read-only,
// not a folder, no space for a name) is refused before anything is
// measured. Empty: writable.
inline std::string check_output_folder(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) return "cannot create the output folder '" + dir + "': " + ec.message();
    std::string probe = dir + "/.parallax-write-test-XXXXXX";
    const int fd = ::mkstemp(probe.data());
    if (fd < 0) return "cannot write into the output folder '" + dir + "': " + std::strerror(errno);
    ::close(fd);
    ::unlink(probe.c_str());
    return {};
}

// The same for the folder a file is written into (".", when the path names
// no folder), so that a report's destination is refused before the run.
inline std::string check_output_file(const std::string& path) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (std::filesystem::path(path).filename().empty()) return "'" + path + "' names a folder, not a file";
    return check_output_folder(parent.empty() ? std::string(".") : parent.string());
}

// An error about a scene, prefixed with the scene file it came from (when
// it came from one and the message does not name it already).
inline std::string in_scene_file(const std::string& source, const std::string& message) {
    if (source.empty() || message.compare(0, source.size(), source) == 0) return message;
    return source + ": " + message;
}

// "512x512" (or "512X512") into two integers within 1..limit. Digits only:
// no sign, no spaces, no overflow (each side is checked against the limit
// while it is read).
inline bool parse_size(const std::string& text, int& width, int& height, int limit = 16384) {
    int* out[2] = {&width, &height};
    size_t i = 0;
    for (int side = 0; side < 2; ++side) {
        if (side == 1) {
            if (i >= text.size() || (text[i] != 'x' && text[i] != 'X')) return false;
            ++i;
        }
        long value = 0;
        const size_t start = i;
        while (i < text.size() && text[i] >= '0' && text[i] <= '9') {
            value = value * 10 + (text[i] - '0');
            if (value > limit) return false;
            ++i;
        }
        if (i == start || value < 1) return false;
        *out[side] = static_cast<int>(value);
    }
    return i == text.size();
}

// A progress bar on a terminal; a line per tenth of the work otherwise
// ("LABEL: done/total (what)"), both on stderr.
inline void show_progress(const char* label, int done, int total, const std::string& what) {
    static const bool terminal = isatty(STDERR_FILENO) != 0;
    if (terminal) {
        const int width = 30;
        const int filled = total > 0 ? done * width / total : width;
        std::fprintf(stderr, "\r[%s%s] %d/%d %-50.50s", std::string(static_cast<size_t>(filled), '#').c_str(),
                     std::string(static_cast<size_t>(width - filled), '.').c_str(), done, total, what.c_str());
        if (done == total) std::fprintf(stderr, "\n");
    } else if (total > 0 && (done * 10 / total != (done - 1) * 10 / total || done == total)) {
        std::fprintf(stderr, "%s: %d/%d (%s)\n", label, done, total, what.c_str());
    }
    std::fflush(stderr);
}

}  // namespace px::tools
