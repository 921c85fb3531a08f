// Unit tests for the real GPU compilers' output readers
// (include/parallaxes/profiling/costs/gpu_compilers.h), on what Mesa 22.3.6's
// Panfrost, V3D, Freedreno and Lima printed for this project's shaders under
// qemu-aarch64 (tests/data/gpu/README.md says how each file was made). The
// expected figures are read off the driver's line in each file by eye.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "parallaxes/profiling/costs/gpu_compilers.h"
#include "parallaxes/shaders/shader_source.h"

namespace px::profiling {
namespace {

const std::string kData = std::string(PX_SOURCE_DIR) + "/tests/data/gpu/";

std::string read_sample(const std::string& name) {
    std::ifstream in(kData + name, std::ios::binary);
    EXPECT_TRUE(in) << "cannot read " << kData + name;
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

GpuTarget target(const std::string& name) {
    Result<std::vector<GpuTarget>> t = parse_gpu_targets(name);
    EXPECT_TRUE(t) << name;
    return t ? t->front() : GpuTarget{};
}

GpuProgram parse_one(const std::string& gpu, const std::string& file, std::string* context = nullptr) {
    Result<GpuRun> run = parse_probe_output(target(gpu), read_sample(file), 1);
    EXPECT_TRUE(run) << (run ? "" : run.error().message);
    if (!run) return {};
    if (context) *context = run->context;
    return run->programs.at(0);
}

TEST(GpuCompilers, BifrostShaderDbLine) {
    std::string context;
    const GpuProgram p = parse_one("mali-g52", "mali-g52_normal_es3.txt", &context);
    EXPECT_EQ(context, "Mali-G52 (Panfrost) | OpenGL ES 3.1 Mesa 22.3.6");
    EXPECT_TRUE(p.error.empty()) << p.error;
    // Panfrost compiles the vertex shader twice (index-driven vertex shading).
    ASSERT_EQ(p.stages.size(), 3u);
    EXPECT_EQ(p.stages[0].stage, "MESA_SHADER_POSITION");
    EXPECT_EQ(p.stages[1].stage, "MESA_SHADER_VARYING");
    const GpuSummary s = summarise(target("mali-g52"), p);
    EXPECT_EQ(s.instructions, 369);
    EXPECT_DOUBLE_EQ(s.cycles, 11.25);
    EXPECT_EQ(s.bound, "arith");
    EXPECT_EQ(s.threads, 2);
    EXPECT_EQ(s.loops, 0);
    EXPECT_EQ(s.spills, 0);
    EXPECT_EQ(s.fills, 0);
    EXPECT_EQ(s.vertex_instructions, 58 + 273);
    EXPECT_EQ(p.fragment()->figure("tuples").value_or(-1), 275);
    EXPECT_EQ(p.fragment()->figure("texture").value_or(-1), 1.0);
    EXPECT_NE(p.fragment()->line.find("369 inst, 275 tuples, 53 clauses"), std::string::npos);
}

TEST(GpuCompilers, ValhallBoundPipeIsTheOneThatSetsTheCycles) {
    const GpuProgram p = parse_one("mali-g57", "mali-g57_pom_es3.txt");
    const GpuSummary s = summarise(target("mali-g57"), p);
    EXPECT_EQ(s.instructions, 1161);
    EXPECT_DOUBLE_EQ(s.cycles, 10.53125);
    EXPECT_EQ(s.bound, "cvt");  // 10.531250 cvt, beside 5.656250 fma and 8.750000 t
    EXPECT_EQ(s.threads, 1);
}

// The 16-bit share from the compiler's instruction listing
// (BIFROST_MESA_DEBUG=shaderdb,shaders): the fragment stage's last listing
// only (the IR is printed three times, the vertex stages before it), counted
// as a separate script counted the same file (tests/data/gpu/README.md).
TEST(GpuCompilers, ListingsGiveTheFragmentStagesSixteenBitShare) {
    struct Case {
        const char* gpu;
        const char* file;
        int narrow, wide, conversions;
    };
    for (const Case& c : {Case{"mali-g57", "mali-g57_flat_es3_listing.txt", 125, 114, 43},
                          Case{"mali-g52", "mali-g52_flat_es3_listing.txt", 125, 107, 43}}) {
        const GpuProgram p = parse_one(c.gpu, c.file);
        EXPECT_TRUE(p.error.empty()) << c.gpu << ": " << p.error;
        ASSERT_NE(p.fragment(), nullptr) << c.gpu;
        EXPECT_EQ(p.fragment()->narrow_ops, c.narrow) << c.gpu;
        EXPECT_EQ(p.fragment()->wide_ops, c.wide) << c.gpu;
        EXPECT_EQ(p.fragment()->conversions, c.conversions) << c.gpu;
        for (const GpuStage& st : p.stages)
            if (!st.fragment) EXPECT_EQ(st.narrow_ops, -1) << c.gpu << " " << st.stage << ": vertex listings are not counted";
        const GpuSummary s = summarise(target(c.gpu), p);
        EXPECT_NEAR(s.narrow_share, static_cast<double>(c.narrow) / (c.narrow + c.wide), 1e-12) << c.gpu;
        EXPECT_EQ(s.conversions, c.conversions) << c.gpu;
        EXPECT_GT(s.cycles, 0.0) << c.gpu << ": the statistics line is still read beside the listing";
    }
    // Without a listing (the statistics switch alone) nothing is counted.
    const GpuSummary plain = summarise(target("mali-g52"), parse_one("mali-g52", "mali-g52_normal_es3.txt"));
    EXPECT_EQ(plain.narrow_share, -1.0);
    // One line at a time: what counts and what does not.
    GpuStage st;
    count_listing_line("   r15 = FADD.v2f16 r25.h00, ^r15.neg.h00", st);
    count_listing_line("\t*    r3 = FMA.f32 t0, r12, t.neg", st);
    count_listing_line("   r10 = F16_TO_F32 ^r10.h00", st);
    count_listing_line("   r12 = TEX_SINGLE.skip.2d.rgba.explicit.f16 r30, ^r12, ^r13, sr_count:3", st);
    count_listing_line("   BRANCHZ.i16.flow10.eq ^r12.h00, u256 -> block95", st);
    count_listing_line("\tvec1 16 ssa_1154 = phi block_119: ssa_1462, block_118: ssa_1151", st);
    EXPECT_EQ(st.narrow_ops, 1);
    EXPECT_EQ(st.wide_ops, 1);
    EXPECT_EQ(st.conversions, 1);
}

TEST(GpuCompilers, MidgardRegistersAndNoCycles) {
    const GpuProgram p = parse_one("mali-t860", "mali-t860_normal_es3.txt");
    const GpuSummary s = summarise(target("mali-t860"), p);
    EXPECT_EQ(s.instructions, 252);
    EXPECT_LT(s.cycles, 0.0);  // Midgard's shader-db line has no cycle estimate
    EXPECT_EQ(s.bound, "");
    EXPECT_EQ(s.registers, 6);
    EXPECT_EQ(s.vertex_instructions, 195);
}

TEST(GpuCompilers, V3dAllVertexStagesCount) {
    const GpuProgram p = parse_one("v3d-4.2", "v3d-4.2_normal_es3.txt");
    const GpuSummary s = summarise(target("v3d-4.2"), p);
    EXPECT_EQ(s.instructions, 356);
    EXPECT_EQ(s.threads, 4);
    EXPECT_EQ(s.registers, 29);  // max-temps
    EXPECT_EQ(s.vertex_instructions, 347 + 77);  // VERTEX and VERTEX_BIN
    EXPECT_EQ(p.fragment()->figure("sfu-stalls").value_or(-1), 7);
}

TEST(GpuCompilers, Ir3SummaryLinesOfTheProgramAloneNotMesasBlitShaders) {
    std::string context;
    const GpuProgram p = parse_one("adreno-630", "adreno-630_normal_es3.txt", &context);
    EXPECT_EQ(context, "FD630 | OpenGL ES 3.2 Mesa 22.3.6");
    ASSERT_EQ(p.stages.size(), 3u);  // VERT, BVERT, FRAG of the program; the TTN blits before it are not
    EXPECT_EQ(p.stages[0].stage, "VERT");
    EXPECT_EQ(p.stages[1].stage, "BVERT");
    const GpuSummary s = summarise(target("adreno-630"), p);
    EXPECT_EQ(s.instructions, 507);
    EXPECT_EQ(s.registers, 6);  // "6 full"
    EXPECT_EQ(s.loops, 0);
    EXPECT_EQ(s.vertex_instructions, 283 + 109);
    EXPECT_EQ(p.fragment()->figure("nops").value_or(-1), 225);
    EXPECT_EQ(p.fragment()->figure("(ss)").value_or(-1), 20);
}

// Without FD_MESA_DEBUG=serialc a blit shader of Mesa's own (TTN) can be
// compiled inside a program's draw: its real lines, moved there, must not
// count as the program's.
TEST(GpuCompilers, Ir3BlitShadersInsideAProgramAreLeftOut) {
    std::string text = read_sample("adreno-630_normal_es3.txt");
    const size_t blit = text.find("MESA: info: Native code for unnamed FRAG shader TTN");
    const size_t blit_end = text.find("0 loops\n", text.find("; FRAG prog 1/1: 0 sstall", blit));
    const size_t begin = text.find("px-probe begin 0\n");
    ASSERT_NE(blit, std::string::npos);
    ASSERT_NE(blit_end, std::string::npos);
    ASSERT_NE(begin, std::string::npos);
    const std::string lines = text.substr(blit, blit_end + 8 - blit);
    text.insert(begin + 17, lines);
    Result<GpuRun> run = parse_probe_output(target("adreno-630"), text, 1);
    ASSERT_TRUE(run) << run.error().message;
    ASSERT_EQ(run->programs[0].stages.size(), 3u);
    EXPECT_EQ(summarise(target("adreno-630"), run->programs[0]).instructions, 507);
}

TEST(GpuCompilers, LimaSpillsAreRead) {
    const GpuProgram p = parse_one("mali-450", "mali-450_normal_es2.txt");
    const GpuSummary s = summarise(target("mali-450"), p);
    EXPECT_EQ(s.instructions, 126);
    EXPECT_EQ(s.spills, 1);
    EXPECT_EQ(s.fills, 5);
    EXPECT_EQ(s.vertex_instructions, 170);
}

TEST(GpuCompilers, AProgramWithoutItsEndIsMarkedAndAnErrorIsKept) {
    const std::string out =
        "px-probe context Mali-G52 (Panfrost) | OpenGL ES 3.1 Mesa 22.3.6\n"
        "px-probe begin 0\npx-probe end 0 error fragment shader: 0:3(1): error: syntax error\n"
        "px-probe begin 1\n"
        "SHADER-DB: MESA_SHADER_FRAGMENT shader: 3 inst, 1.000000 cycles, 1.000000 arith, 0.000000 texture, "
        "0.000000 vary, 0.000000 ldst, 2 threads, 0 loops, 0:0 spills:fills\n";
    Result<GpuRun> run = parse_probe_output(target("mali-g52"), out, 2);
    ASSERT_TRUE(run) << run.error().message;
    EXPECT_NE(run->programs[0].error.find("syntax error"), std::string::npos);
    EXPECT_EQ(run->programs[1].error, "the probe did not finish this program");
}

TEST(GpuCompilers, AStatisticsLineThatDoesNotParseIsRefusedQuoted) {
    const std::string out =
        "px-probe context x\npx-probe begin 0\n"
        "SHADER-DB: MESA_SHADER_FRAGMENT shader: many inst, 2 threads\npx-probe end 0 ok\n";
    Result<GpuRun> run = parse_probe_output(target("mali-g52"), out, 1);
    ASSERT_FALSE(run);
    EXPECT_NE(run.error().message.find("'many inst'"), std::string::npos) << run.error().message;
    const std::string spills =
        "px-probe begin 0\nSHADER-DB: MESA_SHADER_FRAGMENT shader: 3 inst, 0-0 spills:fills\npx-probe end 0 ok\n";
    EXPECT_FALSE(parse_probe_output(target("mali-g52"), spills, 1));
    // A program number past the ones given.
    EXPECT_FALSE(parse_probe_output(target("mali-g52"), "px-probe begin 7\n", 1));
}

TEST(GpuCompilers, NamesAreCheckedAndListed) {
    Result<std::vector<GpuTarget>> two = parse_gpu_targets("Mali-G57, adreno-630,mali-g57");
    ASSERT_TRUE(two);
    ASSERT_EQ(two->size(), 2u);
    EXPECT_EQ((*two)[0].name, "mali-g57");
    EXPECT_EQ((*two)[1].name, "adreno-630");
    Result<std::vector<GpuTarget>> all = parse_gpu_targets("all");
    ASSERT_TRUE(all);
    EXPECT_EQ(all->size(), gpu_targets().size());
    Result<std::vector<GpuTarget>> bad = parse_gpu_targets("mali-g78");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("'mali-g78'"), std::string::npos);
    EXPECT_NE(bad.error().message.find("mali-450"), std::string::npos);  // the known names
    EXPECT_FALSE(parse_gpu_targets(" , "));
    const std::string list = gpu_targets_text();
    for (const GpuTarget& t : gpu_targets()) EXPECT_NE(list.find(t.name), std::string::npos) << t.name;
}

TEST(GpuCompilers, MissingCompilersNameTheCommandThatMakesThem) {
    const std::string dir = std::string(::testing::TempDir()) + "/px_no_gpu_compilers";
    std::filesystem::create_directories(dir);
    const char* before = std::getenv("PX_GPU_COMPILERS");
    const std::string saved = before ? before : "";
    setenv("PX_GPU_COMPILERS", dir.c_str(), 1);
    Result<GpuCompilers> found = find_gpu_compilers();
    if (before) setenv("PX_GPU_COMPILERS", saved.c_str(), 1);
    else unsetenv("PX_GPU_COMPILERS");
    ASSERT_FALSE(found);
    EXPECT_NE(found.error().message.find("tools/cross/make_gpu_compilers.sh"), std::string::npos) << found.error().message;
    EXPECT_NE(found.error().message.find(dir), std::string::npos);
}

TEST(GpuCompilers, AnEs2OnlyGpuRefusesEs3Variants) {
    GpuCompilers none;
    Result<GpuRun> r = compile_on_gpu(none, target("mali-450"), 3, {{"v", "f"}});
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("OpenGL ES 2.0 only"), std::string::npos);
}

// Per pixel: the static estimate where the compiler kept no loop; times the
// counted passes (at least one) where it kept one; unknown (-1) where it
// kept one and nothing was counted, or gave no estimate.
TEST(GpuCompilers, CyclesPerPixelMultiplyOnlyAKeptLoopByItsCountedPasses) {
    EXPECT_DOUBLE_EQ(cycles_per_pixel(10.4, 0.0, false, 0.0), 10.4);
    EXPECT_DOUBLE_EQ(cycles_per_pixel(10.4, 0.0, true, 17.0), 10.4);
    EXPECT_DOUBLE_EQ(cycles_per_pixel(3.4, 1.0, true, 17.0), 3.4 * 17.0);
    EXPECT_DOUBLE_EQ(cycles_per_pixel(3.4, 2.0, true, 0.0), 3.4);
    EXPECT_DOUBLE_EQ(cycles_per_pixel(3.4, 1.0, false, 17.0), -1.0);
    EXPECT_DOUBLE_EQ(cycles_per_pixel(-1.0, 0.0, true, 17.0), -1.0);
}

// The share of the listing inside a kept loop: maxmip's walk on Valhall,
// counted by the separate script over the same file (tests/data/gpu/README.md):
// 317 of the final listing's 810 instructions (its statistics line says 812
// inst) in the blocks its one back edge closes; none in flat's.
TEST(GpuCompilers, ListingsGiveTheShareOfAKeptLoop) {
    const GpuProgram p = parse_one("mali-g57", "mali-g57_maxmip_es3_listing.txt");
    ASSERT_NE(p.fragment(), nullptr);
    const GpuSummary s = summarise(target("mali-g57"), p);
    EXPECT_EQ(s.loops, 1);
    EXPECT_NEAR(s.loop_share, 317.0 / 810.0, 1e-12);
    EXPECT_EQ(s.spills, 4);
    EXPECT_EQ(s.fills, 37);
    // Per pixel at 6 passes: the loop's share six times, the rest once.
    EXPECT_NEAR(cycles_per_pixel(s.cycles, s.loops, true, 6.0, s.loop_share), 41.0 * (1.0 + 5.0 * 317.0 / 810.0), 1e-9);
    EXPECT_NEAR(cycles_per_pixel(s.cycles, s.loops, true, 6.0), 41.0 * 6.0, 1e-9);  // without the share: the bound
    EXPECT_EQ(summarise(target("mali-g57"), parse_one("mali-g57", "mali-g57_flat_es3_listing.txt")).loop_share, 0.0);
}

// The bounds a cost per pixel sets (the lights loop's, the search's): the
// lines the variant's defines write, in a real variant; a source without
// one is an error, not a silent no-op.
TEST(GpuCompilers, TheLoopBoundsAreSetInARealVariant) {
    VariantKey key;
    key.technique = Technique::pom;
    key.max_samples = 32;
    key.shadow = ShadowMode::soft;
    key.shadow_samples = 16;
    Result<VariantSources> sources = assemble_variant(key.canonical());
    ASSERT_TRUE(sources) << sources.error().message;
    for (const std::string* text : {&sources->vertex.text, &sources->fragment.text}) {
        Result<std::string> one = with_define(*text, "PX_MAX_LIGHTS", 1);
        ASSERT_TRUE(one) << one.error().message;
        EXPECT_NE(one->find("#define PX_MAX_LIGHTS 1\n"), std::string::npos);
        EXPECT_EQ(one->find("#define PX_MAX_LIGHTS 4"), std::string::npos);
        EXPECT_EQ(one->size(), text->size());
    }
    Result<std::string> cut = with_define(sources->fragment.text, "PX_MAX_SAMPLES", 7);
    ASSERT_TRUE(cut) << cut.error().message;
    EXPECT_NE(cut->find("#define PX_MAX_SAMPLES 7\n"), std::string::npos);
    EXPECT_EQ(cut->find("#define PX_MAX_SAMPLES 32"), std::string::npos);
    Result<std::string> first = with_define("#define PX_A 3\nx\n", "PX_A", 5);
    ASSERT_TRUE(first);
    EXPECT_EQ(*first, "#define PX_A 5\nx\n");
    Result<std::string> none = with_define("void main() {}\n", "PX_MAX_LIGHTS", 1);
    ASSERT_FALSE(none);
    EXPECT_NE(none.error().message.find("PX_MAX_LIGHTS"), std::string::npos);
}

}  // namespace
}  // namespace px::profiling
