// GLSL ES 1.00's varying packing (Appendix A.7 of the 1.0.17 specification):
// the rule by which an OpenGL ES 2.0 implementation must accept a program's
// varyings within GL_MAX_VARYING_VECTORS, at least 8. llvmpipe offers 32, so
// a variant that needs more than 8 links here and fails on a minimum ES 2.0
// GPU; this checks every ES 2.0 variant's vertex outputs against the rule.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include <glslang/Include/intermediate.h>
#include <glslang/MachineIndependent/localintermediate.h>

#include "parallaxes/effects/variant.h"
#include "parallaxes/emulation/glslang_front.h"
#include "parallaxes/shaders/shader_source.h"

namespace px {
namespace {

// One varying: `rows` rows (an array's elements) of `columns` components.
// Matrices are not used by this project's shaders and are refused.
struct Varying {
    std::string name;
    int columns = 0;
    int rows = 0;
};

// A.7: vec4s, then vec3s, then vec2s (arrays and the larger first within a
// kind) from the first row down, aligned to column 0; once no row is left,
// vec2s go from the last row up into columns 2 and 3; then floats, each
// into the column whose free (contiguous) space it leaves the least of, at
// that space's lowest rows. Returns whether all fit in `max_rows`.
bool packs(std::vector<Varying> varyings, int max_rows) {
    std::stable_sort(varyings.begin(), varyings.end(), [](const Varying& a, const Varying& b) {
        if (a.columns != b.columns) return a.columns > b.columns;
        return a.rows > b.rows;
    });
    for (const Varying& v : varyings)
        if (v.columns < 1 || v.columns > 4 || v.rows < 1) return false;
    std::vector<std::array<bool, 4>> used(static_cast<std::size_t>(max_rows), std::array<bool, 4>{});
    int top = 0;               // the next row from the top for 2 to 4 columns
    int bottom = max_rows - 1; // vec2s from the bottom, columns 2 and 3
    for (const Varying& v : varyings) {
        if (v.columns < 2) continue;
        if (top + v.rows <= max_rows) {
            for (int r = top; r < top + v.rows; ++r)
                for (int c = 0; c < v.columns; ++c) used[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)] = true;
            top += v.rows;
            continue;
        }
        if (v.columns != 2) return false;
        for (int n = 0; n < v.rows; ++n, --bottom) {
            if (bottom < 0 || used[static_cast<std::size_t>(bottom)][2] || used[static_cast<std::size_t>(bottom)][3]) return false;
            used[static_cast<std::size_t>(bottom)][2] = used[static_cast<std::size_t>(bottom)][3] = true;
        }
    }
    for (const Varying& v : varyings) {
        if (v.columns != 1) continue;
        int best_column = -1, best_start = 0, best_left = max_rows + 1;
        for (int c = 0; c < 4; ++c) {
            // The column's free space: contiguous by the rule's construction.
            int start = -1, free = 0;
            for (int r = 0; r < max_rows; ++r)
                if (!used[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)]) {
                    if (start < 0) start = r;
                    ++free;
                }
            if (free >= v.rows && free - v.rows < best_left) {
                best_column = c;
                best_start = start;
                best_left = free - v.rows;
            }
        }
        if (best_column < 0) return false;
        for (int r = best_start; r < best_start + v.rows; ++r)
            used[static_cast<std::size_t>(r)][static_cast<std::size_t>(best_column)] = true;
    }
    return true;
}

// The vertex stage's outputs, from glslang's parse of the assembled source.
class OutputCollector : public glslang::TIntermTraverser {
public:
    void visitSymbol(glslang::TIntermSymbol* s) override {
        if (s->getQualifier().storage != glslang::EvqVaryingOut) return;
        if (std::find_if(found.begin(), found.end(), [&](const Varying& v) { return v.name == s->getName().c_str(); }) !=
            found.end())
            return;
        const glslang::TType& t = s->getType();
        Varying v;
        v.name = s->getName().c_str();
        v.columns = t.isMatrix() ? 0 : t.getVectorSize();
        v.rows = t.isArray() ? t.getOuterArraySize() : 1;
        found.push_back(v);
    }
    std::vector<Varying> found;
};

std::vector<Varying> vertex_outputs(const VariantKey& key, std::string& error) {
    Result<VariantSources> sources = assemble_variant(key);
    if (!sources) {
        error = sources.error().message;
        return {};
    }
    std::string log;
    std::unique_ptr<glslang::TShader> shader =
        emulation::parse_es_source(sources->vertex.text, ShaderStage::vertex, nullptr, log);
    if (!shader) {
        error = log;
        return {};
    }
    OutputCollector c;
    shader->getIntermediate()->getTreeRoot()->traverse(&c);
    return c.found;
}

std::string describe(const std::vector<Varying>& varyings) {
    std::string s;
    for (const Varying& v : varyings)
        s += v.name + " (" + std::to_string(v.columns) + " x " + std::to_string(v.rows) + ") ";
    return s;
}

TEST(VaryingPacking, TheRuleItself) {
    // Eight vec4s fill the minimum; a ninth does not fit.
    EXPECT_TRUE(packs(std::vector<Varying>(8, {"a", 4, 1}), 8));
    EXPECT_FALSE(packs(std::vector<Varying>(9, {"a", 4, 1}), 8));
    // vec3s leave their fourth column to floats: 8 vec3 and 8 floats fit,
    // a ninth float does not.
    std::vector<Varying> v(8, {"v3", 3, 1});
    for (int i = 0; i < 8; ++i) v.push_back({"f", 1, 1});
    EXPECT_TRUE(packs(v, 8));
    v.push_back({"f", 1, 1});
    EXPECT_FALSE(packs(v, 8));
    // Two vec2s share a row (the second from the bottom, columns 2 and 3)
    // only once the rows from the top are used up.
    std::vector<Varying> w(7, {"v3", 3, 1});
    w.push_back({"uv", 2, 1});
    w.push_back({"st", 2, 1});
    EXPECT_TRUE(packs(w, 8));
    w.push_back({"v4", 4, 1});  // no row left for a vec4
    EXPECT_FALSE(packs(w, 8));
    // An array takes contiguous rows; a float array one column.
    EXPECT_TRUE(packs({{"lights", 3, 4}, {"weights", 1, 4}}, 4));
    EXPECT_FALSE(packs({{"lights", 3, 4}, {"weights", 1, 5}}, 4));
    EXPECT_FALSE(packs({{"m", 0, 1}}, 8));  // a matrix: not handled, refused
}

// Every ES 2.0 variant's varyings fit the ES 2.0 minimum of 8 vectors by the
// rule, so a minimum ES 2.0 GPU links all of them. The curved variant uses
// all 8 rows (view, view position, four lights and its bend as vec3s, two
// vec2s in one row) and its shell's four floats in the fourth column.
TEST(VaryingPacking, EveryEs2VariantFitsTheMinimumOf8Vectors) {
    int checked = 0, curved = 0;
    for (const VariantKey& key : enumerate_variants(2)) {
        std::string error;
        const std::vector<Varying> outputs = vertex_outputs(key, error);
        ASSERT_TRUE(error.empty()) << key.describe() << ": " << error;
        ASSERT_FALSE(outputs.empty()) << key.describe();
        EXPECT_TRUE(packs(outputs, 8)) << key.describe() << ": " << describe(outputs);
        ++checked;
        if (key.curved) {
            ++curved;
            // The fullest: with one vec4 more it would not fit.
            std::vector<Varying> more = outputs;
            more.push_back({"one_more", 4, 1});
            EXPECT_FALSE(packs(more, 8)) << key.describe() << ": " << describe(outputs);
        }
    }
    EXPECT_GT(checked, 100);
    EXPECT_GT(curved, 0);
}

}  // namespace
}  // namespace px
