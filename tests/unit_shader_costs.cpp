// The static cost extraction counts what the compiler emitted: glslang's
// SPIR-V for hand-written stages whose costs are known, and for real
// variants whose differences are known; the NIR reader on a dump written
// for the test in Mesa 22.3's format; the cost model's file and arithmetic.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "parallaxes/profiling/costs/cost_model.h"
#include "parallaxes/profiling/costs/shader_costs.h"
#include "parallaxes/shaders/shader_source.h"

namespace px::profiling {
namespace {

StageCost fragment(const std::string& body) {
    const std::string source = "#version 300 es\nprecision highp float;\nuniform sampler2D u_a;\nuniform sampler2D u_b;\n"
                               "uniform sampler2D u_c;\nin highp vec2 v_uv;\nin highp vec2 v_offset;\n"
                               "layout(location = 0) out highp vec4 o;\n" + body;
    Result<std::vector<std::uint32_t>> words = compile_spirv(source, ShaderStage::fragment);
    EXPECT_TRUE(words) << (words ? "" : words.error().message);
    if (!words) return {};
    Result<StageCost> cost = analyse_spirv(*words, ShaderStage::fragment);
    EXPECT_TRUE(cost) << (cost ? "" : cost.error().message);
    return cost ? *cost : StageCost{};
}

StageCost variant_stage(const VariantKey& key, ShaderStage stage) {
    Result<VariantSources> sources = assemble_variant(key);
    EXPECT_TRUE(sources) << (sources ? "" : sources.error().message);
    if (!sources) return {};
    Result<StageCost> cost = stage_cost(stage == ShaderStage::vertex ? sources->vertex : sources->fragment, stage);
    EXPECT_TRUE(cost) << key.describe() << ": " << (cost ? "" : cost.error().message);
    return cost ? *cost : StageCost{};
}

TEST(ShaderCosts, OneMoreDependentReadShowsAsOneMoreSampleAndOneMoreDependentRead) {
    const StageCost two = fragment(R"(void main() {
    float h = texture(u_a, v_uv).r;
    vec2 uv = v_uv + h * v_offset;
    o = texture(u_b, uv);
})");
    const StageCost three = fragment(R"(void main() {
    float h = texture(u_a, v_uv).r;
    vec2 uv = v_uv + h * v_offset;
    o = texture(u_b, uv) + texture(u_c, uv);
})");
    EXPECT_EQ(two.samples.size(), 2u);
    EXPECT_EQ(two.dependent_samples, 1);
    EXPECT_EQ(three.samples.size(), 3u);
    EXPECT_EQ(three.dependent_samples, 2);
    EXPECT_DOUBLE_EQ(three.total.samples, two.total.samples + 1.0);
    // Both dependent reads wait on the same first read: one round trip more than none.
    EXPECT_DOUBLE_EQ(two.texture_round_trips, 2.0);
    EXPECT_DOUBLE_EQ(three.texture_round_trips, 2.0);
    EXPECT_FALSE(three.samples[0].dependent);
    EXPECT_EQ(three.samples[1].waits_on, std::vector<int>{0});
    // In order: read, wait, two reads back to back, wait.
    EXPECT_EQ(three.in_order_waits, 2);
}

TEST(ShaderCosts, InterleavedReadsWaitMoreOftenThanBackToBackOnes) {
    const StageCost interleaved = fragment(R"(void main() {
    vec4 a = texture(u_a, v_uv);
    vec4 x = a * 2.0 - 1.0;
    vec4 b = texture(u_b, v_uv);
    o = x + b;
})");
    const StageCost together = fragment(R"(void main() {
    vec4 a = texture(u_a, v_uv);
    vec4 b = texture(u_b, v_uv);
    vec4 x = a * 2.0 - 1.0;
    o = x + b;
})");
    EXPECT_EQ(interleaved.in_order_waits, 2);
    EXPECT_EQ(together.in_order_waits, 1);
    EXPECT_DOUBLE_EQ(interleaved.total.arithmetic, together.total.arithmetic);
}

TEST(ShaderCosts, IndependentReadsAreNotDependent) {
    const StageCost c = fragment(R"(void main() {
    o = texture(u_a, v_uv) + texture(u_b, v_uv * 2.0 + 0.5);
})");
    EXPECT_EQ(c.samples.size(), 2u);
    EXPECT_EQ(c.dependent_samples, 0);
    EXPECT_DOUBLE_EQ(c.texture_round_trips, 1.0);
}

TEST(ShaderCosts, AReadUnderABranchOnAReadIsDependent) {
    const StageCost c = fragment(R"(void main() {
    o = vec4(0.0);
    if (texture(u_a, v_uv).r > 0.5) o = texture(u_b, v_uv);
})");
    ASSERT_EQ(c.samples.size(), 2u);
    EXPECT_TRUE(c.samples[1].dependent);
}

TEST(ShaderCosts, ALoopBoundOf32ShowsAsATripCountOf32) {
    const StageCost c = fragment(R"(void main() {
    vec4 sum = vec4(0.0);
    for (int i = 0; i < 32; i++) sum += texture(u_a, v_uv + float(i) * v_offset);
    for (int j = 1; j <= 8; j++) sum *= 0.5;
    o = sum;
})");
    ASSERT_EQ(c.loops.size(), 2u);
    EXPECT_EQ(c.loops[0].trip_count, 32);
    EXPECT_TRUE(c.loops[0].has_samples);
    EXPECT_EQ(c.loops[1].trip_count, 8);
    EXPECT_FALSE(c.loops[1].has_samples);
    // The longest path runs the loop 32 times; each instruction is counted once in the total.
    EXPECT_DOUBLE_EQ(c.total.samples, 1.0);
    EXPECT_DOUBLE_EQ(c.longest.samples, 32.0);
    EXPECT_DOUBLE_EQ(c.samples[0].repeats, 32.0);
    // The reads do not wait on each other: one round trip.
    EXPECT_DOUBLE_EQ(c.texture_round_trips, 1.0);
}

TEST(ShaderCosts, AMarchWaitsOnItsOwnReadsEveryIteration) {
    const StageCost c = fragment(R"(void main() {
    vec2 uv = v_uv;
    for (int i = 0; i < 16; i++) {
        if (texture(u_a, uv).r > 0.5) break;
        uv += v_offset;
    }
    o = texture(u_b, uv);
})");
    ASSERT_EQ(c.samples.size(), 2u);
    EXPECT_TRUE(c.samples[0].dependent);  // on its own previous iterations (the break)
    EXPECT_TRUE(c.samples[1].dependent);
    EXPECT_DOUBLE_EQ(c.texture_round_trips, 17.0);  // 16 iterations, then the shading read
    ASSERT_EQ(c.loops.size(), 1u);
    EXPECT_EQ(c.loops[0].trip_count, 16);
    // The shortest path leaves the loop at its first exit.
    EXPECT_DOUBLE_EQ(c.shortest.samples, 1.0);
    EXPECT_DOUBLE_EQ(c.longest.samples, 17.0);
}

TEST(ShaderCosts, AnUncountedLoopHasNoTripCount) {
    const StageCost c = fragment(R"(uniform int u_n;
void main() {
    vec4 sum = vec4(0.0);
    for (int i = 0; i < u_n; i++) sum += vec4(1.0);
    o = sum;
})");
    ASSERT_EQ(c.loops.size(), 1u);
    EXPECT_EQ(c.loops[0].trip_count, -1);
    EXPECT_TRUE(c.unknown_trips);
}

TEST(ShaderCosts, MediumPrecisionIsRelaxedWhereTheSourceAskedForIt) {
    const StageCost high = fragment(R"(void main() {
    highp vec4 a = vec4(v_uv, v_offset);
    highp vec4 b = a * a + vec4(0.5);
    o = b;
})");
    // An operation takes its operands' precision (GLSL ES 3.00, 4.5.2):
    // mediump operands make mediump arithmetic.
    const StageCost medium = fragment(R"(void main() {
    mediump vec4 a = vec4(v_uv, v_offset);
    mediump vec4 b = a * a + vec4(0.5);
    o = b;
})");
    const StageCost mixed = fragment(R"(void main() {
    highp vec4 a = vec4(v_uv, v_offset);
    mediump vec4 b = a * a + vec4(0.5);
    o = b;
})");
    EXPECT_EQ(high.relaxed_results, 0);
    EXPECT_DOUBLE_EQ(high.total.fp16, 0.0);
    EXPECT_GT(medium.relaxed_results, 0);
    EXPECT_DOUBLE_EQ(mixed.total.fp16, 0.0);  // stored mediump, computed highp
    // Same arithmetic either way: a vec4 multiply and a vec4 add.
    EXPECT_DOUBLE_EQ(high.total.arithmetic, 8.0);
    EXPECT_DOUBLE_EQ(medium.total.arithmetic, 8.0);
    EXPECT_DOUBLE_EQ(medium.total.fp16, 8.0);
}

TEST(ShaderCosts, ScalarOperationsAndTranscendentals) {
    const StageCost c = fragment(R"(uniform highp mat3 u_m;
void main() {
    vec3 v = u_m * vec3(v_uv, 1.0);   // 9
    float l = length(v);                // 3 + 1 transcendental
    o = vec4(normalize(v) * l, 1.0);    // 6 + 1 transcendental, then 3
})");
    EXPECT_DOUBLE_EQ(c.total.arithmetic, 9.0 + 3.0 + 6.0 + 3.0);
    EXPECT_DOUBLE_EQ(c.total.transcendental, 2.0);
    EXPECT_EQ(c.transcendental_instructions, 2);
    EXPECT_EQ(c.varying_components, 2);  // v_uv; v_offset is declared but never read
}

TEST(ShaderCosts, BranchesTakeTheDearerSideOnTheLongestPath) {
    const StageCost c = fragment(R"(void main() {
    vec4 r = vec4(v_uv, 0.0, 1.0);
    if (v_uv.x > 0.5) { r = r * r * r * r; } else { r = r + vec4(1.0); }
    o = r;
})");
    // A compare, then 12 or 4 operations.
    EXPECT_DOUBLE_EQ(c.longest.arithmetic, 1.0 + 12.0);
    EXPECT_DOUBLE_EQ(c.shortest.arithmetic, 1.0 + 4.0);
    EXPECT_DOUBLE_EQ(c.total.arithmetic, 1.0 + 12.0 + 4.0);
    EXPECT_DOUBLE_EQ(c.longest.branches, 1.0);
}

TEST(ShaderCosts, FunctionCallsCountTheirBodiesAndCarryDependence) {
    const StageCost c = fragment(R"(vec2 shift(vec2 uv, float h) { return uv + h * v_offset; }
void main() {
    float h = texture(u_a, v_uv).r;
    o = texture(u_b, shift(v_uv, h));
})");
    ASSERT_EQ(c.samples.size(), 2u);
    EXPECT_TRUE(c.samples[1].dependent);
    EXPECT_DOUBLE_EQ(c.total.arithmetic, 4.0);  // the call's multiply and add, 2 components each
}

TEST(ShaderCosts, RealVariants) {
    VariantKey normal;
    normal.technique = Technique::normal;
    const StageCost n = variant_stage(normal, ShaderStage::fragment);
    EXPECT_EQ(n.samples.size(), 2u);  // albedo and normal map
    EXPECT_EQ(n.dependent_samples, 0);

    VariantKey offset;
    offset.technique = Technique::offset_limited;
    offset.packed_height = false;
    const StageCost o = variant_stage(offset, ShaderStage::fragment);
    EXPECT_EQ(o.samples.size(), 3u);  // height, then albedo and normal at the shifted uv
    EXPECT_EQ(o.dependent_samples, 2);
    EXPECT_DOUBLE_EQ(o.texture_round_trips, 2.0);
    // Lines map back to shaders_es/ files.
    EXPECT_TRUE(std::any_of(o.samples.begin(), o.samples.end(), [](const SampleCost& s) {
        return s.where.rfind("shaders_es/chunks/surface_main.glsl:", 0) == 0;
    }));

    // The march's loop bound is the variant's sample-count option.
    VariantKey steep;
    steep.technique = Technique::steep;
    steep.max_samples = 32;
    const StageCost s = variant_stage(steep, ShaderStage::fragment);
    const auto march = std::find_if(s.loops.begin(), s.loops.end(), [](const LoopCost& l) {
        return l.where.rfind("shaders_es/chunks/march.glsl:", 0) == 0;
    });
    ASSERT_NE(march, s.loops.end());
    EXPECT_EQ(march->trip_count, 32);
    EXPECT_TRUE(march->has_samples);
    steep.max_samples = 64;
    const StageCost s64 = variant_stage(steep, ShaderStage::fragment);
    EXPECT_GT(s64.longest.samples, s.longest.samples);
    EXPECT_DOUBLE_EQ(s64.total.samples, s.total.samples);  // the same instructions, run more often

    // GLSL ES 1.00 without fragment highp: more of it is relaxed.
    VariantKey es2 = offset;
    es2.es_major = 2;
    VariantKey es2_no_highp = es2;
    es2_no_highp.no_fragment_highp = true;
    es2.debug_output = es2_no_highp.debug_output = 2;
    const StageCost with_highp = variant_stage(es2, ShaderStage::fragment);
    const StageCost without = variant_stage(es2_no_highp, ShaderStage::fragment);
    EXPECT_GT(without.relaxed_share(), with_highp.relaxed_share());
}

TEST(ShaderCosts, TheLadderStepsChangeWhatTheyClaim) {
    VariantKey key;
    key.technique = Technique::offset_limited;
    key.packed_height = false;
    auto step = [&](int s, ShaderStage stage) {
        VariantKey k = key;
        k.ladder_step = static_cast<std::uint8_t>(s);
        return variant_stage(k, stage);
    };
    // Step 2: no per-vertex matrix product.
    EXPECT_LT(step(2, ShaderStage::vertex).total.arithmetic, step(1, ShaderStage::vertex).total.arithmetic);
    // Step 3: the fragment normalise goes to the vertex stage.
    EXPECT_LT(step(3, ShaderStage::fragment).total.transcendental, step(2, ShaderStage::fragment).total.transcendental);
    EXPECT_GT(step(3, ShaderStage::vertex).total.transcendental, step(2, ShaderStage::vertex).total.transcendental);
    // Step 4: the scale moves to the vertex stage.
    EXPECT_GT(step(4, ShaderStage::vertex).total.arithmetic, step(3, ShaderStage::vertex).total.arithmetic);
    // Step 5: the dependent reads back to back, one wait fewer.
    EXPECT_EQ(step(5, ShaderStage::fragment).in_order_waits, step(4, ShaderStage::fragment).in_order_waits - 1);
    // Step 6: relaxed precision.
    EXPECT_GT(step(6, ShaderStage::fragment).relaxed_share(), step(5, ShaderStage::fragment).relaxed_share());
    for (int s = 1; s <= kLadderSteps; ++s) EXPECT_EQ(step(s, ShaderStage::fragment).samples.size(), 3u) << s;
}

TEST(ShaderCosts, MalformedSpirvIsAnErrorNotACrash) {
    EXPECT_FALSE(analyse_spirv({}, ShaderStage::fragment));
    EXPECT_FALSE(analyse_spirv({0x07230203u, 0x00010000u, 0u, 100u, 0u, 0xFFFF0001u}, ShaderStage::fragment));
    Result<std::vector<std::uint32_t>> good = compile_spirv(
        "#version 300 es\nprecision mediump float;\nout vec4 o;\nvoid main() { o = vec4(1.0); }\n", ShaderStage::fragment);
    ASSERT_TRUE(good);
    // Every truncation of a valid module is refused or analysed, never a crash.
    for (std::size_t n = 0; n < good->size(); ++n) {
        std::vector<std::uint32_t> cut(good->begin(), good->begin() + static_cast<std::ptrdiff_t>(n));
        (void)analyse_spirv(cut, ShaderStage::fragment);
    }
    // Words flipped one at a time.
    for (std::size_t i = 5; i < good->size(); ++i) {
        std::vector<std::uint32_t> bad = *good;
        bad[i] ^= 0x00FF00FFu;
        (void)analyse_spirv(bad, ShaderStage::fragment);
    }
    Result<std::vector<std::uint32_t>> broken = compile_spirv("#version 300 es\nvoid main() { nope; }\n", ShaderStage::fragment);
    ASSERT_FALSE(broken);
    EXPECT_NE(broken.error().message.find("glslang"), std::string::npos);
}

TEST(NirDump, CountsWhatMesaPrinted) {
    // In the layout Mesa 22.3 prints with ST_DEBUG=nir (written for the test).
    const std::string dump = R"(shader: MESA_SHADER_VERTEX
name: GLSL3
impl main {
	block block_0:
	vec1 32 ssa_0 = load_const (0x00000000 = 0.000000)
	vec4 32 ssa_1 = intrinsic load_ubo (ssa_0, ssa_0) (access=0)
	vec4 32 ssa_2 = fmul ssa_1, ssa_1
	intrinsic store_output (ssa_2, ssa_0) (base=0)
}
shader: MESA_SHADER_FRAGMENT
name: GLSL3
impl main {
	block block_0:
	vec2 32 ssa_3 = intrinsic load_deref (ssa_0) (access=0)
	vec4 16 ssa_4 = (float16)txl ssa_3 (coord), ssa_0 (lod), 1 (texture), 1 (sampler)
	vec1 16 ssa_5 = fadd ssa_4.w, ssa_4.x
	vec1 32 ssa_6 = f2f32 ssa_5
	loop {
		block block_1:
		vec1 1 ssa_7 = flt ssa_6, ssa_6
		if ssa_7 {
			block block_2:
			break
		} else {
			block block_3:
		}
		vec4 32 ssa_8 = (float32)tex ssa_3 (coord), 0 (texture), 0 (sampler)
	}
}
shader: MESA_SHADER_COMPUTE
name: internal
impl main {
	vec1 32 ssa_0 = fadd ssa_0, ssa_0
}
)";
    Result<std::vector<NirShader>> shaders = parse_nir_dump(dump);
    ASSERT_TRUE(shaders) << shaders.error().message;
    ASSERT_EQ(shaders->size(), 2u);
    EXPECT_EQ((*shaders)[0].stage, ShaderStage::vertex);
    EXPECT_EQ((*shaders)[0].cost.alu, 1);
    EXPECT_EQ((*shaders)[0].cost.intrinsics, 2);
    const NirCost& f = (*shaders)[1].cost;
    EXPECT_EQ(f.texture, 2);
    EXPECT_EQ(f.alu, 3);  // fadd, f2f32, flt
    EXPECT_EQ(f.alu_16bit, 1);
    EXPECT_EQ(f.loops, 1);
    EXPECT_EQ(f.branches, 1);
    EXPECT_FALSE(parse_nir_dump("nothing here\n"));
}

TEST(CostModel, TheShippedFileParsesAndEveryFieldIsChecked) {
    const CostModel& m = default_cost_model();
    EXPECT_FALSE(m.name.empty());
    EXPECT_FALSE(m.assumptions.empty());
    EXPECT_GT(m.fp16_ops_per_cycle, 0.0);
    EXPECT_FALSE(m.loop_trips.empty());
    Result<CostModel> bad = parse_cost_model(R"({"arithmetic": {"fp32_ops_per_cycle": -1}, "texture": {}, "varying": {}})", "m.json");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("m.json: $.arithmetic.fp32_ops_per_cycle"), std::string::npos) << bad.error().message;
    Result<CostModel> missing = parse_cost_model(R"({"arithmetic": {}})", "m.json");
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("$.texture"), std::string::npos) << missing.error().message;
    EXPECT_FALSE(parse_cost_model("{", "m.json"));
    EXPECT_FALSE(parse_cost_model("[]", "m.json"));
}

TEST(CostModel, EstimateIsTheBusiestPipePlusExposedLatency) {
    CostModel m;
    m.fp32_ops_per_cycle = 1;
    m.fp16_ops_per_cycle = 2;
    m.transcendental_cycles = 4;
    m.branch_cycles = 1;
    m.samples_per_cycle = 1;
    m.texture_latency_cycles = 100;
    m.latency_hidden_share = 0.75;
    m.varying_components_per_cycle = 2;
    StageCost s;
    s.stage = ShaderStage::fragment;
    s.varying_components = 8;
    OpCounts path;
    path.arithmetic = 10;
    path.fp16 = 4;
    path.transcendental = 1;
    path.samples = 3;
    const PipeCycles c = estimate(s, path, 2.0, m);
    EXPECT_DOUBLE_EQ(c.arithmetic, 6.0 + 2.0 + 4.0);
    EXPECT_DOUBLE_EQ(c.texture, 3.0);
    EXPECT_DOUBLE_EQ(c.varying, 4.0);
    EXPECT_DOUBLE_EQ(c.latency, 50.0);
    EXPECT_DOUBLE_EQ(c.total, 62.0);
    EXPECT_EQ(c.bound, "A");
    // mediump varyings interpolate at the 16-bit rate.
    m.varying_fp16_components_per_cycle = 4;
    s.relaxed_varying_components = 4;
    EXPECT_DOUBLE_EQ(estimate(s, path, 2.0, m).varying, 4.0 / 2.0 + 4.0 / 4.0);
}

TEST(ShaderCosts, MediumpVaryingsAreCountedApart) {
    const char* fs = "#version 100\nprecision mediump float;\nvarying highp vec3 a;\nvarying vec2 b;\n"
                     "varying lowp vec4 c;\nvoid main() { gl_FragColor = vec4(a, b.x) + c; }\n";
    Result<std::vector<std::uint32_t>> words = compile_spirv(fs, ShaderStage::fragment);
    ASSERT_TRUE(words) << words.error().message;
    Result<StageCost> cost = analyse_spirv(*words, ShaderStage::fragment);
    ASSERT_TRUE(cost) << cost.error().message;
    EXPECT_EQ(cost->varying_components, 9);
    EXPECT_EQ(cost->relaxed_varying_components, 6);
}

}  // namespace
}  // namespace px::profiling
