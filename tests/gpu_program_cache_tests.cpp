// Program binaries across runs (gl/program_binary.h) through an in-memory
// store: a second renderer loads what the first stored and draws the same
// bits; every kind of bad entry is counted, discarded and replaced, and the
// image never changes. OpenGL ES 3.0 section 2.12.3 (glProgramBinary resets
// every uniform, so the sampler units must be set again) and
// GL_OES_get_program_binary on ES 2.0. Mesa 22.3 offers one format
// (GL_PROGRAM_BINARY_FORMAT_MESA) unless MESA_SHADER_CACHE_DISABLE is set.
#include "gpu_fixture.h"

#include <functional>
#include <map>

#include "parallaxes/gl/caps.h"
#include "parallaxes/gl/program.h"

namespace px::test {
namespace {

struct MemoryStore {
    std::map<std::string, std::vector<std::uint8_t>> entries;
    int loads = 0;
    int stores = 0;
    SipKey secret{};

    ProgramBinaryStore callbacks() {
        ProgramBinaryStore s;
        s.secret = secret;
        s.load = [this](const std::string& key) -> std::optional<std::vector<std::uint8_t>> {
            ++loads;
            auto it = entries.find(key);
            if (it == entries.end()) return std::nullopt;
            return it->second;
        };
        s.store = [this](const std::string& key, const std::vector<std::uint8_t>& bytes) {
            ++stores;
            entries[key] = bytes;
        };
        return s;
    }
};

struct CachedRender {
    Image image;
    ProgramStats stats;
    size_t programs = 0;
};

// The built-in scene at 64x64 through a renderer that uses `store`.
CachedRender render_cached(const SceneDesc& scene, MemoryStore& store) {
    CachedRender out;
    RendererOptions options;
    options.effect_planner = effect_planner;
    options.texture_files = texture_files();
    options.get_proc_address = platform::HeadlessContext::proc_loader();
    options.program_binaries = store.callbacks();
    auto renderer = Renderer::create(options);
    EXPECT_TRUE(renderer.ok()) << renderer.error().message;
    if (!renderer) return out;
    auto target = OffscreenTarget::create(64, 64);
    EXPECT_TRUE(target.ok());
    if (!target) return out;
    Status loaded = (*renderer)->load(scene);
    EXPECT_TRUE(loaded.ok()) << loaded.error().message;
    if (!loaded) return out;
    Status drawn = (*renderer)->draw(target->target());
    EXPECT_TRUE(drawn.ok()) << drawn.error().message;
    auto image = target->read_pixels();
    EXPECT_TRUE(image.ok());
    if (image) out.image = std::move(*image);
    out.stats = (*renderer)->program_stats();
    out.programs = (*renderer)->program_count();
    return out;
}

// Two materials drawn with one program (the same variant): the counts
// below are per program. (The default scene's bounded panel is a second.)
SceneDesc scene_with(Technique t) {
    Result<SceneDesc> scene = builtin_scene("lettering");
    EXPECT_TRUE(scene.ok());
    SceneDesc s = scene.ok() ? *scene : SceneDesc{};
    for (MaterialDesc& m : s.materials) m.technique.technique = t;
    return s;
}

// Why this context cannot use binaries, or empty. A skip names it; the
// counters must then show nothing from binaries.
std::string binaries_off(const SceneDesc& scene) {
    MemoryStore store;
    const CachedRender r = render_cached(scene, store);
    if (!r.stats.binaries_off.empty()) {
        EXPECT_EQ(r.stats.from_binary, 0);
        EXPECT_EQ(store.loads, 0);
        EXPECT_GT(r.stats.compiled, 0);
    }
    return r.stats.binaries_off;
}

#define PX_REQUIRE_BINARIES(scene)                                                                  \
    if (const std::string off = binaries_off(scene); !off.empty())                                  \
    GTEST_SKIP() << "this context has no program binaries: " << off

TEST(ProgramBinaries, WithoutAStoreEverythingCompiles) {
    auto renderer = Renderer::create({platform::HeadlessContext::proc_loader()});
    ASSERT_TRUE(renderer.ok());
    ASSERT_TRUE((*renderer)->load(scene_with(Technique::pom)).ok());
    const ProgramStats stats = (*renderer)->program_stats();
    EXPECT_EQ(stats.compiled, static_cast<int>((*renderer)->program_count()));
    EXPECT_EQ(stats.from_binary, 0);
    EXPECT_EQ(stats.binaries_off, "no program binary store");
}

// First run compiles and stores; a second renderer with the same store
// compiles nothing and draws the same bits. The sampler units and attribute
// slots of a binary-loaded program must be right for that (albedo and normal
// map sit on different units).
TEST(ProgramBinaries, SecondRendererLoadsFromTheStoreBitIdentical) {
    const SceneDesc scene = scene_with(Technique::pom);
    PX_REQUIRE_BINARIES(scene);
    MemoryStore store;
    const CachedRender first = render_cached(scene, store);
    ASSERT_GT(first.programs, 0u);
    EXPECT_EQ(first.stats.compiled, static_cast<int>(first.programs));
    EXPECT_EQ(first.stats.from_binary, 0);
    EXPECT_EQ(first.stats.rejected, 0);
    EXPECT_EQ(first.stats.store_problem, "");
    EXPECT_EQ(store.entries.size(), first.programs);
    for (const auto& [key, bytes] : store.entries) {
        EXPECT_EQ(key.size(), 16u) << key;
        ASSERT_GT(bytes.size(), kProgramBinaryHeaderSize);
        EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "PXPB");
    }

    const int stores_before = store.stores;
    const CachedRender second = render_cached(scene, store);
    EXPECT_EQ(second.stats.compiled, 0);
    EXPECT_EQ(second.stats.from_binary, static_cast<int>(first.programs));
    EXPECT_EQ(second.stats.rejected, 0) << second.stats.last_rejection;
    EXPECT_EQ(store.stores, stores_before) << "a program loaded from its binary is not stored again";
    ASSERT_FALSE(second.image.pixels.empty());
    EXPECT_TRUE(second.image.pixels == first.image.pixels) << "mean difference " << compare(first.image, second.image).mean;
}

// Entries are authenticated with the store's secret: whoever can write the
// store but lacks the secret cannot make an entry the renderer will use,
// whether by recomputing the checks over an altered payload (which crashed
// llvmpipe's compiler when it reached the driver) or by moving one
// program's valid entry under another's name or identity. Each is refused
// before the driver sees it, rebuilt from source, and the image is the same.
TEST(ProgramBinaries, EntriesForgedWithoutTheSecretAreRefused) {
    const SceneDesc scene = scene_with(Technique::pom);
    PX_REQUIRE_BINARIES(scene);
    MemoryStore store;
    for (size_t i = 0; i < store.secret.size(); ++i) store.secret[i] = static_cast<std::uint8_t>(0x5a ^ (i * 37));
    const CachedRender reference = render_cached(scene, store);
    render_cached(scene_with(Technique::relief), store);  // another program's entry in the same store
    ASSERT_GE(store.entries.size(), 2u);
    const int programs = static_cast<int>(reference.programs);
    const std::map<std::string, std::vector<std::uint8_t>> valid = store.entries;
    auto field = [](const std::vector<std::uint8_t>& b, size_t at, int bytes) {
        std::uint64_t v = 0;
        for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | b[at + static_cast<size_t>(i)];
        return v;
    };
    struct Forgery {
        const char* name;
        std::function<std::vector<std::uint8_t>(const std::string& key, const std::vector<std::uint8_t>& b)> make;
        const char* reason;
    };
    const std::vector<Forgery> forgeries = {
        {"the payload altered and re-encoded without the secret",
         [&](const std::string&, const std::vector<std::uint8_t>& b) {
             std::vector<std::uint8_t> payload(b.begin() + kProgramBinaryHeaderSize, b.end());
             payload[payload.size() / 2] ^= 0x40;
             return encode_program_binary_entry(field(b, 24, 8), static_cast<GLenum>(field(b, 8, 4)), payload);
         },
         "fails its authentication"},
        {"another program's entry under this name",
         [&](const std::string& key, const std::vector<std::uint8_t>&) {
             for (const auto& [other, bytes] : valid)
                 if (other != key) return bytes;
             return std::vector<std::uint8_t>{};
         },
         "made for another program"},
        {"another program's payload under this program's identity",
         [&](const std::string& key, const std::vector<std::uint8_t>& b) {
             for (const auto& [other, bytes] : valid)
                 if (other != key) {
                     std::vector<std::uint8_t> swapped = bytes;
                     std::copy(b.begin() + 24, b.begin() + 32, swapped.begin() + 24);  // this program's identity check
                     return swapped;
                 }
             return std::vector<std::uint8_t>{};
         },
         "fails its authentication"},
    };
    for (const Forgery& f : forgeries) {
        SCOPED_TRACE(f.name);
        for (auto& [key, bytes] : store.entries) bytes = f.make(key, valid.at(key));
        const CachedRender rebuilt = render_cached(scene, store);
        EXPECT_EQ(rebuilt.stats.rejected, programs);
        EXPECT_EQ(rebuilt.stats.from_binary, 0);
        EXPECT_NE(rebuilt.stats.last_rejection.find(f.reason), std::string::npos) << rebuilt.stats.last_rejection;
        EXPECT_TRUE(rebuilt.image.pixels == reference.image.pixels) << compare(rebuilt.image, reference.image).mean;
    }
    // The same entries under the secret they were written with load again.
    store.entries = valid;
    const CachedRender again = render_cached(scene, store);
    EXPECT_EQ(again.stats.from_binary, programs) << again.stats.last_rejection;
}

// Each way an entry can be wrong, applied to every stored entry: the renderer
// rebuilds from source, counts each rejection with its reason, stores a
// fresh entry (the next renderer loads it again) and draws the same bits.
TEST(ProgramBinaries, CorruptEntriesAreRebuiltAndReplaced) {
    const SceneDesc scene = scene_with(Technique::pom);
    PX_REQUIRE_BINARIES(scene);
    MemoryStore store;
    const CachedRender reference = render_cached(scene, store);
    ASSERT_FALSE(store.entries.empty());
    const int programs = static_cast<int>(reference.programs);

    // A valid header around a payload the driver will refuse: our checks
    // pass, so this reaches glProgramBinary and its GL_LINK_STATUS.
    const auto reencode = [](std::vector<std::uint8_t>& b, const std::function<void(std::vector<std::uint8_t>&)>& edit) {
        std::uint64_t check = 0;
        for (int i = 7; i >= 0; --i) check = (check << 8) | b[24 + static_cast<size_t>(i)];
        std::uint32_t format = 0;
        for (int i = 3; i >= 0; --i) format = (format << 8) | b[8 + static_cast<size_t>(i)];
        std::vector<std::uint8_t> payload(b.begin() + kProgramBinaryHeaderSize, b.end());
        edit(payload);
        b = encode_program_binary_entry(check, format, payload);
    };
    struct Corruption {
        const char* name;
        std::function<void(std::vector<std::uint8_t>&)> apply;
        const char* reason;  // in ProgramStats::last_rejection
    };
    const std::vector<Corruption> corruptions = {
        {"a flipped payload byte", [](auto& b) { b[kProgramBinaryHeaderSize + (b.size() - kProgramBinaryHeaderSize) / 2] ^= 0x40; },
         "fails its authentication"},
        {"a flipped format byte", [](auto& b) { b[8] ^= 0x01; }, "fails its authentication"},
        {"truncated to half", [](auto& b) { b.resize(b.size() / 2); }, "truncated"},
        {"truncated to 3 bytes", [](auto& b) { b.resize(3); }, "shorter than its 32-byte header"},
        {"empty", [](auto& b) { b.clear(); }, "entry of 0 bytes"},
        {"wrong magic", [](auto& b) { b[0] = 'X'; }, "magic"},
        {"a header claiming a huge length",
         [](auto& b) { for (size_t i = 0; i < 4; ++i) b[kProgramBinaryLengthOffset + i] = 0xff; },
         "payload of 4294967295 bytes"},
        {"another entry version", [](auto& b) { b[4] = 99; }, "entry version 99"},
        {"a format the context lacks, authenticated",
         [](auto& b) {
             std::uint64_t check = 0;
             for (int i = 7; i >= 0; --i) check = (check << 8) | b[24 + static_cast<size_t>(i)];
             std::uint32_t format = 0;
             for (int i = 3; i >= 0; --i) format = (format << 8) | b[8 + static_cast<size_t>(i)];
             b = encode_program_binary_entry(check, format ^ 0x1001u,
                                             std::vector<std::uint8_t>(b.begin() + kProgramBinaryHeaderSize, b.end()));
         },
         "not one this context offers"},
        {"the driver's payload flipped under a valid header",
         [&](auto& b) { reencode(b, [](auto& p) { p[p.size() / 2] ^= 0x40; }); }, "GL_LINK_STATUS false"},
        {"the driver's payload cut under a valid header",
         [&](auto& b) { reencode(b, [](auto& p) { p.resize(p.size() / 2); }); }, "GL_LINK_STATUS false"},
    };
    for (const Corruption& c : corruptions) {
        SCOPED_TRACE(c.name);
        for (auto& [key, bytes] : store.entries) c.apply(bytes);
        const CachedRender rebuilt = render_cached(scene, store);
        EXPECT_EQ(rebuilt.stats.rejected, programs);
        EXPECT_EQ(rebuilt.stats.compiled, programs);
        EXPECT_EQ(rebuilt.stats.from_binary, 0);
        EXPECT_NE(rebuilt.stats.last_rejection.find(c.reason), std::string::npos) << rebuilt.stats.last_rejection;
        EXPECT_TRUE(rebuilt.image.pixels == reference.image.pixels) << compare(rebuilt.image, reference.image).mean;
        // The fresh entries it stored load again.
        const CachedRender again = render_cached(scene, store);
        EXPECT_EQ(again.stats.from_binary, programs) << again.stats.last_rejection;
        EXPECT_EQ(again.stats.rejected, 0);
        EXPECT_TRUE(again.image.pixels == reference.image.pixels);
    }
}

// The entry of another variant stored under this variant's key (what a key
// collision would look like): same format, authenticated, and the driver
// would load it, so only the identity check in the header catches it.
TEST(ProgramBinaries, EntryOfAnotherProgramIsRejected) {
    const SceneDesc pom = scene_with(Technique::pom);
    const SceneDesc relief = scene_with(Technique::relief);
    PX_REQUIRE_BINARIES(pom);
    MemoryStore pom_store, relief_store;
    render_cached(pom, pom_store);
    const CachedRender reference = render_cached(relief, relief_store);
    ASSERT_EQ(pom_store.entries.size(), 1u);
    ASSERT_EQ(relief_store.entries.size(), 1u);
    ASSERT_NE(pom_store.entries.begin()->first, relief_store.entries.begin()->first);
    relief_store.entries.begin()->second = pom_store.entries.begin()->second;
    const CachedRender swapped = render_cached(relief, relief_store);
    EXPECT_EQ(swapped.stats.rejected, 1);
    EXPECT_EQ(swapped.stats.compiled, 1);
    EXPECT_EQ(swapped.stats.from_binary, 0);
    EXPECT_NE(swapped.stats.last_rejection.find("made for another program"), std::string::npos)
        << swapped.stats.last_rejection;
    EXPECT_TRUE(swapped.image.pixels == reference.image.pixels);
}

// A program from its binary has each attribute at the interface's slot and
// each sampler on its unit, read back from GL.
TEST(ProgramBinaries, BinaryLoadedProgramHasTheBoundSlotsAndUnits) {
    const ProgramBinarySupport support =
        query_program_binary_support(query_caps(), platform::HeadlessContext::proc_loader());
    if (!support.available) GTEST_SKIP() << "this context has no program binaries: " << support.unavailable_reason;
    VariantKey key;
    key.technique = Technique::pom;
    key.es_major = static_cast<std::uint8_t>(test_es_major());
    key.max_samples = 16;
    MemoryStore store;
    {
        ProgramCache compiling({}, store.callbacks(), support);
        ASSERT_TRUE(compiling.get(key).ok());
        EXPECT_EQ(compiling.stats().compiled, 1);
    }
    ProgramCache loading({}, store.callbacks(), support);
    Result<const Program*> program = loading.get(key);
    ASSERT_TRUE(program.ok()) << program.error().message;
    ASSERT_EQ(loading.stats().from_binary, 1) << loading.stats().last_rejection;
    const GLuint id = (*program)->id();
    int samplers = 0;
    for (const shader::SamplerInfo& s : shader::samplers()) {
        const GLint location = (*program)->location(s.uniform);
        if (location < 0) continue;
        GLint unit = -1;
        glGetUniformiv(id, location, &unit);
        EXPECT_EQ(unit, s.unit) << shader::info(s.uniform).name;
        ++samplers;
    }
    EXPECT_GE(samplers, 2);
    int attributes = 0;
    for (const shader::AttributeInfo& a : shader::attributes()) {
        const GLint location = glGetAttribLocation(id, a.name);
        if (location < 0) continue;
        EXPECT_EQ(location, a.slot) << a.name;
        ++attributes;
    }
    EXPECT_GE(attributes, 3);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

}  // namespace
}  // namespace px::test
