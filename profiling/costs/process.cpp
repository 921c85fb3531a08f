#include "parallaxes/profiling/costs/process.h"

#include "parallaxes/core/interrupts.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

extern char** environ;

namespace px::profiling {

namespace {

// Ours, less the names removed, with the extra entries replacing same-named ones.
std::vector<std::string> child_environment(const ProcessOptions& options) {
    std::vector<std::string> env;
    for (char** e = environ; e && *e; ++e) {
        const std::string entry = *e;
        const std::string name = entry.substr(0, entry.find('='));
        bool replaced = false;
        for (const std::string& x : options.remove_env)
            if (x == name) replaced = true;
        for (const std::string& x : options.extra_env)
            if (x.substr(0, x.find('=')) == name) replaced = true;
        if (!replaced) env.push_back(entry);
    }
    for (const std::string& x : options.extra_env) env.push_back(x);
    return env;
}

// Starts argv[0] (searched on PATH when it names no folder) in a process
// group of its own, stdin from /dev/null, the captured streams into
// `write_fd` and the others to /dev/null, every signal at its default and
// none blocked. 0, or the errno of the failure.
int spawn(const std::vector<std::string>& argv, const ProcessOptions& options, int write_fd, interrupts::ChildGroup& group) {
    std::vector<std::string> env = child_environment(options);
    std::vector<char*> envp, args;
    for (std::string& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);
    std::vector<std::string> argv_copy = argv;
    for (std::string& a : argv_copy) args.push_back(a.data());
    args.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    if (options.capture_stdout) posix_spawn_file_actions_adddup2(&actions, write_fd, STDOUT_FILENO);
    else posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    if (options.capture_stderr) posix_spawn_file_actions_adddup2(&actions, write_fd, STDERR_FILENO);
    else posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t no_signals, all_signals;
    sigemptyset(&no_signals);
    sigfillset(&all_signals);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    posix_spawnattr_setpgroup(&attributes, 0);
    posix_spawnattr_setsigmask(&attributes, &no_signals);
    posix_spawnattr_setsigdefault(&attributes, &all_signals);
    const int spawned = group.start([&](pid_t& child) {
        return argv[0].find('/') == std::string::npos
                   ? posix_spawnp(&child, argv[0].c_str(), &actions, &attributes, args.data(), envp.data())
                   : posix_spawn(&child, argv[0].c_str(), &actions, &attributes, args.data(), envp.data());
    });
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    return spawned;
}

// The child's time: what is left of it, and the one kill of its group.
struct Watch {
    std::chrono::steady_clock::time_point deadline;
    pid_t group = 0;
    bool killed = false;
    int remaining_ms() const {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        return static_cast<int>(std::clamp<long long>(left.count(), 0, 1000000000));
    }
    void kill_group() {
        if (!killed) kill(-group, SIGKILL);
        killed = true;
    }
};

// Reads the child's output until it ends, the time runs out or the output
// passes its limit (the last two kill the group).
void collect_output(int fd, std::size_t max_output, Watch& watch, ProcessResult& result) {
    char buffer[65536];
    for (;;) {
        pollfd p{fd, POLLIN, 0};
        const int ready = poll(&p, 1, watch.remaining_ms());
        if (ready < 0 && errno == EINTR) continue;
        if (ready == 0) {
            result.timed_out = true;
            watch.kill_group();
            return;
        }
        const ssize_t n = read(fd, buffer, sizeof buffer);
        if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (n <= 0) return;  // end of output (or a read error: nothing more to collect)
        if (result.output.size() + static_cast<std::size_t>(n) > max_output) {
            result.truncated = true;
            watch.kill_group();
            return;
        }
        result.output.append(buffer, static_cast<std::size_t>(n));
    }
}

// The output has ended; the child gets what is left of its time to exit.
Status wait_for_exit(Watch& watch, ProcessResult& result) {
    int status = 0;
    for (;;) {
        const pid_t done = waitpid(watch.group, &status, watch.killed ? 0 : WNOHANG);
        if (done == watch.group) break;
        if (done < 0 && errno == EINTR) continue;
        if (done < 0) return make_error(std::string("waitpid: ") + std::strerror(errno));
        if (watch.remaining_ms() == 0) {
            result.timed_out = true;
            watch.kill_group();
            continue;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (!watch.killed) kill(-watch.group, SIGKILL);  // anything the child left running in its group
    if (WIFEXITED(status)) result.exit_status = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
    return {};
}

}  // namespace

Result<ProcessResult> run_process(const std::vector<std::string>& argv, const ProcessOptions& options) {
    if (argv.empty() || argv[0].empty()) return make_error("run_process: no program given");
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) return make_error(std::string("pipe: ") + std::strerror(errno));
    // Registered while it runs: an interrupt (SIGINT, SIGTERM, SIGHUP) kills
    // its whole group before this program dies (core/interrupts.h).
    interrupts::ChildGroup group;
    const int spawned = spawn(argv, options, fds[1], group);
    close(fds[1]);
    if (spawned != 0) {
        close(fds[0]);
        return make_error("cannot run '" + argv[0] + "': " + std::strerror(spawned));
    }
    Watch watch;
    watch.deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                            std::chrono::duration<double>(options.timeout_s));
    watch.group = group.pgid();
    ProcessResult result;
    collect_output(fds[0], options.max_output, watch, result);
    close(fds[0]);
    if (Status s = wait_for_exit(watch, result); !s) return s.error();
    return result;
}

}  // namespace px::profiling
