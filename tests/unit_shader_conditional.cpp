// The partial preprocessor (include/parallaxes/shaders/conditional.h) on small inputs, and
// the assembled sources of every variant: no code of an effect a variant
// does not use (include/parallaxes/shaders/effect_code.h). Pure text, no GL.
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <sstream>

#include "parallaxes/effects/variant.h"
#include "parallaxes/shaders/conditional.h"
#include "parallaxes/shaders/effect_code.h"
#include "parallaxes/shaders/shader_source.h"

namespace px {
namespace {

std::string resolved(const std::string& text) {
    Result<std::string> r = resolve_conditionals(text, "t");
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? *r : "<error>";
}

std::string error_of(const std::string& text, const std::vector<LineOrigin>& origins = {}) {
    Result<std::string> r = resolve_conditionals(text, "t", origins);
    EXPECT_FALSE(r.ok()) << "resolved to:\n" << (r.ok() ? *r : "");
    return r.ok() ? "" : r.error().message;
}

TEST(Conditional, NestedBlocksResolveAndTheirDirectivesGo) {
    EXPECT_EQ(resolved("#define PX_A\n"
                       "#ifdef PX_A\n"
                       "a\n"
                       "#ifdef PX_B\n"
                       "b\n"
                       "#ifndef PX_A\n"
                       "deep\n"
                       "#endif\n"
                       "#else\n"
                       "not b\n"
                       "#ifndef PX_B\n"
                       "not b either\n"
                       "#endif\n"
                       "#endif\n"
                       "#else\n"
                       "not a\n"
                       "#endif\n"
                       "tail\n"),
              "#define PX_A\na\nnot b\nnot b either\ntail\n");
}

TEST(Conditional, ElifChainsTakeTheFirstTrueBranch) {
    const std::string chain =
        "#if PX_N == 1\none\n#elif PX_N == 2\ntwo\n#elif PX_N >= 2\nthree\n#else\nother\n#endif\n";
    EXPECT_EQ(resolved("#define PX_N 1\n" + chain), "#define PX_N 1\none\n");
    EXPECT_EQ(resolved("#define PX_N 2\n" + chain), "#define PX_N 2\ntwo\n") << "not three: the first true wins";
    EXPECT_EQ(resolved("#define PX_N 5\n" + chain), "#define PX_N 5\nthree\n");
    EXPECT_EQ(resolved("#define PX_N 0\n" + chain), "#define PX_N 0\nother\n");
    // A name defined as another name that is an integer; hex and octal.
    EXPECT_EQ(resolved("#define PX_THREE 0x3\n#define PX_N PX_THREE\n#if PX_N == 03 && PX_N < 4 && PX_N > 2 "
                       "&& PX_N <= 3 && PX_N != 2\nyes\n#endif\n"),
              "#define PX_THREE 0x3\n#define PX_N PX_THREE\nyes\n");
}

// The driver's macros (GL_*): the structure is kept as written, and what the
// source decides inside its branches is resolved.
TEST(Conditional, UnknownConditionsStayVerbatimWithKnownOnesInsideResolved) {
    EXPECT_EQ(resolved("#define PX_A 1\n"
                       "#if defined(GL_FRAGMENT_PRECISION_HIGH)  // the driver's\n"
                       "hi\n"
                       "#ifdef PX_A\n"
                       "a\n"
                       "#endif\n"
                       "#else\n"
                       "lo\n"
                       "#if PX_A == 2\n"
                       "two\n"
                       "#endif\n"
                       "#endif\n"),
              "#define PX_A 1\n#if defined(GL_FRAGMENT_PRECISION_HIGH)  // the driver's\nhi\na\n#else\nlo\n#endif\n");
    EXPECT_EQ(resolved("#ifdef GL_ES\nes\n#endif\n"), "#ifdef GL_ES\nes\n#endif\n");
    EXPECT_EQ(resolved("#if __VERSION__ >= 300\nv3\n#endif\n"), "#if __VERSION__ >= 300\nv3\n#endif\n");
    // A name outside PX_ that we never defined is the driver's too.
    EXPECT_EQ(resolved("#ifndef SOME_MACRO\nx\n#endif\n"), "#ifndef SOME_MACRO\nx\n#endif\n");

    // An #elif chain with a driver's branch in the middle: the false branches
    // go, the unknown one opens the kept structure, the first true one after
    // it becomes its #else, and nothing after that is left.
    const std::string chain =
        "#if PX_N == 1\none\n#elif GL_ES\nes\n#elif PX_N == 2\ntwo\n#else\nother\n#endif\n";
    EXPECT_EQ(resolved("#define PX_N 1\n" + chain), "#define PX_N 1\none\n");
    EXPECT_EQ(resolved("#define PX_N 2\n" + chain), "#define PX_N 2\n#if GL_ES\nes\n#else\ntwo\n#endif\n");
    EXPECT_EQ(resolved("#define PX_N 3\n" + chain), "#define PX_N 3\n#if GL_ES\nes\n#else\nother\n#endif\n");
    EXPECT_EQ(resolved("#if GL_A\na\n#elif defined(PX_NONE)\nnone\n#elif GL_B\nb\n#endif\n"),
              "#if GL_A\na\n#elif GL_B\nb\n#endif\n");
}

TEST(Conditional, DefinesInActiveCodeDecideLaterConditions) {
    EXPECT_EQ(resolved("#ifdef PX_OFF\n"
                       "#define PX_C\n"  // never compiled: PX_C stays undefined
                       "#endif\n"
                       "#define PX_B 2\n"
                       "#if PX_B >= 2\n"
                       "#define PX_HAS\n"
                       "#endif\n"
                       "#ifdef PX_HAS\n"
                       "has\n"
                       "#endif\n"
                       "#ifdef PX_C\n"
                       "c\n"
                       "#endif\n"
                       "#undef PX_B\n"
                       "#ifdef PX_B\n"
                       "b\n"
                       "#endif\n"),
              "#define PX_B 2\n#define PX_HAS\nhas\n#undef PX_B\n");
    // Defined inside a branch the driver decides: unknown from then on, in
    // both directions (#define and #undef).
    EXPECT_EQ(resolved("#ifdef GL_ES\n#define PX_X\n#endif\n#ifdef PX_X\nx\n#endif\n"),
              "#ifdef GL_ES\n#define PX_X\n#endif\n#ifdef PX_X\nx\n#endif\n");
    EXPECT_EQ(resolved("#define PX_Y\n#ifdef GL_ES\n#undef PX_Y\n#endif\n#ifndef PX_Y\ny\n#endif\n"),
              "#define PX_Y\n#ifdef GL_ES\n#undef PX_Y\n#endif\n#ifndef PX_Y\ny\n#endif\n");
    // ... and known again once redefined in code that is certainly compiled.
    EXPECT_EQ(resolved("#ifdef GL_ES\n#define PX_X 1\n#endif\n#define PX_X 2\n#if PX_X == 2\ntwo\n#endif\n"),
              "#ifdef GL_ES\n#define PX_X 1\n#endif\n#define PX_X 2\ntwo\n");
}

TEST(Conditional, ThreeValuedLogicShortCircuits) {
    // unknown && false is false; false && unknown too.
    EXPECT_EQ(resolved("#if defined(GL_FRAGMENT_PRECISION_HIGH) && !defined(PX_NO_HIGHP) \n#define PX_HIGHP highp\n"
                       "#else\n#define PX_HIGHP mediump\n#endif\n"),
              "#if defined(GL_FRAGMENT_PRECISION_HIGH) && !defined(PX_NO_HIGHP) \n#define PX_HIGHP highp\n"
              "#else\n#define PX_HIGHP mediump\n#endif\n")
        << "unknown && true: kept";
    EXPECT_EQ(resolved("#define PX_NO_HIGHP\n#if defined(GL_FRAGMENT_PRECISION_HIGH) && !defined(PX_NO_HIGHP)\n"
                       "#define PX_HIGHP highp\n#else\n#define PX_HIGHP mediump\n#endif\n"),
              "#define PX_NO_HIGHP\n#define PX_HIGHP mediump\n");
    EXPECT_EQ(resolved("#if defined PX_NONE && GL_X == 2\nx\n#endif\n"), "");
    // unknown || true is true, true || unknown too.
    EXPECT_EQ(resolved("#define PX_ES 3\n#if GL_X || PX_ES >= 3\nx\n#else\ny\n#endif\n"), "#define PX_ES 3\nx\n");
    EXPECT_EQ(resolved("#if 1 || GL_X\nx\n#endif\n"), "x\n");
    // unknown || false stays unknown.
    EXPECT_EQ(resolved("#if GL_X || defined(PX_NONE)\nx\n#endif\n"), "#if GL_X || defined(PX_NONE)\nx\n#endif\n");
    // A decided false beside an unknown one, through ! and parentheses.
    EXPECT_EQ(resolved("#if !(GL_X || 1)\nx\n#endif\n"), "");
}

// What it cannot read stays for the driver: never decided wrongly.
TEST(Conditional, WhatItCannotParseIsKeptVerbatim) {
    for (const std::string condition : {"PX_A + 1 == 2", "PX_UNDEFINED == 0", "PX_EMPTY", "PX_F(1)", "(1",
                                        "defined", "1 ? 2 : 3", "1u", "99999999999 > 1"}) {
        const std::string text = "#define PX_A 1\n#define PX_EMPTY\n#define PX_F(x) x\n#if " + condition +
                                 "\nx\n#endif\n";
        EXPECT_EQ(resolved(text), text) << condition;
    }
    EXPECT_EQ(resolved("#ifdef PX_A PX_B\nx\n#endif\n"), "#ifdef PX_A PX_B\nx\n#endif\n");
}

TEST(Conditional, CommentsAndSplicesAreReadAsThePreprocessorDoes) {
    // A '#' inside a block comment starts no directive; comments on
    // directive lines are not part of the condition.
    EXPECT_EQ(resolved("/* a comment\n#ifdef PX_NONE\n*/\nkept\n#ifdef PX_NONE /* off */ // still off\ngone\n"
                       "// a comment in a dropped block goes with it\n#endif\n"),
              "/* a comment\n#ifdef PX_NONE\n*/\nkept\n");
    // A backslash splices a directive across lines (GLSL ES 3.00).
    EXPECT_EQ(resolved("#define PX_A\n#if defined(PX_A) \\\n && defined(PX_B)\nx\n#endif\n"), "#define PX_A\n");
    // Spaces around the '#'.
    EXPECT_EQ(resolved("  #  ifdef PX_NONE\nx\n\t# endif\ny\n"), "y\n");
    EXPECT_NE(error_of("#ifdef PX_A /* runs on\n*/\n#endif\n").find("t:1"), std::string::npos);
}

TEST(Conditional, MalformedStructureIsAnErrorNamingTheLine) {
    EXPECT_NE(error_of("a\n#endif\n").find("t:2: #endif without #if"), std::string::npos);
    EXPECT_NE(error_of("#else\n").find("t:1: #else without #if"), std::string::npos);
    EXPECT_NE(error_of("#elif 1\n").find("t:1: #elif without #if"), std::string::npos);
    EXPECT_NE(error_of("#if 1\n#else\n#else\n#endif\n").find("t:3: #else after #else (the #if at t:1)"),
              std::string::npos);
    EXPECT_NE(error_of("#if 1\n#else\n#elif 1\n#endif\n").find("t:3: #elif after #else"), std::string::npos);
    EXPECT_NE(error_of("x\n#ifdef PX_A\n#if 1\n#endif\n").find("t:2: #if without #endif"), std::string::npos);
    // In dead code too: the structure is read everywhere.
    EXPECT_NE(error_of("#if 0\n#ifdef GL_ES\n#else\n#else\n#endif\n#endif\n").find("t:4"), std::string::npos);
    // With origins, the message names the file and line they give.
    const std::vector<LineOrigin> origins = {{"shaders_es/a.glsl", 7}, {"shaders_es/b.glsl", 12}};
    EXPECT_NE(error_of("#if 1\n#else\n#else\n", origins).find("#else after #else (the #if at shaders_es/a.glsl:7)"),
              std::string::npos);
    EXPECT_NE(error_of("x\n#endif\n", origins).find("shaders_es/b.glsl:12: #endif without #if"), std::string::npos);
}

std::vector<VariantKey> every_variant() {
    std::vector<VariantKey> keys = enumerate_variants(2);
    for (const VariantKey& k : enumerate_variants(3)) keys.push_back(k);
    return keys;
}

// Every enumerated variant carries no marker of an effect it does not use,
// and every marker occurs in some variant that uses its effect (so the check
// can fail: a marker that never occurs would pass vacuously).
TEST(AssembledSource, NoVariantCarriesCodeOfAnEffectItDoesNotUse) {
    std::vector<int> seen_where_used(effect_markers().size(), 0);
    int variants = 0;
    for (const VariantKey& key : every_variant()) {
        Result<VariantSources> s = assemble_variant(key);
        ASSERT_TRUE(s.ok()) << s.error().message;
        ++variants;
        for (const std::string& found : unused_effect_code(key, *s)) ADD_FAILURE() << found;
        for (std::size_t i : effect_markers_in(*s))
            if (effect_markers()[i].used(key.canonical())) ++seen_where_used[i];
    }
    EXPECT_GT(variants, 200);
    for (std::size_t i = 0; i < effect_markers().size(); ++i)
        EXPECT_GT(seen_where_used[i], 0) << effect_markers()[i].effect << ": '" << effect_markers()[i].code
                                         << "' occurs in no variant that uses it";
}

// The negative control: the unresolved body of a variant (what the driver
// got before) carries the code of effects it does not use, and the check
// finds it.
TEST(AssembledSource, TheCheckFindsCodeInAnUnresolvedSource) {
    VariantKey key;
    key.technique = Technique::pom;
    key.max_samples = 16;
    Result<std::string> vertex = expand_includes("surface.vert");
    Result<std::string> fragment = expand_includes("techniques/pom.frag");
    ASSERT_TRUE(vertex.ok() && fragment.ok());
    VariantSources raw;
    raw.vertex.text = *vertex;
    raw.fragment.text = *fragment;
    const std::vector<std::string> found = unused_effect_code(key, raw);
    std::string all;
    for (const std::string& f : found) all += f + "\n";
    for (const char* marker : {"px_light_visibility", "px_write_depth", "px_mip_level", "px_debug_output", "PX_SHADOW"})
        EXPECT_NE(all.find(std::string("'") + marker + "'"), std::string::npos) << marker << " in\n" << all;
}

// What the driver still decides is only what it alone knows: every
// conditional directive left in an assembled source names one of its
// macros (GL_*), and the #version line stays first.
TEST(AssembledSource, OnlyTheDriversConditionsRemain) {
    const std::regex conditional(R"(^\s*#\s*(if|ifdef|ifndef|elif)\b(.*)$)");
    const std::regex drivers(R"(\bGL_\w+)");
    std::map<std::string, int> kept;
    for (const VariantKey& key : every_variant()) {
        Result<VariantSources> s = assemble_variant(key);
        ASSERT_TRUE(s.ok()) << s.error().message;
        for (const std::string* text : {&s->vertex.text, &s->fragment.text}) {
            EXPECT_EQ(text->rfind("#version", 0), 0u);
            std::istringstream in(*text);
            for (std::string line; std::getline(in, line);) {
                std::smatch m;
                if (!std::regex_search(line, m, conditional)) continue;
                EXPECT_TRUE(std::regex_search(m[2].str(), drivers)) << key.describe() << ": " << line;
                ++kept[line];
            }
        }
    }
    // GLSL ES 1.00 keeps the fragment-highp choice (the preamble's PX_HIGHP
    // and the debug packing); GLSL ES 3.00 keeps none.
    EXPECT_FALSE(kept.empty());
}

TEST(AssembledSource, Es3SourcesKeepNoConditionalAtAll) {
    for (const VariantKey& key : enumerate_variants(3)) {
        Result<VariantSources> s = assemble_variant(key);
        ASSERT_TRUE(s.ok()) << s.error().message;
        for (const std::string* text : {&s->vertex.text, &s->fragment.text})
            EXPECT_EQ(text->find("#if"), std::string::npos) << key.describe();
    }
}

}  // namespace
}  // namespace px
