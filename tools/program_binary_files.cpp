#include "program_binary_files.h"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
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

namespace {

std::string octal(unsigned mode) {
    char b[8];
    std::snprintf(b, sizeof b, "%04o", mode & 07777u);
    return b;
}

// The folder, made 0700 where it is missing, and checked: a folder (not a
// link), this user's, not writable by others.
Status private_folder(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) return make_error("cannot create folder '" + echo_path(dir) + "': " + ec.message());
    struct stat st {};
    if (::lstat(dir.c_str(), &st) != 0) return make_error("cannot read folder '" + echo_path(dir) + "': " + std::strerror(errno));
    if (!S_ISDIR(st.st_mode)) return make_error("'" + echo_path(dir) + "' is not a folder");
    if (st.st_uid != ::geteuid())
        return make_error("folder '" + echo_path(dir) + "' belongs to user " + std::to_string(st.st_uid) + ", not to this user");
    if (st.st_mode & (S_IWGRP | S_IWOTH))
        return make_error("folder '" + echo_path(dir) + "' is writable by other users (mode " + octal(st.st_mode) + ")");
    if (st.st_mode & (S_IRWXG | S_IRWXO)) ::chmod(dir.c_str(), 0700);  // readable by others: tighten, as we made it
    return {};
}

// Reads `path` as a key: a regular file (not a link) of 16 bytes, this
// user's, readable by no one else. nullopt (and no error) when missing.
Result<std::optional<SipKey>> read_key(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) {
        if (errno == ENOENT) return std::optional<SipKey>{};
        return make_error("cannot open the key '" + echo_path(path) + "': " + std::strerror(errno));
    }
    struct stat st {};
    SipKey key{};
    std::string problem;
    if (::fstat(fd, &st) != 0) problem = std::strerror(errno);
    else if (!S_ISREG(st.st_mode)) problem = "not a regular file";
    else if (st.st_uid != ::geteuid()) problem = "belongs to user " + std::to_string(st.st_uid) + ", not to this user";
    else if (st.st_mode & (S_IRWXG | S_IRWXO)) problem = "readable or writable by other users (mode " + octal(st.st_mode) + ")";
    else if (st.st_size != static_cast<off_t>(key.size())) problem = std::to_string(st.st_size) + " bytes, not 16";
    else if (::read(fd, key.data(), key.size()) != static_cast<ssize_t>(key.size())) problem = "short read";
    ::close(fd);
    if (!problem.empty()) return make_error("the key '" + echo_path(path) + "' is unusable: " + problem);
    return std::optional<SipKey>{key};
}

// This folder's key: read, or made (16 bytes from getrandom, mode 0600,
// created exclusively: a racing process's key wins and is read back).
Result<SipKey> folder_key(const std::string& dir) {
    const std::string path = dir + "/key";
    Result<std::optional<SipKey>> existing = read_key(path);
    if (!existing) return existing.error();
    if (*existing) return **existing;
    SipKey key{};
    size_t got = 0;
    while (got < key.size()) {
        const ssize_t n = ::getrandom(key.data() + got, key.size() - got, 0);
        if (n < 0) {
            if (errno == EINTR) continue;
            return make_error(std::string("no random bytes for a key: ") + std::strerror(errno));
        }
        got += static_cast<size_t>(n);
    }
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd < 0) {
        if (errno != EEXIST) return make_error("cannot create the key '" + echo_path(path) + "': " + std::strerror(errno));
    } else {
        const bool written = ::write(fd, key.data(), key.size()) == static_cast<ssize_t>(key.size());
        const bool closed = ::close(fd) == 0;
        if (!written || !closed) {
            ::unlink(path.c_str());
            return make_error("cannot write the key '" + echo_path(path) + "'");
        }
    }
    Result<std::optional<SipKey>> made = read_key(path);
    if (!made) return made.error();
    if (!*made) return make_error("the key '" + echo_path(path) + "' vanished");
    return **made;
}

}  // namespace

ProgramBinaryStore file_program_store(const std::string& dir) {
    auto warnings = std::make_shared<Warnings>();
    ProgramBinaryStore store;
    // Without a private folder and key, no binaries: an entry anyone else
    // could have written would reach the driver.
    Status folder = private_folder(dir);
    Result<SipKey> secret = folder ? folder_key(dir) : Result<SipKey>(folder.error());
    if (!secret) {
        std::fprintf(stderr, "parallax: warning: program binary cache: %s; not using program binaries\n",
                     secret.error().message.c_str());
        return store;
    }
    store.secret = *secret;
    store.load = [dir, warnings](const std::string& key) -> std::optional<std::vector<std::uint8_t>> {
        if (!valid_key(key)) return std::nullopt;
        const std::string path = dir + "/" + key + ".pxbin";
        std::error_code ec;
        const std::filesystem::file_status status = std::filesystem::symlink_status(path, ec);
        if (status.type() == std::filesystem::file_type::not_found) return std::nullopt;  // a miss, not a problem
        struct stat st {};
        if (::lstat(path.c_str(), &st) == 0 && st.st_uid != ::geteuid()) {
            warn(warnings->read, "entry '" + echo_path(path) + "' belongs to user " + std::to_string(st.st_uid) +
                                     ", not to this user; compiling from source");
            return std::nullopt;
        }
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
