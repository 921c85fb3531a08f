// `parallax`: the command-line program. Thin: parses arguments, calls the
// library, prints results and errors, and sets the exit status.
#include <exception>
#include <new>
#include <string>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>

#include "cli_common.h"
#include "commands.h"
#include "parallaxes/core/interrupts.h"

int main(int argc, char** argv) {
    // Before any thread starts: SIGINT/SIGTERM/SIGHUP kill our children and remove our temporary folders.
    if (px::Status s = px::interrupts::install(); !s) std::fprintf(stderr, "parallax: warning: %s\n", s.error().message.c_str());
    CLI::App app{"ParallaxES: parallax-mapping renderer for OpenGL ES 2.0/3.0, headless on EGL"};
    app.require_subcommand(1);
    px::tools::add_render_command(app);
    px::tools::add_shaders_command(app);
    px::tools::add_bench_command(app, argc, argv);
    px::tools::add_stability_command(app, argc, argv);
    px::tools::add_plan_command(app, argc, argv);
    px::tools::add_profile_command(app, argc, argv);
    px::tools::add_texture_commands(app);
    px::tools::add_compare_command(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const std::bad_alloc&) {
        // The library's limits and its own out-of-memory checks make this the
        // last resort: a message and a failing exit, never an abort.
        return px::tools::fail("out of memory");
    } catch (const std::exception& e) {
        return px::tools::fail(std::string("internal error: ") + e.what());
    }
    return px::tools::exit_status();
}
