// Texture containers (texture/containers.h): round trips through each writer
// and reader, and hostile files, each refused with a message naming the
// container and the field. Suites: Ktx1*, Ktx2*, Pvr*, TextureFile*.
#include <gtest/gtest.h>

#include <zstd.h>

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "parallaxes/core/files.h"
#include "parallaxes/texture/containers.h"

namespace {

using px::ContainerKind;
using px::Result;
using px::TextureData;
using px::TextureFormat;
using px::RowOrder;
using Bytes = std::vector<std::uint8_t>;

// A texture with every byte set from a position hash (or a repeating
// pattern when `compressible`), so a mislaid image shows.
TextureData make_texture(TextureFormat format, std::uint32_t w, std::uint32_t h, int levels = 0,
                         std::uint32_t layers = 1, std::uint32_t faces = 1, bool compressible = false) {
    if (levels == 0) levels = px::full_mip_count(w, h);
    Result<TextureData> t = px::allocate_texture(format, w, h, levels, layers, faces, px::kMaxTextureFileBytes);
    EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.error().message);
    if (!t) return TextureData{};
    std::uint32_t x = 0x12345678u;
    for (std::size_t i = 0; i < t->bytes.size(); ++i) {
        x = x * 1664525u + 1013904223u;
        t->bytes[i] = compressible ? static_cast<std::uint8_t>(i % 7) : static_cast<std::uint8_t>(x >> 24);
    }
    return std::move(t.value());
}

void expect_same(const TextureData& a, const TextureData& b) {
    EXPECT_EQ(a.format, b.format);
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.layers, b.layers);
    EXPECT_EQ(a.faces, b.faces);
    ASSERT_EQ(a.levels.size(), b.levels.size());
    for (std::size_t i = 0; i < a.levels.size(); ++i) {
        EXPECT_EQ(a.levels[i].width, b.levels[i].width) << i;
        EXPECT_EQ(a.levels[i].height, b.levels[i].height) << i;
        EXPECT_EQ(a.levels[i].image_bytes, b.levels[i].image_bytes) << i;
        EXPECT_EQ(a.levels[i].offset, b.levels[i].offset) << i;
    }
    EXPECT_TRUE(a.bytes == b.bytes);
}

::testing::AssertionResult fails_with(const Result<TextureData>& r, const std::string& needle) {
    if (r.ok()) return ::testing::AssertionFailure() << "read succeeded; expected an error with \"" << needle << "\"";
    if (r.error().message.find(needle) == std::string::npos)
        return ::testing::AssertionFailure() << "\"" << r.error().message << "\" lacks \"" << needle << "\"";
    return ::testing::AssertionSuccess();
}

std::uint32_t get32(const Bytes& b, std::size_t at) {
    return static_cast<std::uint32_t>(b[at]) | static_cast<std::uint32_t>(b[at + 1]) << 8 |
           static_cast<std::uint32_t>(b[at + 2]) << 16 | static_cast<std::uint32_t>(b[at + 3]) << 24;
}
std::uint64_t get64(const Bytes& b, std::size_t at) {
    return get32(b, at) | static_cast<std::uint64_t>(get32(b, at + 4)) << 32;
}
Bytes patch32(Bytes b, std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
    return b;
}
Bytes patch64(Bytes b, std::size_t at, std::uint64_t v) {
    b = patch32(std::move(b), at, static_cast<std::uint32_t>(v));
    return patch32(std::move(b), at + 4, static_cast<std::uint32_t>(v >> 32));
}

Bytes ktx1(const TextureData& t) {
    auto r = px::write_ktx1(t);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? r.value() : Bytes{};
}
Bytes ktx2(const TextureData& t, int zstd = 0) {
    auto r = px::write_ktx2(t, zstd);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? r.value() : Bytes{};
}
Bytes pvr(const TextureData& t) {
    auto r = px::write_pvr3(t);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? r.value() : Bytes{};
}
Result<TextureData> rd1(const Bytes& b, std::uint64_t max = px::kMaxTextureFileBytes) {
    return px::read_ktx1(b.data(), b.size(), max);
}
Result<TextureData> rd2(const Bytes& b, std::uint64_t max = px::kMaxTextureFileBytes) {
    return px::read_ktx2(b.data(), b.size(), max);
}
Result<TextureData> rdp(const Bytes& b, std::uint64_t max = px::kMaxTextureFileBytes) {
    return px::read_pvr3(b.data(), b.size(), max);
}

bool contains(const Bytes& b, const std::string& s) {
    return std::search(b.begin(), b.end(), s.begin(), s.end()) != b.end();
}

// Every proper prefix is refused (never a crash or a read past the end);
// the whole file reads.
template <typename Reader>
void every_prefix_refused(const Bytes& file, Reader read) {
    for (std::size_t n = 0; n < file.size(); ++n) {
        const Bytes prefix(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(n));
        const Result<TextureData> r = read(prefix.data(), prefix.size());
        EXPECT_FALSE(r.ok()) << "a " << n << "-byte prefix of a " << file.size() << "-byte file was read";
    }
    EXPECT_TRUE(read(file.data(), file.size()).ok());
}

const TextureFormat kRoundTripFormats[] = {TextureFormat::rgba8,     TextureFormat::r8,
                                           TextureFormat::rgb8,      TextureFormat::rg8,
                                           TextureFormat::etc2_rgb8, TextureFormat::eac_r11,
                                           TextureFormat::astc_6x6,  TextureFormat::pvrtc1_rgb_4bpp,
                                           TextureFormat::bc5,       TextureFormat::etc2_rgba8};

// ------------------------------------------------------------ round trips

TEST(Ktx1RoundTrip, FormatsWithFullChainsOfNonPowerOfTwoSizes) {
    for (TextureFormat f : kRoundTripFormats) {
        SCOPED_TRACE(px::format_name(f));
        const TextureData t = make_texture(f, 37, 20);
        ASSERT_EQ(t.levels.size(), 6u);
        const Bytes file = ktx1(t);
        Result<TextureData> back = rd1(file);
        ASSERT_TRUE(back.ok()) << back.error().message;
        EXPECT_EQ(back->container, ContainerKind::ktx1);
        EXPECT_TRUE(back->supercompression.empty());
        expect_same(t, *back);
        EXPECT_TRUE(ktx1(*back) == file);
        EXPECT_TRUE(contains(file, std::string("KTXorientation\0S=r,T=d", 22)));
        EXPECT_EQ(back->rows, RowOrder::top_first);
    }
}

TEST(Ktx1RoundTrip, UncompressedRowsArePaddedToFourBytesInTheFile) {
    const TextureData t = make_texture(TextureFormat::rgb8, 5, 3, 1);
    const Bytes file = ktx1(t);
    // 64-byte header, 28 bytes of key/value data, then imageSize.
    EXPECT_EQ(get32(file, 92), 16u * 3u);
    EXPECT_EQ(file.size(), 96u + 48u);
    Result<TextureData> back = rd1(file);
    ASSERT_TRUE(back.ok()) << back.error().message;
    expect_same(t, *back);
}

TEST(Ktx1RoundTrip, ArraysCubeMapsAndCubeArrays) {
    struct Case {
        TextureFormat f;
        std::uint32_t w, h, layers, faces;
    } cases[] = {{TextureFormat::rgba8, 37, 20, 3, 1},
                 {TextureFormat::etc2_rgb8, 37, 20, 4, 1},
                 {TextureFormat::r8, 16, 16, 1, 6},
                 {TextureFormat::bc5, 16, 16, 1, 6},
                 {TextureFormat::astc_6x6, 8, 8, 2, 6}};
    for (const Case& c : cases) {
        SCOPED_TRACE(std::string(px::format_name(c.f)) + " " + std::to_string(c.layers) + "x" + std::to_string(c.faces));
        const TextureData t = make_texture(c.f, c.w, c.h, 0, c.layers, c.faces);
        const Bytes file = ktx1(t);
        Result<TextureData> back = rd1(file);
        ASSERT_TRUE(back.ok()) << back.error().message;
        expect_same(t, *back);
        EXPECT_TRUE(ktx1(*back) == file);
    }
    // A non-array cube map's imageSize is one face's.
    const TextureData cube = make_texture(TextureFormat::bc5, 16, 16, 1, 1, 6);
    EXPECT_EQ(get32(ktx1(cube), 92), 4u * 4u * 16u);
}

TEST(Ktx1RoundTrip, ReadsAnUnsizedEs2FormatWithoutKeyValues) {
    // Built by hand: GL_RGBA / GL_RGBA / GL_UNSIGNED_BYTE, 2x1, one level.
    Bytes f = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31, 0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
    const std::uint32_t header[13] = {0x04030201, 0x1401, 1, 0x1908, 0x1908, 0x1908, 2, 1, 0, 0, 1, 1, 0};
    for (std::uint32_t v : header)
        for (int i = 0; i < 4; ++i) f.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    f.resize(f.size() + 4, 0);
    f = patch32(f, 64, 8);
    for (std::uint8_t i = 0; i < 8; ++i) f.push_back(i);
    Result<TextureData> t = rd1(f);
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_EQ(t->format, TextureFormat::rgba8);
    EXPECT_EQ(t->bytes, (Bytes{0, 1, 2, 3, 4, 5, 6, 7}));
}

TEST(Ktx2RoundTrip, FormatsWithFullChainsOfNonPowerOfTwoSizes) {
    for (TextureFormat f : kRoundTripFormats) {
        if (f == TextureFormat::pvrtc1_rgb_4bpp) continue;  // no vkFormat (below)
        SCOPED_TRACE(px::format_name(f));
        const TextureData t = make_texture(f, 37, 20);
        const Bytes file = ktx2(t);
        Result<TextureData> back = rd2(file);
        ASSERT_TRUE(back.ok()) << back.error().message;
        EXPECT_EQ(back->container, ContainerKind::ktx2);
        EXPECT_EQ(back->supercompression, "none");
        expect_same(t, *back);
        EXPECT_TRUE(ktx2(*back) == file);
        EXPECT_TRUE(contains(file, std::string("KTXorientation\0rd", 17)));
        EXPECT_EQ(back->rows, RowOrder::top_first);
        // Levels are stored smallest first, each aligned to lcm(block bytes, 4).
        const std::size_t n = t.levels.size();
        EXPECT_LT(get64(file, 80 + 24 * (n - 1)), get64(file, 80));
        const std::uint64_t b = static_cast<std::uint64_t>(px::format_info(f).block_bytes);
        for (std::size_t i = 0; i < n; ++i) {
            EXPECT_EQ(get64(file, 80 + 24 * i) % b, 0u);
            EXPECT_EQ(get64(file, 80 + 24 * i) % 4, 0u);
        }
    }
    const TextureData pvrtc = make_texture(TextureFormat::pvrtc1_rgb_4bpp, 16, 16);
    auto refused = px::write_ktx2(pvrtc);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("vkFormat"), std::string::npos);
    const TextureData pvrtc_rgba = make_texture(TextureFormat::pvrtc1_rgba_4bpp, 37, 20);
    Result<TextureData> back = rd2(ktx2(pvrtc_rgba));
    ASSERT_TRUE(back.ok()) << back.error().message;
    expect_same(pvrtc_rgba, *back);
}

TEST(Ktx2RoundTrip, ArraysCubeMapsAndZstd) {
    struct Case {
        TextureFormat f;
        std::uint32_t w, h, layers, faces;
        int zstd;
    } cases[] = {{TextureFormat::rgba8, 37, 20, 3, 1, 0},  {TextureFormat::eac_r11, 37, 20, 2, 1, 3},
                 {TextureFormat::rgba8, 16, 16, 1, 6, 0},  {TextureFormat::astc_6x6, 37, 20, 1, 1, 1},
                 {TextureFormat::bc5, 32, 32, 2, 6, 19},   {TextureFormat::r8, 37, 20, 1, 1, 22}};
    for (const Case& c : cases) {
        SCOPED_TRACE(std::string(px::format_name(c.f)) + " zstd " + std::to_string(c.zstd));
        const TextureData t = make_texture(c.f, c.w, c.h, 0, c.layers, c.faces, c.zstd > 0);
        const Bytes file = ktx2(t, c.zstd);
        Result<TextureData> back = rd2(file);
        ASSERT_TRUE(back.ok()) << back.error().message;
        EXPECT_EQ(back->supercompression, c.zstd ? "zstd" : "none");
        expect_same(t, *back);
        EXPECT_TRUE(ktx2(*back, c.zstd) == file);
        if (c.zstd) {
            EXPECT_LT(file.size(), t.bytes.size());
        }
    }
    auto bad_level = px::write_ktx2(make_texture(TextureFormat::r8, 4, 4), 23);
    ASSERT_FALSE(bad_level.ok());
    EXPECT_NE(bad_level.error().message.find("Zstandard level 23"), std::string::npos);
}

TEST(Ktx2RoundTrip, WritesABasicDataFormatDescriptor) {
    const Bytes file = ktx2(make_texture(TextureFormat::astc_6x6, 12, 12));
    const std::size_t dfd = get32(file, 48);
    EXPECT_EQ(get32(file, 52), 4u + 24u + 16u);
    EXPECT_EQ(get32(file, dfd), get32(file, 52));       // dfdTotalSize
    EXPECT_EQ(get32(file, dfd + 8) >> 16, 24u + 16u);  // descriptorBlockSize
    EXPECT_EQ(get32(file, dfd + 12) & 0xFF, 162u);     // KHR_DF_MODEL_ASTC
    EXPECT_EQ(get32(file, dfd + 16) & 0xFFFF, 0x0505u);  // 6x6 texel blocks
    EXPECT_EQ(get32(file, dfd + 20), 16u);              // bytesPlane0
    const Bytes rgba = ktx2(make_texture(TextureFormat::rgba8, 4, 4));
    EXPECT_EQ(get32(rgba, 52), 4u + 24u + 4u * 16u);
    const Bytes packed = ktx2(make_texture(TextureFormat::rgba8, 4, 4), 5);
    EXPECT_EQ(get32(packed, get32(packed, 48) + 20), 0u);  // supercompressed: bytesPlane0 0
}

TEST(PvrRoundTrip, FormatsArraysAndCubeMaps) {
    for (TextureFormat f : kRoundTripFormats) {
        SCOPED_TRACE(px::format_name(f));
        const TextureData t = make_texture(f, 37, 20);
        const Bytes file = pvr(t);
        EXPECT_EQ(file.size(), 52 + 15 + t.bytes.size());  // the orientation metadata block
        Result<TextureData> back = rdp(file);
        ASSERT_TRUE(back.ok()) << back.error().message;
        EXPECT_EQ(back->container, ContainerKind::pvr3);
        expect_same(t, *back);
        EXPECT_TRUE(pvr(*back) == file);
    }
    for (const TextureData& t : {make_texture(TextureFormat::rgba8, 37, 20, 0, 3, 1),
                                 make_texture(TextureFormat::etc2_rgb8, 16, 16, 0, 1, 6),
                                 make_texture(TextureFormat::pvrtc1_rgb_4bpp, 8, 8, 0, 2, 6)}) {
        Result<TextureData> back = rdp(pvr(t));
        ASSERT_TRUE(back.ok()) << back.error().message;
        expect_same(t, *back);
    }
    auto refused = px::write_pvr3(make_texture(TextureFormat::bc1_rgba, 4, 4));
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("PVR v3 pixel format"), std::string::npos);
}

TEST(PvrRoundTrip, SkipsMetadata) {
    const TextureData t = make_texture(TextureFormat::bc5, 8, 8);
    Bytes file = pvr(t);
    const Bytes meta = {'P', 'V', 'R', 3, 1, 0, 0, 0, 4, 0, 0, 0, 9, 9, 9, 9};
    file.insert(file.begin() + 52, meta.begin(), meta.end());
    file = patch32(file, 48, static_cast<std::uint32_t>(meta.size() + 15));
    Result<TextureData> back = rdp(file);
    ASSERT_TRUE(back.ok()) << back.error().message;
    expect_same(t, *back);
}

// ------------------------------------------------------------ orientation

// A key/value block of one pair, as KTX 1.1 and 2.0 lay it out.
Bytes one_key_value(const std::string& key, const std::string& value) {
    Bytes kv;
    const std::uint32_t n = static_cast<std::uint32_t>(key.size() + 1 + value.size() + 1);
    for (int i = 0; i < 4; ++i) kv.push_back(static_cast<std::uint8_t>(n >> (8 * i)));
    kv.insert(kv.end(), key.begin(), key.end());
    kv.push_back(0);
    kv.insert(kv.end(), value.begin(), value.end());
    kv.push_back(0);
    while (kv.size() % 4) kv.push_back(0);
    return kv;
}

// The KTX 1.1 file of `t` with its key/value data replaced by `kv`.
Bytes ktx1_with_key_values(const TextureData& t, const Bytes& kv) {
    Bytes file = ktx1(t);
    const std::uint32_t old = get32(file, 60);
    file.erase(file.begin() + 64, file.begin() + 64 + old);
    file.insert(file.begin() + 64, kv.begin(), kv.end());
    return patch32(file, 60, static_cast<std::uint32_t>(kv.size()));
}

TEST(Orientation, WritersDeclareTheRowOrderAndReadersReadItBack) {
    for (RowOrder rows : {RowOrder::top_first, RowOrder::bottom_first}) {
        TextureData t = make_texture(TextureFormat::etc2_rgb8, 16, 8);
        t.rows = rows;
        const bool top = rows == RowOrder::top_first;
        const Bytes k1 = ktx1(t), k2 = ktx2(t), p = pvr(t);
        EXPECT_TRUE(contains(k1, std::string("KTXorientation\0S=r,T=", 21) + (top ? "d" : "u")));
        EXPECT_TRUE(contains(k2, std::string("KTXorientation\0r", 16) + (top ? "d" : "u")));
        EXPECT_EQ(p[52 + 12 + 1], top ? 0 : 2);  // PVR v3 orientation metadata: y down (0) or up
        for (const Result<TextureData>& back : {rd1(k1), rd2(k2), rdp(p)}) {
            ASSERT_TRUE(back.ok()) << back.error().message;
            EXPECT_EQ(back->rows, rows) << back->rows_source;
        }
    }
}

TEST(Orientation, KeysAsTheToolsSpellThemAndTheDefaults) {
    const TextureData t = make_texture(TextureFormat::etc2_rgb8, 8, 8, 1);
    // PVRTexToolCLI 4.17 writes "KTXOrientation" with a capital O, and an R= part.
    Result<TextureData> ptt = rd1(ktx1_with_key_values(t, one_key_value("KTXOrientation", "S=r,T=u,R=i")));
    ASSERT_TRUE(ptt.ok()) << ptt.error().message;
    EXPECT_EQ(ptt->rows, RowOrder::bottom_first);
    EXPECT_NE(ptt->rows_source.find("KTXOrientation \"S=r,T=u,R=i\""), std::string::npos) << ptt->rows_source;
    // No key (astcenc, basisu): top row first, and the source says why.
    Result<TextureData> none = rd1(ktx1_with_key_values(t, {}));
    ASSERT_TRUE(none.ok()) << none.error().message;
    EXPECT_EQ(none->rows, RowOrder::top_first);
    EXPECT_NE(none->rows_source.find("no KTXorientation"), std::string::npos) << none->rows_source;
    // Other keys leave the default alone.
    Result<TextureData> other = rd1(ktx1_with_key_values(t, one_key_value("KTXwriter", "S=r,T=u")));
    ASSERT_TRUE(other.ok());
    EXPECT_EQ(other->rows, RowOrder::top_first);
    // A value that says nothing usable is refused by name.
    EXPECT_TRUE(fails_with(rd1(ktx1_with_key_values(t, one_key_value("KTXorientation", "S=r,T=x"))),
                           "KTXorientation \"S=r,T=x\""));
    // PVR v3 without metadata: top row first (PVRTexTool's default).
    Bytes p = pvr(t);
    p.erase(p.begin() + 52, p.begin() + 52 + 15);
    p = patch32(p, 48, 0);
    Result<TextureData> bare = rdp(p);
    ASSERT_TRUE(bare.ok()) << bare.error().message;
    EXPECT_EQ(bare->rows, RowOrder::top_first);
    EXPECT_NE(bare->rows_source.find("no PVR v3 orientation"), std::string::npos);
    // A metadata block whose dataSize passes the metadata's end is refused.
    Bytes bad = pvr(t);
    bad = patch32(bad, 52 + 8, 1000);
    EXPECT_TRUE(fails_with(rdp(bad), "dataSize 1000"));
}

// ------------------------------------------------------------ .astc

Bytes astc_file(int bx, int by, std::uint32_t w, std::uint32_t h, std::size_t block_count) {
    Bytes f = {0x13, 0xAB, 0xA1, 0x5C, static_cast<std::uint8_t>(bx), static_cast<std::uint8_t>(by), 1};
    for (std::uint32_t v : {w, h, 1u})
        for (int i = 0; i < 3; ++i) f.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    f.resize(f.size() + 16 * block_count, 0x5A);
    return f;
}

TEST(AstcFile, ReadsAstcencsContainerAndRefusesWhatDoesNotFit) {
    Result<TextureData> t = px::read_texture(astc_file(6, 6, 64, 40, 11 * 7).data(), 16 + 16 * 77);
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_EQ(t->container, ContainerKind::astc);
    EXPECT_EQ(t->format, TextureFormat::astc_6x6);
    EXPECT_EQ(t->width, 64u);
    EXPECT_EQ(t->height, 40u);
    EXPECT_EQ(t->levels.size(), 1u);
    EXPECT_EQ(t->rows, RowOrder::top_first);
    const Bytes short_file = astc_file(6, 6, 64, 40, 76);
    EXPECT_TRUE(fails_with(px::read_astc(short_file.data(), short_file.size()), "takes 1232 bytes"));
    const Bytes odd_block = astc_file(7, 7, 64, 64, 100);
    EXPECT_TRUE(fails_with(px::read_astc(odd_block.data(), odd_block.size()), "block size 7x7"));
    const Bytes volume = {0x13, 0xAB, 0xA1, 0x5C, 4, 4, 4, 4, 0, 0, 4, 0, 0, 4, 0, 0};
    EXPECT_TRUE(fails_with(px::read_astc(volume.data(), volume.size()), "3D texture"));
    const Bytes huge = astc_file(4, 4, 0xFFFFFF, 4, 0);
    EXPECT_TRUE(fails_with(px::read_astc(huge.data(), huge.size()), "width 16777215"));
    EXPECT_TRUE(fails_with(px::read_astc(huge.data(), 10), "shorter than its 16-byte header"));
}

TEST(Ktx1RoundTrip, WritersRefuseAnInconsistentTexture) {
    TextureData t = make_texture(TextureFormat::rgba8, 8, 8);
    t.bytes.pop_back();
    for (const auto& r : {px::write_ktx1(t), px::write_ktx2(t), px::write_pvr3(t)}) {
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().message.find("writer"), std::string::npos) << r.error().message;
    }
    TextureData none;
    EXPECT_FALSE(px::write_ktx1(none).ok());
}

// --------------------------------------------------------------- KTX 1.1

const Bytes& small_ktx1() {
    static const Bytes file = ktx1(make_texture(TextureFormat::rgb8, 5, 3));
    return file;
}

TEST(Ktx1Hostile, EveryPrefixIsRefused) {
    const auto read = [](const std::uint8_t* p, std::size_t n) { return px::read_ktx1(p, n); };
    every_prefix_refused(small_ktx1(), read);
    every_prefix_refused(ktx1(make_texture(TextureFormat::etc2_rgb8, 9, 5, 0, 1, 1)), read);
    every_prefix_refused(ktx1(make_texture(TextureFormat::r8, 4, 4, 0, 1, 6)), read);
}

TEST(Ktx1Hostile, IdentifierAndEndianness) {
    Bytes f = small_ktx1();
    f[5] = '2';
    EXPECT_TRUE(fails_with(rd1(f), "KTX 1.1 identifier"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 12, 0x01020304)), "big-endian"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 12, 0x11223344)), "endianness 0x11223344"));
}

TEST(Ktx1Hostile, FormatCodes) {
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 28, 0x1234)), "KTX 1.1 glInternalFormat 0x1234"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 16, 0x1406)), "glType 0x1406"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 20, 4)), "glTypeSize 4"));
    const Bytes etc = ktx1(make_texture(TextureFormat::etc2_rgb8, 8, 8));
    // An sRGB code is the linear format of the same bits, declared sRGB; it
    // writes back as the same code. BC7's sRGB form stays unsupported.
    Result<TextureData> srgb = rd1(patch32(etc, 28, 0x9275));
    ASSERT_TRUE(srgb.ok()) << srgb.error().message;
    EXPECT_TRUE(srgb->srgb);
    EXPECT_EQ(srgb->format, TextureFormat::etc2_rgb8);
    EXPECT_NE(srgb->color_space_source.find("GL_COMPRESSED_SRGB8_ETC2"), std::string::npos) << srgb->color_space_source;
    Result<std::vector<std::uint8_t>> again = write_ktx1(*srgb);
    ASSERT_TRUE(again.ok());
    Result<TextureData> back = rd1(*again);
    ASSERT_TRUE(back.ok());
    EXPECT_TRUE(back->srgb);
    EXPECT_FALSE(rd1(etc)->srgb);
    EXPECT_TRUE(fails_with(rd1(patch32(etc, 28, 0x8E8D)), "BC7 sRGB"));
    EXPECT_TRUE(fails_with(rd1(patch32(etc, 16, 0x1401)), "glType 0x1401 with the compressed"));
    EXPECT_TRUE(fails_with(rd1(patch32(etc, 24, 0x1908)), "glFormat 0x1908 with the compressed"));
}

TEST(Ktx1Hostile, Extents) {
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 36, 0)), "KTX 1.1 pixelWidth 0"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 36, 0xFFFFFFFF)), "pixelWidth 4294967295"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 40, 0)), "pixelHeight 0"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 40, 0xFFFFFFFF)), "pixelHeight 4294967295"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 44, 2)), "pixelDepth 2"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 48, 0xFFFFFFFF)), "numberOfArrayElements 4294967295"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 52, 3)), "numberOfFaces 3"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 52, 6)), "must be square"));
    // A large size that the file does not hold: the level walk refuses it.
    EXPECT_TRUE(fails_with(rd1(patch32(patch32(small_ktx1(), 36, 4096), 40, 4096)), "imageSize"));
}

TEST(Ktx1Hostile, LevelCounts) {
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 56, 0)), "numberOfMipmapLevels 0 asks for the mip chain"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 56, 4)), "numberOfMipmapLevels 4 is more than the 3 levels"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 56, 0xFFFFFFFF)), "numberOfMipmapLevels 4294967295"));
    // Fewer levels than the file holds: the rest is trailing data.
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 56, 2)), "after the last level"));
}

TEST(Ktx1Hostile, LyingImageSizes) {
    const std::uint32_t size0 = get32(small_ktx1(), 92);
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 92, size0 + 4)), "level [0] (5x3 rgb8) imageSize 52"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 92, size0 - 3)), "does not match the 48 bytes"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 92, 0xFFFFFFFF)), "imageSize 4294967295"));
    const std::size_t level1 = 92 + 4 + size0;
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), level1, 0)), "level [1] (2x1 rgb8) imageSize 0"));
    Bytes longer = small_ktx1();
    longer.push_back(0);
    EXPECT_TRUE(fails_with(rd1(longer), "1 bytes after the last level"));
}

TEST(Ktx1Hostile, KeyValueData) {
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 60, 0xFFFFFFF0)), "bytesOfKeyValueData 4294967280 passes the end"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 64, 1000)), "keyAndValueByteSize 1000 passes the end"));
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 64, 0xFFFFFFFF)), "keyAndValueByteSize 4294967295"));
    Bytes no_nul = small_ktx1();
    for (std::size_t i = 68; i < 92; ++i) no_nul[i] = 'x';
    EXPECT_TRUE(fails_with(rd1(no_nul), "no NUL"));
    // A shorter block than its pairs: the pair's size passes the block end.
    EXPECT_TRUE(fails_with(rd1(patch32(small_ktx1(), 60, 8)), "keyAndValueByteSize 23"));
}

TEST(Ktx1Hostile, MaxBytes) {
    EXPECT_TRUE(fails_with(rd1(small_ktx1(), 40), "more than the 40 allowed"));
    EXPECT_TRUE(rd1(small_ktx1(), 45 + 6 + 3).ok());
}

// --------------------------------------------------------------- KTX 2.0

const Bytes& small_ktx2() {
    static const Bytes file = ktx2(make_texture(TextureFormat::rgba8, 5, 3));
    return file;
}
const Bytes& small_zstd_ktx2() {
    static const Bytes file = ktx2(make_texture(TextureFormat::bc5, 9, 8, 0, 1, 1, true), 3);
    return file;
}

TEST(Ktx2Hostile, EveryPrefixIsRefused) {
    const auto read = [](const std::uint8_t* p, std::size_t n) { return px::read_ktx2(p, n); };
    every_prefix_refused(small_ktx2(), read);
    every_prefix_refused(small_zstd_ktx2(), read);
    every_prefix_refused(ktx2(make_texture(TextureFormat::astc_6x6, 7, 7, 0, 2, 6)), read);
}

TEST(Ktx2Hostile, HeaderFields) {
    Bytes f = small_ktx2();
    f[6] = '1';
    EXPECT_TRUE(fails_with(rd2(f), "KTX 2.0 identifier"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 12, 0)), "KTX 2.0 vkFormat 0"));
    // VK_FORMAT_R8G8B8A8_SRGB: RGBA8, declared sRGB (the small file is RGBA8).
    Result<TextureData> srgb = rd2(patch32(small_ktx2(), 12, 43));
    ASSERT_TRUE(srgb.ok()) << srgb.error().message;
    EXPECT_TRUE(srgb->srgb);
    EXPECT_EQ(srgb->format, TextureFormat::rgba8);
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 12, 1000054006u)), "PVRTC2 sRGB"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 12, 123456)), "vkFormat 123456"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 16, 4)), "typeSize 4"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 20, 0)), "pixelWidth 0"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 20, 0xFFFFFFFF)), "pixelWidth 4294967295"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 24, 0)), "pixelHeight 0"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 24, 0xFFFFFFFF)), "pixelHeight 4294967295"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 28, 16)), "pixelDepth 16: a 3D texture"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 32, 0xFFFFFFFF)), "layerCount 4294967295"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 36, 2)), "faceCount 2"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 40, 0)), "levelCount 0 asks"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 40, 4)), "levelCount 4 is more than the 3 levels"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 44, 1)), "supercompressionScheme 1 (BasisLZ)"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 44, 3)), "supercompressionScheme 3 (ZLIB)"));
    EXPECT_TRUE(fails_with(rd2(patch32(small_ktx2(), 44, 9)), "supercompressionScheme 9 is not a known"));
    // Big sizes with the file's level index: the lengths no longer match.
    EXPECT_TRUE(fails_with(rd2(patch32(patch32(small_ktx2(), 20, 4096), 24, 4096)), "level index [0]"));
}

TEST(Ktx2Hostile, IndexOffsets) {
    const Bytes& f = small_ktx2();
    const std::string end = "passes the end of the " + std::to_string(f.size()) + "-byte file";
    EXPECT_TRUE(fails_with(rd2(patch32(f, 48, 0xFFFFFFF0)), "dfdByteOffset 4294967280 + dfdByteLength"));
    EXPECT_TRUE(fails_with(rd2(patch32(f, 52, 0xFFFFFFFF)), end));
    EXPECT_TRUE(fails_with(rd2(patch32(f, 52, 2)), "dfdByteLength 2"));
    EXPECT_TRUE(fails_with(rd2(patch32(f, get32(f, 48), 999)), "dfdTotalSize 999"));
    EXPECT_TRUE(fails_with(rd2(patch32(f, 56, static_cast<std::uint32_t>(f.size()))), "kvdByteOffset"));
    EXPECT_TRUE(fails_with(rd2(patch32(f, 60, 0xFFFFFFFF)), "kvdByteLength 4294967295 " + end));
    EXPECT_TRUE(fails_with(rd2(patch32(f, get32(f, 56), 500)), "keyAndValueByteSize 500 passes the end"));
    EXPECT_TRUE(fails_with(rd2(patch64(f, 64, 0xFFFFFFFFFFFFFFF0ull)), "sgdByteOffset"));
    EXPECT_TRUE(fails_with(rd2(patch64(patch64(f, 64, 8), 72, 0xFFFFFFFFFFFFFFFFull)), "sgdByteLength"));
}

TEST(Ktx2Hostile, LevelIndex) {
    const Bytes& f = small_ktx2();
    const std::string file = std::to_string(f.size()) + "-byte file";
    // Level 2 (1x1 rgba8, 4 bytes) moved past the end.
    EXPECT_TRUE(fails_with(rd2(patch64(f, 80 + 48, f.size() - 2)),
                           "KTX 2.0 level index [2].byteOffset " + std::to_string(f.size() - 2) +
                               " + byteLength 4 passes the end of the " + file));
    EXPECT_TRUE(fails_with(rd2(patch64(f, 80, 0xFFFFFFFFFFFFFFFCull)), "level index [0].byteOffset"));
    EXPECT_TRUE(fails_with(rd2(patch64(f, 88, 0xFFFFFFFFFFFFFFFFull)), "level index [0].byteOffset"));
    EXPECT_TRUE(fails_with(rd2(patch64(patch64(f, 104, 0), 112, 0)), "level index [1].byteLength 0 does not match the 8"));
    EXPECT_TRUE(fails_with(rd2(patch64(f, 88, 56)), "level index [0].byteLength 56 does not match the 60 bytes"));
    EXPECT_TRUE(fails_with(rd2(patch64(f, 96, 64)), "level index [0].uncompressedByteLength 64 differs"));
    // The level index itself past the end: many levels in a short file.
    Bytes big = patch32(patch32(patch32(Bytes(f.begin(), f.begin() + 120), 20, 4096), 24, 4096), 40, 13);
    EXPECT_TRUE(fails_with(rd2(big), "level index of 13 entries"));
}

TEST(Ktx2Hostile, ZstdLevels) {
    const Bytes& f = small_zstd_ktx2();
    ASSERT_TRUE(rd2(f).ok());
    const std::uint64_t u0 = get64(f, 96);
    EXPECT_EQ(u0, 3u * 2u * 16u);
    EXPECT_TRUE(fails_with(rd2(patch64(f, 96, u0 + 16)), "level index [0].uncompressedByteLength 112 does not match the 96"));
    EXPECT_TRUE(fails_with(rd2(patch64(f, 96, 0xFFFFFFFFFFFFFFFFull)), "uncompressedByteLength"));
    // Garbage where level 0's payload is.
    Bytes garbage = f;
    for (std::uint64_t i = 0; i < get64(f, 88); ++i) garbage[get64(f, 80) + i] = 0xA5;
    EXPECT_TRUE(fails_with(rd2(garbage), "KTX 2.0 level [0] Zstandard data"));
    // A valid frame of the wrong size (a short one, then a long one) appended
    // and pointed at.
    for (std::size_t n : {std::size_t{40}, std::size_t{200}}) {
        const Bytes raw(n, 7);
        Bytes packed(ZSTD_compressBound(n));
        packed.resize(ZSTD_compress(packed.data(), packed.size(), raw.data(), n, 1));
        Bytes g = f;
        const std::uint64_t at = g.size();
        g.insert(g.end(), packed.begin(), packed.end());
        g = patch64(patch64(g, 80, at), 88, packed.size());
        EXPECT_TRUE(fails_with(rd2(g), "level [0] Zstandard data")) << n;
    }
}

TEST(Ktx2Hostile, MaxBytes) {
    EXPECT_TRUE(fails_with(rd2(small_zstd_ktx2(), 100), "more than the 100 allowed"));
    EXPECT_TRUE(fails_with(rd2(small_ktx2(), 10), "allowed"));
}

// ----------------------------------------------------------------- PVR v3

const Bytes& small_pvr() {
    static const Bytes file = pvr(make_texture(TextureFormat::etc2_rgb8, 9, 5));
    return file;
}

TEST(PvrHostile, EveryPrefixIsRefused) {
    const auto read = [](const std::uint8_t* p, std::size_t n) { return px::read_pvr3(p, n); };
    every_prefix_refused(small_pvr(), read);
    every_prefix_refused(pvr(make_texture(TextureFormat::rgb8, 3, 2, 0, 2, 1)), read);
}

TEST(PvrHostile, HeaderFields) {
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 0, 0x50565203)), "PVR v3 version 0x50565203: the file was written in the other"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 0, 0x02525650)), "version 0x2525650"));
    Result<TextureData> srgb = rdp(patch32(small_pvr(), 16, 1));  // colour space 1: sRGB colour
    ASSERT_TRUE(srgb.ok()) << srgb.error().message;
    EXPECT_TRUE(srgb->srgb);
    EXPECT_EQ(srgb->color_space_source, "PVR v3 colour space 1 (sRGB)");
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 16, 7)), "colour space 7"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 8, 4)), "PVRTC-II"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 8, 200)), "pixel format 200"));
    // The format table's "no PVR code" marker is no pixel format (a fuzz finding).
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 8, 0xFFFFFFFF)), "pixel format 4294967295"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 12, 0x10101010)), "uncompressed pixel format"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 24, 0)), "height 0"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 24, 0xFFFFFFFF)), "height 4294967295"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 28, 0)), "width 0"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 28, 0xFFFFFFFF)), "width 4294967295"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 32, 2)), "depth 2: a 3D texture"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 36, 0)), "numSurfaces 0"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 36, 0xFFFFFFFF)), "numSurfaces 4294967295"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 40, 2)), "numFaces 2"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 44, 0)), "MIPMapCount 0"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 44, 5)), "MIPMapCount 5 is more than the 4 levels"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 44, 3)), "bytes after the last MIP level"));
    EXPECT_TRUE(fails_with(rdp(patch32(patch32(small_pvr(), 24, 4096), 28, 4096)), "MIP level [0] (4096x4096"));
}

TEST(PvrHostile, MetadataAndData) {
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 48, 0xFFFFFFFF)), "PVR v3 metaDataSize 4294967295 passes the end"));
    const std::uint32_t size = static_cast<std::uint32_t>(small_pvr().size());
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 48, size - 52 + 1)), "metaDataSize"));
    EXPECT_TRUE(fails_with(rdp(patch32(small_pvr(), 48, 8)), "passes the end of the"));
    Bytes longer = small_pvr();
    longer.push_back(1);
    EXPECT_TRUE(fails_with(rdp(longer), "1 bytes after the last MIP level"));
    EXPECT_TRUE(fails_with(rdp(small_pvr(), 32), "more than the 32 allowed"));
}

// ------------------------------------------------------ dispatch and files

TEST(TextureFile, SniffsEachContainer) {
    EXPECT_EQ(px::sniff_container(small_ktx1().data(), small_ktx1().size()), ContainerKind::ktx1);
    EXPECT_EQ(px::sniff_container(small_ktx2().data(), small_ktx2().size()), ContainerKind::ktx2);
    EXPECT_EQ(px::sniff_container(small_pvr().data(), small_pvr().size()), ContainerKind::pvr3);
    const Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n', 0, 0, 0, 13};
    EXPECT_EQ(px::sniff_container(png.data(), png.size()), ContainerKind::image);
    EXPECT_EQ(px::sniff_container(small_ktx1().data(), 11), ContainerKind::image);
    EXPECT_EQ(px::sniff_container(nullptr, 0), ContainerKind::image);
}

TEST(TextureFile, ReadsByIdentifier) {
    for (const Bytes* f : {&small_ktx1(), &small_ktx2(), &small_pvr()}) {
        Result<TextureData> t = px::read_texture(f->data(), f->size());
        ASSERT_TRUE(t.ok()) << t.error().message;
        EXPECT_EQ(t->container, px::sniff_container(f->data(), f->size()));
    }
    // The other byte order of PVR is read far enough to be named.
    const Bytes swapped = patch32(small_pvr(), 0, 0x50565203);
    EXPECT_TRUE(fails_with(px::read_texture(swapped.data(), swapped.size()), "other (big-endian) byte order"));
    const Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n', 0, 0, 0, 13, 'I', 'H'};
    const Result<TextureData> r = px::read_texture(png.data(), png.size());
    EXPECT_TRUE(fails_with(r, "starts with 89 50 4E 47 0D 0A 1A 0A 00 00 00 0D"));
    EXPECT_TRUE(fails_with(r, "a PNG image"));
    EXPECT_TRUE(fails_with(r, "KTX 1.1"));
    EXPECT_TRUE(fails_with(r, "PVR v3"));
    EXPECT_TRUE(fails_with(px::read_texture(nullptr, 0), "empty"));
}

TEST(TextureFile, ReadsFilesAndPrefixesErrorsWithThePath) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("px_texture_file_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string good = (dir / "good.ktx2").string();
    ASSERT_TRUE(px::write_file_atomically(good, small_ktx2().data(), small_ktx2().size()).ok());
    Result<TextureData> t = px::read_texture_file(good);
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_EQ(t->container, ContainerKind::ktx2);

    const std::string bad = (dir / "bad.pvr").string();
    const Bytes b = patch32(small_pvr(), 16, 3);  // neither linear (0) nor sRGB (1)
    ASSERT_TRUE(px::write_file_atomically(bad, b.data(), b.size()).ok());
    EXPECT_TRUE(fails_with(px::read_texture_file(bad), bad + ": PVR v3 colour space 3"));
    EXPECT_TRUE(fails_with(px::read_texture_file((dir / "missing.ktx").string()), "missing.ktx"));
    EXPECT_TRUE(fails_with(px::read_texture_file(dir.string()), "folder"));
    EXPECT_TRUE(fails_with(px::read_texture_file(good, 16), good + ": KTX 2.0 the texture needs"));
    std::filesystem::remove_all(dir);
}

// Kind and size from the header alone (what a scene check and a material
// read look at before any data is inflated): the first kTextureHeaderBytes
// give what the full read gives, and a bad header field the same error.
TEST(TextureFile, ShapeFromTheHeaderAloneMatchesTheFullRead) {
    const Bytes files[] = {ktx1(make_texture(TextureFormat::etc2_rgb8, 37, 20, 0, 3, 1)),
                           ktx2(make_texture(TextureFormat::bc5, 32, 32, 0, 2, 6, true), 19),
                           ktx2(make_texture(TextureFormat::r8, 64, 16, 2, 1, 1), 0),
                           pvr(make_texture(TextureFormat::rgba8, 16, 16, 0, 1, 6))};
    for (const Bytes& file : files) {
        Result<TextureData> full = px::read_texture(file.data(), file.size());
        ASSERT_TRUE(full.ok()) << full.error().message;
        SCOPED_TRACE(px::container_name(full->container));
        const std::size_t head = std::min(file.size(), px::kTextureHeaderBytes);
        ASSERT_LT(head, file.size());  // the data really is left unread
        Result<px::TextureShape> shape = px::read_texture_shape(file.data(), head);
        ASSERT_TRUE(shape.ok()) << shape.error().message;
        EXPECT_EQ(shape->container, full->container);
        EXPECT_EQ(shape->format, full->format);
        EXPECT_EQ(shape->width, full->width);
        EXPECT_EQ(shape->height, full->height);
        EXPECT_EQ(shape->layers, full->layers);
        EXPECT_EQ(shape->faces, full->faces);
        EXPECT_EQ(shape->levels, full->levels.size());
        EXPECT_EQ(shape->bytes, full->bytes.size());
    }
    // Width 0 in each container's header: the same message either way.
    const std::pair<Bytes, std::size_t> bad[] = {{files[0], 36}, {files[1], 20}, {files[3], 28}};
    for (const auto& [file, width_at] : bad) {
        const Bytes patched = patch32(file, width_at, 0);
        Result<TextureData> full = px::read_texture(patched.data(), patched.size());
        Result<px::TextureShape> shape = px::read_texture_shape(patched.data(), px::kTextureHeaderBytes);
        ASSERT_FALSE(full.ok());
        ASSERT_FALSE(shape.ok());
        EXPECT_EQ(shape.error().message, full.error().message);
    }
    Result<px::TextureShape> png = px::read_texture_shape(reinterpret_cast<const std::uint8_t*>("\x89PNG\r\n\x1a\n"), 8);
    ASSERT_FALSE(png.ok());
    EXPECT_NE(png.error().message.find("not a texture container"), std::string::npos) << png.error().message;
}

}  // namespace
