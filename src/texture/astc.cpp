// ASTC LDR through libastcenc: linear LDR profile (ASTCENC_PRF_LDR), the
// block size from format_info, single-threaded contexts, 8-bit images.
#ifndef PX_NO_ASTCENC
#include <astcenc.h>
#endif

#include <memory>
#include <string>

#include "parallaxes/texture/codecs.h"

namespace px {

#ifndef PX_NO_ASTCENC
namespace {

bool is_astc(TextureFormat f) { return format_info(f).family == FormatFamily::astc; }

std::string dims(TextureFormat f, std::uint32_t w, std::uint32_t h) {
    return std::string(format_name(f)) + " " + std::to_string(w) + "x" + std::to_string(h);
}

Error astc_error(const char* fn, const char* step, astcenc_error e) {
    const char* msg = astcenc_get_error_string(e);
    return make_error(std::string(fn) + ": astcenc " + step + " failed: " + (msg ? msg : "unknown error") +
                      " (astcenc_error " + std::to_string(static_cast<int>(e)) + ")");
}

struct ContextDeleter {
    void operator()(astcenc_context* c) const { astcenc_context_free(c); }
};
using Context = std::unique_ptr<astcenc_context, ContextDeleter>;

Result<Context> make_context(const char* fn, TextureFormat format, float quality, unsigned flags) {
    const FormatInfo& fi = format_info(format);
    astcenc_config config{};
    astcenc_error e = astcenc_config_init(ASTCENC_PRF_LDR, static_cast<unsigned>(fi.block_width),
                                          static_cast<unsigned>(fi.block_height), 1, quality, flags, &config);
    if (e != ASTCENC_SUCCESS) return astc_error(fn, "astcenc_config_init", e);
    astcenc_context* ctx = nullptr;
    e = astcenc_context_alloc(&config, 1, &ctx);
    if (e != ASTCENC_SUCCESS) return astc_error(fn, "astcenc_context_alloc", e);
    return Context(ctx);
}

const astcenc_swizzle kIdentity{ASTCENC_SWZ_R, ASTCENC_SWZ_G, ASTCENC_SWZ_B, ASTCENC_SWZ_A};

}  // namespace

Status decode_astc_rgba8(TextureFormat format, std::uint32_t width, std::uint32_t height,
                         const std::uint8_t* data, std::size_t size, std::uint8_t* rgba) {
    const char* fn = "decode_astc_rgba8";
    if (!is_astc(format)) return make_error(std::string(fn) + ": format " + format_name(format) + " is not ASTC");
    if (width == 0 || height == 0)
        return make_error(std::string(fn) + ": " + dims(format, width, height) +
                          " (width and height must be at least 1)");
    const auto expected = image_bytes(format, width, height);
    if (!expected) return make_error(std::string(fn) + ": " + dims(format, width, height) + " is too large");
    if (*expected != size)
        return make_error(std::string(fn) + ": " + dims(format, width, height) + " image needs " +
                          std::to_string(*expected) + " bytes, " + std::to_string(size) + " given");
    if (!data || !rgba) return make_error(std::string(fn) + ": null data or output pointer");
    return out_of_memory_is_an_error(fn, [&]() -> Status {
        Result<Context> ctx = make_context(fn, format, ASTCENC_PRE_FASTEST, ASTCENC_FLG_DECOMPRESS_ONLY);
        if (!ctx) return ctx.error();
        void* slices[1] = {rgba};
        astcenc_image image{width, height, 1, ASTCENC_TYPE_U8, slices};
        const astcenc_error e = astcenc_decompress_image(ctx->get(), data, size, &image, &kIdentity, 0);
        if (e != ASTCENC_SUCCESS) return astc_error(fn, "astcenc_decompress_image", e);
        return Status{};
    });
}

Result<std::vector<std::uint8_t>> encode_astc_rgba8(TextureFormat format, std::uint32_t width,
                                                    std::uint32_t height, const std::uint8_t* rgba,
                                                    float quality) {
    const char* fn = "encode_astc_rgba8";
    if (!is_astc(format)) return make_error(std::string(fn) + ": format " + format_name(format) + " is not ASTC");
    if (width == 0 || height == 0)
        return make_error(std::string(fn) + ": " + dims(format, width, height) +
                          " (width and height must be at least 1)");
    if (!(quality >= 0.0f && quality <= 100.0f))
        return make_error(std::string(fn) + ": quality " + std::to_string(quality) + " is outside 0..100");
    const auto bytes = image_bytes(format, width, height);
    if (!bytes) return make_error(std::string(fn) + ": " + dims(format, width, height) + " is too large");
    if (!rgba) return make_error(std::string(fn) + ": null pixel pointer");
    return out_of_memory_is_an_error(fn, [&]() -> Result<std::vector<std::uint8_t>> {
        Result<Context> ctx = make_context(fn, format, quality, 0);
        if (!ctx) return ctx.error();
        std::vector<std::uint8_t> out(static_cast<std::size_t>(*bytes));
        // astcenc reads the image through a non-const pointer but does not
        // write it.
        void* slices[1] = {const_cast<std::uint8_t*>(rgba)};
        astcenc_image image{width, height, 1, ASTCENC_TYPE_U8, slices};
        const astcenc_error e = astcenc_compress_image(ctx->get(), &image, &kIdentity, out.data(), out.size(), 0);
        if (e != ASTCENC_SUCCESS) return astc_error(fn, "astcenc_compress_image", e);
        return out;
    });
}

#else
// A build without libastcenc (the web build): ASTC files cannot be decoded
// for the CPU's copy (the exact reference, the planner), so they are refused.
Status decode_astc_rgba8(TextureFormat, std::uint32_t, std::uint32_t, const std::uint8_t*, std::size_t, std::uint8_t*) {
    return make_error("decode_astc_rgba8: ASTC decoding is not in this build (built without libastcenc: the web build)");
}

Result<std::vector<std::uint8_t>> encode_astc_rgba8(TextureFormat, std::uint32_t, std::uint32_t, const std::uint8_t*, float) {
    return make_error("encode_astc_rgba8: ASTC encoding is not in this build (built without libastcenc: the web build)");
}
#endif  // PX_NO_ASTCENC

}  // namespace px
