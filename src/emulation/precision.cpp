// Precision emulation by rewriting the shader (precision.h).
//
// The source is parsed by glslang and its AST emitted again as GLSL ES 3.00.
// In the rounding profiles every declaration is highp (so the driver
// computes in fp32 and nothing rounds but what is emitted), and a rounding
// call, px_q16 (binary16) or px_qlow (lowp minimum), wraps every float value
// whose precision the profile maps to a rounding:
//   - the result of each operation: binary and unary operators, built-in
//     calls, constructors, int-to-float conversions; texture lookups by
//     their sampler's precision;
//   - constant operands (rounded here, on the CPU, with the same function);
//   - reads of uniforms and shader inputs;
//   - values assigned or initialised into variables (by the variable's
//     precision), arguments bound to `in` parameters (by the parameter's),
//     returned values (by the return type's).
// L-values are never wrapped. A built-in call (dot, normalize, mix, ...) and
// a matrix product are one operation: their result is rounded once, as by a
// GPU with such a unit; their inner multiply-adds are not.
//
// The precision of an expression is the one glslang gives its node: glslang
// 12 propagates precision to operations from their operands (the higher
// one), to constants from what they combine with, and to built-in results
// from their arguments. A float node glslang leaves without precision (a
// constant with no precise neighbour) takes the precision of the operation
// it feeds, else the source's default float precision for the stage.
//
// Profiles: identity rounds nothing and keeps the source's precision qualifiers
// (a pure re-emission: the driver treats every value as in the original,
// which is what makes it a control; Mesa lowers mediump to fp16 on CPUs with
// F16C, so an all-highp emission would not compute what the original does).
// fp32: nothing rounded, everything declared highp (strict fp32 arithmetic).
// fp16: mediump and lowp -> fp16. lowp: mediump -> fp16, lowp -> lowp.
// nohighp: in the fragment stage every precision -> fp16; the vertex stage
// as fp16. Integers are not emulated (declared highp in the rounding
// profiles). Functions on the exempt list are emitted without rounding.
#include "parallaxes/emulation/precision.h"
#include "parallaxes/emulation/glslang_front.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>

#include <glslang/Include/intermediate.h>
#include <glslang/MachineIndependent/localintermediate.h>
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>

namespace px::emulation {

using namespace glslang;

const char* profile_name(PrecisionProfile profile) {
    switch (profile) {
        case PrecisionProfile::identity: return "identity";
        case PrecisionProfile::fp32: return "fp32";
        case PrecisionProfile::fp16: return "fp16";
        case PrecisionProfile::lowp: return "lowp";
        case PrecisionProfile::nohighp: return "nohighp";
        case PrecisionProfile::lowp_all: return "lowp_all";
    }
    return "?";
}

Result<PrecisionProfile> parse_profile(std::string_view name) {
    for (PrecisionProfile p :
         {PrecisionProfile::identity, PrecisionProfile::fp32, PrecisionProfile::fp16, PrecisionProfile::lowp,
          PrecisionProfile::nohighp, PrecisionProfile::lowp_all})
        if (name == profile_name(p)) return p;
    return make_error("unknown precision profile '" + std::string(name) + "' (identity, fp32, fp16, lowp, nohighp or lowp_all)");
}

const std::vector<std::string>& default_exempt_functions() {
    static const std::vector<std::string> names = {"px_debug_output", "px_pack24", "px_pack16", "px_pack11"};
    return names;
}

float round_fp16(float x) {
    std::uint32_t u;
    std::memcpy(&u, &x, 4);
    const std::uint32_t sign = u & 0x80000000u;
    const std::uint32_t a = u & 0x7fffffffu;
    std::uint32_t r;
    if (a >= 0x7f800000u) return x;                 // inf and NaN as they are
    if (a >= 0x477ff000u) {                          // 65520 and up: past 65504 by half a step or more
        r = 0x7f800000u;
    } else if (a < 0x38800000u) {                    // below 2^-14: fp16 subnormals, steps of 2^-24
        const float q = std::nearbyint(std::fabs(x) * 16777216.0f) * (1.0f / 16777216.0f);  // both exact scalings
        std::memcpy(&r, &q, 4);
    } else {                                         // normal: 10 of fp32's 23 fraction bits, nearest even
        r = (a + 0x0fffu + ((a >> 13) & 1u)) & 0xffffe000u;
    }
    r |= sign;
    float out;
    std::memcpy(&out, &r, 4);
    return out;
}

float round_lowp(float x) {
    if (std::isnan(x)) return x;
    const float c = std::fmin(std::fmax(x, -2.0f), 2.0f);
    return std::nearbyint(c * 256.0f) * (1.0f / 256.0f);
}

namespace {

// The same rounding in GLSL ES 3.00 (exact: bit operations and power-of-two
// scalings, which are exact in fp32; roundEven is exact).
const char* kRoundingFunctions = R"(highp float px_q16(highp float x) {
    highp uint u = floatBitsToUint(x);
    highp uint s = u & 0x80000000u;
    highp uint a = u & 0x7fffffffu;
    if (a >= 0x7f800000u) return x;
    if (a >= 0x477ff000u) return uintBitsToFloat(s | 0x7f800000u);
    if (a < 0x38800000u) return uintBitsToFloat(s | floatBitsToUint(roundEven(abs(x) * 16777216.0) * (1.0 / 16777216.0)));
    return uintBitsToFloat(s | ((a + 0x0fffu + ((a >> 13u) & 1u)) & 0xffffe000u));
}
highp vec2 px_q16(highp vec2 v) { return vec2(px_q16(v.x), px_q16(v.y)); }
highp vec3 px_q16(highp vec3 v) { return vec3(px_q16(v.x), px_q16(v.y), px_q16(v.z)); }
highp vec4 px_q16(highp vec4 v) { return vec4(px_q16(v.x), px_q16(v.y), px_q16(v.z), px_q16(v.w)); }
highp mat2 px_q16(highp mat2 m) { return mat2(px_q16(m[0]), px_q16(m[1])); }
highp mat3 px_q16(highp mat3 m) { return mat3(px_q16(m[0]), px_q16(m[1]), px_q16(m[2])); }
highp mat4 px_q16(highp mat4 m) { return mat4(px_q16(m[0]), px_q16(m[1]), px_q16(m[2]), px_q16(m[3])); }
highp float px_qlow(highp float x) {
    if ((floatBitsToUint(x) & 0x7fffffffu) > 0x7f800000u) return x;
    return roundEven(clamp(x, -2.0, 2.0) * 256.0) * (1.0 / 256.0);
}
highp vec2 px_qlow(highp vec2 v) { return vec2(px_qlow(v.x), px_qlow(v.y)); }
highp vec3 px_qlow(highp vec3 v) { return vec3(px_qlow(v.x), px_qlow(v.y), px_qlow(v.z)); }
highp vec4 px_qlow(highp vec4 v) { return vec4(px_qlow(v.x), px_qlow(v.y), px_qlow(v.z), px_qlow(v.w)); }
highp mat2 px_qlow(highp mat2 m) { return mat2(px_qlow(m[0]), px_qlow(m[1])); }
highp mat3 px_qlow(highp mat3 m) { return mat3(px_qlow(m[0]), px_qlow(m[1]), px_qlow(m[2])); }
highp mat4 px_qlow(highp mat4 m) { return mat4(px_qlow(m[0]), px_qlow(m[1]), px_qlow(m[2]), px_qlow(m[3])); }
)";

// A parsed shader; the tree lives as long as the TShader.
struct Parsed {
    std::unique_ptr<TShader> shader;
    std::string error;
};

Parsed parse(const std::string& source, ShaderStage stage) {
    Parsed p;
    std::string log;
    p.shader = parse_es_source(source, stage, nullptr, log);
    if (!p.shader) {
        p.error = std::string("glslang rejected the ") + (stage == ShaderStage::vertex ? "vertex" : "fragment") +
                  " source:\n" + log;
        if (p.error.back() != '\n') p.error += '\n';
    }
    return p;
}

enum class Rounding { none, fp16, lowp };

// An unsupported construct: thrown inside the emitter, caught at its edge
// and returned as an error value.
struct Unsupported {
    std::string what;
};

bool is_float(const TType& t) { return t.getBasicType() == EbtFloat; }

std::string basic_name(const TType& t) {
    const int v = t.getVectorSize();
    if (t.isMatrix()) {
        if (t.getBasicType() != EbtFloat) throw Unsupported{"a non-float matrix"};
        const int c = t.getMatrixCols(), r = t.getMatrixRows();
        return c == r ? "mat" + std::to_string(c) : "mat" + std::to_string(c) + "x" + std::to_string(r);
    }
    auto vec = [&](const char* scalar, const char* prefix) {
        return v > 1 && !t.isScalar() ? std::string(prefix) + "vec" + std::to_string(v) : std::string(scalar);
    };
    switch (t.getBasicType()) {
        case EbtFloat: return vec("float", "");
        case EbtInt: return vec("int", "i");
        case EbtUint: return vec("uint", "u");
        case EbtBool: return vec("bool", "b");
        case EbtVoid: return "void";
        case EbtStruct: return t.getTypeName().c_str();
        case EbtSampler: {
            const TSampler& s = t.getSampler();
            if (s.isImage() || s.isSubpass() || s.isPureSampler() || s.isCombined() == false || s.isMultiSample())
                throw Unsupported{"a sampler that is not a combined texture sampler"};
            std::string name = s.type == EbtInt ? "isampler" : s.type == EbtUint ? "usampler" : "sampler";
            switch (s.dim) {
                case Esd2D: name += "2D"; break;
                case Esd3D: name += "3D"; break;
                case EsdCube: name += "Cube"; break;
                default: throw Unsupported{"a sampler dimension other than 2D, 3D or cube"};
            }
            if (s.isArrayed()) name += "Array";
            if (s.isShadow()) name += "Shadow";
            return name;
        }
        default: throw Unsupported{std::string("the type '") + t.getBasicTypeString().c_str() + "'"};
    }
}

const char* precision_keyword(TPrecisionQualifier p) {
    switch (p) {
        case EpqLow: return "lowp";
        case EpqMedium: return "mediump";
        case EpqHigh: return "highp";
        default: return nullptr;
    }
}

bool takes_precision(const TType& t) {
    const TBasicType b = t.getBasicType();
    return b == EbtFloat || b == EbtInt || b == EbtUint || b == EbtSampler;
}

std::string base_name(const std::string& mangled) {
    const std::string& s = mangled;
    const size_t paren = s.find('(');
    return paren == std::string::npos ? s : s.substr(0, paren);
}

std::string float_literal(float f) {
    if (std::isnan(f)) return "uintBitsToFloat(0x7fc00000u)";
    if (std::isinf(f)) return f > 0 ? "uintBitsToFloat(0x7f800000u)" : "uintBitsToFloat(0xff800000u)";
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.9g", static_cast<double>(f));  // 9 digits: every float round-trips
    std::string s = buffer;
    if (s.find_first_of(".e") == std::string::npos) s += ".0";
    if (s.find('e') != std::string::npos && s.find('.') == std::string::npos) s.insert(s.find('e'), ".0");
    return s;
}

const char* unary_builtin(TOperator op) {
    switch (op) {
        case EOpRadians: return "radians"; case EOpDegrees: return "degrees";
        case EOpSin: return "sin"; case EOpCos: return "cos"; case EOpTan: return "tan";
        case EOpAsin: return "asin"; case EOpAcos: return "acos"; case EOpAtan: return "atan";
        case EOpSinh: return "sinh"; case EOpCosh: return "cosh"; case EOpTanh: return "tanh";
        case EOpAsinh: return "asinh"; case EOpAcosh: return "acosh"; case EOpAtanh: return "atanh";
        case EOpExp: return "exp"; case EOpLog: return "log"; case EOpExp2: return "exp2"; case EOpLog2: return "log2";
        case EOpSqrt: return "sqrt"; case EOpInverseSqrt: return "inversesqrt";
        case EOpAbs: return "abs"; case EOpSign: return "sign"; case EOpFloor: return "floor";
        case EOpTrunc: return "trunc"; case EOpRound: return "round"; case EOpRoundEven: return "roundEven";
        case EOpCeil: return "ceil"; case EOpFract: return "fract";
        case EOpIsNan: return "isnan"; case EOpIsInf: return "isinf";
        case EOpFloatBitsToInt: return "floatBitsToInt"; case EOpFloatBitsToUint: return "floatBitsToUint";
        case EOpIntBitsToFloat: return "intBitsToFloat"; case EOpUintBitsToFloat: return "uintBitsToFloat";
        case EOpPackSnorm2x16: return "packSnorm2x16"; case EOpUnpackSnorm2x16: return "unpackSnorm2x16";
        case EOpPackUnorm2x16: return "packUnorm2x16"; case EOpUnpackUnorm2x16: return "unpackUnorm2x16";
        case EOpPackHalf2x16: return "packHalf2x16"; case EOpUnpackHalf2x16: return "unpackHalf2x16";
        case EOpLength: return "length"; case EOpNormalize: return "normalize";
        case EOpDPdx: return "dFdx"; case EOpDPdy: return "dFdy"; case EOpFwidth: return "fwidth";
        case EOpDeterminant: return "determinant"; case EOpMatrixInverse: return "inverse";
        case EOpTranspose: return "transpose";
        case EOpAny: return "any"; case EOpAll: return "all"; case EOpVectorLogicalNot: return "not";
        default: return nullptr;
    }
}

// Built-in calls with several arguments (aggregates). Texture functions get
// their GLSL ES 3.00 names whatever the source called them (texture2D,
// texture2DLodEXT, ...).
const char* aggregate_builtin(TOperator op) {
    switch (op) {
        case EOpAtan: return "atan"; case EOpPow: return "pow"; case EOpMod: return "mod";
        case EOpMin: return "min"; case EOpMax: return "max"; case EOpClamp: return "clamp";
        case EOpMix: return "mix"; case EOpStep: return "step"; case EOpSmoothStep: return "smoothstep";
        case EOpDistance: return "distance"; case EOpDot: return "dot"; case EOpCross: return "cross";
        case EOpFaceForward: return "faceforward"; case EOpReflect: return "reflect"; case EOpRefract: return "refract";
        case EOpMul: return "matrixCompMult"; case EOpOuterProduct: return "outerProduct";
        case EOpLessThan: return "lessThan"; case EOpGreaterThan: return "greaterThan";
        case EOpLessThanEqual: return "lessThanEqual"; case EOpGreaterThanEqual: return "greaterThanEqual";
        case EOpVectorEqual: return "equal"; case EOpVectorNotEqual: return "notEqual";
        case EOpTexture: return "texture"; case EOpTextureProj: return "textureProj";
        case EOpTextureLod: return "textureLod"; case EOpTextureOffset: return "textureOffset";
        case EOpTextureFetch: return "texelFetch"; case EOpTextureFetchOffset: return "texelFetchOffset";
        case EOpTextureProjOffset: return "textureProjOffset"; case EOpTextureLodOffset: return "textureLodOffset";
        case EOpTextureProjLod: return "textureProjLod"; case EOpTextureProjLodOffset: return "textureProjLodOffset";
        case EOpTextureGrad: return "textureGrad"; case EOpTextureGradOffset: return "textureGradOffset";
        case EOpTextureProjGrad: return "textureProjGrad"; case EOpTextureProjGradOffset: return "textureProjGradOffset";
        case EOpTextureQuerySize: return "textureSize";
        default: return nullptr;
    }
}

bool is_texture_lookup(TOperator op) {
    return op > EOpTextureGuardBegin && op < EOpTextureGuardEnd && op != EOpTextureQuerySize;
}

const char* binary_operator(TOperator op) {
    switch (op) {
        case EOpAdd: return "+"; case EOpSub: return "-";
        case EOpMul: case EOpVectorTimesScalar: case EOpVectorTimesMatrix: case EOpMatrixTimesVector:
        case EOpMatrixTimesScalar: case EOpMatrixTimesMatrix: return "*";
        case EOpDiv: return "/"; case EOpMod: return "%";
        case EOpRightShift: return ">>"; case EOpLeftShift: return "<<";
        case EOpAnd: return "&"; case EOpInclusiveOr: return "|"; case EOpExclusiveOr: return "^";
        case EOpEqual: return "=="; case EOpNotEqual: return "!=";
        case EOpLessThan: return "<"; case EOpGreaterThan: return ">";
        case EOpLessThanEqual: return "<="; case EOpGreaterThanEqual: return ">=";
        case EOpLogicalOr: return "||"; case EOpLogicalXor: return "^^"; case EOpLogicalAnd: return "&&";
        default: return nullptr;
    }
}

// Compound assignments: the operator they apply.
const char* compound_operator(TOperator op) {
    switch (op) {
        case EOpAddAssign: return "+"; case EOpSubAssign: return "-";
        case EOpMulAssign: case EOpVectorTimesMatrixAssign: case EOpVectorTimesScalarAssign:
        case EOpMatrixTimesScalarAssign: case EOpMatrixTimesMatrixAssign: return "*";
        case EOpDivAssign: return "/"; case EOpModAssign: return "%";
        case EOpAndAssign: return "&"; case EOpInclusiveOrAssign: return "|"; case EOpExclusiveOrAssign: return "^";
        case EOpLeftShiftAssign: return "<<"; case EOpRightShiftAssign: return ">>";
        default: return nullptr;
    }
}

bool is_pipeline_input(TStorageQualifier q) {
    return q == EvqUniform || q == EvqVaryingIn || q == EvqFragCoord || q == EvqFace || q == EvqPointCoord;
}

bool is_global_storage(TStorageQualifier q) {
    return q == EvqGlobal || q == EvqUniform || q == EvqVaryingIn || q == EvqVaryingOut;
}

// ---- Pre-pass: functions, symbols and the scopes they live in -------------

struct FunctionInfo {
    TIntermAggregate* node = nullptr;
    std::vector<TIntermSymbol*> params;
    TIntermAggregate* body = nullptr;
};

// A scope is a node the emitter prints as a braced block: a function body,
// a loop body, a branch of an if, a switch body, a for loop's header.
struct SymbolInfo {
    const TIntermSymbol* first = nullptr;
    // The scope in which the first occurrence is the left side of a plain
    // `x = ...` statement (a declaration with an initialiser), if it is.
    const TIntermNode* init_scope = nullptr;
    std::vector<const TIntermNode*> scope_path;  // the scopes of the first occurrence, outermost first
    size_t common = 0;                           // how many of them every occurrence shares
    std::string name;                            // as emitted
};

class Emitter {
public:
    Emitter(ShaderStage stage, PrecisionProfile profile, const std::set<std::string>& exempt,
            TPrecisionQualifier default_float)
        : stage_(stage), profile_(profile), exempt_(exempt), default_float_(default_float) {}

    std::string emit(TIntermediate& intermediate);

private:
    ShaderStage stage_;
    PrecisionProfile profile_;
    const std::set<std::string>& exempt_;
    TPrecisionQualifier default_float_;
    bool in_exempt_ = false;
    bool es100_ = false;

    std::map<std::string, FunctionInfo> functions_;            // by mangled name
    std::vector<const TTypeList*> struct_order_;
    std::map<const TTypeList*, std::string> struct_names_;
    std::map<long long, const TIntermSymbol*> globals_;        // by symbol id
    std::vector<long long> global_order_;
    std::map<long long, std::string> global_initializers_;
    std::map<long long, SymbolInfo> locals_;                    // of the function being emitted
    std::set<long long> declared_;                              // locals declared so far
    const TType* current_return_ = nullptr;
    std::string out_;
    int indent_ = 0;

    // Every profile but the identity declares everything highp.
    bool rounds() const { return profile_ != PrecisionProfile::identity; }

    Rounding rounding(TPrecisionQualifier p) const {
        if (in_exempt_) return Rounding::none;
        if (p == EpqNone) p = default_float_;
        switch (profile_) {
            case PrecisionProfile::identity:
            case PrecisionProfile::fp32: return Rounding::none;
            case PrecisionProfile::fp16: return p == EpqHigh ? Rounding::none : Rounding::fp16;
            case PrecisionProfile::lowp:
                return p == EpqHigh ? Rounding::none : p == EpqLow ? Rounding::lowp : Rounding::fp16;
            case PrecisionProfile::nohighp:
                if (stage_ == ShaderStage::fragment) return Rounding::fp16;
                return p == EpqHigh ? Rounding::none : Rounding::fp16;
            case PrecisionProfile::lowp_all:
                if (stage_ == ShaderStage::fragment) return Rounding::lowp;
                return p == EpqHigh ? Rounding::none : Rounding::fp16;
        }
        return Rounding::none;
    }

    static TPrecisionQualifier precision_of(const TIntermTyped* n, TPrecisionQualifier context) {
        const TPrecisionQualifier p = n->getQualifier().precision;
        return p != EpqNone ? p : context;
    }

    std::string wrap(Rounding r, const TType& t, const std::string& text, const char* what) const {
        if (r == Rounding::none || !is_float(t)) return text;
        if (t.isArray() || t.isStruct()) throw Unsupported{std::string("rounding a whole float array or struct (") + what + ")"};
        return std::string(r == Rounding::fp16 ? "px_q16(" : "px_qlow(") + text + ")";
    }

    // Type text of a declaration, with its precision keyword.
    std::string declared_type(const TType& t) {
        std::string s;
        if (takes_precision(t)) {
            const char* p = rounds() ? "highp" : precision_keyword(t.getQualifier().precision);
            if (p) s += std::string(p) + " ";
        }
        if (t.isStruct()) note_struct(t);
        s += basic_name(t);
        return s;
    }
    std::string array_suffix(const TType& t) {
        if (!t.isArray()) return "";
        const TArraySizes* sizes = t.getArraySizes();
        if (sizes->getNumDims() != 1 || sizes->getDimSize(0) <= 0) throw Unsupported{"an unsized or multidimensional array"};
        return "[" + std::to_string(sizes->getDimSize(0)) + "]";
    }

    void note_struct(const TType& t) {
        const TTypeList* members = t.getStruct();
        if (struct_names_.count(members)) return;
        for (const TTypeLoc& m : *members)
            if (m.type->isStruct()) note_struct(*m.type);
        struct_names_[members] = t.getTypeName().c_str();
        struct_order_.push_back(members);
    }

    // ---- pre-pass ----
    void collect(TIntermNode* root);
    void collect_types(TIntermNode* n);
    void scan_function(const FunctionInfo& f);
    void scan(TIntermNode* n, std::vector<const TIntermNode*>& scopes);
    void scan_statements(TIntermNode* n, std::vector<const TIntermNode*>& scopes);
    void record(const TIntermSymbol* s, const std::vector<const TIntermNode*>& scopes);

    // ---- statements ----
    void line(const std::string& text) { out_ += std::string(static_cast<size_t>(indent_) * 4, ' ') + text + "\n"; }
    std::string emit_function(const FunctionInfo& f);
    void emit_scope(TIntermNode* scope_node, TIntermNode* content);
    void emit_statements(TIntermNode* n, const TIntermNode* scope);
    void emit_statement(TIntermNode* n, const TIntermNode* scope);
    bool emit_for(TIntermAggregate* seq, const TIntermNode* scope);
    std::string declaration(long long id, const TIntermSymbol* s);

    // ---- expressions ----
    std::string symbol_name(const TIntermSymbol* s);
    std::string value(TIntermTyped* n, TPrecisionQualifier context);
    std::string binary_value(TIntermBinary* b, TPrecisionQualifier p, TPrecisionQualifier context);
    std::string unary_value(TIntermUnary* u, TPrecisionQualifier p);
    std::string aggregate_value(TIntermAggregate* a, TPrecisionQualifier p);
    std::string lvalue(TIntermTyped* n);
    std::string chain(TIntermTyped* n, bool& from_input);
    std::string constant(TIntermConstantUnion* c, TPrecisionQualifier context);
    std::string assignment(TIntermBinary* b);
    std::string call(TIntermAggregate* a);
    std::string args(TIntermAggregate* a, TPrecisionQualifier context, size_t first = 0);
    bool has_side_effects(TIntermNode* n);
};

// Struct types reach declarations through symbols, function signatures and
// constructors: note every one before anything is printed.
class TypeCollector : public TIntermTraverser {
public:
    explicit TypeCollector(std::vector<const TType*>& types) : types_(types) {}
    void visitSymbol(TIntermSymbol* s) override { types_.push_back(&s->getType()); }
    bool visitAggregate(TVisit, TIntermAggregate* a) override {
        types_.push_back(&a->getType());
        return true;
    }
    std::vector<const TType*>& types_;
};

void Emitter::collect_types(TIntermNode* n) {
    std::vector<const TType*> types;
    TypeCollector c(types);
    n->traverse(&c);
    for (const TType* t : types)
        if (t->isStruct()) note_struct(*t);
}

class GlobalCollector : public TIntermTraverser {
public:
    GlobalCollector(std::map<long long, const TIntermSymbol*>& globals, std::vector<long long>& order)
        : globals_(globals), order_(order) {}
    void visitSymbol(TIntermSymbol* s) override {
        const TStorageQualifier q = s->getQualifier().storage;
        if (!is_global_storage(q) || std::strncmp(s->getName().c_str(), "gl_", 3) == 0) return;
        if (globals_.emplace(s->getId(), s).second) order_.push_back(s->getId());
    }
    std::map<long long, const TIntermSymbol*>& globals_;
    std::vector<long long>& order_;
};

void Emitter::collect(TIntermNode* root) {
    TIntermAggregate* top = root->getAsAggregate();
    if (!top) throw Unsupported{"a tree whose root is not a sequence"};
    GlobalCollector g(globals_, global_order_);
    root->traverse(&g);
    collect_types(root);
    for (TIntermNode* child : top->getSequence()) {
        TIntermAggregate* a = child->getAsAggregate();
        if (a && a->getOp() == EOpFunction) {
            FunctionInfo f;
            f.node = a;
            for (TIntermNode* part : a->getSequence()) {
                TIntermAggregate* pa = part->getAsAggregate();
                if (pa && pa->getOp() == EOpParameters) {
                    for (TIntermNode* p : pa->getSequence()) {
                        if (!p->getAsSymbolNode()) throw Unsupported{"a parameter that is not a symbol"};
                        f.params.push_back(p->getAsSymbolNode());
                    }
                } else if (pa) {
                    f.body = pa;
                } else {
                    throw Unsupported{"a function body that is not a sequence"};
                }
            }
            functions_[a->getName().c_str()] = f;
        } else if (a && a->getOp() == EOpLinkerObjects) {
            continue;
        } else if (a && a->getOp() == EOpSequence) {
            // Global initialisers: `T g = constant;` at file scope.
            for (TIntermNode* s : a->getSequence()) {
                TIntermBinary* b = s->getAsBinaryNode();
                if (!b || b->getOp() != EOpAssign || !b->getLeft()->getAsSymbolNode() || !b->getRight()->getAsConstantUnion())
                    throw Unsupported{"a global initialiser that is not a constant"};
                const TIntermSymbol* sym = b->getLeft()->getAsSymbolNode();
                global_initializers_[sym->getId()] =
                    constant(b->getRight()->getAsConstantUnion(), precision_of(sym, default_float_));
            }
        } else {
            throw Unsupported{"a file-scope statement that is neither a function nor a global declaration"};
        }
    }
}

void Emitter::record(const TIntermSymbol* s, const std::vector<const TIntermNode*>& scopes) {
    const TStorageQualifier q = s->getQualifier().storage;
    if (is_global_storage(q) || std::strncmp(s->getName().c_str(), "gl_", 3) == 0) return;
    auto it = locals_.find(s->getId());
    if (it == locals_.end()) {
        SymbolInfo info;
        info.first = s;
        info.scope_path = scopes;
        info.common = scopes.size();
        locals_.emplace(s->getId(), info);
        return;
    }
    SymbolInfo& info = it->second;
    size_t k = 0;
    while (k < info.common && k < scopes.size() && info.scope_path[k] == scopes[k]) ++k;
    info.common = k;
}

// glslang makes a for loop a sequence [inits..., loop]: that sequence is the
// scope of the loop's own variable.
bool is_for_header(const TIntermNode* n) {
    const TIntermAggregate* a = n ? n->getAsAggregate() : nullptr;
    if (!a || a->getOp() != EOpSequence || a->getSequence().empty()) return false;
    const TIntermLoop* l = a->getSequence().back()->getAsLoopNode();
    return l && l->testFirst();
}

// Expressions: every symbol occurrence with the scopes around it.
void Emitter::scan(TIntermNode* n, std::vector<const TIntermNode*>& scopes) {
    if (!n) return;
    if (TIntermSymbol* s = n->getAsSymbolNode()) {
        record(s, scopes);
    } else if (TIntermBinary* b = n->getAsBinaryNode()) {
        scan(b->getLeft(), scopes);
        scan(b->getRight(), scopes);
    } else if (TIntermUnary* u = n->getAsUnaryNode()) {
        scan(u->getOperand(), scopes);
    } else if (TIntermAggregate* a = n->getAsAggregate()) {
        for (TIntermNode* c : a->getSequence()) scan(c, scopes);
    } else if (TIntermSelection* sel = n->getAsSelectionNode()) {
        scan(sel->getCondition(), scopes);
        scan(sel->getTrueBlock(), scopes);
        scan(sel->getFalseBlock(), scopes);
    } else if (TIntermBranch* br = n->getAsBranchNode()) {
        scan(br->getExpression(), scopes);
    } else if (n->getAsLoopNode() || n->getAsSwitchNode()) {
        throw Unsupported{"a loop or switch inside an expression"};
    }
}

// Statements, in the order the emitter prints them: sequences flattened
// into the scope around them (glslang makes one of a declaration too, so a
// sequence is not a block), a for loop's header, if branches, loop and
// switch bodies as scopes of their own.
void Emitter::scan_statements(TIntermNode* n, std::vector<const TIntermNode*>& scopes) {
    if (!n) return;
    TIntermAggregate* a = n->getAsAggregate();
    if (a && a->getOp() == EOpSequence) {
        const bool header = is_for_header(a);
        if (header) scopes.push_back(a);
        for (TIntermNode* c : a->getSequence()) scan_statements(c, scopes);
        if (header) scopes.pop_back();
        return;
    }
    if (TIntermSelection* sel = n->getAsSelectionNode(); sel && sel->getBasicType() == EbtVoid) {
        scan(sel->getCondition(), scopes);
        for (TIntermNode* branch : {sel->getTrueBlock(), sel->getFalseBlock()}) {
            if (!branch) continue;
            scopes.push_back(branch);
            scan_statements(branch, scopes);
            scopes.pop_back();
        }
        return;
    }
    if (TIntermLoop* l = n->getAsLoopNode()) {
        scan(l->getTest(), scopes);
        scan(l->getTerminal(), scopes);
        scopes.push_back(l);
        scan_statements(l->getBody(), scopes);
        scopes.pop_back();
        return;
    }
    if (TIntermSwitch* sw = n->getAsSwitchNode()) {
        scan(sw->getCondition(), scopes);
        scopes.push_back(sw);
        scan_statements(sw->getBody(), scopes);
        scopes.pop_back();
        return;
    }
    // `x = ...` as the first occurrence of x: a declaration with its initialiser.
    if (TIntermBinary* b = n->getAsBinaryNode(); b && b->getOp() == EOpAssign && b->getLeft()->getAsSymbolNode()) {
        const TIntermSymbol* s = b->getLeft()->getAsSymbolNode();
        const bool first = !locals_.count(s->getId());
        scan(n, scopes);
        auto it = locals_.find(s->getId());
        if (first && it != locals_.end()) it->second.init_scope = scopes.back();
        return;
    }
    scan(n, scopes);
}

void Emitter::scan_function(const FunctionInfo& f) {
    locals_.clear();
    declared_.clear();
    std::vector<const TIntermNode*> scopes{f.node};
    for (TIntermSymbol* p : f.params) record(p, scopes);
    if (f.body) {
        scopes.push_back(f.body);
        scan_statements(f.body, scopes);
    }
    // Names: a local keeps its own unless another symbol of the function, or
    // a global, has it (two loops' `i`, a shadowing declaration): then it
    // gets its id as a suffix. Declarations move to the innermost scope that
    // holds every occurrence, so two symbols must never share a name there.
    std::set<std::string> taken;
    for (const auto& g : globals_) taken.insert(g.second->getName().c_str());
    for (const auto& fn : functions_) taken.insert(base_name(fn.first));
    for (auto& entry : locals_) {
        SymbolInfo& info = entry.second;
        std::string name = info.first->getName().c_str();
        if (name.empty()) throw Unsupported{"an unnamed parameter"};
        if (taken.count(name)) name += "_px" + std::to_string(entry.first);
        taken.insert(name);
        info.name = name;
        const bool parameter = info.scope_path.size() == 1;
        if (!parameter) {
            if (info.common < 2) throw Unsupported{"a local used outside its function's body"};
        }
    }
}

std::string Emitter::symbol_name(const TIntermSymbol* s) {
    const std::string name = s->getName().c_str();
    if (name == "gl_FragColor") return "px_emulated_frag_color";
    if (name == "gl_FragDepthEXT") return "gl_FragDepth";
    if (name.rfind("gl_", 0) == 0) {
        if (name == "gl_FragData") throw Unsupported{"gl_FragData"};
        return name;
    }
    auto it = locals_.find(s->getId());
    if (it != locals_.end()) return it->second.name;
    return name;
}

std::string Emitter::constant(TIntermConstantUnion* c, TPrecisionQualifier context) {
    const TType& t = c->getType();
    if (t.isArray() || t.isStruct()) throw Unsupported{"a constant array or struct"};
    const TConstUnionArray& values = c->getConstArray();
    const Rounding r = is_float(t) ? rounding(precision_of(c, context)) : Rounding::none;
    std::vector<std::string> parts;
    for (int i = 0; i < values.size(); ++i) {
        const TConstUnion& v = values[i];
        switch (v.getType()) {
            case EbtFloat: case EbtDouble: {
                float f = static_cast<float>(v.getDConst());
                if (r == Rounding::fp16) f = round_fp16(f);
                if (r == Rounding::lowp) f = round_lowp(f);
                parts.push_back(float_literal(f));
                break;
            }
            case EbtInt: parts.push_back(std::to_string(v.getIConst())); break;
            case EbtUint: parts.push_back(std::to_string(v.getUConst()) + "u"); break;
            case EbtBool: parts.push_back(v.getBConst() ? "true" : "false"); break;
            default: throw Unsupported{"a constant of an unsupported type"};
        }
    }
    if (parts.size() == 1 && t.isScalar()) {
        const std::string& s = parts[0];
        return s[0] == '-' ? "(" + s + ")" : s;
    }
    std::string text = basic_name(t) + "(";
    for (size_t i = 0; i < parts.size(); ++i) text += (i ? ", " : "") + parts[i];
    return text + ")";
}

bool Emitter::has_side_effects(TIntermNode* n) {
    if (!n) return false;
    if (TIntermBinary* b = n->getAsBinaryNode()) {
        if (b->getOp() >= EOpAssign && b->getOp() <= EOpRightShiftAssign) return true;
        return has_side_effects(b->getLeft()) || has_side_effects(b->getRight());
    }
    if (TIntermUnary* u = n->getAsUnaryNode()) {
        const TOperator op = u->getOp();
        if (op == EOpPostIncrement || op == EOpPostDecrement || op == EOpPreIncrement || op == EOpPreDecrement) return true;
        return has_side_effects(u->getOperand());
    }
    if (TIntermAggregate* a = n->getAsAggregate()) {
        if (a->getOp() == EOpFunctionCall) return true;
        for (TIntermNode* c : a->getSequence())
            if (has_side_effects(c)) return true;
        return false;
    }
    if (TIntermSelection* s = n->getAsSelectionNode())
        return has_side_effects(s->getCondition()) || has_side_effects(s->getTrueBlock()) ||
               has_side_effects(s->getFalseBlock());
    return false;
}

// An access chain (indexing, fields, swizzles) as text, without rounding;
// `from_input` says whether its base is a uniform or a shader input.
std::string Emitter::chain(TIntermTyped* n, bool& from_input) {
    if (TIntermSymbol* s = n->getAsSymbolNode()) {
        from_input = is_pipeline_input(s->getQualifier().storage);
        return symbol_name(s);
    }
    TIntermBinary* b = n->getAsBinaryNode();
    if (b) {
        const TOperator op = b->getOp();
        if (op == EOpIndexDirect || op == EOpIndexIndirect || op == EOpIndexDirectStruct || op == EOpVectorSwizzle) {
            TIntermTyped* base = b->getLeft();
            std::string base_text;
            if (base->getAsSymbolNode() || (base->getAsBinaryNode() && base->getAsBinaryNode()->getOp() >= EOpIndexDirect &&
                                            base->getAsBinaryNode()->getOp() <= EOpVectorSwizzle)) {
                base_text = chain(base, from_input);
            } else {
                from_input = false;
                base_text = value(base, EpqNone);
            }
            switch (op) {
                case EOpIndexDirect: case EOpIndexIndirect:
                    return base_text + "[" + value(b->getRight(), EpqHigh) + "]";
                case EOpIndexDirectStruct: {
                    const int index = b->getRight()->getAsConstantUnion()->getConstArray()[0].getIConst();
                    return base_text + "." + (*base->getType().getStruct())[static_cast<size_t>(index)].type->getFieldName().c_str();
                }
                default: {
                    std::string swizzle;
                    TIntermAggregate* components = b->getRight()->getAsAggregate();
                    if (!components) throw Unsupported{"a swizzle without components"};
                    for (TIntermNode* c : components->getSequence())
                        swizzle += "xyzw"[c->getAsConstantUnion()->getConstArray()[0].getIConst() & 3];
                    return base_text + "." + swizzle;
                }
            }
        }
    }
    throw Unsupported{"an l-value that is not a variable, element, field or swizzle"};
}

std::string Emitter::lvalue(TIntermTyped* n) {
    bool from_input = false;
    return chain(n, from_input);
}

std::string Emitter::assignment(TIntermBinary* b) {
    TIntermTyped* lhs = b->getLeft();
    const TPrecisionQualifier target = precision_of(lhs, default_float_);
    const std::string l = lvalue(lhs);
    if (b->getOp() == EOpAssign) {
        // The result of an exempt (measurement) function is stored as it is:
        // rounding it into a mediump output (gl_FragColor is mediump in GLSL
        // ES 1.00) would corrupt the measurement, e.g. a debug uv of 100
        // rounded to fp16 is 16 texels off.
        if (TIntermAggregate* call = b->getRight()->getAsAggregate(); call && call->getOp() == EOpFunctionCall) {
            std::string name = call->getName().c_str();
            name = name.substr(0, name.find('('));
            if (exempt_.count(name)) return l + " = " + value(b->getRight(), target);
        }
        return l + " = " + wrap(rounding(target), lhs->getType(), value(b->getRight(), target), "an assignment");
    }
    const char* op = compound_operator(b->getOp());
    if (!op) throw Unsupported{"an assignment operator"};
    const Rounding r_op = rounding(precision_of(b, target));
    const Rounding r_target = rounding(target);
    if (!is_float(lhs->getType()) || (r_op == Rounding::none && r_target == Rounding::none))
        return l + " " + op + "= " + value(b->getRight(), precision_of(b, target));
    // a op= b is a = a op b, rounded as the operation, then as the target.
    if (has_side_effects(lhs)) throw Unsupported{"a compound assignment to an l-value with side effects"};
    std::string result = wrap(r_op, b->getType(), "(" + l + " " + op + " " + value(b->getRight(), precision_of(b, target)) + ")",
                              "a compound assignment");
    if (r_target != r_op) result = wrap(r_target, lhs->getType(), result, "a compound assignment");
    return l + " = " + result;
}

std::string Emitter::args(TIntermAggregate* a, TPrecisionQualifier context, size_t first) {
    std::string s;
    TIntermSequence& seq = a->getSequence();
    for (size_t i = first; i < seq.size(); ++i) {
        TIntermTyped* t = seq[i]->getAsTyped();
        if (!t) throw Unsupported{"an argument that is not an expression"};
        s += (i > first ? ", " : "") + value(t, context);
    }
    return s;
}

std::string Emitter::call(TIntermAggregate* a) {
    auto it = functions_.find(a->getName().c_str());
    if (it == functions_.end()) throw Unsupported{std::string("a call of '") + a->getName().c_str() + "', which has no body"};
    const FunctionInfo& f = it->second;
    TIntermSequence& seq = a->getSequence();
    if (seq.size() != f.params.size()) throw Unsupported{"a call whose argument count differs from its function's"};
    std::string s = base_name(a->getName().c_str()) + "(";
    for (size_t i = 0; i < seq.size(); ++i) {
        TIntermTyped* arg = seq[i]->getAsTyped();
        const TType& pt = f.params[i]->getType();
        const TStorageQualifier q = pt.getQualifier().storage;
        const TPrecisionQualifier pp = precision_of(f.params[i], default_float_);
        std::string text;
        if (q == EvqOut || q == EvqInOut) {
            // Copied back on return: exact only when both sides round alike.
            if (is_float(pt) && rounding(pp) != rounding(precision_of(arg, default_float_)))
                throw Unsupported{"an out or inout argument whose precision differs from its parameter's"};
            text = lvalue(arg);
        } else {
            text = wrap(rounding(pp), pt, value(arg, pp), "an argument");
        }
        s += (i ? ", " : "") + text;
    }
    return s + ")";
}

std::string Emitter::value(TIntermTyped* n, TPrecisionQualifier context) {
    const TPrecisionQualifier p = precision_of(n, context);
    const TType& type = n->getType();
    if (TIntermConstantUnion* c = n->getAsConstantUnion()) return constant(c, context);
    if (TIntermSymbol* s = n->getAsSymbolNode()) {
        const std::string name = symbol_name(s);
        if (is_pipeline_input(s->getQualifier().storage) && is_float(type)) {
            if (type.isArray() && rounding(p) != Rounding::none) throw Unsupported{"a whole uniform or input array as a value"};
            return wrap(rounding(p), type, name, "an input");
        }
        return name;
    }
    if (TIntermBinary* b = n->getAsBinaryNode()) return binary_value(b, p, context);
    if (TIntermUnary* u = n->getAsUnaryNode()) return unary_value(u, p);
    if (TIntermAggregate* a = n->getAsAggregate()) return aggregate_value(a, p);
    if (TIntermSelection* sel = n->getAsSelectionNode()) {
        TIntermTyped* t = sel->getTrueBlock() ? sel->getTrueBlock()->getAsTyped() : nullptr;
        TIntermTyped* f = sel->getFalseBlock() ? sel->getFalseBlock()->getAsTyped() : nullptr;
        if (!t || !f) throw Unsupported{"a conditional expression without two values"};
        return "(" + value(sel->getCondition(), EpqNone) + " ? " + value(t, p) + " : " + value(f, p) + ")";
    }
    throw Unsupported{"an expression node of an unknown kind"};
}

// A binary node as a value (p its precision, context the one it is read
// in): an assignment, an index or swizzle chain, a comma, an operation.
std::string Emitter::binary_value(TIntermBinary* b, TPrecisionQualifier p, TPrecisionQualifier context) {
    const TType& type = b->getType();
    const TOperator op = b->getOp();
    if (op >= EOpAssign && op <= EOpRightShiftAssign) return "(" + assignment(b) + ")";
    if (op == EOpIndexDirect || op == EOpIndexIndirect || op == EOpIndexDirectStruct || op == EOpVectorSwizzle) {
        bool from_input = false;
        const std::string text = chain(b, from_input);
        return from_input ? wrap(rounding(p), type, text, "an input") : text;
    }
    if (op == EOpComma) return "(" + value(b->getLeft(), EpqNone) + ", " + value(b->getRight(), context) + ")";
    const char* o = binary_operator(op);
    if (!o) throw Unsupported{"binary operator #" + std::to_string(op)};
    // Comparisons: the operands' own precision is the context of a constant among them.
    const TPrecisionQualifier operand_context =
        type.getBasicType() == EbtBool && is_float(b->getLeft()->getType()) ? EpqNone : p;
    const std::string text = "(" + value(b->getLeft(), operand_context == EpqNone ? precision_of(b->getRight(), p) : p) +
                             " " + o + " " +
                             value(b->getRight(), operand_context == EpqNone ? precision_of(b->getLeft(), p) : p) + ")";
    return wrap(rounding(p), type, text, "an operation");
}

// A unary node as a value: a negation, a logical or bitwise not, an
// increment or decrement (rounded where a float is), a conversion, a
// built-in of one argument.
std::string Emitter::unary_value(TIntermUnary* u, TPrecisionQualifier p) {
    const TType& type = u->getType();
    const TOperator op = u->getOp();
    TIntermTyped* operand = u->getOperand();
    std::string text;
    switch (op) {
        case EOpNegative: text = "(-" + value(operand, p) + ")"; break;
        case EOpLogicalNot: return "(!" + value(operand, p) + ")";
        case EOpBitwiseNot: return "(~" + value(operand, p) + ")";
        case EOpPreIncrement: case EOpPreDecrement: case EOpPostIncrement: case EOpPostDecrement: {
            const bool inc = op == EOpPreIncrement || op == EOpPostIncrement;
            const bool pre = op == EOpPreIncrement || op == EOpPreDecrement;
            const std::string l = lvalue(operand);
            if (!is_float(type) || rounding(p) == Rounding::none)
                return pre ? std::string("(") + (inc ? "++" : "--") + l + ")" : "(" + l + (inc ? "++" : "--") + ")";
            if (!pre) throw Unsupported{"a float post-increment or post-decrement under rounding"};
            if (has_side_effects(operand)) throw Unsupported{"an increment of an l-value with side effects"};
            return "(" + l + " = " + wrap(rounding(p), type, "(" + l + (inc ? " + 1.0)" : " - 1.0)"), "an increment") + ")";
        }
        default:
            if (op >= EOpConvInt8ToBool && op < EOpConvUint64ToPtr) {
                // A conversion: the constructor of the result type.
                text = basic_name(type) + "(" + value(operand, EpqNone) + ")";
            } else if (const char* f = unary_builtin(op)) {
                text = std::string(f) + "(" + value(operand, p) + ")";
            } else {
                throw Unsupported{"unary operator #" + std::to_string(op)};
            }
    }
    return wrap(rounding(p), type, text, "an operation");
}

// An aggregate node as a value: a function call, a constructor, a texture
// lookup (rounded as its sampler's precision), another built-in call.
std::string Emitter::aggregate_value(TIntermAggregate* a, TPrecisionQualifier p) {
    const TType& type = a->getType();
    const TOperator op = a->getOp();
    if (op == EOpFunctionCall) return call(a);
    if (op > EOpConstructGuardStart && op < EOpConstructGuardEnd) {
        if (op == EOpConstructStruct) {
            note_struct(type);
            const TTypeList& members = *type.getStruct();
            TIntermSequence& seq = a->getSequence();
            std::string s = basic_name(type) + "(";
            for (size_t i = 0; i < seq.size() && i < members.size(); ++i) {
                const TType& mt = *members[i].type;
                const TPrecisionQualifier mp = mt.getQualifier().precision != EpqNone ? mt.getQualifier().precision : default_float_;
                s += (i ? ", " : "") + wrap(rounding(mp), mt, value(seq[i]->getAsTyped(), mp), "a struct member");
            }
            return s + ")";
        }
        if (type.isArray()) throw Unsupported{"an array constructor"};
        return wrap(rounding(p), type, basic_name(type) + "(" + args(a, p) + ")", "a constructor");
    }
    if (is_texture_lookup(op)) {
        TIntermSequence& seq = a->getSequence();
        TIntermTyped* sampler = seq.empty() ? nullptr : seq[0]->getAsTyped();
        if (!sampler || sampler->getBasicType() != EbtSampler) throw Unsupported{"a texture lookup without a sampler"};
        const char* f = aggregate_builtin(op);
        if (!f) throw Unsupported{"texture function #" + std::to_string(op)};
        const TPrecisionQualifier sp = precision_of(sampler, EpqLow);
        return wrap(rounding(sp), type, std::string(f) + "(" + args(a, EpqHigh) + ")", "a texture lookup");
    }
    if (op == EOpModf || op == EOpFrexp) throw Unsupported{"modf or frexp (out parameters of built-ins)"};
    const char* f = aggregate_builtin(op);
    if (!f) throw Unsupported{"built-in #" + std::to_string(op)};
    // Comparisons of vectors: bool results, the operands' precision.
    const TPrecisionQualifier arg_context = type.getBasicType() == EbtBool ? EpqNone : p;
    return wrap(rounding(p), type, std::string(f) + "(" + args(a, arg_context) + ")", "a built-in call");
}

// ---- statements --------------------------------------------------------------

std::string Emitter::declaration(long long id, const TIntermSymbol* s) {
    declared_.insert(id);
    const TType& t = s->getType();
    std::string q;
    if (t.getQualifier().storage == EvqConst) q = "const ";
    return q + declared_type(t) + " " + locals_.at(id).name + array_suffix(t);
}

// The scope whose every occurrence of the symbol lies in it (innermost).
const TIntermNode* home_scope(const SymbolInfo& info) {
    return info.common ? info.scope_path[info.common - 1] : nullptr;
}

void Emitter::emit_scope(TIntermNode* scope_node, TIntermNode* content) {
    line("{");
    ++indent_;
    // Symbols that live in this scope are declared first, unless their first
    // occurrence is an initialising `x = ...` directly in it (printed there
    // as the declaration, by emit_statement).
    for (auto& entry : locals_) {
        const SymbolInfo& info = entry.second;
        if (declared_.count(entry.first) || home_scope(info) != scope_node || info.init_scope == scope_node) continue;
        line(declaration(entry.first, info.first) + ";");
    }
    emit_statements(content, scope_node);
    --indent_;
    line("}");
}

void Emitter::emit_statements(TIntermNode* n, const TIntermNode* scope) {
    if (!n) return;
    TIntermAggregate* a = n->getAsAggregate();
    if (a && a->getOp() == EOpSequence) {
        if (emit_for(a, scope)) return;
        for (TIntermNode* c : a->getSequence()) emit_statements(c, scope);
        return;
    }
    emit_statement(n, scope);
}

// `for (T i = init; test; terminal) body` when the sequence glslang made of
// a for loop holds one declaration of a symbol that lives in the loop only.
bool Emitter::emit_for(TIntermAggregate* seq, const TIntermNode* scope) {
    TIntermSequence& s = seq->getSequence();
    if (s.empty() || !s.back()->getAsLoopNode() || !s.back()->getAsLoopNode()->testFirst()) return false;
    TIntermLoop* loop = s.back()->getAsLoopNode();
    std::string init;
    // The for header is a scope of its own: its inits are statements before
    // the loop unless they declare exactly one symbol living in the header.
    std::vector<TIntermNode*> inits(s.begin(), s.end() - 1);
    if (inits.size() == 1 && inits[0]->getAsAggregate() && inits[0]->getAsAggregate()->getOp() == EOpSequence &&
        inits[0]->getAsAggregate()->getSequence().size() == 1)
        inits[0] = inits[0]->getAsAggregate()->getSequence()[0];
    bool header = false;
    if (inits.size() == 1) {
        TIntermBinary* b = inits[0]->getAsBinaryNode();
        if (b && b->getOp() == EOpAssign && b->getLeft()->getAsSymbolNode()) {
            const TIntermSymbol* sym = b->getLeft()->getAsSymbolNode();
            auto it = locals_.find(sym->getId());
            if (it != locals_.end() && it->second.first == sym && home_scope(it->second) == seq) {
                // Every other symbol whose scope is the header makes this form wrong.
                bool alone = true;
                for (auto& e : locals_)
                    if (e.first != sym->getId() && home_scope(e.second) == seq)
                        alone = false;
                if (alone) {
                    const TPrecisionQualifier tp = precision_of(sym, default_float_);
                    init = declaration(sym->getId(), sym) + " = " +
                           wrap(rounding(tp), sym->getType(), value(b->getRight(), tp), "an initialiser");
                    header = true;
                }
            }
        }
    }
    if (!header) {
        line("{");
        ++indent_;
        for (auto& e : locals_)
            if (!declared_.count(e.first) && home_scope(e.second) == seq)
                line(declaration(e.first, e.second.first) + ";");
        for (TIntermNode* i : inits) emit_statements(i, seq);
    }
    const std::string test = loop->getTest() ? value(loop->getTest(), EpqNone) : "";
    const std::string terminal = loop->getTerminal() ? value(loop->getTerminal(), EpqNone) : "";
    line("for (" + init + "; " + test + "; " + terminal + ")");
    emit_scope(loop, loop->getBody());
    if (!header) {
        --indent_;
        line("}");
    }
    (void)scope;
    return true;
}

void Emitter::emit_statement(TIntermNode* n, const TIntermNode* scope) {
    if (TIntermBranch* br = n->getAsBranchNode()) {
        switch (br->getFlowOp()) {
            case EOpKill: line("discard;"); return;
            case EOpBreak: line("break;"); return;
            case EOpContinue: line("continue;"); return;
            case EOpReturn:
                if (!br->getExpression()) {
                    line("return;");
                } else {
                    const TPrecisionQualifier rp =
                        current_return_->getQualifier().precision != EpqNone ? current_return_->getQualifier().precision : default_float_;
                    line("return " + wrap(rounding(rp), *current_return_, value(br->getExpression(), rp), "a returned value") + ";");
                }
                return;
            case EOpCase: line("case " + value(br->getExpression(), EpqNone) + ":"); return;
            case EOpDefault: line("default:"); return;
            default: throw Unsupported{"a branch other than discard, break, continue, return, case or default"};
        }
    }
    if (TIntermSelection* sel = n->getAsSelectionNode()) {
        if (sel->getBasicType() != EbtVoid) {
            line(value(sel, EpqNone) + ";");
            return;
        }
        line("if (" + value(sel->getCondition(), EpqNone) + ")");
        emit_scope(sel->getTrueBlock(), sel->getTrueBlock());
        if (sel->getFalseBlock()) {
            line("else");
            emit_scope(sel->getFalseBlock(), sel->getFalseBlock());
        }
        return;
    }
    if (TIntermLoop* loop = n->getAsLoopNode()) {
        const std::string test = loop->getTest() ? value(loop->getTest(), EpqNone) : "true";
        if (loop->testFirst()) {
            if (loop->getTerminal()) {
                line("for (; " + test + "; " + value(loop->getTerminal(), EpqNone) + ")");
            } else {
                line("while (" + test + ")");
            }
            emit_scope(loop, loop->getBody());
        } else {
            line("do");
            emit_scope(loop, loop->getBody());
            line("while (" + test + ");");
        }
        return;
    }
    if (TIntermSwitch* sw = n->getAsSwitchNode()) {
        line("switch (" + value(sw->getCondition()->getAsTyped(), EpqNone) + ")");
        emit_scope(sw, sw->getBody());
        return;
    }
    TIntermTyped* t = n->getAsTyped();
    if (!t) throw Unsupported{"a statement of an unknown kind"};
    // `x = ...` that first mentions a local declared here: the declaration
    // with its initialiser.
    if (TIntermBinary* b = t->getAsBinaryNode(); b && b->getOp() == EOpAssign && b->getLeft()->getAsSymbolNode()) {
        const TIntermSymbol* sym = b->getLeft()->getAsSymbolNode();
        auto it = locals_.find(sym->getId());
        if (it != locals_.end() && !declared_.count(sym->getId()) && it->second.first == sym) {
            const TPrecisionQualifier tp = precision_of(sym, default_float_);
            line(declaration(sym->getId(), sym) + " = " +
                 wrap(rounding(tp), sym->getType(), value(b->getRight(), tp), "an initialiser") + ";");
            return;
        }
    }
    (void)scope;
    std::string text = t->getAsBinaryNode() && t->getAsBinaryNode()->getOp() >= EOpAssign &&
                               t->getAsBinaryNode()->getOp() <= EOpRightShiftAssign
                           ? assignment(t->getAsBinaryNode())
                           : value(t, EpqNone);
    line(text + ";");
}

std::string Emitter::emit_function(const FunctionInfo& f) {
    const std::string name = base_name(f.node->getName().c_str());
    in_exempt_ = exempt_.count(name) != 0;
    scan_function(f);
    current_return_ = &f.node->getType();
    std::string sig = declared_type(f.node->getType()) + " " + name + "(";
    for (size_t i = 0; i < f.params.size(); ++i) {
        const TIntermSymbol* p = f.params[i];
        const TStorageQualifier q = p->getQualifier().storage;
        std::string qual = q == EvqOut ? "out " : q == EvqInOut ? "inout " : q == EvqConstReadOnly ? "const in " : "";
        sig += (i ? ", " : "") + qual + declared_type(p->getType()) + " " + locals_.at(p->getId()).name +
               array_suffix(p->getType());
        declared_.insert(p->getId());
    }
    sig += ")";
    line(sig);
    emit_scope(f.body ? static_cast<TIntermNode*>(f.body) : f.node, f.body);
    in_exempt_ = false;
    out_ += "\n";
    return sig;
}

std::string Emitter::emit(TIntermediate& intermediate) {
    es100_ = intermediate.getVersion() < 300;
    for (const std::string& e : intermediate.getRequestedExtensions()) {
        // Core in GLSL ES 3.00: derivatives, gl_FragDepth, lod and grad lookups.
        if (e != "GL_OES_standard_derivatives" && e != "GL_EXT_frag_depth" && e != "GL_EXT_shader_texture_lod")
            throw Unsupported{"the extension " + e};
    }
    TIntermNode* root = intermediate.getTreeRoot();
    if (!root) throw Unsupported{"an empty shader"};
    collect(root);

    std::string head = "#version 300 es\n// Emitted by px::emulation (profile ";
    head += profile_name(profile_);
    head += ") from a GLSL ES " + std::string(es100_ ? "1.00" : "3.00") + " source.\n";
    if (rounds()) {
        head += "precision highp float;\nprecision highp int;\n";
        head += kRoundingFunctions;
    } else {
        head += stage_ == ShaderStage::vertex ? "precision highp float;\nprecision highp int;\n"
                                              : std::string("precision ") + precision_keyword(default_float_) +
                                                    " float;\nprecision mediump int;\n";
    }

    // Functions print first (into out_), so that every struct and the
    // ES 1.00 colour output are known before the declarations are printed.
    std::string prototypes;
    for (const TIntermNode* child : root->getAsAggregate()->getSequence()) {
        const TIntermAggregate* a = child->getAsAggregate();
        if (!a || a->getOp() != EOpFunction) continue;
        const FunctionInfo& f = functions_.at(a->getName().c_str());
        const std::string name = base_name(f.node->getName().c_str());
        if (name == "px_q16" || name == "px_qlow") throw Unsupported{"a function named " + name + " (the emitter's own)"};
        const std::string signature = emit_function(f);
        if (name != "main") prototypes += signature + ";\n";
    }

    std::string decls;
    for (const TTypeList* members : struct_order_) {
        decls += "struct " + struct_names_.at(members) + " {\n";
        for (const TTypeLoc& m : *members)
            decls += "    " + declared_type(*m.type) + " " + m.type->getFieldName().c_str() + array_suffix(*m.type) + ";\n";
        decls += "};\n";
    }
    bool frag_color = false;
    struct ColorFinder : TIntermTraverser {
        bool found = false;
        void visitSymbol(TIntermSymbol* s) override { found = found || s->getName() == "gl_FragColor"; }
    } color_finder;
    root->traverse(&color_finder);
    frag_color = color_finder.found;
    for (long long id : global_order_) {
        const TIntermSymbol* s = globals_.at(id);
        const TType& t = s->getType();
        const TQualifier& q = t.getQualifier();
        if (t.getBasicType() == EbtBlock) throw Unsupported{"an interface block"};
        std::string d;
        if (q.hasLocation()) d += "layout(location = " + std::to_string(q.layoutLocation) + ") ";
        if (q.invariant) d += "invariant ";
        if (q.flat) d += "flat ";
        if (q.centroid) d += "centroid ";
        switch (q.storage) {
            case EvqUniform: d += "uniform "; break;
            case EvqVaryingIn: d += "in "; break;
            case EvqVaryingOut: d += "out "; break;
            case EvqGlobal: break;
            default: throw Unsupported{"a global of an unsupported storage"};
        }
        d += declared_type(t) + " " + s->getName().c_str() + array_suffix(t);
        auto init = global_initializers_.find(id);
        if (init != global_initializers_.end()) d += " = " + init->second;
        decls += d + ";\n";
    }
    if (frag_color) {
        if (stage_ != ShaderStage::fragment) throw Unsupported{"gl_FragColor outside the fragment stage"};
        decls += std::string("layout(location = 0) out ") + (rounds() ? "highp" : "mediump") + " vec4 px_emulated_frag_color;\n";
    }
    return head + decls + prototypes + "\n" + out_;
}

// The stage's default float precision, from the source's first
// `precision ... float;` statement (glslang keeps no node for it): the
// precision of a float expression glslang leaves without one.
TPrecisionQualifier default_float_precision(const std::string& source, ShaderStage stage) {
    static const std::regex statement(R"(precision\s+(lowp|mediump|highp)\s+float\s*;)");
    std::smatch m;
    if (std::regex_search(source, m, statement)) {
        const std::string p = m[1];
        return p == "lowp" ? EpqLow : p == "mediump" ? EpqMedium : EpqHigh;
    }
    return stage == ShaderStage::vertex ? EpqHigh : EpqMedium;
}

}  // namespace

Status check_parses(const std::string& source, ShaderStage stage) {
    Parsed p = parse(source, stage);
    if (!p.error.empty()) return make_error(p.error);
    return {};
}

Result<std::string> emulate_precision(const std::string& source, ShaderStage stage, PrecisionProfile profile,
                                      const std::vector<std::string>& exempt_functions) {
    Parsed p = parse(source, stage);
    if (!p.error.empty()) return make_error(p.error);
    const std::set<std::string> exempt(exempt_functions.begin(), exempt_functions.end());
    Emitter emitter(stage, profile, exempt, default_float_precision(source, stage));
    try {
        return emitter.emit(*p.shader->getIntermediate());
    } catch (const Unsupported& u) {
        return make_error(std::string("precision emulation (") + profile_name(profile) + ", " +
                          (stage == ShaderStage::vertex ? "vertex" : "fragment") + " stage) does not support " + u.what);
    }
}

}  // namespace px::emulation
