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
#include <cstdio>
#include <string>
#include <vector>

#include "cli_common.h"
#include "parallaxes/core/files.h"
#include "parallaxes/platform/headless_context.h"
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

}  // namespace

int run_texture_bench(const std::string& scene_name, int width, int height, int frames, const std::string& out,
                      const std::string& command) {
    Result<SceneDesc> loaded = load_scene(scene_name.empty() ? "default" : scene_name);
    if (!loaded) return fail(loaded.error().message);
    platform::ContextOptions context_options;
    context_options.es_major = 3;
    auto context = platform::HeadlessContext::create(context_options);
    if (!context) return fail(context.error().message);
    auto target = OffscreenTarget::create(width, height);
    if (!target) return fail(target.error().message);
    Result<TempFolder> folder = make_texture_folder();
    if (!folder) return fail(folder.error().message);

    const std::vector<std::string> variants = {"raw", "etc1", "etc2", "astc", "astc_8x8", "bc", "pvrtc"};
    std::vector<VariantRow> rows;
    std::vector<std::unique_ptr<Renderer>> timed;  // per variant, loaded
    std::optional<reference::ReferenceImage> truth;
    int step = 0;
    const int steps = static_cast<int>(variants.size());
    for (const std::string& v : variants) {
        show_progress("bench", step++, steps, v);
        SceneDesc scene = *loaded;
        ConvertOptions o;
        o.formats = *asset_formats(v);
        Result<std::vector<ConvertedFile>> files = convert_scene_textures(scene, o, folder->path() + "/" + v, nullptr);
        if (!files) return fail(v + ": " + files.error().message);
        VariantRow row;
        row.variant = v;
        row.formats = std::string(format_name(o.formats.height)) + " / " + format_name(o.formats.normal) + " / " +
                      format_name(o.formats.albedo);
        for (const ConvertedFile& f : *files) {
            row.bytes += f.bytes;
            row.rgba8_bytes += f.rgba8_bytes;
            row.encode_s += f.seconds;
        }
        // Frame time with the scene's own techniques: loaded now, timed
        // below in interleaved rounds.
        RendererOptions ro;
        ro.effect_planner = effect_planner;
        ro.texture_files = texture_files();
        ro.get_proc_address = platform::HeadlessContext::proc_loader();
        auto renderer = Renderer::create(ro);
        if (!renderer) return fail(renderer.error().message);
        Status s = (*renderer)->load(scene);
        if (!s) return fail(v + ": " + s.error().message);
        for (const TextureUpload& u : (*renderer)->texture_uploads())
            if (u.container != "image") row.paths.push_back(std::string(format_name(u.format)) + ": " + u.path);
        if (!(s = (*renderer)->draw(target->target()))) return fail(s.error().message);
        glFinish();
        timed.push_back(std::move(*renderer));
        // Hit error from the height format: maxmip on the variant's texels
        // against the reference of the uncompressed (8-bit) assets.
        SceneDesc exact = scene;
        for (MaterialDesc& m : exact.materials) {
            m.effects.reset();
            m.technique = TechniqueOptions{};
            m.technique.technique = Technique::maxmip;
        }
        if (!truth) {
            Result<reference::ReferenceImage> r = reference::render_reference(exact, width, height);
            if (!r) return fail(r.error().message);
            truth = std::move(*r);
        }
        auto tracer = Renderer::create(ro);
        if (!tracer) return fail(tracer.error().message);
        if (!(s = (*tracer)->load(exact))) return fail(v + " (maxmip): " + s.error().message);
        Result<SurfaceImage> surfaces = capture_surfaces(**tracer, width, height);
        if (!surfaces) return fail(surfaces.error().message);
        for (size_t i = 0; i < exact.objects.size(); ++i) {
            Result<reference::ObjectError> e = reference::compare_object(*surfaces, *truth, static_cast<int>(i));
            if (!e) return fail(e.error().message);
            row.error_mean.push_back(e->base_error_mean);
            row.error_p95.push_back(e->base_error_p95);
        }
        rows.push_back(std::move(row));
    }
    // Rounds: each draws every variant once, so that the machine's drift
    // falls on all of them alike; per variant the median over rounds.
    std::vector<std::vector<double>> times(rows.size());
    for (int round = 0; round < frames; ++round) {
        for (size_t i = 0; i < rows.size(); ++i) {
            const auto start = std::chrono::steady_clock::now();
            Status s = timed[i]->draw(target->target());
            glFinish();
            times[i].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
            if (!s) return fail(s.error().message);
        }
    }
    for (size_t i = 0; i < rows.size(); ++i) {
        std::sort(times[i].begin(), times[i].end());
        rows[i].frame_ms = times[i][times[i].size() / 2];
    }
    show_progress("bench", steps, steps, "done");

    std::string md = "# Texture formats on the " + loaded->name + " scene\n\n";
    md += "Measured by `" + command + "` on " + std::string(reinterpret_cast<const char*>(glGetString(GL_RENDERER))) +
          ", " + std::to_string(width) + "x" + std::to_string(height) + ", median of " + std::to_string(frames) +
          " rounds that draw every variant once each (wall clock around glFinish; compare ratios within one run).\n\n";
    md += "Bytes: every texture file's texel data (full mip chains) against the same textures as RGBA8 with mips. "
          "Encode: the asset step's encoding time for the variant's textures, all levels, one thread. ";
    md += "Hit error: maxmip (exact on the texels it is given) on the variant's height maps against the exact reference of "
          "the uncompressed 8-bit assets, per object, in texels of its height map: what the height format alone moves the "
          "hit.\n\n";
    md += "| variant | height / normal / albedo | bytes | of RGBA8 | encode s | frame ms | time vs raw |";
    for (const ObjectDesc& o : loaded->objects) md += " " + o.name + " hit error mean / p95 |";
    md += "\n|---|---|---|---|---|---|---|";
    for (size_t i = 0; i < loaded->objects.size(); ++i) md += "---|";
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
