#pragma once

#include <CLI/CLI.hpp>

namespace px::tools {

// Each subcommand registers itself and runs from its callback; the status it
// sets is the program's exit status.
void add_render_command(CLI::App& app);
void add_shaders_command(CLI::App& app);
void add_bench_command(CLI::App& app, int argc, char** argv);
void add_stability_command(CLI::App& app, int argc, char** argv);
void add_plan_command(CLI::App& app, int argc, char** argv);
void add_texture_commands(CLI::App& app);  // texinfo, convert
void add_profile_command(CLI::App& app, int argc, char** argv);
void add_compare_command(CLI::App& app);  // compare_command.h: what render --golden shares

void set_exit_status(int status);
int exit_status();

}  // namespace px::tools
