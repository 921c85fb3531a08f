// Running another program and capturing what it prints, with a time limit
// and an output cap: the vendor compilers, git (`profile --against`) and
// the NIR capture (a child `parallax` with Mesa's debug variables set).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "parallaxes/core/result.h"

namespace px::profiling {

struct ProcessOptions {
    double timeout_s = 60.0;              // the child is killed (SIGKILL) past this
    std::size_t max_output = 4u << 20;    // past this the child is killed and the output marked truncated
    std::vector<std::string> extra_env;   // "NAME=value", added to (or replacing in) this environment
    std::vector<std::string> remove_env;  // names left out of the child's environment
    bool capture_stdout = true;
    bool capture_stderr = true;           // both into one stream, in the order written
};

struct ProcessResult {
    int exit_status = -1;   // the child's exit status; -1 when a signal ended it
    int signal = 0;         // the signal that ended it, if one did
    bool timed_out = false;
    bool truncated = false;  // output past max_output was dropped
    std::string output;
};

// argv[0] is looked up on PATH when it has no '/'. The child reads
// /dev/null, leads its own process group (the time limit and the cap kill
// whatever it started too: a wrapper script's child would otherwise hold the
// pipe open) and starts with no signal blocked. A program that cannot start
// is an error; one that runs and fails is a result with its status.
Result<ProcessResult> run_process(const std::vector<std::string>& argv, const ProcessOptions& options = {});

}  // namespace px::profiling
