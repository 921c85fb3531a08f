// parallax bench --textures [SCENE]: for one scene (default: the default
// scene), every asset variant's texture bytes (against RGBA8 with mips),
// median frame time (and its ratio to the uncompressed variant, within the
// run), and the hit error each height-map format causes against the 8-bit
// original: maxmip, exact on whatever texels it is given, traced on the
// variant's height maps and compared per object with the exact reference
// of the uncompressed assets.
#include <GLES3/gl3.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <chrono>
#include <functional>
#include <memory>
#include <cstdio>
#include <string>
#include <vector>

#include "cli_common.h"
#include "draw_surface.h"
#include "parallaxes/core/files.h"
#include "parallaxes/platform/headless_context.h"
#include "parallaxes/profiling/measurement/interleaved.h"
#include "parallaxes/reference/metrics.h"
#include "parallaxes/reference/reference_image.h"
#include "parallaxes/render/offscreen_target.h"
#include "parallaxes/render/renderer.h"
#include "parallaxes/render/surface_capture.h"
#include "texture_assets.h"

namespace px::tools {

namespace {

struct VariantRow {
    std::string variant;
    std::string formats;   // height / normal / albedo
    std::uint64_t bytes = 0, rgba8_bytes = 0;
    std::vector<std::string> paths;  // per texture: direct or CPU decode
    double frame_ms = 0.0;
    double encode_s = 0.0;  // the asset step, all of the variant's textures
    std::vector<double> error_mean, error_p95;  // per height-reading object, texels of its height map
};

// One asset variant: its textures converted, their bytes, and the scene
// loaded with them (drawn once), for the timing rounds.
Result<std::unique_ptr<Renderer>> load_variant(const SceneDesc& loaded, const std::string& variant, const TempFolder& folder,
                                               const OffscreenTarget& target, VariantRow& row, SceneDesc& scene) {
    scene = loaded;
    ConvertOptions o;
    o.formats = *asset_formats(variant);
    Result<std::vector<ConvertedFile>> files = convert_scene_textures(scene, o, folder.path() + "/" + variant, nullptr);
    if (!files) return make_error(variant + ": " + files.error().message);
    row.variant = variant;
    row.formats = std::string(format_name(o.formats.height)) + " / " + format_name(o.formats.normal) + " / " +
                  format_name(o.formats.albedo);
    for (const ConvertedFile& f : *files) {
        row.bytes += f.bytes;
        row.rgba8_bytes += f.rgba8_bytes;
        row.encode_s += f.seconds;
    }
    auto renderer = Renderer::create(program_renderer_options());
    if (!renderer) return renderer.error();
    if (Status s = (*renderer)->load(scene); !s) return make_error(variant + ": " + s.error().message);
    for (const TextureUpload& u : (*renderer)->texture_uploads())
        if (u.container != "image") row.paths.push_back(std::string(format_name(u.format)) + ": " + u.path);
    if (Status s = (*renderer)->draw(target.target()); !s) return s.error();
    glFinish();
    return std::move(*renderer);
}

// Hit error from the height format: maxmip on the variant's texels against
// the reference of the uncompressed (8-bit) assets, made on first use.
Status variant_errors(const SceneDesc& scene, int width, int height, std::optional<reference::ReferenceImage>& truth,
                      VariantRow& row) {
    SceneDesc exact = scene;
    for (MaterialDesc& m : exact.materials) {
        m.effects.reset();
        m.technique = TechniqueOptions{};
        m.technique.technique = Technique::maxmip;
    }
    if (!truth) {
        Result<reference::ReferenceImage> r = reference::render_reference(exact, width, height);
        if (!r) return r.error();
        truth = std::move(*r);
    }
    auto tracer = Renderer::create(program_renderer_options());
    if (!tracer) return tracer.error();
    if (Status s = (*tracer)->load(exact); !s) return make_error(row.variant + " (maxmip): " + s.error().message);
    Result<SurfaceImage> surfaces = capture_surfaces(**tracer, width, height);
    if (!surfaces) return surfaces.error();
    for (size_t i = 0; i < exact.objects.size(); ++i) {
        Result<reference::ObjectError> e = reference::compare_object(*surfaces, *truth, static_cast<int>(i));
        if (!e) return e.error();
        row.error_mean.push_back(e->base_error_mean);
        row.error_p95.push_back(e->base_error_p95);
    }
    return {};
}

std::string textures_markdown(const SceneDesc& scene, const std::vector<VariantRow>& rows, int width, int height,
                              int frames, const std::string& command) {
    std::string md = "# Texture formats on the " + scene.name + " scene\n\n";
    md += "Measured by `" + command + "` on " + std::string(reinterpret_cast<const char*>(glGetString(GL_RENDERER))) +
          ", " + std::to_string(width) + "x" + std::to_string(height) + ", median of " + std::to_string(frames) +
          " rounds that draw every variant once each (wall clock around glFinish; compare ratios within one run).\n\n";
    md += "Bytes: every texture file's texel data (full mip chains) against the same textures as RGBA8 with mips. "
          "Encode: the asset step's encoding time for the variant's textures, all levels, one thread. ";
    md += "Hit error: maxmip (exact on the texels it is given) on the variant's height maps against the exact reference of "
          "the uncompressed 8-bit assets, per object, in texels of its height map: what the height format alone moves the "
          "hit.\n\n";
    md += "| variant | height / normal / albedo | bytes | of RGBA8 | encode s | frame ms | time vs raw |";
    for (const ObjectDesc& o : scene.objects) md += " " + o.name + " hit error mean / p95 |";
    md += "\n|---|---|---|---|---|---|---|";
    for (size_t i = 0; i < scene.objects.size(); ++i) md += "---|";
    md += "\n";
    const double raw_ms = rows.front().frame_ms;
    char b[256];
    for (const VariantRow& r : rows) {
        std::snprintf(b, sizeof b, "| %s | %s | %llu | %.1f%% | %.2f | %.2f | %.2f |", r.variant.c_str(), r.formats.c_str(),
                      static_cast<unsigned long long>(r.bytes),
                      r.rgba8_bytes ? 100.0 * static_cast<double>(r.bytes) / static_cast<double>(r.rgba8_bytes) : 0.0,
                      r.encode_s, r.frame_ms, r.frame_ms / std::max(1e-9, raw_ms));
        md += b;
        for (size_t i = 0; i < r.error_mean.size(); ++i) {
            std::snprintf(b, sizeof b, " %.3f / %.3f |", r.error_mean[i], r.error_p95[i]);
            md += b;
        }
        md += "\n";
    }
    md += "\nUpload path per texture on this context:\n\n";
    for (const VariantRow& r : rows) {
        md += "- " + r.variant + ": ";
        std::vector<std::string> unique;
        for (const std::string& p : r.paths)
            if (std::find(unique.begin(), unique.end(), p) == unique.end()) unique.push_back(p);
        for (size_t i = 0; i < unique.size(); ++i) md += (i ? "; " : "") + unique[i];
        md += "\n";
    }
    return md;
}

}  // namespace

int run_texture_bench(const std::string& scene_name, int width, int height, int frames, const std::string& out,
                      const std::string& command) {
    Result<SceneDesc> loaded = load_scene(scene_name.empty() ? "lettering" : scene_name);
    if (!loaded) return fail(loaded.error().message);
    Result<DrawSurface> surface = make_draw_surface(width, height);
    if (!surface) return fail(surface.error().message);
    OffscreenTarget* target = &*surface->target;
    Result<TempFolder> folder = make_texture_folder();
    if (!folder) return fail(folder.error().message);

    const std::vector<std::string> variants = {"raw", "etc1", "etc2", "astc", "astc_8x8", "bc", "pvrtc"};
    std::vector<VariantRow> rows(variants.size());
    std::vector<std::unique_ptr<Renderer>> timed;  // per variant, loaded
    std::optional<reference::ReferenceImage> truth;
    const int steps = static_cast<int>(variants.size());
    for (size_t i = 0; i < variants.size(); ++i) {
        show_progress("bench", static_cast<int>(i), steps, variants[i]);
        SceneDesc scene;
        Result<std::unique_ptr<Renderer>> renderer = load_variant(*loaded, variants[i], *folder, *target, rows[i], scene);
        if (!renderer) return fail(renderer.error().message);
        timed.push_back(std::move(*renderer));
        if (Status s = variant_errors(scene, width, height, truth, rows[i]); !s) return fail(s.error().message);
    }
    // Rounds: each draws every variant once, so that the machine's drift
    // falls on all of them alike; per variant the median over rounds.
    std::vector<std::function<Status()>> draws;
    for (const std::unique_ptr<Renderer>& r : timed) draws.push_back([&r, &target] { return r->draw(target->target()); });
    Result<std::vector<std::vector<double>>> times = profiling::time_in_rounds(draws, frames, false);
    if (!times) return fail(times.error().message);
    for (size_t i = 0; i < rows.size(); ++i) rows[i].frame_ms = profiling::median_of((*times)[i]);
    show_progress("bench", steps, steps, "done");
    const std::string md = textures_markdown(*loaded, rows, width, height, frames, command);
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (ec) return fail("cannot create '" + out + "': " + ec.message());
    Status w = write_file_atomically(out + "/textures.md", md);
    if (!w) return fail(w.error().message);
    std::fputs(md.c_str(), stdout);
    std::printf("\nbench: wrote %s/textures.md\n", out.c_str());
    return 0;
}

}  // namespace px::tools
