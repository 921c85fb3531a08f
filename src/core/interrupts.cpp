#include "parallaxes/core/interrupts.h"

#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <system_error>
#include <thread>

// Why a waiting thread rather than a signal handler: removing a folder tree
// takes opendir, readdir and allocation, none of which is async-signal-safe
// (POSIX.1-2017 XSH 2.4.3), and a handler would also have to take the
// registry's lock, which the interrupted thread may hold. With the signals
// blocked in every thread, the kernel leaves them pending for the one thread
// in sigwait(), which runs ordinary code: it takes the lock (waiting for a
// registration or a removal in progress to finish, so it never sees half of
// one), kills the child groups, removes the folders, and then lets the
// signal kill the process with its default action. It never gives the lock
// back, so no other thread starts a child or makes a folder afterwards.

namespace px::interrupts {

namespace {

struct Registry {
    std::mutex mutex;
    std::set<std::string> folders;
    std::multiset<pid_t> groups;
    bool handling = false;  // an interrupt's cleanup has begun
};

// Never destroyed: the waiting thread may run while the program exits.
Registry& registry() {
    static Registry* r = new Registry;
    return *r;
}

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

// remove_all, again while something remains: a child killed a moment ago
// may still finish a write into the folder (kill() does not wait for it).
void remove_tree(const std::string& path) {
    for (int attempt = 0; attempt < 50; ++attempt) {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
        struct stat st;
        if (::lstat(path.c_str(), &st) != 0 && errno == ENOENT) return;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

[[noreturn]] void wait_and_clean(sigset_t set) {
    int sig = 0;
    while (sigwait(&set, &sig) != 0) {
    }
    Registry& r = registry();
    r.mutex.lock();  // never unlocked: the process ends below
    r.handling = true;
    for (pid_t group : r.groups) ::kill(-group, SIGKILL);
    for (const std::string& folder : r.folders) remove_tree(folder);
    // Die of the signal itself, so that the parent sees "killed by SIGINT"
    // (a shell's 130), not an exit status we made up.
    struct sigaction default_action {};
    default_action.sa_handler = SIG_DFL;
    sigemptyset(&default_action.sa_mask);
    ::sigaction(sig, &default_action, nullptr);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, sig);
    pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
    ::raise(sig);
    _exit(128 + sig);  // not reached: the default action of all three ends the process
}

}  // namespace

Status install() {
    static bool installed = false;
    if (installed) return {};
    sigset_t set;
    sigemptyset(&set);
    bool any = false;
    for (int sig : kSignals) {
        struct sigaction current {};
        if (::sigaction(sig, nullptr, &current) == 0 && current.sa_handler == SIG_IGN) continue;
        sigaddset(&set, sig);
        any = true;
    }
    if (!any) return {};
    if (const int e = pthread_sigmask(SIG_BLOCK, &set, nullptr); e != 0)
        return make_error(std::string("cannot block the interrupt signals: ") + std::strerror(e));
    try {
        std::thread(wait_and_clean, set).detach();
    } catch (const std::system_error& e) {
        pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
        return make_error(std::string("cannot start the interrupt thread: ") + e.what());
    }
    installed = true;
    return {};
}

Result<std::string> make_registered_folder(const std::string& prefix) {
    const char* tmp = std::getenv("TMPDIR");
    const std::string pattern = std::string(tmp && tmp[0] == '/' ? tmp : "/tmp") + "/" + prefix + "XXXXXX";
    std::string path = pattern;
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    if (r.handling) return make_error("cannot make a temporary folder: the program is being interrupted");
    if (!mkdtemp(path.data()))
        return make_error("cannot make a temporary folder from '" + pattern + "': " + std::strerror(errno));
    r.folders.insert(path);
    return path;
}

void remove_registered_folder(const std::string& path) {
    if (path.empty()) return;
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
    r.folders.erase(path);
}

Result<TempFolder> TempFolder::create(const std::string& prefix) {
    Result<std::string> path = make_registered_folder(prefix);
    if (!path) return path.error();
    return TempFolder(std::move(*path));
}

TempFolder::~TempFolder() { remove_registered_folder(path_); }

int ChildGroup::start(const std::function<int(pid_t&)>& spawn) {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    if (r.handling) return EINTR;
    pid_t pid = -1;
    const int e = spawn(pid);
    if (e != 0) return e;
    pgid_ = pid;
    r.groups.insert(pid);
    return 0;
}

ChildGroup::~ChildGroup() {
    if (pgid_ <= 0) return;
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    const auto found = r.groups.find(pgid_);
    if (found != r.groups.end()) r.groups.erase(found);
}

}  // namespace px::interrupts
