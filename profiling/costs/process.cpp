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

Result<ProcessResult> run_process(const std::vector<std::string>& argv, const ProcessOptions& options) {
    if (argv.empty() || argv[0].empty()) return make_error("run_process: no program given");
    // The environment: ours, less the names removed, with the extra entries replacing same-named ones.
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
    std::vector<char*> envp, args;
    for (std::string& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);
    std::vector<std::string> argv_copy = argv;
    for (std::string& a : argv_copy) args.push_back(a.data());
    args.push_back(nullptr);

    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) return make_error(std::string("pipe: ") + std::strerror(errno));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    if (options.capture_stdout) posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
    else posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    if (options.capture_stderr) posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);
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
    // Registered while it runs: an interrupt (SIGINT, SIGTERM, SIGHUP) kills
    // its whole group before this program dies (core/interrupts.h).
    interrupts::ChildGroup group;
    const int spawned = group.start([&](pid_t& child) {
        return argv[0].find('/') == std::string::npos
                   ? posix_spawnp(&child, argv[0].c_str(), &actions, &attributes, args.data(), envp.data())
                   : posix_spawn(&child, argv[0].c_str(), &actions, &attributes, args.data(), envp.data());
    });
    const pid_t pid = group.pgid();
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    close(fds[1]);
    if (spawned != 0) {
        close(fds[0]);
        return make_error("cannot run '" + argv[0] + "': " + std::strerror(spawned));
    }

    ProcessResult result;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.timeout_s);
    auto remaining_ms = [&] {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        return static_cast<int>(std::clamp<long long>(left.count(), 0, 1000000000));
    };
    bool killed = false;
    auto kill_group = [&] {
        if (!killed) kill(-pid, SIGKILL);
        killed = true;
    };
    char buffer[65536];
    for (;;) {
        pollfd p{fds[0], POLLIN, 0};
        const int ready = poll(&p, 1, remaining_ms());
        if (ready < 0 && errno == EINTR) continue;
        if (ready == 0) {
            result.timed_out = true;
            kill_group();
            break;
        }
        const ssize_t n = read(fds[0], buffer, sizeof buffer);
        if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (n <= 0) break;  // end of output (or a read error: nothing more to collect)
        if (result.output.size() + static_cast<std::size_t>(n) > options.max_output) {
            result.truncated = true;
            kill_group();
            break;
        }
        result.output.append(buffer, static_cast<std::size_t>(n));
    }
    close(fds[0]);
    // The output has ended; the child gets what is left of its time to exit.
    int status = 0;
    for (;;) {
        const pid_t done = waitpid(pid, &status, killed ? 0 : WNOHANG);
        if (done == pid) break;
        if (done < 0 && errno == EINTR) continue;
        if (done < 0) return make_error(std::string("waitpid: ") + std::strerror(errno));
        if (remaining_ms() == 0) {
            result.timed_out = true;
            kill_group();
            continue;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (!killed) kill(-pid, SIGKILL);  // anything the child left running in its group
    if (WIFEXITED(status)) result.exit_status = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
    return result;
}

}  // namespace px::profiling
