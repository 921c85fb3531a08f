// The SPIR-V analysis (shader_costs.h: analyse_spirv, stage_cost): the
// module's instructions classified and costed along its paths, its loops'
// trip counts, and which texture reads wait on which.
#include "parallaxes/profiling/costs/shader_costs.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>

#define SPV_ENABLE_UTILITY_CODE
#include <glslang/SPIRV/GLSL.std.450.h>
#include <glslang/SPIRV/spirv.hpp>

namespace px::profiling {

OpCounts& OpCounts::operator+=(const OpCounts& o) {
    arithmetic += o.arithmetic;
    fp16 += o.fp16;
    transcendental += o.transcendental;
    samples += o.samples;
    branches += o.branches;
    return *this;
}

OpCounts OpCounts::operator*(double k) const {
    OpCounts c = *this;
    c.arithmetic *= k;
    c.fp16 *= k;
    c.transcendental *= k;
    c.samples *= k;
    c.branches *= k;
    return c;
}

namespace {

using Id = std::uint32_t;

struct Instruction {
    spv::Op op;
    std::vector<std::uint32_t> words;  // operands after the opcode word
    Id result = 0;
    Id type = 0;
    std::string where;  // source line from the last OpLine
};

struct Block {
    Id label = 0;
    std::vector<Instruction> body;  // merge and terminator included
    std::vector<Id> successors;
    Id merge = 0, continue_target = 0;  // OpLoopMerge / OpSelectionMerge
    bool loop_header = false, selection_header = false;
    Id condition = 0;  // of a conditional terminator
    bool returns = false;
};

struct Function {
    Id id = 0;
    std::vector<Id> parameters;
    std::vector<Block> blocks;
    std::unordered_map<Id, std::size_t> index;  // label -> block
};

// A set of texture reads (by index), small and dense.
struct ReadSet {
    std::vector<std::uint64_t> bits;
    bool add(const ReadSet& o) {
        bool changed = false;
        if (bits.size() < o.bits.size()) bits.resize(o.bits.size(), 0);
        for (std::size_t i = 0; i < o.bits.size(); ++i) {
            const std::uint64_t merged = bits[i] | o.bits[i];
            changed |= merged != bits[i];
            bits[i] = merged;
        }
        return changed;
    }
    void set(int i) {
        const std::size_t w = static_cast<std::size_t>(i) / 64;
        if (bits.size() <= w) bits.resize(w + 1, 0);
        bits[w] |= std::uint64_t{1} << (i % 64);
    }
    bool empty() const {
        return std::all_of(bits.begin(), bits.end(), [](std::uint64_t b) { return b == 0; });
    }
    std::vector<int> members() const {
        std::vector<int> m;
        for (std::size_t w = 0; w < bits.size(); ++w)
            for (int b = 0; b < 64; ++b)
                if (bits[w] >> b & 1) m.push_back(static_cast<int>(w * 64 + b));
        return m;
    }
};

bool is_sample(spv::Op op) {
    switch (op) {
        case spv::OpImageSampleImplicitLod:
        case spv::OpImageSampleExplicitLod:
        case spv::OpImageSampleDrefImplicitLod:
        case spv::OpImageSampleDrefExplicitLod:
        case spv::OpImageSampleProjImplicitLod:
        case spv::OpImageSampleProjExplicitLod:
        case spv::OpImageSampleProjDrefImplicitLod:
        case spv::OpImageSampleProjDrefExplicitLod:
        case spv::OpImageFetch:
        case spv::OpImageGather:
        case spv::OpImageDrefGather: return true;
        default: return false;
    }
}

bool is_arithmetic(spv::Op op) {
    const int o = static_cast<int>(op);
    // Conversions (109..123), arithmetic (126..152), relational and logical
    // (154..191), bit operations (194..205), derivatives (207..215).
    return (o >= 109 && o <= 123) || (o >= 126 && o <= 152) || (o >= 154 && o <= 191) || (o >= 194 && o <= 205) ||
           (o >= 207 && o <= 215);
}

class Module {
public:
    Status parse(const std::vector<std::uint32_t>& words, const std::vector<LineOrigin>& origins) {
        if (words.size() < 5) return make_error("SPIR-V: shorter than its 5-word header");
        if (words[0] != spv::MagicNumber) return make_error("SPIR-V: bad magic number");
        bound_ = words[3];
        if (bound_ == 0 || bound_ > (1u << 22)) return make_error("SPIR-V: id bound " + std::to_string(bound_) + " out of range");
        Cursor cursor;
        for (std::size_t at = 5; at < words.size();) {
            Result<Instruction> read = read_instruction(words, at);
            if (!read) return read.error();
            Instruction& in = *read;
            Result<bool> taken = structure(in, origins, cursor);
            if (!taken) return taken.error();
            if (*taken) continue;
            in.where = cursor.where;
            if (in.result) definitions_[in.result] = in;
            if (!cursor.block) continue;  // module-level: types, constants, globals
            if (Status s = control_flow(in, *cursor.block); !s) return s;
            cursor.block->body.push_back(std::move(in));
        }
        for (const Function& f : functions_)
            for (const Block& b : f.blocks)
                for (Id s : b.successors)
                    if (!f.index.count(s)) return make_error("SPIR-V: a branch to a label outside its function");
        return {};
    }

    // Where parse is: the function and block being read, the last source line.
    struct Cursor {
        Function* function = nullptr;
        Block* block = nullptr;
        std::string where;
    };

    // The instruction at words[at] with its type and result split off; `at`
    // moves past it.
    Result<Instruction> read_instruction(const std::vector<std::uint32_t>& words, std::size_t& at) const {
        const std::uint32_t count = words[at] >> 16;
        const auto op = static_cast<spv::Op>(words[at] & 0xFFFF);
        if (count == 0 || at + count > words.size())
            return make_error("SPIR-V: instruction at word " + std::to_string(at) + " runs past the module");
        Instruction in;
        in.op = op;
        in.words.assign(words.begin() + static_cast<std::ptrdiff_t>(at) + 1, words.begin() + static_cast<std::ptrdiff_t>(at + count));
        at += count;
        bool has_result = false, has_type = false;
        spv::HasResultAndType(op, &has_result, &has_type);
        std::size_t next = 0;
        if (has_type) {
            if (in.words.size() <= next) return make_error("SPIR-V: truncated instruction");
            in.type = in.words[next++];
        }
        if (has_result) {
            if (in.words.size() <= next) return make_error("SPIR-V: truncated instruction");
            in.result = in.words[next++];
            if (in.result >= bound_) return make_error("SPIR-V: id past the bound");
        }
        in.words.erase(in.words.begin(), in.words.begin() + static_cast<std::ptrdiff_t>(next));
        return in;
    }

    // Debug lines, decorations, the entry point, and the function and block
    // structure: true where the instruction is taken here (not a body's).
    Result<bool> structure(const Instruction& in, const std::vector<LineOrigin>& origins, Cursor& c) {
        switch (in.op) {
            case spv::OpLine:
                if (in.words.size() >= 2) {
                    const std::uint32_t line = in.words[1];
                    if (line >= 1 && line <= origins.size())
                        c.where = origins[line - 1].file + ":" + std::to_string(origins[line - 1].line);
                    else
                        c.where = "source:" + std::to_string(line);
                }
                return true;
            case spv::OpNoLine: c.where.clear(); return true;
            case spv::OpDecorate:
                if (in.words.size() >= 2 && in.words[1] == spv::DecorationRelaxedPrecision) relaxed_.insert(in.words[0]);
                if (in.words.size() >= 2 && in.words[1] == spv::DecorationBuiltIn) builtin_.insert(in.words[0]);
                return true;
            case spv::OpEntryPoint:
                if (in.words.size() >= 2) entry_ = in.words[1];
                return true;
            case spv::OpFunction:
                functions_.emplace_back();
                c.function = &functions_.back();
                c.function->id = in.result;
                c.block = nullptr;
                return true;
            case spv::OpFunctionParameter:
                if (c.function) c.function->parameters.push_back(in.result);
                return true;
            case spv::OpFunctionEnd:
                c.function = nullptr;
                c.block = nullptr;
                return true;
            case spv::OpLabel:
                if (!c.function) return make_error("SPIR-V: a label outside a function");
                c.function->index[in.result] = c.function->blocks.size();
                c.function->blocks.emplace_back();
                c.block = &c.function->blocks.back();
                c.block->label = in.result;
                return true;
            default: return false;
        }
    }

    // A block's merge, branches and exits.
    static Status control_flow(const Instruction& in, Block& block) {
        switch (in.op) {
            case spv::OpLoopMerge:
                if (in.words.size() < 2) return make_error("SPIR-V: truncated OpLoopMerge");
                block.loop_header = true;
                block.merge = in.words[0];
                block.continue_target = in.words[1];
                break;
            case spv::OpSelectionMerge:
                if (in.words.empty()) return make_error("SPIR-V: truncated OpSelectionMerge");
                block.selection_header = true;
                block.merge = in.words[0];
                break;
            case spv::OpBranch:
                if (in.words.empty()) return make_error("SPIR-V: truncated OpBranch");
                block.successors = {in.words[0]};
                break;
            case spv::OpBranchConditional:
                if (in.words.size() < 3) return make_error("SPIR-V: truncated OpBranchConditional");
                block.condition = in.words[0];
                block.successors = {in.words[1], in.words[2]};
                break;
            case spv::OpSwitch:
                if (in.words.size() < 2) return make_error("SPIR-V: truncated OpSwitch");
                block.condition = in.words[0];
                block.successors.push_back(in.words[1]);
                for (std::size_t i = 3; i < in.words.size(); i += 2) block.successors.push_back(in.words[i]);
                break;
            case spv::OpReturn:
            case spv::OpReturnValue:
            case spv::OpKill:
            case spv::OpUnreachable: block.returns = true; break;
            default: break;
        }
        return {};
    }

    const Instruction* def(Id id) const {
        const auto found = definitions_.find(id);
        return found == definitions_.end() ? nullptr : &found->second;
    }

    // Scalar components of a type (vectors, matrices, arrays of them).
    int components(Id type, int depth = 0) const {
        const Instruction* t = def(type);
        if (!t || depth > 8) return 1;
        switch (t->op) {
            case spv::OpTypeVector: return t->words.size() >= 2 ? static_cast<int>(t->words[1]) : 1;
            case spv::OpTypeMatrix:
                return t->words.size() >= 2 ? static_cast<int>(t->words[1]) * components(t->words[0], depth + 1) : 1;
            case spv::OpTypeArray: {
                const Instruction* length = t->words.size() >= 2 ? def(t->words[1]) : nullptr;
                const int n = length && length->op == spv::OpConstant && !length->words.empty()
                                  ? static_cast<int>(std::min<std::uint32_t>(length->words[0], 4096))
                                  : 1;
                return n * components(t->words[0], depth + 1);
            }
            case spv::OpTypePointer: return t->words.size() >= 2 ? components(t->words[1], depth + 1) : 1;
            default: return 1;
        }
    }

    bool numeric(Id type) const {
        const Instruction* t = def(type);
        if (!t) return false;
        if (t->op == spv::OpTypeVector || t->op == spv::OpTypeMatrix) return !t->words.empty() && numeric(t->words[0]);
        return t->op == spv::OpTypeFloat || t->op == spv::OpTypeInt;
    }

    std::optional<std::int32_t> int_constant(Id id) const {
        const Instruction* c = def(id);
        if (!c || c->op != spv::OpConstant || c->words.empty()) return std::nullopt;
        const Instruction* t = def(c->type);
        if (!t || t->op != spv::OpTypeInt) return std::nullopt;
        return static_cast<std::int32_t>(c->words[0]);
    }

    // What an instruction costs where it stands (calls excluded).
    OpCounts own_cost(const Instruction& in) const {
        OpCounts c;
        if (is_sample(in.op)) {
            c.samples = 1;
            return c;
        }
        if (in.op == spv::OpBranchConditional || in.op == spv::OpSwitch || in.op == spv::OpKill) {
            c.branches = 1;
            return c;
        }
        const bool relaxed = relaxed_.count(in.result) != 0;
        const double n = in.type ? components(in.type) : 1;
        double arithmetic = 0.0, transcendental = 0.0;
        if (in.op == spv::OpExtInst && in.words.size() >= 2) {
            const int operand_n = in.words.size() >= 3 ? operand_components(in.words[2]) : 1;
            switch (static_cast<GLSLstd450>(in.words[1])) {
                case GLSLstd450Sin: case GLSLstd450Cos: case GLSLstd450Tan: case GLSLstd450Asin:
                case GLSLstd450Acos: case GLSLstd450Atan: case GLSLstd450Atan2: case GLSLstd450Sinh:
                case GLSLstd450Cosh: case GLSLstd450Tanh: case GLSLstd450Asinh: case GLSLstd450Acosh:
                case GLSLstd450Atanh: case GLSLstd450Exp: case GLSLstd450Log: case GLSLstd450Exp2:
                case GLSLstd450Log2: case GLSLstd450Sqrt: case GLSLstd450InverseSqrt:
                    transcendental = n;
                    break;
                case GLSLstd450Pow:  // exp2(y * log2(x))
                    transcendental = 2 * n;
                    arithmetic = n;
                    break;
                case GLSLstd450Normalize:  // dot, inversesqrt, scale
                    transcendental = 1;
                    arithmetic = 2 * n;
                    break;
                case GLSLstd450Length:
                    transcendental = 1;
                    arithmetic = operand_n;
                    break;
                case GLSLstd450Distance:
                    transcendental = 1;
                    arithmetic = 2 * operand_n;
                    break;
                case GLSLstd450Cross: arithmetic = 6; break;
                case GLSLstd450FMix: case GLSLstd450IMix: case GLSLstd450FClamp: case GLSLstd450UClamp:
                case GLSLstd450SClamp: case GLSLstd450NClamp: case GLSLstd450Fma: arithmetic = 2 * n; break;
                case GLSLstd450SmoothStep: arithmetic = 5 * n; break;
                case GLSLstd450Reflect: arithmetic = 3 * n; break;
                case GLSLstd450Refract:
                    transcendental = 1;
                    arithmetic = 4 * n;
                    break;
                case GLSLstd450Determinant: arithmetic = operand_n * 2; break;
                case GLSLstd450MatrixInverse: arithmetic = 4 * n; transcendental = 1; break;
                default: arithmetic = n; break;
            }
        } else if (is_arithmetic(in.op)) {
            switch (in.op) {
                case spv::OpDot: arithmetic = in.words.empty() ? 1 : operand_components(in.words[0]); break;
                case spv::OpMatrixTimesVector:
                    arithmetic = n * (in.words.size() >= 2 ? operand_components(in.words[1]) : 1);
                    break;
                case spv::OpVectorTimesMatrix:
                    arithmetic = n * (in.words.empty() ? 1 : operand_components(in.words[0]));
                    break;
                case spv::OpMatrixTimesMatrix: {
                    // (r x k) * (k x c): r*c results, k products each.
                    const Instruction* left = in.words.empty() ? nullptr : def(in.words[0]);
                    const Instruction* lt = left ? def(left->type) : nullptr;
                    const int k = lt && lt->op == spv::OpTypeMatrix && lt->words.size() >= 2 ? int(lt->words[1]) : 1;
                    arithmetic = n * k;
                    break;
                }
                case spv::OpAny:
                case spv::OpAll: arithmetic = in.words.empty() ? 1 : operand_components(in.words[0]); break;
                default: arithmetic = n; break;
            }
        }
        c.arithmetic = arithmetic;
        c.transcendental = transcendental;
        if (relaxed) c.fp16 = arithmetic;
        return c;
    }

    int operand_components(Id id) const {
        const Instruction* d = def(id);
        if (d && d->type) return components(d->type);
        // Function parameters and variables: their pointer type.
        return 1;
    }

    std::vector<Function> functions_;
    std::unordered_map<Id, Instruction> definitions_;
    std::set<Id> relaxed_;
    std::set<Id> builtin_;
    Id bound_ = 0;
    Id entry_ = 0;
};

// Which blocks each loop and selection construct holds: glslang lays a
// construct's blocks out between its header and its merge block.
struct Construct {
    std::size_t header = 0, merge = 0;  // block indices; the construct is [header, merge)
    bool loop = false;
    int trip_count = -1;
    int counted = -1;  // trip_count, or an override for the loop's file
    std::string where;
};

std::vector<Construct> constructs_of(const Function& f) {
    std::vector<Construct> out;
    for (std::size_t i = 0; i < f.blocks.size(); ++i) {
        const Block& b = f.blocks[i];
        if (!b.loop_header && !b.selection_header) continue;
        const auto merge = f.index.find(b.merge);
        if (merge == f.index.end() || merge->second <= i) continue;
        Construct c;
        c.header = i;
        c.merge = merge->second;
        c.loop = b.loop_header;
        out.push_back(c);
    }
    return out;
}

// The trip count of a counted loop: `for (int i = A; i < B; i += S)` (or
// <=, >, >=, !=) with A, B and S constants, as glslang translates it: the
// induction variable stored before the header, compared in the header's
// conditional branch (or a block it branches to), stepped in the loop.
// A loop's exit test: the first conditional branch from the header on
// whose targets include the merge block.
const Block* exit_test(const Function& f, const Construct& loop) {
    const Id merge_label = f.blocks[loop.merge].label;
    for (std::size_t i = loop.header, hops = 0; i < loop.merge && hops < 4; ++hops) {
        const Block& b = f.blocks[i];
        if (b.condition && b.successors.size() == 2)
            return b.successors[0] == merge_label || b.successors[1] == merge_label ? &b : nullptr;
        if (b.successors.size() != 1) return nullptr;
        i = f.index.at(b.successors[0]);
    }
    return nullptr;
}

// The induction variable's start (the last constant stored to it before the
// header) and step (its one store inside the loop, of itself +/- a constant).
struct Induction {
    std::optional<std::int32_t> start, step;
};
Induction induction(const Module& m, const Function& f, const Construct& loop, Id variable) {
    Induction v;
    for (std::size_t i = 0; i < loop.header; ++i)
        for (const Instruction& in : f.blocks[i].body)
            if (in.op == spv::OpStore && in.words.size() >= 2 && in.words[0] == variable) v.start = m.int_constant(in.words[1]);
    int steps_seen = 0;
    for (std::size_t i = loop.header; i < loop.merge; ++i)
        for (const Instruction& in : f.blocks[i].body) {
            if (in.op != spv::OpStore || in.words.size() < 2 || in.words[0] != variable) continue;
            ++steps_seen;
            const Instruction* value = m.def(in.words[1]);
            if (!value || (value->op != spv::OpIAdd && value->op != spv::OpISub) || value->words.size() < 2) continue;
            const Instruction* from = m.def(value->words[0]);
            const std::optional<std::int32_t> s = m.int_constant(value->words[1]);
            if (!from || from->op != spv::OpLoad || from->words.empty() || from->words[0] != variable || !s) continue;
            v.step = value->op == spv::OpIAdd ? *s : -*s;
        }
    if (steps_seen != 1) v.step.reset();
    return v;
}

// The comparison as "continue while i OP bound": mirrored where the
// constant is on the left, negated where the branch exits on true;
// OpNop where it cannot be.
spv::Op continue_condition(spv::Op op, bool swapped, bool exits_when_true) {
    if (swapped) {
        switch (op) {
            case spv::OpSLessThan: op = spv::OpSGreaterThan; break;
            case spv::OpSLessThanEqual: op = spv::OpSGreaterThanEqual; break;
            case spv::OpSGreaterThan: op = spv::OpSLessThan; break;
            case spv::OpSGreaterThanEqual: op = spv::OpSLessThanEqual; break;
            default: break;
        }
    }
    if (!exits_when_true) return op;
    switch (op) {
        case spv::OpSLessThan: return spv::OpSGreaterThanEqual;
        case spv::OpSLessThanEqual: return spv::OpSGreaterThan;
        case spv::OpSGreaterThan: return spv::OpSLessThanEqual;
        case spv::OpSGreaterThanEqual: return spv::OpSLessThan;
        case spv::OpIEqual: return spv::OpINotEqual;
        default: return spv::OpNop;
    }
}

// Iterations of "for (i = a; i OP b; i += s)"; -1 where it does not end.
std::int64_t iterations(spv::Op op, std::int64_t a, std::int64_t b, std::int64_t s) {
    switch (op) {
        case spv::OpSLessThan: return s > 0 ? (b > a ? (b - a + s - 1) / s : 0) : -1;
        case spv::OpSLessThanEqual: return s > 0 ? (b >= a ? (b - a) / s + 1 : 0) : -1;
        case spv::OpSGreaterThan: return s < 0 ? (a > b ? (a - b - s - 1) / -s : 0) : -1;
        case spv::OpSGreaterThanEqual: return s < 0 ? (a >= b ? (a - b) / -s + 1 : 0) : -1;
        case spv::OpINotEqual: return (b - a) % s == 0 && (b - a) / s >= 0 ? (b - a) / s : -1;
        default: return -1;
    }
}

// A counted loop's trips: its exit test compares the induction variable
// with a constant; -1 where the loop is not of that shape.
int trip_count(const Module& m, const Function& f, const Construct& loop) {
    const Block* test = exit_test(f, loop);
    if (!test) return -1;
    const Instruction* compare = m.def(test->condition);
    if (!compare || compare->words.size() < 2) return -1;
    const bool exits_when_true = test->successors[0] == f.blocks[loop.merge].label;
    // One side loads the induction variable, the other is a constant.
    const Instruction* left = m.def(compare->words[0]);
    std::optional<std::int32_t> bound = m.int_constant(compare->words[1]);
    bool swapped = false;
    if (!bound) {
        bound = m.int_constant(compare->words[0]);
        left = m.def(compare->words[1]);
        swapped = true;
    }
    if (!bound || !left || left->op != spv::OpLoad || left->words.empty()) return -1;
    const Induction v = induction(m, f, loop, left->words[0]);
    if (!v.start || !v.step || *v.step == 0) return -1;
    const spv::Op op = continue_condition(compare->op, swapped, exits_when_true);
    const std::int64_t trips = iterations(op, *v.start, *bound, *v.step);
    return trips >= 0 && trips <= 1 << 20 ? static_cast<int>(trips) : -1;
}

struct FunctionCost {
    OpCounts total, shortest, longest;
    bool computing = false, done = false;
};

class Analysis {
public:
    Analysis(const Module& m, const TripOverrides& overrides) : m_(m) {
        for (std::size_t i = 0; i < m_.functions_.size(); ++i) function_index_[m_.functions_[i].id] = i;
        for (const Function& f : m_.functions_) constructs_.push_back(constructs_of(f));
        for (std::size_t fi = 0; fi < m_.functions_.size(); ++fi)
            for (Construct& c : constructs_[fi]) {
                if (!c.loop) continue;
                c.trip_count = trip_count(m_, m_.functions_[fi], c);
                c.counted = c.trip_count;
                const Function& f = m_.functions_[fi];
                for (std::size_t i = c.header; i < c.merge && c.where.empty(); ++i)
                    for (const Instruction& in : f.blocks[i].body)
                        if (!in.where.empty()) {
                            c.where = in.where;
                            break;
                        }
                const std::string file = c.where.substr(0, c.where.rfind(':'));
                const auto found = overrides.find(file);
                if (found != overrides.end()) c.counted = found->second;
            }
    }

    Status run(StageCost& out) {
        const Function* entry = function(m_.entry_);
        if (!entry) return make_error("SPIR-V: no entry point");
        Result<FunctionCost> main_cost = cost(*entry, 0);
        if (!main_cost) return main_cost.error();
        out.total = main_cost->total;
        out.shortest = main_cost->shortest;
        out.longest = main_cost->longest;
        out.unknown_trips = unknown_trips_;
        classify(out);
        loops(out);
        Status reads = dependences(*entry, out);
        if (!reads) return reads;
        InOrder walk;
        waits_in_order(*entry, walk, 0);
        out.in_order_waits = walk.waits;
        return {};
    }

private:
    const Function* function(Id id) const {
        const auto found = function_index_.find(id);
        return found == function_index_.end() ? nullptr : &m_.functions_[found->second];
    }
    std::size_t index_of(const Function& f) const { return static_cast<std::size_t>(&f - m_.functions_.data()); }

    // Enclosing loops' trip product for a block (unknown trips count 1).
    double multiplier(const Function& f, std::size_t block) {
        double k = 1.0;
        for (const Construct& c : constructs_[index_of(f)])
            if (c.loop && block >= c.header && block < c.merge) {
                if (c.counted >= 0) k *= c.counted;
                else unknown_trips_ = true;
            }
        return k;
    }

    Result<FunctionCost> cost(const Function& f, int depth) {
        FunctionCost& memo = costs_[f.id];
        if (memo.done) return memo;
        if (memo.computing || depth > 64) return make_error("SPIR-V: recursive function calls");
        memo.computing = true;
        const std::size_t n = f.blocks.size();
        std::vector<OpCounts> own(n), own_short(n), own_long(n);
        for (std::size_t i = 0; i < n; ++i) {
            for (const Instruction& in : f.blocks[i].body) {
                OpCounts c = m_.own_cost(in);
                own[i] += c;
                own_short[i] += c;
                own_long[i] += c;
                if (in.op == spv::OpFunctionCall && !in.words.empty()) {
                    const Function* callee = function(in.words[0]);
                    if (!callee) return make_error("SPIR-V: a call to an unknown function");
                    Result<FunctionCost> sub = cost(*callee, depth + 1);
                    if (!sub) return sub.error();
                    own[i] += sub->total;
                    own_short[i] += sub->shortest;
                    own_long[i] += sub->longest;
                }
            }
        }
        FunctionCost result;
        for (std::size_t i = 0; i < n; ++i) result.total += own[i];
        // Acyclic successors: a back edge (to a loop header at or before the
        // block) goes to that loop's merge block instead, so that a path
        // through the loop body leaves the loop.
        auto successors = [&](std::size_t i) {
            std::vector<std::size_t> s;
            for (Id label : f.blocks[i].successors) {
                std::size_t j = f.index.at(label);
                if (j <= i) {
                    const Block& header = f.blocks[j];
                    if (!header.loop_header) continue;  // not structured: ignore the edge
                    j = f.index.count(header.merge) ? f.index.at(header.merge) : n;
                    if (j <= i || j >= n) continue;
                }
                s.push_back(j);
            }
            return s;
        };
        // Blocks are in an order where every acyclic edge goes forward, so
        // one backward sweep finds both paths.
        std::vector<OpCounts> best_long(n), best_short(n);
        std::vector<bool> reaches_end(n, false);
        for (std::size_t r = n; r-- > 0;) {
            const std::vector<std::size_t> next = successors(r);
            const double k = multiplier(f, r);
            OpCounts longest = own_long[r] * k, shortest = own_short[r];
            bool any = false;
            OpCounts best_l, best_s;
            for (std::size_t j : next) {
                if (!reaches_end[j]) continue;
                if (!any || best_long[j].weight() > best_l.weight()) best_l = best_long[j];
                if (!any || best_short[j].weight() < best_s.weight()) best_s = best_short[j];
                any = true;
            }
            if (any || f.blocks[r].returns || next.empty()) {
                reaches_end[r] = true;
                longest += best_l;
                shortest += best_s;
            }
            best_long[r] = longest;
            best_short[r] = shortest;
        }
        if (n) {
            result.longest = best_long[0];
            result.shortest = best_short[0];
        }
        result.done = true;
        memo = result;
        return result;
    }

    void classify(StageCost& out) {
        std::set<Id> inputs_read;
        for (const Function& f : m_.functions_)
            for (const Block& b : f.blocks)
                for (const Instruction& in : b.body) {
                    if (!in.where.empty()) {
                        OpCounts c = m_.own_cost(in);
                        if (c.weight() > 0) out.by_line[in.where] += c;
                    }
                    const bool sample = is_sample(in.op);
                    const bool control = in.op == spv::OpBranchConditional || in.op == spv::OpSwitch || in.op == spv::OpKill;
                    bool transcendental = false, arithmetic = false;
                    if (in.op == spv::OpExtInst) {
                        const OpCounts c = m_.own_cost(in);
                        transcendental = c.transcendental > 0;
                        arithmetic = !transcendental;
                    } else if (is_arithmetic(in.op)) {
                        arithmetic = true;
                    }
                    if (sample || in.op == spv::OpImageQuerySizeLod || in.op == spv::OpImageQuerySize ||
                        in.op == spv::OpImageQueryLod || in.op == spv::OpImageQueryLevels)
                        ++out.texture_instructions;
                    else if (control) ++out.control_instructions;
                    else if (transcendental) ++out.transcendental_instructions;
                    else if (arithmetic) ++out.arithmetic_instructions;
                    if ((sample || transcendental || arithmetic) && in.type && m_.numeric(in.type)) {
                        ++out.typed_results;
                        if (m_.relaxed_.count(in.result)) ++out.relaxed_results;
                    }
                    if (in.op == spv::OpLoad && !in.words.empty()) {
                        Id root = root_of(in.words[0]);
                        const Instruction* v = m_.def(root);
                        if (v && v->op == spv::OpVariable && !v->words.empty() && v->words[0] == spv::StorageClassInput &&
                            !m_.builtin_.count(root))
                            inputs_read.insert(root);
                    }
                }
        if (out.stage == ShaderStage::fragment)
            for (Id v : inputs_read) {
                const int components = m_.components(m_.def(v)->type);
                out.varying_components += components;
                if (m_.relaxed_.count(v)) out.relaxed_varying_components += components;
            }
    }

    void loops(StageCost& out) {
        for (std::size_t fi = 0; fi < m_.functions_.size(); ++fi) {
            const Function& f = m_.functions_[fi];
            for (const Construct& c : constructs_[fi]) {
                if (!c.loop) continue;
                LoopCost l;
                l.trip_count = c.trip_count;
                l.counted_trips = c.counted;
                l.where = c.where;
                for (const Construct& o : constructs_[fi])
                    if (o.loop && &o != &c && o.header < c.header && c.header < o.merge) ++l.depth;
                for (std::size_t i = c.header; i < c.merge; ++i)
                    for (const Instruction& in : f.blocks[i].body)
                        if (is_sample(in.op) || in.op == spv::OpFunctionCall) l.has_samples |= is_sample(in.op) || calls_sample(in);
                out.loops.push_back(l);
            }
        }
    }

    bool calls_sample(const Instruction& call, int depth = 0) const {
        if (call.words.empty() || depth > 64) return false;
        const Function* f = function(call.words[0]);
        if (!f) return false;
        for (const Block& b : f->blocks)
            for (const Instruction& in : b.body)
                if (is_sample(in.op) || (in.op == spv::OpFunctionCall && calls_sample(in, depth + 1))) return true;
        return false;
    }

    // Texture results in flight, in program order.
    struct InOrder {
        std::set<Id> pending_values, pending_memory;
        int waits = 0;
    };

    void waits_in_order(const Function& f, InOrder& w, int depth) {
        if (depth > 64) return;
        auto pending = [&](Id id) { return w.pending_values.count(id) != 0; };
        auto wait = [&]() {
            ++w.waits;
            w.pending_values.clear();
            w.pending_memory.clear();
        };
        for (const Block& b : f.blocks)
            for (const Instruction& in : b.body) {
                switch (in.op) {
                    case spv::OpStore:
                        // A register move, not a use: the value stays in flight.
                        if (in.words.size() >= 2) {
                            if (pending(in.words[1])) w.pending_memory.insert(root_of(in.words[0]));
                            else w.pending_memory.erase(root_of(in.words[0]));
                        }
                        continue;
                    case spv::OpLoad:
                        if (!in.words.empty() && w.pending_memory.count(root_of(in.words[0])))
                            w.pending_values.insert(in.result);
                        continue;
                    case spv::OpAccessChain:
                    case spv::OpInBoundsAccessChain:
                    case spv::OpCompositeExtract:
                    case spv::OpVectorShuffle:
                    case spv::OpCopyObject:
                        // Moves: a part of a value in flight is in flight.
                        for (Id operand : in.words)
                            if (pending(operand)) w.pending_values.insert(in.result);
                        continue;
                    case spv::OpFunctionCall:
                        if (const Function* callee = in.words.empty() ? nullptr : function(in.words[0])) {
                            for (std::size_t a = 0; a + 1 < in.words.size() && a < callee->parameters.size(); ++a)
                                if (w.pending_memory.count(root_of(in.words[a + 1])))
                                    w.pending_memory.insert(callee->parameters[a]);
                            const int before = w.waits;
                            waits_in_order(*callee, w, depth + 1);
                            // What the callee returned is in flight only if it waited on nothing since.
                            if (w.waits == before && returns_pending_) w.pending_values.insert(in.result);
                            returns_pending_ = false;
                        }
                        continue;
                    case spv::OpReturnValue:
                        returns_pending_ = !in.words.empty() && pending(in.words[0]);
                        continue;
                    default: break;
                }
                bool uses = false;
                for (Id operand : in.words) uses |= operand < m_.bound_ && pending(operand);
                if (uses) wait();
                if (is_sample(in.op)) w.pending_values.insert(in.result);
            }
    }

    bool returns_pending_ = false;

    Id root_of(Id pointer) const {
        for (int hops = 0; hops < 64; ++hops) {
            const Instruction* d = m_.def(pointer);
            if (!d || (d->op != spv::OpAccessChain && d->op != spv::OpInBoundsAccessChain) || d->words.empty()) break;
            pointer = d->words[0];
        }
        const auto alias = alias_.find(pointer);
        return alias == alias_.end() ? pointer : alias->second;
    }

    // What the dependence fixpoint tracks: which reads each value, memory
    // location (by its root variable), function result and block waits on.
    struct Read {
        const Instruction* in;
        std::size_t function, block;
    };
    struct Flow {
        std::vector<Read> reads;  // in order, each with its function and block
        std::unordered_map<const Instruction*, int> read_index;
        std::unordered_map<Id, ReadSet> value, memory, returns;
        std::vector<std::vector<ReadSet>> control;  // per function, per block
        std::vector<ReadSet> function_control;      // what decides that a function runs at all
    };

    void collect_reads(Flow& flow) const {
        for (std::size_t fi = 0; fi < m_.functions_.size(); ++fi)
            for (std::size_t bi = 0; bi < m_.functions_[fi].blocks.size(); ++bi)
                for (const Instruction& in : m_.functions_[fi].blocks[bi].body)
                    if (is_sample(in.op)) {
                        flow.read_index[&in] = static_cast<int>(flow.reads.size());
                        flow.reads.push_back({&in, fi, bi});
                    }
        flow.control.resize(m_.functions_.size());
        flow.function_control.resize(m_.functions_.size());
        for (std::size_t fi = 0; fi < m_.functions_.size(); ++fi) flow.control[fi].resize(m_.functions_[fi].blocks.size());
    }

    // Parameters alias what each call passes (context-insensitive).
    void alias_parameters() {
        for (const Function& f : m_.functions_)
            for (const Block& b : f.blocks)
                for (const Instruction& in : b.body)
                    if (in.op == spv::OpFunctionCall && !in.words.empty())
                        if (const Function* callee = function(in.words[0]))
                            for (std::size_t a = 0; a + 1 < in.words.size() && a < callee->parameters.size(); ++a)
                                param_args_[callee->parameters[a]].push_back(in.words[a + 1]);
    }

    // Control: a block inside a branch waits on the branch's condition; a
    // block inside a loop on whether an iteration runs, which is every way
    // out of the loop (its exit test, a break under a branch) and what
    // decides that way is taken.
    bool propagate_control(std::size_t fi, Flow& flow) {
        const Function& f = m_.functions_[fi];
        bool changed = false;
        for (std::size_t bi = 0; bi < f.blocks.size(); ++bi) {
            ReadSet c = flow.function_control[fi];
            for (const Construct& k : constructs_[fi]) {
                if (bi < k.header || bi >= k.merge) continue;
                if (!k.loop) {
                    if (bi > k.header && f.blocks[k.header].condition) c.add(flow.value[f.blocks[k.header].condition]);
                    continue;
                }
                const Id merge = f.blocks[k.merge].label;
                for (std::size_t j = k.header; j < k.merge; ++j) {
                    const Block& e = f.blocks[j];
                    if (std::find(e.successors.begin(), e.successors.end(), merge) == e.successors.end()) continue;
                    if (e.condition) c.add(flow.value[e.condition]);
                    if (j != bi) c.add(flow.control[fi][j]);
                }
            }
            changed |= flow.control[fi][bi].add(c);
        }
        return changed;
    }

    // One instruction's data flow: through loads, stores, returns and calls;
    // a read waits on itself; any other result on its operands.
    bool propagate_instruction(const Instruction& in, std::size_t fi, std::size_t bi, Flow& flow) {
        auto memory_of = [&](Id pointer) -> ReadSet& { return flow.memory[root_of(pointer)]; };
        switch (in.op) {
            case spv::OpLoad: return !in.words.empty() && flow.value[in.result].add(memory_of(in.words[0]));
            case spv::OpStore: {
                if (in.words.size() < 2) return false;
                ReadSet stored = flow.value[in.words[1]];
                stored.add(flow.control[fi][bi]);
                return memory_of(in.words[0]).add(stored);
            }
            case spv::OpAccessChain:
            case spv::OpInBoundsAccessChain: return false;  // roots are followed by root_of
            case spv::OpReturnValue: {
                if (in.words.empty()) return false;
                ReadSet r = flow.value[in.words[0]];
                r.add(flow.control[fi][bi]);
                return flow.returns[m_.functions_[fi].id].add(r);
            }
            case spv::OpFunctionCall: {
                if (in.words.empty()) return false;
                bool changed = flow.value[in.result].add(flow.returns[in.words[0]]);
                if (const Function* callee = function(in.words[0]))
                    changed |= flow.function_control[index_of(*callee)].add(flow.control[fi][bi]);
                return changed;
            }
            default: break;
        }
        if (is_sample(in.op)) {
            ReadSet self;
            self.set(flow.read_index[&in]);
            return flow.value[in.result].add(self);
        }
        if (!in.result) return false;
        ReadSet r;
        for (Id operand : in.words)
            if (operand < m_.bound_) {
                const auto found = flow.value.find(operand);
                if (found != flow.value.end()) r.add(found->second);
            }
        return flow.value[in.result].add(r);
    }

    bool propagate_data(std::size_t fi, Flow& flow) {
        const Function& f = m_.functions_[fi];
        bool changed = false;
        // Parameters: what the caller's locations hold (both ways: out and inout).
        for (Id p : f.parameters)
            for (Id arg : param_args_[p]) {
                changed |= flow.memory[p].add(flow.memory[root_of(arg)]);
                changed |= flow.memory[root_of(arg)].add(flow.memory[p]);
            }
        for (std::size_t bi = 0; bi < f.blocks.size(); ++bi)
            for (const Instruction& in : f.blocks[bi].body) changed |= propagate_instruction(in, fi, bi, flow);
        return changed;
    }

    // Each read's waits: its coordinates (and lod or gradients), and its block's control.
    std::vector<std::vector<int>> read_waits(Flow& flow) const {
        std::vector<std::vector<int>> waits(flow.reads.size());
        for (std::size_t r = 0; r < flow.reads.size(); ++r) {
            ReadSet w = flow.control[flow.reads[r].function][flow.reads[r].block];
            const Instruction& in = *flow.reads[r].in;
            for (std::size_t o = 1; o < in.words.size(); ++o)
                if (in.words[o] < m_.bound_) {
                    const auto found = flow.value.find(in.words[o]);
                    if (found != flow.value.end()) w.add(found->second);
                }
            waits[r] = w.members();
        }
        return waits;
    }

    // How often each function runs on the longest path: its callers' repeats
    // times the trips of the loops around each call.
    std::vector<double> function_repeats(const Function& entry) {
        std::vector<double> repeats(m_.functions_.size(), 0.0);
        repeats[index_of(entry)] = 1.0;
        for (int pass = 0; pass < 64; ++pass) {
            bool moved = false;
            for (std::size_t fi = 0; fi < m_.functions_.size(); ++fi) {
                const Function& f = m_.functions_[fi];
                for (std::size_t bi = 0; bi < f.blocks.size(); ++bi)
                    for (const Instruction& in : f.blocks[bi].body) {
                        if (in.op != spv::OpFunctionCall || in.words.empty()) continue;
                        const Function* callee = function(in.words[0]);
                        if (!callee) continue;
                        const double k = repeats[fi] * multiplier(f, bi);
                        double& target = repeats[index_of(*callee)];
                        if (k > target) {
                            target = k;
                            moved = true;
                        }
                    }
            }
            if (!moved) break;
        }
        return repeats;
    }

    // Which reads each value, memory location and block waits on: a
    // flow-insensitive fixpoint over data (through loads, stores and calls)
    // and control (a block inside a branch or loop whose condition, or exit
    // test, waits on a read waits on it too).
    Status dependences(const Function& entry, StageCost& out) {
        Flow flow;
        collect_reads(flow);
        alias_parameters();
        bool changed = true;
        for (int round = 0; changed && round < 256; ++round) {
            changed = false;
            for (std::size_t fi = 0; fi < m_.functions_.size(); ++fi) {
                changed |= propagate_control(fi, flow);
                changed |= propagate_data(fi, flow);
            }
        }
        const std::vector<std::vector<int>> waits = read_waits(flow);
        const std::vector<double> repeats = function_repeats(entry);
        for (std::size_t r = 0; r < flow.reads.size(); ++r) {
            SampleCost s;
            s.where = flow.reads[r].in->where;
            s.waits_on = waits[r];
            s.dependent = !waits[r].empty();
            s.repeats = repeats[flow.reads[r].function] * multiplier(m_.functions_[flow.reads[r].function], flow.reads[r].block);
            if (s.dependent) ++out.dependent_samples;
            out.samples.push_back(s);
        }
        out.texture_round_trips = round_trips(out.samples);
        return {};
    }

    // The longest chain of reads each waiting on the previous: over the
    // strongly connected components of the wait graph, a component with a
    // cycle (a read waiting on its own last iteration, a march) counting its
    // repeats, any other read once.
    static double round_trips(const std::vector<SampleCost>& samples) {
        const int n = static_cast<int>(samples.size());
        if (n == 0) return 0.0;
        // Tarjan's algorithm, iteratively bounded by n.
        std::vector<int> index(n, -1), low(n, 0), component(n, -1);
        std::vector<bool> on_stack(n, false);
        std::vector<int> stack;
        int next_index = 0, components = 0;
        std::function<void(int)> connect = [&](int v) {
            index[v] = low[v] = next_index++;
            stack.push_back(v);
            on_stack[v] = true;
            for (int w : samples[v].waits_on) {
                if (w < 0 || w >= n) continue;
                if (index[w] < 0) {
                    connect(w);
                    low[v] = std::min(low[v], low[w]);
                } else if (on_stack[w]) {
                    low[v] = std::min(low[v], index[w]);
                }
            }
            if (low[v] == index[v]) {
                int w;
                do {
                    w = stack.back();
                    stack.pop_back();
                    on_stack[w] = false;
                    component[w] = components;
                } while (w != v);
                ++components;
            }
        };
        for (int v = 0; v < n; ++v)
            if (index[v] < 0) connect(v);
        std::vector<double> weight(components, 1.0);
        std::vector<int> size(components, 0);
        std::vector<bool> cyclic(components, false);
        for (int v = 0; v < n; ++v) {
            ++size[component[v]];
            for (int w : samples[v].waits_on)
                if (w == v) cyclic[component[v]] = true;
        }
        for (int v = 0; v < n; ++v)
            if (cyclic[component[v]] || size[component[v]] > 1)
                weight[component[v]] = std::max(weight[component[v]], samples[v].repeats);
        // Tarjan numbers components so that waits point to lower numbers.
        std::vector<double> chain(components, 0.0);
        std::vector<std::vector<int>> members(components);
        for (int v = 0; v < n; ++v) members[component[v]].push_back(v);
        double best = 0.0;
        for (int c = 0; c < components; ++c) {
            double before = 0.0;
            for (int v : members[c])
                for (int w : samples[v].waits_on)
                    if (w >= 0 && w < n && component[w] != c) before = std::max(before, chain[component[w]]);
            chain[c] = before + weight[c];
            best = std::max(best, chain[c]);
        }
        return best;
    }

    const Module& m_;
    std::unordered_map<Id, std::size_t> function_index_;
    std::vector<std::vector<Construct>> constructs_;
    std::unordered_map<Id, FunctionCost> costs_;
    std::unordered_map<Id, std::vector<Id>> param_args_;
    std::unordered_map<Id, Id> alias_;
    bool unknown_trips_ = false;
};

}  // namespace

Result<StageCost> analyse_spirv(const std::vector<std::uint32_t>& words, ShaderStage stage,
                                const std::vector<LineOrigin>& origins, const TripOverrides& trips) {
    Module m;
    Status parsed = m.parse(words, origins);
    if (!parsed) return parsed.error();
    StageCost out;
    out.stage = stage;
    out.spirv_words = words.size();
    Analysis analysis(m, trips);
    Status ran = analysis.run(out);
    if (!ran) return ran.error();
    return out;
}

Result<StageCost> stage_cost(const AssembledSource& source, ShaderStage stage, const TripOverrides& trips) {
    Result<std::vector<std::uint32_t>> words = compile_spirv(source.text, stage);
    if (!words) return words.error();
    return analyse_spirv(*words, stage, source.origins, trips);
}

}  // namespace px::profiling
