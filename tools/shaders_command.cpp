// parallax shaders --es 2|3 --out DIR: writes the full source of every shader
// variant the program can build, for offline validation (glslangValidator)
// and for reading what a variant really contains. --emulate PROFILE writes
// them as the precision emulation rewrites them (include/parallaxes/emulation/precision.h).
#include "parallaxes/core/files.h"
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

#include "cli_common.h"
#include "commands.h"
#include "parallaxes/emulation/precision.h"
#include "parallaxes/gl/program.h"

namespace px::tools {

namespace {

struct ShadersArgs {
    int es = 3;
    std::string out = "out/shaders";
    std::string emulate;  // empty: the sources as the GPU gets them
};

int run_shaders(const ShadersArgs& a) {
    std::optional<emulation::PrecisionProfile> profile;
    if (!a.emulate.empty()) {
        Result<emulation::PrecisionProfile> parsed = emulation::parse_profile(a.emulate);
        if (!parsed) {
            std::fprintf(stderr, "parallax: error: --emulate: %s\n", parsed.error().message.c_str());
            return 1;
        }
        profile = *parsed;
    }
    if (const std::string unwritable = check_output_folder(a.out); !unwritable.empty()) return fail(unwritable);
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
            std::string written = *text;
            if (profile) {
                Result<std::string> emulated = emulation::emulate_precision(
                    *text, suffix[1] == 'v' ? ShaderStage::vertex : ShaderStage::fragment, *profile);
                if (!emulated) {
                    std::fprintf(stderr, "parallax: error: %s: %s\n", key.describe().c_str(), emulated.error().message.c_str());
                    return 1;
                }
                written = std::move(*emulated);
            }
            // Renamed over the target (core/files.h): a planted symlink is
            // replaced, not followed; a full disk leaves no truncated file.
            Status saved = write_file_atomically(path, written);
            if (!saved) {
                std::fprintf(stderr, "parallax: error: %s\n", saved.error().message.c_str());
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
    cmd->add_option("--emulate", args->emulate,
                    "Write them as rewritten for a precision profile: identity, fp32, fp16, lowp, nohighp or lowp_all");
    cmd->callback([args]() { set_exit_status(run_shaders(*args)); });
}

}  // namespace px::tools
