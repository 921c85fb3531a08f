// The technique catalogue, variant keys, the planner and shader assembly:
// pure logic, no GL.
#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <sstream>

#include "parallaxes/effects/variant.h"
#include "parallaxes/planner/planner.h"
#include "parallaxes/shaders/interface.h"
#include "parallaxes/shaders/shader_source.h"
#include "parallaxes/scene/scene.h"

namespace px {
namespace {

TEST(Catalogue, NamesAreUniqueAndParseBack) {
    std::set<std::string> names;
    for (const TechniqueInfo& info : technique_table()) {
        EXPECT_TRUE(names.insert(info.name).second) << info.name;
        Result<Technique> t = parse_technique(info.name);
        ASSERT_TRUE(t.ok());
        EXPECT_EQ(*t, info.id);
        EXPECT_EQ(&technique_info(info.id), &info) << "table order must match the enum";
    }
    EXPECT_EQ(names.size(), static_cast<size_t>(kTechniqueCount));
}

TEST(Catalogue, UnknownTechniqueListsTheKnownOnes) {
    Result<Technique> t = parse_technique("pomm");
    ASSERT_FALSE(t.ok());
    EXPECT_NE(t.error().message.find("'pomm'"), std::string::npos);
    EXPECT_NE(t.error().message.find("relief"), std::string::npos);
}

TEST(Catalogue, OptionRangesAreChecked) {
    TechniqueOptions o;
    o.max_samples = 300;
    EXPECT_FALSE(validate_options(o).ok());
    o.max_samples = 4;
    o.min_samples = 8;
    Status s = validate_options(o);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("max_samples"), std::string::npos);
    EXPECT_TRUE(validate_options(TechniqueOptions{}).ok());
}

TEST(VariantKey, EveryEnumeratedVariantHasItsOwnKey) {
    for (int es : {2, 3}) {
        std::set<std::string> keys;
        const std::vector<VariantKey> variants = enumerate_variants(es);
        for (const VariantKey& k : variants) EXPECT_TRUE(keys.insert(k.id()).second) << k.describe();
        EXPECT_GT(variants.size(), 50u);
    }
}

TEST(VariantKey, OptionsATechniqueLacksDoNotChangeTheKey) {
    VariantKey a;
    a.technique = Technique::parallax;
    VariantKey b = a;
    b.shadow = ShadowMode::soft;
    b.max_samples = 64;
    b.depth_write = true;
    EXPECT_EQ(a.id(), b.id());
    a.technique = b.technique = Technique::pom;
    EXPECT_NE(a.id(), b.id());
}

// The curved search's shape (PX_SHAPE) is part of a curved variant only
// (on every context: without fragment highp too): the same key otherwise.
TEST(VariantKey, TheCurvedShapeNeedsACurvedSearch) {
    VariantKey k;
    k.technique = Technique::pom;
    k.max_samples = 32;
    k.shape = kShapeTorus;
    VariantKey none = k;
    none.shape = 0;
    EXPECT_EQ(k.id(), none.id()) << "not curved: no shape";
    k.curved = none.curved = true;
    EXPECT_NE(k.id(), none.id());
    EXPECT_EQ(k.describe(), "pom es3 samples<=32 packed curved shape=torus");
    Result<VariantKey> parsed = VariantKey::parse(k.describe());
    ASSERT_TRUE(parsed.ok()) << parsed.error().message;
    EXPECT_EQ(parsed->shape, kShapeTorus);
    k.es_major = none.es_major = 2;
    k.no_fragment_highp = none.no_fragment_highp = true;
    EXPECT_NE(k.id(), none.id()) << "no fragment highp: still the shape search";
    EXPECT_EQ(k.describe(), "pom es2 samples<=32 packed curved shape=torus no-fragment-highp");
    k.technique = none.technique = Technique::maxmip;  // no linear search: not curved at all
    k.no_fragment_highp = none.no_fragment_highp = false;
    EXPECT_EQ(k.id(), none.id());
}

MaterialDesc material(Technique t) {
    MaterialDesc m;
    m.name = "m";
    m.technique.technique = t;
    return m;
}

TEST(Planner, KeepsWhatTheContextCanDo) {
    MaterialDesc m = material(Technique::pom);
    m.technique.depth_write = true;
    m.technique.lod = true;
    m.technique.shadow = ShadowMode::soft;
    Result<VariantPlan> plan = plan_variant(m, Caps::full(2));
    ASSERT_TRUE(plan.ok());
    EXPECT_TRUE(plan->key.depth_write);
    EXPECT_TRUE(plan->key.lod);
    EXPECT_EQ(plan->key.shadow, ShadowMode::soft);
    EXPECT_TRUE(plan->key.shade_lod_bias());  // the hit shaded at the unshifted uv's mip level
    EXPECT_TRUE(plan->notes.empty());
}

TEST(Planner, DropsWhatAnEs2ContextLacksAndSaysWhy) {
    Caps bare = Caps::full(2);
    bare.extensions.clear();
    MaterialDesc m = material(Technique::relief);
    m.technique.depth_write = true;
    m.technique.lod = true;
    Result<VariantPlan> plan = plan_variant(m, bare);
    ASSERT_TRUE(plan.ok());
    EXPECT_FALSE(plan->key.depth_write);
    EXPECT_FALSE(plan->key.lod);
    // Without derivatives the hit is shaded at texture2D's own level.
    EXPECT_TRUE(plan->key.no_derivatives);
    EXPECT_FALSE(plan->key.shade_lod_bias());
    ASSERT_EQ(plan->notes.size(), 3u);
    EXPECT_NE(plan->notes[0].find("GL_EXT_frag_depth"), std::string::npos);
    EXPECT_NE(plan->notes[1].find("GL_OES_standard_derivatives"), std::string::npos);
    EXPECT_NE(plan->notes[2].find("blurred mip"), std::string::npos) << plan->notes[2];
    // Normal mapping shades the polygon's own uv: nothing to say.
    Result<VariantPlan> flat = plan_variant(material(Technique::normal), bare);
    ASSERT_TRUE(flat.ok());
    EXPECT_FALSE(flat->key.no_derivatives);
    EXPECT_TRUE(flat->notes.empty());
}

TEST(Planner, ZeroReliefFallsBackToNormalMapping) {
    MaterialDesc m = material(Technique::pom);
    m.height_scale = 0.0f;
    Result<VariantPlan> plan = plan_variant(m, Caps::full(3));
    ASSERT_TRUE(plan.ok());
    EXPECT_EQ(plan->key.technique, Technique::normal);
    ASSERT_EQ(plan->notes.size(), 1u);
    EXPECT_NE(plan->notes[0].find("height_scale is 0"), std::string::npos);
}

// maxmip's pyramid halves every level exactly: a height map that is not a
// power of two on both sides gets the table's fallback, with the reason; a
// square power of two keeps maxmip.
TEST(Planner, MaxmipOnANonPowerOfTwoHeightMapFallsBack) {
    MaterialDesc m = material(Technique::maxmip);
    Result<VariantPlan> npot = plan_variant(m, Caps::full(3), 200, 120);
    ASSERT_TRUE(npot.ok());
    EXPECT_EQ(npot->key.technique, technique_info(Technique::maxmip).fallback);
    ASSERT_EQ(npot->notes.size(), 1u);
    EXPECT_NE(npot->notes[0].find("200x120"), std::string::npos) << npot->notes[0];
    Result<VariantPlan> wide = plan_variant(m, Caps::full(3), 256, 64);
    ASSERT_TRUE(wide.ok());
    EXPECT_EQ(wide->key.technique, Technique::maxmip);
    Result<VariantPlan> one_side = plan_variant(m, Caps::full(3), 256, 96);
    ASSERT_TRUE(one_side.ok());
    EXPECT_NE(one_side->key.technique, Technique::maxmip);
}

TEST(Planner, OptionsTheTechniqueLacksAreNoted) {
    MaterialDesc m = material(Technique::offset_limited);
    m.technique.shadow = ShadowMode::hard;
    Result<VariantPlan> plan = plan_variant(m, Caps::full(3));
    ASSERT_TRUE(plan.ok());
    EXPECT_EQ(plan->key.shadow, ShadowMode::none);
    ASSERT_EQ(plan->notes.size(), 1u);
    EXPECT_NE(plan->notes[0].find("offset_limited"), std::string::npos);
}

// Habit 4 (STYLE.md): #version first, then extensions, then defines.
TEST(ShaderSource, VersionComesFirstThenExtensionsThenDefines) {
    VariantKey k;
    k.technique = Technique::pom;
    k.es_major = 2;
    k.max_samples = 16;
    k.depth_write = true;
    Result<VariantSources> s = assemble_variant(k);
    ASSERT_TRUE(s.ok()) << s.error().message;
    const std::string& text = s->fragment.text;
    EXPECT_EQ(text.rfind("#version 100\n", 0), 0u);
    const size_t extension = text.find("#extension GL_EXT_frag_depth : require");
    const size_t define = text.find("#define PX_MAX_SAMPLES 16");
    ASSERT_NE(extension, std::string::npos);
    ASSERT_NE(define, std::string::npos);
    EXPECT_LT(extension, define);
    EXPECT_EQ(text.find("#include"), std::string::npos) << "includes must be expanded";
    // The ES 3.0 source of the same variant needs no extension.
    k.es_major = 3;
    Result<VariantSources> s3 = assemble_variant(k);
    ASSERT_TRUE(s3.ok());
    EXPECT_EQ(s3->fragment.text.rfind("#version 300 es\n", 0), 0u);
    EXPECT_EQ(s3->fragment.text.find("#extension"), std::string::npos);
}

TEST(ShaderSource, MissingIncludeNamesTheFile) {
    Result<std::string> s = expand_includes("no/such_file.glsl");
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("no/such_file.glsl"), std::string::npos);
}

// Every chunk is included once per source even when two files include it.
TEST(ShaderSource, ChunksAreIncludedOnce) {
    Result<std::string> s = expand_includes("techniques/pom.frag");
    ASSERT_TRUE(s.ok());
    const std::string marker = "struct PxHit";
    const size_t first = s->find(marker);
    ASSERT_NE(first, std::string::npos);
    EXPECT_EQ(s->find(marker, first + 1), std::string::npos);
}

// Every uniform, attribute and varying carries a deliberate precision
// qualifier (Mesa defaults sampler2D to lowp and returns fp16 texels).
TEST(ShaderSource, EveryDeclarationHasAPrecisionQualifier) {
    const std::regex declaration(R"(^\s*(uniform|PX_VARYING|PX_ATTRIBUTE)\s+(\w+)\s+(\w+))");
    const std::regex qualified(R"(^\s*(uniform|PX_VARYING|PX_ATTRIBUTE)\s+(lowp|mediump|highp|PX_HIGHP|PX_VIEW_PRECISION)\s)");
    int declarations = 0;
    for (const EmbeddedShader& file : embedded_shaders()) {
        std::istringstream in(file.text);
        int line_number = 0;
        for (std::string line; std::getline(in, line);) {
            ++line_number;
            if (!std::regex_search(line, declaration)) continue;
            if (line.find("bool ") != std::string::npos) continue;  // bools have no precision
            ++declarations;
            EXPECT_TRUE(std::regex_search(line, qualified)) << file.path << ":" << line_number << ": " << line;
        }
    }
    EXPECT_GT(declarations, 30);
}

}  // namespace
}  // namespace px

namespace px {
namespace {

// The planner's notes come from the technique table: the techniques that
// cast a shadow ray or find a hit depth are every one whose row has the
// option (maxmip among them), not a list written in the note.
TEST(Planner, NotesNameTheTechniquesThatHaveTheOptionFromTheTable) {
    MaterialDesc m;
    m.name = "m";
    m.technique.technique = Technique::parallax;
    m.technique.shadow = ShadowMode::hard;
    m.technique.depth_write = true;
    Result<VariantPlan> plan = plan_variant(m, Caps::full(3));
    ASSERT_TRUE(plan.ok());
    ASSERT_EQ(plan->notes.size(), 2u);
    // "... casts no shadow ray (steep, pom, relief and maxmip do)": the list in brackets.
    auto listed = [](const std::string& note, const std::string& name) {
        const size_t open = note.find('(');
        const std::string list = open == std::string::npos ? "" : note.substr(open);
        return std::regex_search(list, std::regex("[(, ]" + name + "[,) ]"));
    };
    for (const TechniqueInfo& info : technique_table()) {
        EXPECT_EQ(listed(plan->notes[0], info.name), (info.options & kOptShadow) != 0)
            << plan->notes[0] << " / " << info.name;
        EXPECT_EQ(listed(plan->notes[1], info.name), (info.options & kOptDepth) != 0)
            << plan->notes[1] << " / " << info.name;
    }
    EXPECT_NE(plan->notes[0].find("maxmip"), std::string::npos) << "maxmip casts a shadow ray";
    EXPECT_EQ(technique_names_with(kOptShadow), "steep, pom, relief and maxmip");
}

// A technique the context is too old for becomes its table fallback, with
// at least the fallback's sample count, and the note says so.
TEST(Planner, TooNewATechniqueFallsBackAsTheTableSays) {
    for (const TechniqueInfo& info : technique_table()) {
        if (info.min_es_major <= 2) continue;
        MaterialDesc m;
        m.name = "m";
        m.technique.technique = info.id;
        Result<VariantPlan> plan = plan_variant(m, Caps::full(2));
        ASSERT_TRUE(plan.ok()) << info.name;
        EXPECT_EQ(plan->key.technique, info.fallback) << info.name;
        EXPECT_GE(plan->key.max_samples, info.fallback_min_samples) << info.name;
        ASSERT_FALSE(plan->notes.empty());
        EXPECT_NE(plan->notes[0].find(std::string(info.name) + " -> " + technique_name(info.fallback)),
                  std::string::npos)
            << plan->notes[0];
    }
}

// A technique whose row says it always takes the exact view vector gets it
// in every key, asked for or not.
TEST(VariantKey, AlwaysExactViewComesFromTheTable) {
    for (const TechniqueInfo& info : technique_table()) {
        VariantKey k;
        k.technique = info.id;
        k.exact_view = false;
        EXPECT_EQ(k.canonical().exact_view, info.always_exact_view) << info.name;
        const std::vector<ShaderDefine> d = k.defines();
        EXPECT_TRUE(std::any_of(d.begin(), d.end(), [&](const ShaderDefine& x) { return x.name == info.define; }))
            << info.name << " variants define " << info.define;
    }
}

}  // namespace
}  // namespace px

namespace px {
namespace {

// The interface table, read by the shader assembly without a context: every
// variant's declarations are in it, and a declaration that is not (a typo)
// or that has another type fails with the line.
TEST(ShaderInterface, EveryVariantsDeclarationsAreInTheTable) {
    for (int es : {2, 3})
        for (const VariantKey& key : enumerate_variants(es)) {
            Result<VariantSources> s = assemble_variant(key);
            EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
        }
    const Status typo = shader::check_declarations("precision mediump float;\nuniform mediump float u_specularr;\n", "t");
    ASSERT_FALSE(typo.ok());
    EXPECT_NE(typo.error().message.find("t, line 2: uniform 'u_specularr' is not in"), std::string::npos)
        << typo.error().message;
    const Status type = shader::check_declarations("uniform highp vec3 u_model;\n", "t");
    ASSERT_FALSE(type.ok());
    EXPECT_NE(type.error().message.find("declared as vec3"), std::string::npos) << type.error().message;
    const Status array = shader::check_declarations("uniform mediump vec3 u_light_color;\n", "t");
    EXPECT_FALSE(array.ok()) << "u_light_color is an array in the table";
    const Status attribute = shader::check_declarations("PX_ATTRIBUTE highp vec3 a_uv;\n", "t");
    ASSERT_FALSE(attribute.ok());
    EXPECT_NE(attribute.error().message.find("2 components (vec2)"), std::string::npos) << attribute.error().message;
    EXPECT_TRUE(shader::check_declarations("uniform mediump sampler2D u_max_map;\nPX_ATTRIBUTE highp vec2 a_uv;\n", "t").ok());
}

}  // namespace
}  // namespace px

namespace px {
namespace {

// A variant field is one row of one table (effects/variant.cpp): a field
// added at run time reaches the description, the parser, the defines and
// the identity the program cache keys on. The key once held 64 bits and
// every one was in use; here seventy flags each make a variant of their own
// on top of a key that sets every built-in field.
TEST(VariantKey, AFieldAddedToTheTableReachesEveryUseOfTheKey) {
    ASSERT_TRUE(add_variant_field({"test-grain", "PX_TEST_GRAIN", 9, kOptSamples}).ok());
    EXPECT_FALSE(add_variant_field({"test-grain", "PX_TEST_GRAIN", 9, 0}).ok()) << "twice";
    EXPECT_FALSE(add_variant_field({"depth", "PX_DEPTH_AGAIN", 1, 0}).ok()) << "a built-in field's word";
    EXPECT_FALSE(add_variant_field({"bad word", "PX_BAD", 1, 0}).ok());
    EXPECT_FALSE(add_variant_field({"lowercase-define", "px_bad", 1, 0}).ok());

    VariantKey k;
    k.technique = Technique::pom;
    k.max_samples = 32;
    k.shadow = ShadowMode::soft;
    k.shadow_samples = 16;
    k.depth_write = k.lod = k.exact_view = true;
    VariantKey grained = k;
    grained.added["test-grain"] = 5;
    EXPECT_EQ(grained.describe(), k.describe() + " test-grain=5");
    EXPECT_NE(grained.id(), k.id());
    EXPECT_FALSE(grained == k);
    bool defined = false;
    for (const ShaderDefine& d : grained.defines()) defined = defined || (d.name == "PX_TEST_GRAIN" && d.value == "5");
    EXPECT_TRUE(defined);
    Result<VariantKey> parsed = VariantKey::parse(grained.describe());
    ASSERT_TRUE(parsed.ok()) << parsed.error().message;
    EXPECT_EQ(parsed->added.at("test-grain"), 5u);
    EXPECT_TRUE(*parsed == grained);
    EXPECT_FALSE(VariantKey::parse(k.describe() + " test-grain=10").ok()) << "past its range";
    // A technique without the field's options does not carry it.
    VariantKey normal = grained;
    normal.technique = Technique::normal;
    EXPECT_EQ(normal.canonical().added.count("test-grain"), 0u);

    // Past 64 bits: every built-in field set, and seventy more flags.
    std::set<std::string> ids{grained.id()};
    for (int i = 0; i < 70; ++i) {
        std::string word = "test-flag-";
        for (int n = i; n >= 0; n = n / 26 - 1) word += static_cast<char>('a' + n % 26);
        std::string define = "PX_TEST_FLAG_";
        for (char c : word.substr(10)) define += static_cast<char>(c - 'a' + 'A');
        ASSERT_TRUE(add_variant_field({word, define, 1, 0}).ok()) << word;
        VariantKey flagged = grained;
        flagged.added[word] = 1;
        EXPECT_TRUE(ids.insert(flagged.id()).second) << flagged.id();
        Result<VariantKey> back = VariantKey::parse(flagged.describe());
        ASSERT_TRUE(back.ok()) << back.error().message;
        EXPECT_TRUE(*back == flagged);
    }
    EXPECT_EQ(ids.size(), 71u);
}

// Every variant's name names it again (parallax profile takes names, and
// its NIR child process is handed ids, which are names).
TEST(VariantNames, ParseRoundTrips) {
    int checked = 0;
    for (int es : {2, 3})
        for (const VariantKey& k : enumerate_variants(es)) {
            Result<VariantKey> parsed = VariantKey::parse(k.describe());
            ASSERT_TRUE(parsed) << k.describe() << ": " << parsed.error().message;
            EXPECT_EQ(parsed->id(), k.id()) << k.describe();
            EXPECT_EQ(parsed->defines().size(), k.defines().size()) << k.describe();
            ++checked;
        }
    EXPECT_GT(checked, 400);
    // A name for a variant the enumeration does not hold.
    Result<VariantKey> pom64 = VariantKey::parse("pom es3 samples<=64 exact-view packed");
    ASSERT_TRUE(pom64);
    EXPECT_EQ(pom64->max_samples, 64);
    EXPECT_FALSE(VariantKey::parse("pom es3 samples<=64 sparkly"));
    EXPECT_FALSE(VariantKey::parse("nope es3"));
    EXPECT_FALSE(VariantKey::parse(""));
    // An option the technique lacks is not silently dropped.
    EXPECT_FALSE(VariantKey::parse("normal es3 samples<=32"));
    EXPECT_FALSE(VariantKey::parse("pom es3 samples<=9999999"));
}

}  // namespace
}  // namespace px

// Compile logs as real drivers wrote them for the same four-line shader
// (line 4: `undeclared_name = 1.0;`): the source line each points at is
// found whatever the vendor's format, and numbers that are not line
// references (columns, version numbers, error codes) are not taken for one.
TEST(ShaderLog, LinesFromEachDriversFormat) {
    // NVIDIA 580.159.04 on an H200 (EGL device, this project's GPU tests, 2026-12-04).
    EXPECT_EQ(px::shader_log_lines("0(4) : error C1503: undefined variable \"undeclared_name\"\n"), std::vector<long>{4});
    // Mesa 22.3 llvmpipe (this machine): line, then the column in parentheses.
    EXPECT_EQ(px::shader_log_lines("0:4(2): error: `undeclared_name' undeclared\n0:4(2): error: value of type float "
                               "cannot be assigned to variable of type error\n"),
              std::vector<long>{4});
    // glslangValidator 11:12.0.0 (Debian 12), the reference compiler ANGLE's messages follow.
    EXPECT_EQ(px::shader_log_lines("ERROR: 0:4: 'undeclared_name' : undeclared identifier \nERROR: 0:4: '' : "
                               "compilation terminated \nERROR: 2 compilation errors.  No code generated.\n"),
              std::vector<long>{4});
    // Several lines, in order of first mention, and at most `limit`.
    EXPECT_EQ(px::shader_log_lines("0:12(5): error: a\n0:3(1): error: b\n0:12(9): error: c\n"), (std::vector<long>{12, 3}));
    EXPECT_EQ(px::shader_log_lines("0(1) : e\n0(2) : e\n0(3) : e\n", 2), (std::vector<long>{1, 2}));
    // Not line references: "10:" and "1.0:" are not "0:", nor a "0(" without its ")", nor line 0.
    EXPECT_TRUE(px::shader_log_lines("error C1503 at 10:20, version 1.0: (0.5) 0(12 0:0 0(0)").empty());
    EXPECT_TRUE(px::shader_log_lines("").empty());
}
