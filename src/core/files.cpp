#include "parallaxes/core/files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <vector>

#include "parallaxes/core/text.h"

namespace px {

namespace {

std::string reason(int err) { return err != 0 ? std::string(std::strerror(err)) : "unknown error"; }

// An open descriptor, closed when the value goes.
struct OpenFile {
    int fd = -1;
    struct stat st {};
    OpenFile() = default;
    OpenFile(const OpenFile&) = delete;
    OpenFile& operator=(const OpenFile&) = delete;
    ~OpenFile() {
        if (fd >= 0) ::close(fd);
    }
};

// Opens `path` for reading if it is a regular file (O_NONBLOCK, so that a
// FIFO does not wait for a writer; blocking again once it is known to be a
// file), filling `file`; otherwise an error naming it (`name`) and `what`.
Status open_regular(const std::string& path, const std::string& name, const std::string& what, OpenFile& file) {
    file.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (file.fd < 0) return make_error(name + ": cannot open " + what + ": " + reason(errno));
    if (::fstat(file.fd, &file.st) != 0) return make_error(name + ": cannot read " + what + ": " + reason(errno));
    if (S_ISDIR(file.st.st_mode)) return make_error(name + ": cannot read " + what + ": it is a folder");
    if (!S_ISREG(file.st.st_mode))
        return make_error(name + ": cannot read " + what + ": not a regular file (a pipe, socket or device)");
    const int flags = ::fcntl(file.fd, F_GETFL);
    if (flags >= 0) (void)::fcntl(file.fd, F_SETFL, flags & ~O_NONBLOCK);
    return {};
}

// Writes every byte to `fd`; 0 or the errno.
int write_all(int fd, const void* bytes, std::size_t size) {
    const char* p = static_cast<const char*>(bytes);
    std::size_t left = size;
    while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0) {
            if (errno == EINTR) continue;
            return errno;
        }
        p += n;
        left -= static_cast<std::size_t>(n);
    }
    return 0;
}

// `-o /dev/null`, `-o /dev/stdout`, a named pipe: a character device or a
// FIFO (directly, or where a symlink leads) is written into as it is, never
// renamed over (which would put a regular file where /dev/null was). It is
// opened without creating or following anything new and checked on the
// open descriptor, so what is written to is what was checked. Not a stream
// (a regular file, a missing name, a dangling link): false, and the caller
// writes atomically. A FIFO without a reader is an error, not a wait.
bool write_into_stream(const std::string& path, const void* bytes, std::size_t size, Status& result) {
    struct stat target {};
    if (::stat(path.c_str(), &target) != 0 || !(S_ISCHR(target.st_mode) || S_ISFIFO(target.st_mode))) return false;
    const int fd = ::open(path.c_str(), O_WRONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        const int err = errno;
        result = make_error(path + ": cannot write: " +
                            (err == ENXIO ? std::string("a named pipe with no reader") : reason(err)));
        return true;
    }
    struct stat opened {};
    int error = ::fstat(fd, &opened) == 0 ? 0 : errno;
    if (error == 0 && !(S_ISCHR(opened.st_mode) || S_ISFIFO(opened.st_mode))) error = EINVAL;
    if (error == 0) {
        const int flags = ::fcntl(fd, F_GETFL);
        if (flags >= 0) (void)::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
        error = write_all(fd, bytes, size);
    }
    if (::close(fd) != 0 && error == 0) error = errno;
    result = error == 0 ? Status{} : make_error(path + ": cannot write: " + reason(error));
    return true;
}

}  // namespace

Status write_file_atomically(const std::string& path, const void* bytes, std::size_t size) {
    if (path.empty()) return make_error("cannot write a file with an empty path");
    if (Status streamed; write_into_stream(path, bytes, size, streamed)) return streamed;
    struct stat existing {};
    if (::lstat(path.c_str(), &existing) == 0) {
        if (S_ISDIR(existing.st_mode)) return make_error(path + ": cannot write: it is a folder");
        // A block device or a socket is not an output file, nor to be replaced by one.
        if (S_ISBLK(existing.st_mode) || S_ISSOCK(existing.st_mode))
            return make_error(path + ": cannot write: it is a " +
                              (S_ISBLK(existing.st_mode) ? "block device" : "socket") + ", not a file");
        // No write bit for anyone counts as protected even for root, whom
        // access() would let through.
        if (S_ISREG(existing.st_mode) && ((existing.st_mode & 0222) == 0 || ::access(path.c_str(), W_OK) != 0))
            return make_error(path + ": cannot write: the file exists and is write-protected");
    }
    // mkstemp creates the file with O_CREAT | O_EXCL: it never opens a name
    // that exists, so a symlink planted at the temporary name is not followed.
    std::vector<char> name(path.begin(), path.end());
    const char suffix[] = ".tmp-XXXXXX";
    name.insert(name.end(), suffix, suffix + sizeof suffix);  // with the terminating 0
    const int fd = ::mkstemp(name.data());
    if (fd < 0) return make_error(path + ": cannot create a temporary file beside it: " + reason(errno));
    const std::string tmp(name.data());
    // mkstemp makes it 0600; a new output file gets the usual 0666 & ~umask,
    // an existing one keeps its mode.
    mode_t mode = existing.st_mode & 07777;
    if (!S_ISREG(existing.st_mode)) {
        const mode_t mask = ::umask(0);
        ::umask(mask);
        mode = 0666 & ~mask;
    }
    int error = ::fchmod(fd, mode) == 0 ? 0 : errno;
    if (error == 0) error = write_all(fd, bytes, size);
    if (::close(fd) != 0 && error == 0) error = errno;  // a delayed write error (disk full) shows here
    if (error == 0 && std::rename(tmp.c_str(), path.c_str()) != 0) error = errno;
    if (error != 0) {
        ::unlink(tmp.c_str());
        return make_error(path + ": cannot write: " + reason(error));
    }
    return {};
}

Result<std::vector<std::uint8_t>> read_file_bounded(const std::string& path, std::size_t max_bytes,
                                                    const std::string& what) {
    const std::string name = echo_path(path);
    OpenFile file;
    if (Status opened = open_regular(path, name, what, file); !opened) return opened.error();
    const int fd = file.fd;
    const struct stat& st = file.st;
    const auto limit_error = [&] {
        return make_error(name + ": " + what + " is larger than the limit of " + std::to_string(max_bytes >> 20) +
                          " MiB (" + std::to_string(max_bytes) + " bytes)");
    };
    if (st.st_size < 0 || static_cast<std::uint64_t>(st.st_size) > max_bytes) return limit_error();
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(st.st_size));
    std::size_t filled = 0;
    for (;;) {
        if (filled == bytes.size()) {
            // The file may have grown since fstat: read on, up to the limit.
            std::uint8_t probe = 0;
            const ssize_t n = ::read(fd, &probe, 1);
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) return make_error(name + ": cannot read " + what + ": " + reason(errno));
            if (n == 0) break;
            if (bytes.size() + 1 > max_bytes) return limit_error();
            bytes.push_back(probe);
            bytes.resize(std::min(max_bytes, bytes.size() + (std::size_t{1} << 16)));
            ++filled;
            continue;
        }
        const ssize_t n = ::read(fd, bytes.data() + filled, bytes.size() - filled);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return make_error(name + ": cannot read " + what + ": " + reason(errno));
        if (n == 0) break;
        filled += static_cast<std::size_t>(n);
    }
    bytes.resize(filled);
    return bytes;
}

Result<std::vector<std::uint8_t>> read_file_prefix(const std::string& path, std::size_t max_bytes,
                                                   const std::string& what) {
    const std::string name = echo_path(path);
    OpenFile file;
    if (Status opened = open_regular(path, name, what, file); !opened) return opened.error();
    const int fd = file.fd;
    const struct stat& st = file.st;
    const std::size_t want =
        st.st_size > 0 ? std::min(max_bytes, static_cast<std::size_t>(std::min<std::uint64_t>(
                                                 static_cast<std::uint64_t>(st.st_size), SIZE_MAX)))
                       : 0;
    std::vector<std::uint8_t> bytes(want);
    std::size_t filled = 0;
    while (filled < bytes.size()) {
        const ssize_t n = ::read(fd, bytes.data() + filled, bytes.size() - filled);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return make_error(name + ": cannot read " + what + ": " + reason(errno));
        if (n == 0) break;
        filled += static_cast<std::size_t>(n);
    }
    bytes.resize(filled);
    return bytes;
}

}  // namespace px
