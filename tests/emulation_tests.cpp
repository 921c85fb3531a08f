// The precision emulation without GL (include/parallaxes/emulation/precision.h): the CPU
// rounding against IEEE 754 binary16 and GLSL ES 1.00 section 4.5.2, and the
// rewriter over every variant the program can build.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>

#include "parallaxes/emulation/precision.h"
#include "parallaxes/shaders/shader_source.h"

namespace px::emulation {
namespace {

float bits(std::uint32_t u) {
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

TEST(RoundFp16, KnownValues) {
    // 1 + 2^-11 lies halfway between 1 and 1 + 2^-10: ties to even (1).
    EXPECT_EQ(round_fp16(1.0f + std::ldexp(1.0f, -11)), 1.0f);
    // 1 + 3 * 2^-11 lies halfway between 1 + 2^-10 (odd) and 1 + 2^-9: up.
    EXPECT_EQ(round_fp16(1.0f + 3.0f * std::ldexp(1.0f, -11)), 1.0f + std::ldexp(1.0f, -9));
    // Just above the tie: up.
    EXPECT_EQ(round_fp16(std::nextafter(1.0f + std::ldexp(1.0f, -11), 2.0f)), 1.0f + std::ldexp(1.0f, -10));
    EXPECT_EQ(round_fp16(0.1f), 0.0999755859375f);
    EXPECT_EQ(round_fp16(-0.1f), -0.0999755859375f);
    EXPECT_EQ(round_fp16(65504.0f), 65504.0f);  // the largest finite
    EXPECT_EQ(round_fp16(65519.0f), 65504.0f);  // below the midpoint to 65536
    EXPECT_EQ(round_fp16(65520.0f), std::numeric_limits<float>::infinity());  // the tie goes to even: overflow
    EXPECT_EQ(round_fp16(-70000.0f), -std::numeric_limits<float>::infinity());
    EXPECT_EQ(round_fp16(std::ldexp(1.0f, -14)), std::ldexp(1.0f, -14));  // the smallest normal
    EXPECT_EQ(round_fp16(std::ldexp(1.0f, -24)), std::ldexp(1.0f, -24));  // the smallest subnormal
    EXPECT_EQ(round_fp16(std::ldexp(1.0f, -25)), 0.0f);                   // half of it: ties to even (0)
    EXPECT_EQ(round_fp16(std::ldexp(1.5f, -25)), std::ldexp(1.0f, -24));
    EXPECT_EQ(round_fp16(std::ldexp(3.0f, -25)), std::ldexp(2.0f, -24));  // 1.5 quanta: to even (2)
    EXPECT_EQ(round_fp16(std::ldexp(5.0f, -25)), std::ldexp(2.0f, -24));  // 2.5 quanta: to even (2)
    EXPECT_EQ(round_fp16(1e-6f), std::ldexp(17.0f, -24));                 // 16.78 quanta
    EXPECT_TRUE(std::signbit(round_fp16(-1e-9f)));                        // -0 keeps its sign
    EXPECT_TRUE(std::isnan(round_fp16(std::numeric_limits<float>::quiet_NaN())));
    EXPECT_EQ(round_fp16(std::numeric_limits<float>::infinity()), std::numeric_limits<float>::infinity());
}

// The compiler's own IEEE binary16: _Float16 on x86-64, __fp16 on AArch64
// (GCC 12's C++ has no _Float16 there; AArch64's __fp16 is IEEE). 32-bit
// ARM's __fp16 needs -mfp16-format: the test is left out there.
#if defined(__aarch64__)
#define PX_COMPILER_HALF __fp16
#elif defined(__FLT16_MAX__) && !defined(__arm__)
#define PX_COMPILER_HALF _Float16
#endif

#ifdef PX_COMPILER_HALF
// The compiler's own float -> binary16 conversion (IEEE, round to nearest
// even) over random bit patterns and every exponent.
TEST(RoundFp16, MatchesTheCompilersBinary16) {
    std::mt19937 random(12345);
    for (int i = 0; i < 2000000; ++i) {
        const float x = bits(static_cast<std::uint32_t>(random()));
        const float expected = static_cast<float>(static_cast<PX_COMPILER_HALF>(x));
        const float got = round_fp16(x);
        if (std::isnan(x)) {
            EXPECT_TRUE(std::isnan(got));
            continue;
        }
        ASSERT_EQ(std::memcmp(&got, &expected, 4), 0) << "x = " << x << " (bits " << std::hex
                                                       << *reinterpret_cast<const std::uint32_t*>(&x) << ")";
    }
}
#endif

TEST(RoundLowp, Minimums) {
    EXPECT_EQ(round_lowp(0.5f), 0.5f);
    EXPECT_EQ(round_lowp(1.0f / 512.0f), 0.0f);               // half a quantum: ties to even
    EXPECT_EQ(round_lowp(3.0f / 512.0f), 2.0f / 256.0f);      // 1.5 quanta: to even
    EXPECT_EQ(round_lowp(0.3f), 77.0f / 256.0f);              // 76.8 quanta
    EXPECT_EQ(round_lowp(-0.3f), -77.0f / 256.0f);
    EXPECT_EQ(round_lowp(1.999f), 2.0f);
    EXPECT_EQ(round_lowp(3.5f), 2.0f);                         // clamped to the range
    EXPECT_EQ(round_lowp(-100.0f), -2.0f);
    EXPECT_EQ(round_lowp(std::numeric_limits<float>::infinity()), 2.0f);
    EXPECT_TRUE(std::isnan(round_lowp(std::numeric_limits<float>::quiet_NaN())));
}

TEST(Profiles, NamesRoundTrip) {
    for (PrecisionProfile p :
         {PrecisionProfile::identity, PrecisionProfile::fp32, PrecisionProfile::fp16, PrecisionProfile::lowp, PrecisionProfile::nohighp, PrecisionProfile::lowp_all}) {
        auto parsed = parse_profile(profile_name(p));
        ASSERT_TRUE(parsed.ok());
        EXPECT_EQ(*parsed, p);
    }
    auto bad = parse_profile("half");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("half"), std::string::npos);
}

TEST(Emulation, ParseErrorsCarryGlslangsLog) {
    auto r = emulate_precision("#version 300 es\nvoid main() { undeclared = 1.0; }\n", ShaderStage::vertex,
                               PrecisionProfile::fp16);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("undeclared"), std::string::npos) << r.error().message;
}

TEST(Emulation, UnsupportedConstructsAreErrors) {
    // An interface block: not something the shaders use, so not emitted.
    auto r = emulate_precision("#version 300 es\nprecision highp float;\nuniform B { vec4 v; } b;\n"
                               "out vec4 c;\nvoid main() { c = b.v; }\n",
                               ShaderStage::fragment, PrecisionProfile::fp16);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("does not support"), std::string::npos) << r.error().message;
}

TEST(Emulation, RoundsMediumpNotHighp) {
    const std::string source =
        "#version 300 es\nprecision mediump float;\nuniform highp float u_h;\nuniform mediump float u_m;\n"
        "out highp vec4 c;\nvoid main() { highp float h = u_h * 3.0; mediump float m = u_m * 3.0; c = vec4(h, m, 0.0, 1.0); }\n";
    auto fp16 = emulate_precision(source, ShaderStage::fragment, PrecisionProfile::fp16);
    ASSERT_TRUE(fp16.ok()) << fp16.error().message;
    EXPECT_NE(fp16->find("px_q16((px_q16(u_m) * 3.0))"), std::string::npos) << *fp16;
    EXPECT_NE(fp16->find("(u_h * 3.0)"), std::string::npos) << *fp16;
    auto fp32 = emulate_precision(source, ShaderStage::fragment, PrecisionProfile::identity);
    ASSERT_TRUE(fp32.ok()) << fp32.error().message;
    EXPECT_EQ(fp32->find("px_q16("), std::string::npos) << *fp32;
    auto nohighp = emulate_precision(source, ShaderStage::fragment, PrecisionProfile::nohighp);
    ASSERT_TRUE(nohighp.ok()) << nohighp.error().message;
    EXPECT_NE(nohighp->find("px_q16((px_q16(u_h) * 3.0))"), std::string::npos) << *nohighp;
}

// Every variant of both ES versions, both stages, every profile: rewritten
// without error, and the result is valid GLSL ES 3.00 to glslang.
TEST(Emulation, EveryVariantRewritesAndParses) {
    const char* dump = std::getenv("PX_EMULATION_DUMP_DIR");  // keeps the emitted sources, for reading
    int checked = 0;
    for (int es : {2, 3}) {
        for (const VariantKey& key : enumerate_variants(es)) {
            auto sources = assemble_variant(key);
            ASSERT_TRUE(sources.ok()) << sources.error().message;
            for (PrecisionProfile profile :
                 {PrecisionProfile::identity, PrecisionProfile::fp32, PrecisionProfile::fp16, PrecisionProfile::lowp, PrecisionProfile::nohighp, PrecisionProfile::lowp_all}) {
                for (ShaderStage stage : {ShaderStage::vertex, ShaderStage::fragment}) {
                    const std::string& text = stage == ShaderStage::vertex ? sources->vertex.text : sources->fragment.text;
                    auto emitted = emulate_precision(text, stage, profile);
                    ASSERT_TRUE(emitted.ok()) << key.describe() << ": " << emitted.error().message;
                    ASSERT_EQ(emitted->rfind("#version 300 es\n", 0), 0u);
                    Status parsed = check_parses(*emitted, stage);
                    if (dump && (!parsed.ok() || checked < 64)) {
                        std::ofstream(std::string(dump) + "/" + std::to_string(checked) + "_" + profile_name(profile) +
                                      (stage == ShaderStage::vertex ? ".vert" : ".frag"))
                            << "// " << key.describe() << "\n" << *emitted;
                    }
                    ASSERT_TRUE(parsed.ok()) << key.describe() << " " << profile_name(profile) << ": "
                                             << parsed.error().message << "\n" << *emitted;
                    ++checked;
                }
            }
        }
    }
    EXPECT_GT(checked, 400);
}

}  // namespace
}  // namespace px::emulation
