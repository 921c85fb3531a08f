// `parallax`: the command-line program. Thin: parses arguments, calls the
// library, prints results and errors, and sets the exit status.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>

#include "commands.h"

int main(int argc, char** argv) {
    CLI::App app{"ParallaxES: parallax-mapping renderer for OpenGL ES 2.0/3.0, headless on EGL"};
    app.require_subcommand(1);
    px::tools::add_render_command(app);
    px::tools::add_shaders_command(app);
    px::tools::add_bench_command(app, argc, argv);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    return px::tools::exit_status();
}
