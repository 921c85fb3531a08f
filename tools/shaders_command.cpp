// parallax shaders --es 2|3 --out DIR: writes the full source of every shader
// variant the program can build, for offline validation (glslangValidator)
// and for reading what a variant really contains.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "commands.h"
#include "gl/program.h"

namespace px::tools {

namespace {

struct ShadersArgs {
    int es = 3;
    std::string out = "out/shaders";
};

int run_shaders(const ShadersArgs& a) {
    std::error_code ec;
    std::filesystem::create_directories(a.out, ec);
    if (ec) {
        std::fprintf(stderr, "parallax: error: cannot create '%s': %s\n", a.out.c_str(), ec.message().c_str());
        return 1;
    }
    int count = 0;
    for (const VariantKey& key : enumerate_variants(a.es)) {
        Result<VariantSources> sources = assemble_variant(key);
        if (!sources) {
            std::fprintf(stderr, "parallax: error: %s\n", sources.error().message.c_str());
            return 1;
        }
        std::string stem = key.describe();
        for (char& c : stem)
            if (c == ' ' || c == '=' || c == '<') c = '_';
        for (const auto& [suffix, text] : {std::pair<const char*, const std::string*>{".vert", &sources->vertex.text},
                                           {".frag", &sources->fragment.text}}) {
            const std::string path = a.out + "/" + stem + suffix;
            std::ofstream file(path, std::ios::binary);
            file << *text;
            if (!file) {
                std::fprintf(stderr, "parallax: error: cannot write '%s'\n", path.c_str());
                return 1;
            }
        }
        ++count;
    }
    std::printf("wrote %d variants (%d files) for OpenGL ES %d.0 to %s\n", count, 2 * count, a.es, a.out.c_str());
    return 0;
}

}  // namespace

void add_shaders_command(CLI::App& app) {
    auto args = std::make_shared<ShadersArgs>();
    CLI::App* cmd = app.add_subcommand("shaders", "Write every shader variant's full source (for validation)");
    cmd->add_option("--es", args->es, "OpenGL ES major version: 2 or 3")->check(CLI::IsMember({2, 3}))->capture_default_str();
    cmd->add_option("--out", args->out, "Output folder")->capture_default_str();
    cmd->callback([args]() { set_exit_status(run_shaders(*args)); });
}

}  // namespace px::tools
