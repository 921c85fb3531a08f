// Interrupts leave nothing behind: a registry of the temporary folders and
// child process groups a program has alive, emptied when SIGINT, SIGTERM or
// SIGHUP arrives (children killed, folders removed) before the program dies
// of that signal as it would have (a shell sees 130, 143, 129).
//
// Nothing here does anything until install() is called; a host app that
// links the core and never calls it keeps its own signal handling. Without
// install() the registry still works (registrations are cheap), it is just
// never acted on.
#pragma once

#include <sys/types.h>

#include <functional>
#include <string>

#include "parallaxes/core/result.h"

namespace px::interrupts {

// Called once, first thing in main(), before any thread starts: blocks the
// three signals in the calling thread (threads started later inherit the
// mask) and starts the thread that waits for them. A signal inherited as
// ignored (nohup's SIGHUP, a background job's SIGINT) stays ignored.
Status install();

// A fresh folder `$TMPDIR/<prefix>XXXXXX` ($TMPDIR when absolute, else /tmp),
// mode 0700, registered for removal on an interrupt; removed with everything
// in it when the value goes. Movable, not copyable.
class TempFolder {
public:
    static Result<TempFolder> create(const std::string& prefix);
    TempFolder(TempFolder&& o) noexcept : path_(std::move(o.path_)) { o.path_.clear(); }
    TempFolder& operator=(TempFolder&&) = delete;
    TempFolder(const TempFolder&) = delete;
    ~TempFolder();
    const std::string& path() const { return path_; }

private:
    explicit TempFolder(std::string path) : path_(std::move(path)) {}
    std::string path_;
};

// The same, for classes that keep their own path (tools/texture_assets.h):
// the folder is made and registered in one step, and removed (with what is
// in it) and forgotten in one step.
Result<std::string> make_registered_folder(const std::string& prefix);
void remove_registered_folder(const std::string& path);

// A child process group killed (SIGKILL to the whole group) on an interrupt
// while this value lives. The owner reaps the child and kills what is left
// of its group before the value goes.
class ChildGroup {
public:
    ChildGroup() = default;
    ChildGroup(const ChildGroup&) = delete;
    ChildGroup& operator=(const ChildGroup&) = delete;
    ~ChildGroup();
    // Calls spawn(pid) (which starts a child leading its own process group,
    // stores its pid and returns 0, or returns an errno value) with the
    // registry locked, so that no interrupt's cleanup can fall between the
    // start and the registration; registers the group when it started.
    // Returns EINTR without calling spawn once an interrupt is being handled.
    int start(const std::function<int(pid_t&)>& spawn);
    pid_t pgid() const { return pgid_; }

private:
    pid_t pgid_ = -1;
};

}  // namespace px::interrupts
