// Hostile input, one class per test: each fails on a loader that trusts
// what it reads (a hang, an abort, an overwritten file, a silent wrong
// image) and passes when the input is refused with a message naming the
// file or JSON path. The fuzz targets (tests/fuzz) look for more; a crash
// they find becomes a test here.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <array>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "parallaxes/assets/heightfield.h"
#include "parallaxes/assets/image.h"
#include "parallaxes/core/files.h"
#include "parallaxes/core/limits.h"
#include "parallaxes/core/text.h"
#include "parallaxes/scene/material_images.h"
#include "parallaxes/scene/mesh.h"
#include "parallaxes/scene/scene.h"
#include "parallaxes/texture/containers.h"

// stb_image_write's deflate, compiled into the library's image.cpp: the
// tests build PNGs byte by byte with it.
extern "C" unsigned char* stbi_zlib_compress(unsigned char* data, int data_len, int* out_len, int quality);

namespace px {
namespace {

namespace fs = std::filesystem;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// --- PNG building ------------------------------------------------------------------

std::uint32_t crc32(const std::uint8_t* data, std::size_t size) {
    std::uint32_t c = 0xFFFFFFFFu;
    for (std::size_t i = 0; i < size; ++i) {
        c ^= data[i];
        for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    }
    return c ^ 0xFFFFFFFFu;
}

void put32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

void chunk(std::vector<std::uint8_t>& png, const char* type, const std::vector<std::uint8_t>& data,
           bool good_crc = true) {
    put32(png, static_cast<std::uint32_t>(data.size()));
    const std::size_t start = png.size();
    png.insert(png.end(), type, type + 4);
    png.insert(png.end(), data.begin(), data.end());
    const std::uint32_t crc = crc32(png.data() + start, png.size() - start);
    put32(png, good_crc ? crc : crc ^ 1u);
}

std::vector<std::uint8_t> ihdr(std::uint32_t w, std::uint32_t h, int depth, int colour_type) {
    std::vector<std::uint8_t> d;
    put32(d, w);
    put32(d, h);
    d.insert(d.end(), {static_cast<std::uint8_t>(depth), static_cast<std::uint8_t>(colour_type), 0, 0, 0});
    return d;
}

std::vector<std::uint8_t> deflate(const std::vector<std::uint8_t>& raw) {
    int size = 0;
    std::vector<std::uint8_t> copy = raw;
    unsigned char* z = stbi_zlib_compress(copy.data(), static_cast<int>(copy.size()), &size, 8);
    std::vector<std::uint8_t> out(z, z + size);
    std::free(z);
    return out;
}

const std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};

// An 8-bit indexed PNG of w x h pixels with the given indices and palette.
std::vector<std::uint8_t> indexed_png(int w, int h, const std::vector<std::uint8_t>& indices,
                                      const std::vector<std::array<std::uint8_t, 3>>& palette) {
    std::vector<std::uint8_t> png(kSignature, kSignature + 8);
    chunk(png, "IHDR", ihdr(w, h, 8, 3));
    std::vector<std::uint8_t> plte;
    for (const auto& e : palette) plte.insert(plte.end(), e.begin(), e.end());
    chunk(png, "PLTE", plte);
    std::vector<std::uint8_t> raw;
    for (int y = 0; y < h; ++y) {
        raw.push_back(0);  // filter: none
        raw.insert(raw.end(), indices.begin() + y * w, indices.begin() + (y + 1) * w);
    }
    chunk(png, "IDAT", deflate(raw));
    chunk(png, "IEND", {});
    return png;
}

// A grey 8-bit PNG declaring w x h, whose IDAT inflates to `raw_bytes` of zeros.
std::vector<std::uint8_t> grey_png(std::uint32_t w, std::uint32_t h, std::size_t raw_bytes, bool with_iend = true) {
    std::vector<std::uint8_t> png(kSignature, kSignature + 8);
    chunk(png, "IHDR", ihdr(w, h, 8, 0));
    chunk(png, "IDAT", deflate(std::vector<std::uint8_t>(raw_bytes, 0)));
    if (with_iend) chunk(png, "IEND", {});
    return png;
}

Result<Image> decode(const std::vector<std::uint8_t>& bytes) {
    return decode_image(bytes.data(), bytes.size(), "hostile.png", 4);
}

// --- Images --------------------------------------------------------------------------

TEST(HostileImage, ValidHandMadePngsDecode) {
    // The builders make files the loader accepts, so the refusals below are
    // about the one thing each test breaks.
    Result<Image> grey = decode(grey_png(4, 3, 3 * (1 + 4)));
    ASSERT_TRUE(grey.ok()) << grey.error().message;
    EXPECT_EQ(grey->width, 4);
    EXPECT_EQ(grey->height, 3);
    // An indexed image whose indices stay inside a short palette is fine.
    Result<Image> indexed = decode(indexed_png(2, 2, {0, 1, 1, 0}, {{{10, 20, 30}}, {{200, 100, 50}}}));
    ASSERT_TRUE(indexed.ok()) << indexed.error().message;
    // The file's last row {1, 0} is the image's row 0 (v = 0).
    EXPECT_EQ(indexed->texel(0, 0)[0], 200);
    EXPECT_EQ(indexed->texel(1, 0)[2], 30);
    EXPECT_EQ(indexed->texel(1, 1)[1], 100);
}

// A header declaring 30000 x 30000 is refused from the header: nothing of
// that size is allocated (the decoder would need 3.6 GB).
TEST(HostileImage, HugeDeclaredSizeRefusedFromTheHeader) {
    Result<Image> image = decode(grey_png(30000, 30000, 16));
    ASSERT_FALSE(image.ok());
    EXPECT_TRUE(contains(image.error().message, "hostile.png")) << image.error().message;
    EXPECT_TRUE(contains(image.error().message, "30000x30000")) << image.error().message;
    EXPECT_TRUE(contains(image.error().message, std::to_string(kMaxTextureSize))) << image.error().message;
}

// A host can lower the size limit to its device's GL_MAX_TEXTURE_SIZE.
TEST(HostileImage, MaxSideLowersTheLimit) {
    const std::vector<std::uint8_t> png = grey_png(4, 3, 3 * (1 + 4));
    EXPECT_TRUE(decode_image(png.data(), png.size(), "a.png", 4, 4).ok());
    Result<Image> small = decode_image(png.data(), png.size(), "a.png", 4, 2);
    ASSERT_FALSE(small.ok());
    EXPECT_TRUE(contains(small.error().message, "4x3, over the limit of 2 texels per side")) << small.error().message;
    EXPECT_FALSE(decode_image(png.data(), png.size(), "a.png", 4, 0).ok());
    EXPECT_FALSE(decode_image(png.data(), png.size(), "a.png", 4, kMaxTextureSize + 1).ok());
}

// A small image whose data inflates far past its declared size (a deflate
// bomb) is stopped by the decoder's memory cap.
TEST(HostileImage, DataExpandingPastTheHeaderIsRefused) {
    const std::vector<std::uint8_t> bomb = grey_png(16, 16, std::size_t{24} << 20);
    ASSERT_LT(bomb.size(), std::size_t{1} << 20);  // a small file
    Result<Image> image = decode(bomb);
    ASSERT_FALSE(image.ok());
    EXPECT_TRUE(contains(image.error().message, "expands past what its header declares")) << image.error().message;
}

// Pixels that use palette entries the PLTE does not hold: stb would fill
// them from uninitialised stack memory (a silent, nondeterministic image).
TEST(HostileImage, PaletteIndexPastAShortPlteIsRefused) {
    Result<Image> image = decode(indexed_png(2, 2, {0, 1, 5, 0}, {{{10, 20, 30}}, {{200, 100, 50}}}));
    ASSERT_FALSE(image.ok());
    EXPECT_TRUE(contains(image.error().message, "palette indices past the 2 entries")) << image.error().message;
}

TEST(HostileImage, MissingIendGivesAReason) {
    Result<Image> image = decode(grey_png(4, 4, 4 * 5, /*with_iend=*/false));
    ASSERT_FALSE(image.ok());
    EXPECT_TRUE(contains(image.error().message, "hostile.png: not a valid PNG: the file ends before its IEND chunk"))
        << image.error().message;
}

TEST(HostileImage, StructuralDamageIsNamed) {
    std::vector<std::uint8_t> png(kSignature, kSignature + 8);
    chunk(png, "IHDR", ihdr(4, 4, 8, 0), /*good_crc=*/false);
    EXPECT_TRUE(contains(decode(png).error().message, "bad CRC"));

    png.assign(kSignature, kSignature + 8);
    chunk(png, "IHDR", ihdr(4, 4, 3, 2));  // 3-bit RGB does not exist
    EXPECT_TRUE(contains(decode(png).error().message, "not a valid PNG combination"));

    png.assign(kSignature, kSignature + 8);
    chunk(png, "IHDR", ihdr(4, 4, 8, 3));
    chunk(png, "IDAT", deflate(std::vector<std::uint8_t>(20, 0)));
    chunk(png, "IEND", {});
    EXPECT_TRUE(contains(decode(png).error().message, "without a PLTE"));

    png.assign(kSignature, kSignature + 8);
    chunk(png, "IHDR", ihdr(4, 4, 8, 0));
    put32(png, 0x7FFFFFF0u);  // a chunk claiming 2 GB
    png.insert(png.end(), {'I', 'D', 'A', 'T', 0, 0, 0, 0});
    EXPECT_TRUE(contains(decode(png).error().message, "runs past the end of the file"));

    EXPECT_TRUE(contains(decode({}).error().message, "empty"));
    const std::vector<std::uint8_t> junk(100, 0x41);
    EXPECT_FALSE(decode(junk).ok());
}

// TGA has no signature: bytes that are no PNG or JPEG are not guessed to be
// one (stb reads most headers as some TGA and decodes noise), unless the
// file says it is a TGA by its name.
TEST(HostileImage, UnsignedBytesAreNotGuessedToBeTga) {
    // A valid 2x1 24-bit TGA header and pixels.
    const std::vector<std::uint8_t> tga = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 1, 0, 24, 0,
                                           10, 20, 30, 40, 50, 60};
    Result<Image> as_png = decode_image(tga.data(), tga.size(), "texture.png");
    ASSERT_FALSE(as_png.ok());
    EXPECT_TRUE(contains(as_png.error().message, "not a PNG or JPEG file")) << as_png.error().message;
    Result<Image> as_tga = decode_image(tga.data(), tga.size(), "texture.TGA");
    ASSERT_TRUE(as_tga.ok()) << as_tga.error().message;
    EXPECT_EQ(as_tga->width, 2);
    EXPECT_EQ(as_tga->texel(1, 0)[0], 60);  // BGR on disk
    const std::string text = "{\"this is\": \"a scene file saved as .png\"}";
    EXPECT_FALSE(decode_image(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), "a.png").ok());
}

class HostileFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("px_hostile_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(dir_, ec);
    }
    std::string write(const std::string& name, const std::vector<std::uint8_t>& bytes) {
        const fs::path p = dir_ / name;
        std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                 static_cast<std::streamsize>(bytes.size()));
        return p.string();
    }
    std::string write(const std::string& name, const std::string& text) {
        return write(name, std::vector<std::uint8_t>(text.begin(), text.end()));
    }
    std::string read(const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    }
    fs::path dir_;
};

// A file named as an image that is a FIFO would block a plain open forever;
// a folder, or a file past the byte limit, is refused before it is read.
TEST_F(HostileFiles, NonRegularAndOversizedFilesAreRefused) {
    const std::string fifo = (dir_ / "pipe.png").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    Result<Image> from_fifo = load_image(fifo);
    ASSERT_FALSE(from_fifo.ok());
    EXPECT_TRUE(contains(from_fifo.error().message, "not a regular file")) << from_fifo.error().message;

    EXPECT_TRUE(contains(load_image(dir_.string()).error().message, "it is a folder"));

    const std::string big = (dir_ / "big.json").string();
    {
        std::ofstream out(big, std::ios::binary);
        out.seekp(static_cast<std::streamoff>(kMaxSceneFileBytes));  // sparse: no disk used
        out.put('}');
    }
    Result<SceneDesc> scene = load_scene_file(big);
    ASSERT_FALSE(scene.ok());
    EXPECT_TRUE(contains(scene.error().message, "larger than the limit of 16 MiB")) << scene.error().message;
}

// The old writer opened OUT.png.tmp with fopen: a symlink planted there
// made the render overwrite the link's target.
TEST_F(HostileFiles, SymlinkPlantedAtTheTemporaryNameIsNotFollowed) {
    const fs::path victim = dir_ / "victim.txt";
    std::ofstream(victim) << "precious";
    const fs::path out = dir_ / "out.png";
    fs::create_symlink(victim, dir_ / "out.png.tmp");
    ASSERT_TRUE(write_png(out.string(), make_solid_image(2, 2, 1, 2, 3)).ok());
    EXPECT_EQ(read(victim), "precious");
    EXPECT_TRUE(load_image(out.string()).ok());
    // And no temporary is left beside it, the planted link apart.
    int entries = 0;
    for (const auto& e : fs::directory_iterator(dir_)) entries += e.path().filename() != "out.png.tmp";
    EXPECT_EQ(entries, 2);  // victim.txt, out.png
}

TEST_F(HostileFiles, WriteProtectedOutputIsRefusedAndKept) {
    const fs::path out = dir_ / "kept.png";
    std::ofstream(out) << "old";
    fs::permissions(out, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
    const Status s = write_png(out.string(), make_solid_image(2, 2, 1, 2, 3));
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.error().message, "write-protected")) << s.error().message;
    EXPECT_EQ(read(out), "old");
}

// An image file referenced by a scene is checked from its header when the
// scene is read, and the error names the JSON path and the file.
TEST_F(HostileFiles, SceneTextureOverTheLimitNamesPathAndFile) {
    write("huge.png", grey_png(30000, 30000, 16));
    const std::string scene = write("s.json", std::string(R"({"materials": [{"name": "m", "height": "huge.png"}],
                                                            "objects": [{"material": "m"}]})"));
    Result<SceneDesc> s = load_scene_file(scene);
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.error().message, "materials[0].height (material 'm')")) << s.error().message;
    EXPECT_TRUE(contains(s.error().message, "huge.png")) << s.error().message;
    EXPECT_TRUE(contains(s.error().message, "30000x30000")) << s.error().message;
}

// --- Scenes ------------------------------------------------------------------------------

std::string scene_error(const std::string& text) {
    Result<SceneDesc> s = parse_scene(text, "hostile.json");
    return s.ok() ? std::string("(parsed)") : s.error().message;
}

std::string with_material(const std::string& fields, const std::string& object = "") {
    return R"({"materials": [{"name": "m")" + (fields.empty() ? "" : ", " + fields) + R"(}], "objects": [{"material": "m")" +
           object + "}]}";
}

// line_width + 1 overflowed int, passed the spacing check and then looped
// for hours drawing the line.
TEST(HostileScene, OverflowingLineWidthIsRefused) {
    FieldSpec spec;
    spec.kind = FieldKind::lines;
    spec.size = 64;
    spec.count = 1;
    spec.line_width = INT_MAX;
    const Status s = validate_field_spec(spec);
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.error().message, "count * (line_width + 1) must be ≤ size")) << s.error().message;
    EXPECT_FALSE(make_height_field(spec).ok());
    const std::string message =
        scene_error(with_material(R"("height": {"procedural": "lines", "size": 64, "line_width": 2147483647})"));
    EXPECT_TRUE(contains(message, "hostile.json: materials[0].height: field 'lines'")) << message;
}

TEST(HostileScene, FieldTextLengthIsBounded) {
    const std::string message = scene_error(
        with_material(R"("height": {"procedural": "text", "text": ")" + std::string(100000, 'A') + R"("})"));
    EXPECT_TRUE(contains(message, "text must be at most 64 characters, got 100000")) << message;
}

TEST(HostileScene, LightsPastTheFourthAreRefusedNotDropped) {
    std::string lights;
    for (int i = 0; i < 5; ++i) lights += std::string(i ? ", " : "") + R"({"direction": [0, 0, -1]})";
    const std::string message = scene_error(R"({"lights": [)" + lights + R"(], "objects": [{}]})");
    EXPECT_TRUE(contains(message, "hostile.json: lights[4]: at most 4 lights are drawn, got 5")) << message;
}

// Values that are finite but overflow floats in the renderer's products
// (a wrong image with exit 0) are refused at the JSON path.
TEST(HostileScene, ValuesTheRendererCannotHonourAreRefused) {
    EXPECT_TRUE(contains(scene_error(with_material(R"("uv": {"scale": 1e20})")), "materials[0].uv.scale:"));
    EXPECT_TRUE(contains(scene_error(with_material(R"("uv": {"scale": [1, 1e-20]})")), "materials[0].uv.scale:"));
    EXPECT_TRUE(contains(scene_error(with_material(R"("uv": {"offset": [1e30, 0]})")), "materials[0].uv.offset:"));
    EXPECT_TRUE(contains(scene_error(with_material(R"("height_scale": 1e30)")), "materials[0].height_scale:"));
    EXPECT_TRUE(contains(scene_error(with_material("", R"(, "transform": {"scale": 1e-20})")),
                         "objects[0].transform.scale:"));
    EXPECT_TRUE(contains(scene_error(with_material("", R"(, "transform": {"translate": [1e30, 0, 0]})")),
                         "objects[0].transform.translate:"));
    EXPECT_TRUE(contains(scene_error(with_material("", R"(, "mesh": {"size": 1e30})")), "objects[0].mesh.size:"));
    EXPECT_TRUE(contains(scene_error(R"({"camera": {"position": [0, -1e30, 1]}, "objects": [{}]})"),
                         "camera.position:"));
    EXPECT_TRUE(contains(scene_error(R"({"lights": [{"color": [1e30, 1, 1]}], "objects": [{}]})"), "lights[0].color:"));
    EXPECT_TRUE(contains(scene_error(R"({"lights": [{"color": [500, 1, 1], "intensity": 500}], "objects": [{}]})"),
                         "lights[0].intensity: color * intensity must be at most 1000"));
    EXPECT_TRUE(contains(scene_error(R"({"lights": [{"direction": [1e-30, 0, 0]}], "objects": [{}]})"),
                         "lights[0].direction:"));
    // The ranges' ends are accepted.
    EXPECT_EQ(scene_error(with_material(R"("uv": {"scale": [16384, -0.00006103515625]})", R"(, "transform": {"scale": 1e-4})")),
              "(parsed)");
}

// A 10 MB unknown key made the did-you-mean search quadratic (seconds) and
// was echoed whole to stderr.
TEST(HostileScene, HugeUnknownKeyIsEchoedBoundedAndFast) {
    const std::string key(10'000'000, 'k');
    const std::string message = scene_error(R"({")" + key + R"(": 1, "objects": [{}]})");
    EXPECT_TRUE(contains(message, "unknown field 'kkkk")) << message.substr(0, 200);
    EXPECT_TRUE(contains(message, "... (10000000 bytes)")) << message.substr(0, 200);
    EXPECT_LT(message.size(), 400u);
    // Long names are refused too, so no later message quotes them whole.
    const std::string name = scene_error(with_material("").replace(with_material("").find(R"("m")"), 3,
                                                                    "\"" + std::string(1000, 'n') + "\""));
    EXPECT_TRUE(contains(name, "materials[0].name: must be at most 64 bytes")) << name.substr(0, 200);
}

// A displaced plane gets one vertex per texel corner: at the largest field
// that is 16M vertices (800 MB); the budget refuses it from the sizes.
TEST(HostileScene, DisplacedPlaneOverTheVertexBudgetIsRefusedFromSizes) {
    const std::string message = scene_error(with_material(R"("height": {"procedural": "bricks", "size": 4096})",
                                                          R"(, "mesh": {"displaced": true})"));
    EXPECT_TRUE(contains(message, "hostile.json: objects[0].mesh: the scene's meshes pass the limit of 4194304 vertices"))
        << message;
    HeightField sized_only;  // make_displaced_plane checks before it reads a texel
    sized_only.width = sized_only.height = 4096;
    Result<Mesh> mesh = make_displaced_plane(2.0f, sized_only, glm::dmat2(1.0), glm::dvec2(0.0), 0.1f, 1.0f);
    ASSERT_FALSE(mesh.ok());
    EXPECT_TRUE(contains(mesh.error().message, "over the limit")) << mesh.error().message;
}

// The displaced grid follows the uv transform (about one vertex per texel
// of uv'): a 1024 field fits at uv scale 1 (1025^2 vertices) and is refused
// at scale 4 (4097^2), from sizes, with the count make_displaced_plane uses.
TEST(HostileScene, DisplacedPlaneVertexBudgetFollowsTheUvScale) {
    const std::string field = R"("height": {"procedural": "bricks", "size": 1024})";
    Result<SceneDesc> fits = parse_scene(with_material(field, R"(, "mesh": {"displaced": true})"), "hostile.json");
    ASSERT_TRUE(fits.ok()) << fits.error().message;
    EXPECT_TRUE(check_scene_resources(*fits, true).ok());
    const std::string message = scene_error(
        with_material(field + R"(, "uv": {"scale": [4, 4]})", R"(, "mesh": {"displaced": true})"));
    EXPECT_TRUE(contains(message, "objects[0].mesh: the scene's meshes pass the limit of 4194304 vertices in all "
                                  "(this one adds 16785409, about one per texel"))
        << message;
}

TEST(HostileScene, TexturesOverTheSceneBudgetAreRefusedFromSizes) {
    std::string materials;
    for (int i = 0; i < 3; ++i)
        materials += std::string(i ? ", " : "") + R"({"name": "m)" + std::to_string(i) +
                     R"(", "height": {"procedural": "flat", "size": 4096}, "normal": {"procedural": "flat", "size": 4096}})";
    const std::string message = scene_error(R"({"materials": [)" + materials + R"(], "objects": [{"material": "m0"}]})");
    EXPECT_TRUE(contains(message, "hostile.json: materials[1].normal (material 'm1'): the scene's textures pass the limit"))
        << message;
}

TEST(HostileScene, ParsedCountsAreBounded) {
    std::string objects;
    for (int i = 0; i <= kMaxObjects; ++i) objects += std::string(i ? "," : "") + "{}";
    EXPECT_TRUE(contains(scene_error(R"({"objects": [)" + objects + "]}"), "objects: at most 1024 objects"));
    EXPECT_TRUE(contains(scene_error(std::string(kMaxSceneFileBytes + 1, ' ')), "larger than the limit"));
}

// --- The library's edge ----------------------------------------------------------------

TEST(OutOfMemory, BecomesAnErrorAtTheEdge) {
    const Status s = out_of_memory_is_an_error("loading scene 'x'", []() -> Status { throw std::bad_alloc(); });
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().message, "loading scene 'x': out of memory");
    const Result<int> r = out_of_memory_is_an_error("y", []() -> Result<int> {
        std::vector<int> v;
        v.reserve(v.max_size() + 1);  // std::length_error
        return 1;
    });
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "y: out of memory"));
}

TEST(Echo, BoundsAndEscapes) {
    EXPECT_EQ(echo("plain"), "plain");
    EXPECT_EQ(echo("a\nb\x01"), "a\\x0ab\\x01");
    const std::string cut = echo(std::string(1000, 'x'));
    EXPECT_EQ(cut, std::string(kMaxEchoBytes, 'x') + "... (1000 bytes)");
}

}  // namespace
}  // namespace px

namespace px {
namespace {

// The fuzz targets' seed corpora are inputs the library accepts: every
// image seed decodes (each PNG colour type and depth, interlaced, JPEG,
// plain, RLE and colour-mapped TGA), every scene seed parses.
TEST(FuzzSeeds, ImagesDecode) {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(std::string(PX_SOURCE_DIR) + "/tests/fuzz/corpus/image")) {
        Result<Image> image = load_image(e.path().string(), 4);
        EXPECT_TRUE(image.ok()) << image.error().message;
        if (image) EXPECT_EQ(image->width, e.path().extension() == ".jpg" ? 8 : 4) << e.path();
        ++n;
    }
    EXPECT_GE(n, 10);
}

TEST(FuzzSeeds, ScenesParse) {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(std::string(PX_SOURCE_DIR) + "/tests/fuzz/corpus/scene")) {
        std::ifstream in(e.path());
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        Result<SceneDesc> scene = parse_scene(text, e.path().filename().string());
        EXPECT_TRUE(scene.ok()) << scene.error().message;
        ++n;
    }
    EXPECT_GE(n, 5);
}

}  // namespace
}  // namespace px

namespace px {
namespace {

// What the fuzz targets found, kept as inputs (tests/fuzz/findings/).
std::string finding(const std::string& name) { return std::string(PX_SOURCE_DIR) + "/tests/fuzz/findings/" + name; }

// A DHT table declaring more than 256 codes: stb_image 2.27 writes one past its
// code-size array (UBSan: index 257 out of bounds for stbi_uc[257]).
TEST(FuzzFindings, JpegHuffmanTableWithTooManyCodesIsRefused) {
    Result<Image> image = load_image(finding("image_jpeg_dht_257_codes.jpg"));
    ASSERT_FALSE(image.ok());
    EXPECT_TRUE(contains(image.error().message, "Huffman table (DHT)")) << image.error().message;
    EXPECT_TRUE(contains(image.error().message, "codes; at most 256 exist")) << image.error().message;
}

// An unterminated comment: nlohmann's message quoted the whole rest of
// the file as the token it had read ("last read: '...'").
TEST(FuzzFindings, MalformedJsonMessageQuotesABoundedToken) {
    std::ifstream in(finding("scene_unterminated_comment_echoed.json"), std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(text.size(), 2000u);
    Result<SceneDesc> scene = parse_scene(text, "f.json");
    ASSERT_FALSE(scene.ok());
    EXPECT_TRUE(contains(scene.error().message, "invalid comment")) << scene.error().message;
    EXPECT_LT(scene.error().message.size(), 400u) << scene.error().message;
}

}  // namespace
}  // namespace px

namespace px {
namespace {

// Corrupt entropy-coded data: stb_image 2.27 shifted by 33 bits on it
// (UBSan). JPEG now goes through libjpeg-turbo, whose warnings about
// corrupt data refuse the file rather than fill the image with grey.
TEST(FuzzFindings, JpegWithCorruptEntropyDataIsRefused) {
    Result<Image> image = load_image(finding("image_jpeg_corrupt_entropy_data.jpg"));
    ASSERT_FALSE(image.ok());
    EXPECT_TRUE(contains(image.error().message, "image_jpeg_corrupt_entropy_data.jpg: cannot decode JPEG: "))
        << image.error().message;
}

// And a truncated JPEG: the same refusal, where a lenient decoder would
// return the top of the image over grey.
TEST(HostileImage, TruncatedJpegIsRefused) {
    std::ifstream in(std::string(PX_SOURCE_DIR) + "/tests/fuzz/corpus/image/rgb8.jpg", std::ios::binary);
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_TRUE(decode_image(bytes.data(), bytes.size(), "whole.jpg").ok());
    bytes.resize(bytes.size() - 40);
    Result<Image> cut = decode_image(bytes.data(), bytes.size(), "cut.jpg");
    ASSERT_FALSE(cut.ok());
    EXPECT_TRUE(contains(cut.error().message, "cut.jpg: cannot decode JPEG")) << cut.error().message;
}

// A material's texture is one 2D image: a KTX 2.0 array of 2048 zstd
// layers (4 KB on disk, 8 MB inflated) is refused from its header, by the
// scene check and by the material read, before its data is touched. The
// data here does not even inflate: a reader that inflated first would say
// so instead (and it took 21 to 27 s when 64 materials named such a file).
TEST(HostileScene, ATextureArrayIsRefusedFromItsHeaderBeforeItsDataIsInflated) {
    Result<TextureData> layers = allocate_texture(TextureFormat::r8, 64, 64, 1, 2048, 1, 64u << 20);
    ASSERT_TRUE(layers.ok()) << layers.error().message;
    Result<std::vector<std::uint8_t>> file = write_ktx2(*layers, 19);
    ASSERT_TRUE(file.ok()) << file.error().message;
    ASSERT_LT(file->size(), 16384u);
    for (std::size_t i = file->size() - 16; i < file->size(); ++i) (*file)[i] ^= 0xA5;  // the zstd frame's end
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("px_hostile_array_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "layers.ktx2").string();
    ASSERT_TRUE(write_file_atomically(path, file->data(), file->size()).ok());
    Result<TextureData> whole = read_texture_file(path);
    ASSERT_FALSE(whole.ok());
    EXPECT_TRUE(contains(whole.error().message, "Zstandard")) << whole.error().message;

    std::string text;
    for (int i = 0; i < 64; ++i)
        text += std::string(i ? ", " : "") + R"({"name": "m)" + std::to_string(i) + R"(", "height": ")" + path + R"("})";
    Result<SceneDesc> scene = parse_scene(R"({"materials": [)" + text + R"(], "objects": [{"material": "m0"}]})", "array.json");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    const Status checked = check_scene_resources(*scene, true);
    ASSERT_FALSE(checked.ok());
    EXPECT_TRUE(contains(checked.error().message, "materials[0].height (material 'm0')")) << checked.error().message;
    EXPECT_TRUE(contains(checked.error().message, "holds 2048 layers and 1 faces")) << checked.error().message;
    Result<MaterialImages> images = build_material_images(scene->materials[0], "");
    ASSERT_FALSE(images.ok());
    EXPECT_TRUE(contains(images.error().message, "material 'm0' height")) << images.error().message;
    EXPECT_TRUE(contains(images.error().message, "holds 2048 layers and 1 faces")) << images.error().message;
    EXPECT_FALSE(contains(images.error().message, "Zstandard")) << images.error().message;
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace px
