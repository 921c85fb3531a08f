#include "parallaxes/texture/format.h"

#include "parallaxes/texture/texture_data.h"

#include <algorithm>
#include <cctype>

namespace px {

namespace {

using F = TextureFormat;
using Fam = FormatFamily;
constexpr std::uint32_t kNoPvr = 0xFFFFFFFFu;

// vkFormat numbers: Vulkan 1.3 VkFormat (and VK_IMG_format_pvrtc).
std::vector<FormatInfo> make_table() {
    using namespace glenum;
    std::vector<FormatInfo> t = {
        {F::r8, "r8", Fam::uncompressed, 1, 1, 1, 1, 1, 1, 8, kR8, kRed, 9, kNoPvr},
        {F::rg8, "rg8", Fam::uncompressed, 1, 1, 2, 1, 1, 2, 8, kRg8, kRg, 16, kNoPvr},
        {F::rgb8, "rgb8", Fam::uncompressed, 1, 1, 3, 1, 1, 3, 8, kRgb8, kRgb, 23, kNoPvr},
        {F::rgba8, "rgba8", Fam::uncompressed, 1, 1, 4, 1, 1, 4, 8, kRgba8, kRgba, 37, kNoPvr},
        {F::etc1_rgb8, "etc1", Fam::etc1, 4, 4, 8, 1, 1, 3, 8, kEtc1Rgb8, 0, 0, 6},
        {F::etc2_rgb8, "etc2_rgb", Fam::etc2, 4, 4, 8, 1, 1, 3, 8, kRgb8Etc2, 0, 147, 22},
        {F::etc2_rgb8a1, "etc2_rgb_a1", Fam::etc2, 4, 4, 8, 1, 1, 4, 8, kRgb8A1Etc2, 0, 149, 24},
        {F::etc2_rgba8, "etc2_rgba", Fam::etc2, 4, 4, 16, 1, 1, 4, 8, kRgba8Etc2Eac, 0, 151, 23},
        {F::eac_r11, "eac_r11", Fam::eac, 4, 4, 8, 1, 1, 1, 11, kR11Eac, 0, 153, 25},
        {F::eac_rg11, "eac_rg11", Fam::eac, 4, 4, 16, 1, 1, 2, 11, kRg11Eac, 0, 155, 26},
    };
    const int astc[14][2] = {{4, 4}, {5, 4}, {5, 5}, {6, 5}, {6, 6}, {8, 5}, {8, 6},
                             {8, 8}, {10, 5}, {10, 6}, {10, 8}, {10, 10}, {12, 10}, {12, 12}};
    static const char* const astc_names[14] = {"astc_4x4", "astc_5x4", "astc_5x5", "astc_6x5", "astc_6x6",
                                               "astc_8x5", "astc_8x6", "astc_8x8", "astc_10x5", "astc_10x6",
                                               "astc_10x8", "astc_10x10", "astc_12x10", "astc_12x12"};
    for (int i = 0; i < 14; ++i) {
        t.push_back({static_cast<F>(static_cast<int>(F::astc_4x4) + i), astc_names[i], Fam::astc, astc[i][0],
                     astc[i][1], 16, 1, 1, 4, 8, kAstc4x4 + static_cast<std::uint32_t>(i), 0,
                     157u + 2u * static_cast<std::uint32_t>(i), 27u + static_cast<std::uint32_t>(i)});
    }
    // PVRTC1: 2 bpp blocks are 8 x 4 texels, 4 bpp blocks 4 x 4; 8 bytes
    // each; a level is at least 2 x 2 blocks (16 x 8 or 8 x 8 texels).
    // Vulkan has only RGBA PVRTC formats.
    t.push_back({F::pvrtc1_rgb_2bpp, "pvrtc1_rgb_2bpp", Fam::pvrtc, 8, 4, 8, 2, 2, 3, 8, kPvrtcRgb2, 0, 0, 0});
    t.push_back({F::pvrtc1_rgb_4bpp, "pvrtc1_rgb_4bpp", Fam::pvrtc, 4, 4, 8, 2, 2, 3, 8, kPvrtcRgb4, 0, 0, 2});
    t.push_back({F::pvrtc1_rgba_2bpp, "pvrtc1_rgba_2bpp", Fam::pvrtc, 8, 4, 8, 2, 2, 4, 8, kPvrtcRgba2, 0,
                 1000054000u, 1});
    t.push_back({F::pvrtc1_rgba_4bpp, "pvrtc1_rgba_4bpp", Fam::pvrtc, 4, 4, 8, 2, 2, 4, 8, kPvrtcRgba4, 0,
                 1000054001u, 3});
    t.push_back({F::bc1_rgb, "bc1_rgb", Fam::s3tc, 4, 4, 8, 1, 1, 3, 8, kDxt1Rgb, 0, 131, 7});
    t.push_back({F::bc1_rgba, "bc1_rgba", Fam::s3tc, 4, 4, 8, 1, 1, 4, 8, kDxt1Rgba, 0, 133, kNoPvr});
    t.push_back({F::bc2, "bc2", Fam::s3tc, 4, 4, 16, 1, 1, 4, 8, kDxt3, 0, 135, 9});
    t.push_back({F::bc3, "bc3", Fam::s3tc, 4, 4, 16, 1, 1, 4, 8, kDxt5, 0, 137, 11});
    t.push_back({F::bc4, "bc4", Fam::rgtc, 4, 4, 8, 1, 1, 1, 8, kRgtc1, 0, 139, 12});
    t.push_back({F::bc5, "bc5", Fam::rgtc, 4, 4, 16, 1, 1, 2, 8, kRgtc2, 0, 141, 13});
    return t;
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string hex(std::uint64_t v) { return hex_code(v); }

}  // namespace

const std::vector<FormatInfo>& all_formats() {
    static const std::vector<FormatInfo> table = make_table();
    return table;
}

const FormatInfo& format_info(TextureFormat format) {
    return all_formats()[static_cast<std::size_t>(format)];
}

const char* format_name(TextureFormat format) { return format_info(format).name; }

Result<TextureFormat> parse_format(const std::string& name) {
    const std::string n = lower(name);
    std::string names;
    for (const FormatInfo& f : all_formats()) {
        if (n == f.name) return f.format;
        names += names.empty() ? "" : ", ";
        names += f.name;
    }
    return make_error("unknown texture format '" + name.substr(0, 64) + "' (known: " + names + ")");
}

Result<TextureFormat> format_from_gl(std::uint32_t internal, std::uint32_t gl_format, std::uint32_t gl_type) {
    using namespace glenum;
    for (const FormatInfo& f : all_formats()) {
        if (f.gl_internal_format != internal) continue;
        if (f.compressed()) return f.format;
        if (gl_type != kUnsignedByte || gl_format != f.gl_format)
            return make_error("glInternalFormat " + hex(internal) + " (" + f.name + ") with glFormat " +
                              hex(gl_format) + " and glType " + hex(gl_type) +
                              " (expected glFormat " + hex(f.gl_format) + ", glType GL_UNSIGNED_BYTE)");
        return f.format;
    }
    // ES 2.0's unsized formats: the internal format is the format.
    if (gl_type == kUnsignedByte && internal == gl_format) {
        if (internal == kRgba) return F::rgba8;
        if (internal == kRgb) return F::rgb8;
        if (internal == kLuminance || internal == kRed) return F::r8;
        if (internal == kLuminanceAlpha || internal == kRg) return F::rg8;
    }
    if (linear_gl_of_srgb(internal) != 0)
        return make_error("glInternalFormat " + hex(internal) + " (" + srgb_gl_name(internal) +
                          ") is an sRGB format: read it with its colour space (read_ktx1 does)");
    if (internal == kSignedR11Eac || internal == kSignedRg11Eac || internal == kSignedRgtc1 ||
        internal == kSignedRgtc2)
        return make_error("glInternalFormat " + hex(internal) + " is a signed format, which is not supported "
                          "(use the unsigned one)");
    // Compressed formats known by name and not decoded here, named as the
    // KTX 2.0 path names them.
    static const std::pair<std::uint32_t, const char*> unsupported[] = {
        {0x8E8C, "BC7 (GL_COMPRESSED_RGBA_BPTC_UNORM)"},
        {0x8E8D, "BC7 sRGB (GL_COMPRESSED_SRGB_ALPHA_BPTC_UNORM)"},
        {0x8E8E, "BC6H signed float (GL_COMPRESSED_RGB_BPTC_SIGNED_FLOAT)"},
        {0x8E8F, "BC6H unsigned float (GL_COMPRESSED_RGB_BPTC_UNSIGNED_FLOAT)"},
        {0x8C70, "LATC1 (GL_COMPRESSED_LUMINANCE_LATC1_EXT)"},
        {0x8C71, "signed LATC1 (GL_COMPRESSED_SIGNED_LUMINANCE_LATC1_EXT)"},
        {0x8C72, "LATC2 (GL_COMPRESSED_LUMINANCE_ALPHA_LATC2_EXT)"},
        {0x8C73, "signed LATC2 (GL_COMPRESSED_SIGNED_LUMINANCE_ALPHA_LATC2_EXT)"},
        {0x9137, "PVRTC2 2 bpp (GL_COMPRESSED_RGBA_PVRTC_2BPPV2_IMG)"},
        {0x9138, "PVRTC2 4 bpp (GL_COMPRESSED_RGBA_PVRTC_4BPPV2_IMG)"},
        {0x8C92, "ATC RGB (GL_ATC_RGB_AMD)"},
        {0x8C93, "ATC RGBA explicit alpha (GL_ATC_RGBA_EXPLICIT_ALPHA_AMD)"},
        {0x87EE, "ATC RGBA interpolated alpha (GL_ATC_RGBA_INTERPOLATED_ALPHA_AMD)"},
        {0x86B0, "FXT1 RGB (GL_COMPRESSED_RGB_FXT1_3DFX)"},
        {0x86B1, "FXT1 RGBA (GL_COMPRESSED_RGBA_FXT1_3DFX)"},
    };
    for (const auto& [code, name] : unsupported)
        if (internal == code)
            return make_error("glInternalFormat " + hex(internal) + " is " + name +
                              ", which is not supported (ETC1, ETC2/EAC, ASTC, PVRTC1 and BC1 to BC5 are)");
    if (internal == 0)
        return make_error("glInternalFormat 0 (an uncompressed file must give a sized or unsized format; type " +
                          hex(gl_type) + ", format " + hex(gl_format) + ")");
    return make_error("glInternalFormat " + hex(internal) + " with glType " + hex(gl_type) +
                      " is not a supported texture format");
}

Result<TextureFormat> format_from_vk(std::uint32_t vk) {
    for (const FormatInfo& f : all_formats())
        if (f.vk_format != 0 && f.vk_format == vk) return f.format;
    if (vk == 0)
        return make_error("vkFormat 0 (VK_FORMAT_UNDEFINED: a Basis Universal payload, UASTC or ETC1S as glTF's "
                          "KHR_texture_basisu uses, which is not read here): transcode it to a GPU format first, "
                          "for example `basisu -unpack file.ktx2`, which writes KTX 1.1 files of ETC1, ETC2, ASTC, "
                          "BC1 to BC5 and PVRTC that this library reads");
    if (linear_vk_of_srgb(vk) != 0)
        return make_error("vkFormat " + std::to_string(vk) + " is an sRGB format: read it with its colour space "
                          "(read_ktx2 does)");
    if (vk == 1000054006u || vk == 1000054007u)
        return make_error("vkFormat " + std::to_string(vk) + " is PVRTC2 sRGB, which is not supported");
    if (vk == 140 || vk == 142 || vk == 154 || vk == 156)
        return make_error("vkFormat " + std::to_string(vk) + " is a signed format, which is not supported");
    if (vk >= 143 && vk <= 146)
        return make_error("vkFormat " + std::to_string(vk) + " is BC6H or BC7, which are not supported");
    if (vk >= 1000054002u && vk <= 1000054003u)
        return make_error("vkFormat " + std::to_string(vk) + " is PVRTC2, which is not supported");
    return make_error("vkFormat " + std::to_string(vk) + " is not a supported texture format");
}

Result<TextureFormat> format_from_pvr(std::uint64_t pixel_format, std::uint32_t channel_type) {
    const std::uint32_t high = static_cast<std::uint32_t>(pixel_format >> 32);
    if (high == 0) {
        const std::uint32_t code = static_cast<std::uint32_t>(pixel_format);
        for (const FormatInfo& f : all_formats())
            if (f.compressed() && f.pvr_format != kNoPvr && f.pvr_format == code) return f.format;
        static const char* const names[] = {"PVRTC 2bpp RGB", "PVRTC 2bpp RGBA", "PVRTC 4bpp RGB",
                                            "PVRTC 4bpp RGBA", "PVRTC-II 2bpp", "PVRTC-II 4bpp",
                                            "ETC1", "DXT1", "DXT2 (premultiplied)", "DXT3",
                                            "DXT4 (premultiplied)", "DXT5", "BC4", "BC5", "BC6", "BC7"};
        const std::string name = code < 16 ? std::string(" (") + names[code] + ")" : std::string();
        return make_error("pixel format " + std::to_string(code) + name + " is not a supported texture format");
    }
    // Uncompressed: four channel letters, then four bit counts.
    char letters[4];
    int bits[4];
    for (int i = 0; i < 4; ++i) {
        letters[i] = static_cast<char>((pixel_format >> (8 * i)) & 0xFF);
        bits[i] = static_cast<int>((pixel_format >> (32 + 8 * i)) & 0xFF);
    }
    std::string layout;
    for (int i = 0; i < 4 && letters[i]; ++i) {
        if (bits[i] != 8) {
            layout.clear();
            break;
        }
        layout += letters[i];
    }
    // channel type 0: unsigned byte, normalised; 2: unsigned byte.
    if (channel_type == 0 || channel_type == 2) {
        if (layout == "r" || layout == "l") return F::r8;
        if (layout == "rg" || layout == "la") return F::rg8;
        if (layout == "rgb") return F::rgb8;
        if (layout == "rgba") return F::rgba8;
    }
    std::string shown;
    for (int i = 0; i < 4 && letters[i]; ++i) {
        const unsigned char c = static_cast<unsigned char>(letters[i]);
        shown += std::isprint(c) ? std::string(1, letters[i]) : "?";
        shown += std::to_string(bits[i]);
    }
    return make_error("uncompressed pixel format '" + shown + "' with channel type " + std::to_string(channel_type) +
                      " is not supported (8-bit unsigned normalised r, rg, rgb or rgba are)");
}

std::optional<std::uint64_t> image_bytes(TextureFormat format, std::uint64_t width, std::uint64_t height) {
    const FormatInfo& f = format_info(format);
    if (width == 0 || height == 0) return std::nullopt;
    if (width > (std::uint64_t{1} << 31) || height > (std::uint64_t{1} << 31)) return std::nullopt;
    const std::uint64_t bx = std::max<std::uint64_t>((width + f.block_width - 1) / f.block_width, f.min_blocks_x);
    const std::uint64_t by = std::max<std::uint64_t>((height + f.block_height - 1) / f.block_height, f.min_blocks_y);
    // bx, by < 2^31 and block_bytes <= 16: the product stays under 2^66 only
    // in theory; check the first product before the second.
    const std::uint64_t blocks = bx * by;  // < 2^62
    if (blocks > (std::uint64_t{1} << 58)) return std::nullopt;
    return blocks * static_cast<std::uint64_t>(f.block_bytes);
}

int full_mip_count(std::uint32_t width, std::uint32_t height) {
    std::uint32_t m = std::max(width, height);
    int n = 1;
    while (m > 1) {
        m >>= 1;
        ++n;
    }
    return n;
}

const char* format_requirement(TextureFormat format) {
    switch (format_info(format).family) {
    case Fam::uncompressed: return "nothing";
    case Fam::etc1: return "GL_OES_compressed_ETC1_RGB8_texture or OpenGL ES 3.0";
    case Fam::etc2:
    case Fam::eac: return "OpenGL ES 3.0";
    case Fam::astc: return "GL_KHR_texture_compression_astc_ldr";
    case Fam::pvrtc: return "GL_IMG_texture_compression_pvrtc";
    case Fam::s3tc: return "GL_EXT_texture_compression_s3tc";
    case Fam::rgtc: return "GL_EXT_texture_compression_rgtc";
    }
    return "nothing";
}

std::uint32_t upload_internal_format(const Caps& caps, TextureFormat format) {
    // ETC1 goes up as ETC2 RGB wherever ES 3.0 has it: ETC2 decodes valid
    // ETC1 blocks identically, and llvmpipe samples its ETC1 format 4.8x
    // slower than ETC2 (docs/textures.md, `bench --textures`).
    if (format == F::etc1_rgb8 && caps.context_es3()) return glenum::kRgb8Etc2;
    return format_info(format).gl_internal_format;
}

bool context_samples(const Caps& caps, TextureFormat format) {
    const FormatInfo& f = format_info(format);
    bool defined = false;
    switch (f.family) {
    case Fam::uncompressed: return true;
    case Fam::etc1: defined = caps.has("GL_OES_compressed_ETC1_RGB8_texture") || caps.context_es3(); break;
    case Fam::etc2:
    case Fam::eac: defined = caps.context_es3(); break;
    case Fam::astc: defined = caps.has("GL_KHR_texture_compression_astc_ldr"); break;
    case Fam::pvrtc: defined = caps.has("GL_IMG_texture_compression_pvrtc"); break;
    case Fam::s3tc:
        defined = caps.has("GL_EXT_texture_compression_s3tc") ||
                  (format == F::bc1_rgb || format == F::bc1_rgba ? caps.has("GL_EXT_texture_compression_dxt1")
                                                                  : false);
        break;
    case Fam::rgtc: defined = caps.has("GL_EXT_texture_compression_rgtc"); break;
    }
    if (!defined) return false;
    if (caps.compressed_formats.empty()) return true;
    const std::uint32_t gl = upload_internal_format(caps, format);
    return std::find(caps.compressed_formats.begin(), caps.compressed_formats.end(), gl) !=
           caps.compressed_formats.end();
}

std::uint32_t linear_gl_of_srgb(std::uint32_t internal) {
    using namespace glenum;
    switch (internal) {
    case kSrgb8Etc2: return kRgb8Etc2;
    case kSrgb8A1Etc2: return kRgb8A1Etc2;
    case kSrgb8Alpha8Etc2Eac: return kRgba8Etc2Eac;
    case 0x8C43: return kRgba8;  // GL_SRGB8_ALPHA8
    case 0x8C41: return kRgb8;   // GL_SRGB8
    case 0x8C42: return kRgba;   // GL_SRGB_ALPHA_EXT (ES 2.0, unsized)
    case 0x8C40: return kRgb;    // GL_SRGB_EXT
    case 0x8C4C: return kDxt1Rgb;   // GL_COMPRESSED_SRGB_S3TC_DXT1_EXT
    case 0x8C4D: return kDxt1Rgba;  // GL_COMPRESSED_SRGB_ALPHA_S3TC_DXT1_EXT
    case 0x8C4E: return kDxt3;
    case 0x8C4F: return kDxt5;
    case 0x8A54: return kPvrtcRgb2;   // GL_COMPRESSED_SRGB_PVRTC_2BPPV1_EXT
    case 0x8A55: return kPvrtcRgb4;
    case 0x8A56: return kPvrtcRgba2;
    case 0x8A57: return kPvrtcRgba4;
    default: break;
    }
    if (internal >= kSrgbAstc4x4 && internal <= kSrgbAstc4x4 + 13) return internal - kSrgbAstc4x4 + 0x93B0;
    return 0;
}

std::string srgb_gl_name(std::uint32_t internal) {
    using namespace glenum;
    switch (internal) {
    case kSrgb8Etc2: return "GL_COMPRESSED_SRGB8_ETC2";
    case kSrgb8A1Etc2: return "GL_COMPRESSED_SRGB8_PUNCHTHROUGH_ALPHA1_ETC2";
    case kSrgb8Alpha8Etc2Eac: return "GL_COMPRESSED_SRGB8_ALPHA8_ETC2_EAC";
    case 0x8C43: return "GL_SRGB8_ALPHA8";
    case 0x8C41: return "GL_SRGB8";
    case 0x8C42: return "GL_SRGB_ALPHA_EXT";
    case 0x8C40: return "GL_SRGB_EXT";
    case 0x8C4C: return "GL_COMPRESSED_SRGB_S3TC_DXT1_EXT";
    case 0x8C4D: return "GL_COMPRESSED_SRGB_ALPHA_S3TC_DXT1_EXT";
    case 0x8C4E: return "GL_COMPRESSED_SRGB_ALPHA_S3TC_DXT3_EXT";
    case 0x8C4F: return "GL_COMPRESSED_SRGB_ALPHA_S3TC_DXT5_EXT";
    case 0x8A54: return "GL_COMPRESSED_SRGB_PVRTC_2BPPV1_EXT";
    case 0x8A55: return "GL_COMPRESSED_SRGB_PVRTC_4BPPV1_EXT";
    case 0x8A56: return "GL_COMPRESSED_SRGB_ALPHA_PVRTC_2BPPV1_EXT";
    case 0x8A57: return "GL_COMPRESSED_SRGB_ALPHA_PVRTC_4BPPV1_EXT";
    default: break;
    }
    if (internal >= kSrgbAstc4x4 && internal <= kSrgbAstc4x4 + 13) {
        static const char* const blocks[] = {"4x4", "5x4", "5x5", "6x5", "6x6", "8x5", "8x6",
                                             "8x8", "10x5", "10x6", "10x8", "10x10", "12x10", "12x12"};
        return std::string("GL_COMPRESSED_SRGB8_ALPHA8_ASTC_") + blocks[internal - kSrgbAstc4x4] + "_KHR";
    }
    return hex(internal);
}

std::uint32_t linear_vk_of_srgb(std::uint32_t vk) {
    switch (vk) {
    case 15: return 9;    // VK_FORMAT_R8_SRGB -> R8_UNORM
    case 22: return 16;   // R8G8_SRGB
    case 29: return 23;   // R8G8B8_SRGB
    case 43: return 37;   // R8G8B8A8_SRGB
    case 132: case 134: case 136: case 138:  // BC1 RGB, BC1 RGBA, BC2, BC3 *_SRGB_BLOCK
    case 148: case 150: case 152:            // ETC2 R8G8B8, A1, A8 *_SRGB_BLOCK
        return vk - 1;
    case 1000054004u: case 1000054005u: return vk - 4;  // PVRTC1 2 and 4 bpp *_SRGB_BLOCK_IMG
    default: break;
    }
    if (vk >= 158 && vk <= 184 && vk % 2 == 0) return vk - 1;  // ASTC *_SRGB_BLOCK
    return 0;
}

std::uint32_t srgb_internal_format(const Caps& caps, TextureFormat format) {
    if (!caps.context_es3()) return 0;
    using namespace glenum;
    switch (format) {
    case F::etc1_rgb8:  // ETC2 decodes ETC1 blocks identically
    case F::etc2_rgb8: return kSrgb8Etc2;
    case F::etc2_rgb8a1: return kSrgb8A1Etc2;
    case F::etc2_rgba8: return kSrgb8Alpha8Etc2Eac;
    case F::rgba8: return 0x8C43;
    case F::rgb8: return 0x8C41;
    case F::bc1_rgb: return 0x8C4C;
    case F::bc1_rgba: return 0x8C4D;
    case F::bc2: return 0x8C4E;
    case F::bc3: return 0x8C4F;
    case F::pvrtc1_rgb_2bpp: return 0x8A54;
    case F::pvrtc1_rgb_4bpp: return 0x8A55;
    case F::pvrtc1_rgba_2bpp: return 0x8A56;
    case F::pvrtc1_rgba_4bpp: return 0x8A57;
    default: break;
    }
    if (format_info(format).family == Fam::astc)
        return format_info(format).gl_internal_format - 0x93B0 + kSrgbAstc4x4;
    return 0;
}

bool context_samples_srgb(const Caps& caps, TextureFormat format) {
    const std::uint32_t gl = srgb_internal_format(caps, format);
    if (gl == 0) return false;
    const FormatInfo& f = format_info(format);
    if (!f.compressed()) return true;
    bool defined = false;
    switch (f.family) {
    case Fam::etc1:
    case Fam::etc2: defined = true; break;  // ES 3.0
    case Fam::astc: defined = caps.has("GL_KHR_texture_compression_astc_ldr"); break;
    case Fam::s3tc: defined = caps.has("GL_EXT_texture_compression_s3tc_srgb") || caps.has("GL_EXT_texture_sRGB"); break;
    case Fam::pvrtc: defined = caps.has("GL_EXT_pvrtc_sRGB"); break;
    default: break;
    }
    if (!defined) return false;
    if (caps.compressed_formats.empty()) return true;
    return std::find(caps.compressed_formats.begin(), caps.compressed_formats.end(), gl) !=
           caps.compressed_formats.end();
}

namespace {

std::vector<std::uint32_t> srgb_gl_codes() {
    std::vector<std::uint32_t> codes = {glenum::kSrgb8Etc2, glenum::kSrgb8A1Etc2, glenum::kSrgb8Alpha8Etc2Eac,
                                        0x8C43, 0x8C41, 0x8C4C, 0x8C4D, 0x8C4E, 0x8C4F, 0x8A54, 0x8A55, 0x8A56, 0x8A57};
    for (std::uint32_t i = 0; i < 14; ++i) codes.push_back(glenum::kSrgbAstc4x4 + i);
    return codes;
}

}  // namespace

std::uint32_t srgb_gl_of_linear(std::uint32_t linear_internal) {
    for (std::uint32_t code : srgb_gl_codes())
        if (linear_gl_of_srgb(code) == linear_internal) return code;
    return 0;
}

std::uint32_t srgb_vk_of_linear(std::uint32_t linear_vk) {
    if (linear_vk == 0) return 0;
    for (std::uint32_t code = 1; code <= 184; ++code)
        if (linear_vk_of_srgb(code) == linear_vk) return code;
    for (std::uint32_t code : {1000054004u, 1000054005u})
        if (linear_vk_of_srgb(code) == linear_vk) return code;
    return 0;
}

}  // namespace px
