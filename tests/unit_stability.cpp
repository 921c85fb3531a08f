// The stability catalogue's GL-free half: the built-in catalogue parses and
// covers the hard cases the issue lists, malformed catalogues are refused
// with the JSON path, and rows are judged as documented.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "parallaxes/profiling/reports/stability_catalogue.h"

namespace px::profiling {
namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

const char* kMinimalBounds = R"("bounds": {"techniques": {
    "flat": {"error": "parallax", "offset": "zero"}, "normal": {"error": "parallax", "offset": "zero"},
    "parallax": {"error": "parallax", "offset": "parallax"}, "offset_limited": {"error": "parallax", "offset": "limited"},
    "steep": {"error": "step", "offset": "parallax"}, "pom": {"error": "step", "offset": "parallax"},
    "relief": {"error": "refined_step", "offset": "parallax"}, "maxmip": {"error": "exact", "offset": "parallax"}}})";

std::string catalogue_error(const std::string& cases, const std::string& bounds = kMinimalBounds) {
    Result<Catalogue> c = parse_catalogue("{" + bounds + ", \"cases\": [" + cases + "]}", "test.jsonc");
    return c ? std::string("(parsed)") : c.error().message;
}

TEST(StabilityCatalogue, BuiltInCatalogueCoversTheHardCases) {
    Result<Catalogue> c = parse_catalogue(embedded_catalogue_text(), "built-in");
    ASSERT_TRUE(c.ok()) << c.error().message;
    std::set<double> angles;
    bool sweep = false, lod = false, dark = false, npot = false, mirrored = false, zero_scale = false;
    bool deep = false, huge_uv = false, on_plane = false;
    for (const StabilityCase& s : c->cases) {
        angles.insert(s.angles.begin(), s.angles.end());
        sweep |= s.sweep;
        lod |= s.lod && s.distances.size() > 2;
        dark |= s.expect_dark;
        npot |= s.image_width.has_value() && (*s.image_width & (*s.image_width - 1)) != 0;
        mirrored |= s.model_scale.x < 0.0f;
        zero_scale |= s.height_scale == 0.0f;
        deep |= s.height_scale >= 1.0f;
        huge_uv |= s.uv.scale.x >= 10000.0f || s.uv.offset.x >= 10000.0f;
        on_plane |= s.camera_position && s.camera_position->z == 0.0f;
    }
    for (double a : {80.0, 85.0, 89.0, 89.9, 90.0}) EXPECT_TRUE(angles.count(a)) << a << " degrees";
    EXPECT_TRUE(sweep && lod && dark && npot && mirrored && zero_scale && deep && huge_uv && on_plane);
    // Every technique has bounds, and every limit names a real sentence.
    EXPECT_EQ(c->bounds.techniques.size(), 8u);
}

TEST(StabilityCatalogue, MalformedCataloguesNameTheJsonPath) {
    EXPECT_EQ(catalogue_error(R"({"name": "a"})"), "(parsed)");
    EXPECT_TRUE(contains(catalogue_error(R"({"name": "a", "angels": [80]})"), "catalogue.cases[0]: unknown key 'angels'"));
    EXPECT_TRUE(contains(catalogue_error(R"({"name": "a", "angles": [95]})"), "catalogue.cases[0].angles"));
    EXPECT_TRUE(contains(catalogue_error(R"({"name": "a", "field": {"kind": "sinus"}})"), "catalogue.cases[0].field.kind"));
    EXPECT_TRUE(contains(catalogue_error(R"({"name": "a", "limits": {"pomm": "x"}})"), "unknown technique 'pomm'"));
    EXPECT_TRUE(contains(catalogue_error(R"({"name": "a", "limits": {"pom": ""}})"), "catalogue.cases[0].limits.pom"));
    EXPECT_TRUE(contains(catalogue_error(R"({"name": "a"}, {"name": "a"})"), "'a' names another case too"));
    EXPECT_TRUE(contains(catalogue_error(R"({"name": "a", "sweep": true, "angles": [80]})"), "a sweep needs at least two"));
    EXPECT_TRUE(contains(catalogue_error(R"({"why": "no name"})"), "every case needs a name"));
    EXPECT_TRUE(contains(catalogue_error(R"({"name": "a"})", R"("bounds": {"techniques": {}})"), "no bounds for technique 'flat'"));
    Result<Catalogue> bad = parse_catalogue("{\"cases\": [", "broken.jsonc");
    ASSERT_FALSE(bad.ok());
    EXPECT_TRUE(contains(bad.error().message, "broken.jsonc: not valid JSON"));
}

StabilityRow measured(const std::string& precision = "native") {
    StabilityRow r;
    r.case_name = "c";
    r.technique = "pom";
    r.precision = precision;
    r.pixels = 1000;
    r.error_mean = 0.1;
    r.error_bound_mean = 0.5;
    r.nominal_bound_mean = 0.5;
    return r;
}

TEST(StabilityJudge, VerdictsFollowTheBounds) {
    CatalogueBounds bounds;
    StabilityCase c;
    StabilityRow ok = measured();
    judge(ok, bounds, c);
    EXPECT_EQ(ok.verdict, "pass");

    StabilityRow nan = measured();
    nan.non_finite = 3;
    judge(nan, bounds, c);
    EXPECT_EQ(nan.verdict, "fail");
    EXPECT_TRUE(contains(nan.reasons, "3 pixels NaN or Inf"));

    StabilityRow offset = measured();
    offset.offset_violations = 2;
    offset.offset_ratio_max = 1.5;
    judge(offset, bounds, c);
    EXPECT_EQ(offset.verdict, "fail");

    StabilityRow far = measured();
    far.error_mean = 0.6;
    judge(far, bounds, c);
    EXPECT_EQ(far.verdict, "fail");
    EXPECT_TRUE(contains(far.reasons, "mean error"));

    // Within the derived bound (what the search's samples allow) but past
    // the nominal one: the technique's limit, which the case must document.
    StabilityRow missed = measured();
    missed.error_mean = 0.6;
    missed.error_bound_mean = 1.0;
    StabilityRow undocumented = missed;
    judge(undocumented, bounds, c);
    EXPECT_EQ(undocumented.verdict, "fail");
    EXPECT_TRUE(contains(undocumented.reasons, "a limit the catalogue does not document")) << undocumented.reasons;
    StabilityCase limited;
    limited.limits["pom"] = "steps over thin lines";
    StabilityRow known = missed;
    judge(known, bounds, limited);
    EXPECT_EQ(known.verdict, "limit");
    EXPECT_TRUE(contains(known.reasons, "steps over thin lines (mean 0.6 texels against 0.5")) << known.reasons;
    // A documented limit never excuses NaN, nor an error past the derived bound.
    StabilityRow known_nan = missed;
    known_nan.non_finite = 1;
    judge(known_nan, bounds, limited);
    EXPECT_EQ(known_nan.verdict, "fail");
    StabilityRow known_far = far;
    judge(known_far, bounds, limited);
    EXPECT_EQ(known_far.verdict, "fail");

    StabilityRow share = measured();
    share.error_violations = 0.02;  // past violation_share (1 %)
    judge(share, bounds, c);
    EXPECT_EQ(share.verdict, "fail");

    StabilityRow jumps = measured();
    jumps.continuity_max = 9.0;
    jumps.continuity_violations = 0.05;
    judge(jumps, bounds, c);
    EXPECT_EQ(jumps.verdict, "fail");
    EXPECT_TRUE(contains(jumps.reasons, "jump"));

    // Below fp32 the growth of the error is reported, not judged; NaN is.
    StabilityRow fp16 = far;
    fp16.precision = "fp16";
    judge(fp16, bounds, c);
    EXPECT_EQ(fp16.verdict, "pass");
    fp16.non_finite = 1;
    judge(fp16, bounds, c);
    EXPECT_EQ(fp16.verdict, "fail");

    StabilityRow lit = measured();
    lit.dark_max = 0.5;
    judge(lit, bounds, c);
    EXPECT_EQ(lit.verdict, "fail");

    StabilityRow empty;
    empty.technique = "pom";
    empty.precision = "native";
    judge(empty, bounds, c);
    EXPECT_EQ(empty.verdict, "n/a");
}


// The exact tracer where its rays were read back: judged on them, the
// camera-ray figures shown, and a camera-ray miss named as the inputs'.
TEST(StabilityJudge, TheExactTracerIsJudgedOnTheRaysItWasHanded) {
    CatalogueBounds bounds;
    StabilityCase c;
    // As a GPU measured it (docs/exact_tracing.md: `far` on an H200): the
    // camera's rays 17.5 % past the bound, the walk exact on its own.
    StabilityRow gpu = measured();
    gpu.technique = "maxmip";
    gpu.error_bound_mean = gpu.nominal_bound_mean = 0.05;
    gpu.error_mean = 0.038;
    gpu.error_violations = gpu.nominal_violations = 0.175;
    gpu.own_error_mean = 5e-6;
    gpu.own_error_max = 1e-5;
    judge(gpu, bounds, c);
    EXPECT_EQ(gpu.verdict, "pass") << gpu.reasons;
    EXPECT_TRUE(contains(gpu.reasons, "judged on its own rays")) << gpu.reasons;
    EXPECT_TRUE(contains(gpu.reasons, "17.5 % past: the rasteriser's inputs")) << gpu.reasons;

    // Past the bound on its own rays: the walk's own error, a failure
    // however good the camera-ray figures look.
    StabilityRow wrong = measured();
    wrong.technique = "maxmip";
    wrong.error_bound_mean = wrong.nominal_bound_mean = 0.05;
    wrong.error_mean = 0.01;
    wrong.own_error_mean = 0.2;
    wrong.own_violations = wrong.own_nominal_violations = 0.6;
    judge(wrong, bounds, c);
    EXPECT_EQ(wrong.verdict, "fail");
    EXPECT_TRUE(contains(wrong.reasons, "mean error on its own rays 0.2 past its bound")) << wrong.reasons;
    EXPECT_TRUE(contains(wrong.reasons, "60 % of pixels past their error bound on its own rays")) << wrong.reasons;

    // Both within: no note.
    StabilityRow quiet = measured();
    quiet.own_error_mean = 0.01;
    judge(quiet, bounds, c);
    EXPECT_EQ(quiet.verdict, "pass");
    EXPECT_TRUE(quiet.reasons.empty()) << quiet.reasons;
}
TEST(StabilityCatalogue, CasePatterns) {
    EXPECT_TRUE(glob_match("grazing", "sweep_grazing"));
    EXPECT_TRUE(glob_match("grazing*", "grazing_bricks"));
    EXPECT_FALSE(glob_match("grazing*", "sweep_grazing"));
    EXPECT_TRUE(glob_match("*_?px", "lines_1px"));
    EXPECT_FALSE(glob_match("uv_*_100", "uv_offset_10000"));
    EXPECT_TRUE(glob_match("*", ""));
}

}  // namespace
}  // namespace px::profiling
