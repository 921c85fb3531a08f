#include "parallaxes/shaders/conditional.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <map>
#include <optional>
#include <utility>

namespace px {

namespace {

// Three-valued: what the source alone decides, or unknown (the driver's to decide).
enum class Tri { no, yes, unknown };

Tri negate(Tri t) { return t == Tri::unknown ? Tri::unknown : (t == Tri::yes ? Tri::no : Tri::yes); }

struct Macro {
    enum class State { defined, undefined, unknown };
    State state = State::unknown;
    std::string value;  // the replacement list, trimmed, comments removed
    bool function_like = false;
};
using Macros = std::map<std::string, Macro>;

bool is_ident_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool is_ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

std::string trim(const std::string& s) {
    size_t b = 0, e = s.size();
    while (b < e && is_space(s[b])) ++b;
    while (e > b && is_space(s[e - 1])) --e;
    return s.substr(b, e - b);
}

bool is_identifier(const std::string& s) {
    if (s.empty() || !is_ident_start(s[0])) return false;
    for (char c : s)
        if (!is_ident_char(c)) return false;
    return true;
}

// A preprocessor integer: decimal, octal (leading 0) or hex, no suffix. Past
// 2^31 - 1 it is not taken (the drivers' preprocessors evaluate in 32 bits).
std::optional<std::int64_t> parse_integer(const std::string& s) {
    if (s.empty() || !std::isdigit(static_cast<unsigned char>(s[0]))) return std::nullopt;
    int base = 10;
    size_t i = 0;
    if (s.size() > 1 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
        base = 16;
        i = 2;
        if (i == s.size()) return std::nullopt;
    } else if (s[0] == '0') {
        base = 8;
    }
    std::int64_t v = 0;
    for (; i < s.size(); ++i) {
        const char c = static_cast<char>(std::tolower(static_cast<unsigned char>(s[i])));
        int digit;
        if (c >= '0' && c <= '9') digit = c - '0';
        else if (c >= 'a' && c <= 'f') digit = c - 'a' + 10;
        else return std::nullopt;
        if (digit >= base) return std::nullopt;
        v = v * base + digit;
        if (v > 2147483647) return std::nullopt;
    }
    return v;
}

// --- Conditions ---------------------------------------------------------------

struct Token {
    enum class Kind { identifier, number, punct };
    Kind kind;
    std::string text;
};

// Splits a condition into tokens; nullopt on a character outside the grammar.
std::optional<std::vector<Token>> tokenize(const std::string& s) {
    std::vector<Token> out;
    size_t i = 0;
    while (i < s.size()) {
        const char c = s[i];
        if (is_space(c)) {
            ++i;
        } else if (is_ident_start(c) || std::isdigit(static_cast<unsigned char>(c))) {
            size_t j = i;
            while (j < s.size() && is_ident_char(s[j])) ++j;
            out.push_back({is_ident_start(c) ? Token::Kind::identifier : Token::Kind::number, s.substr(i, j - i)});
            i = j;
        } else {
            static const char* const kTwo[] = {"&&", "||", "==", "!=", "<=", ">="};
            bool two = false;
            for (const char* p : kTwo)
                if (s.compare(i, 2, p) == 0) {
                    out.push_back({Token::Kind::punct, p});
                    i += 2;
                    two = true;
                    break;
                }
            if (two) continue;
            if (c != '!' && c != '(' && c != ')' && c != '<' && c != '>') return std::nullopt;
            out.push_back({Token::Kind::punct, std::string(1, c)});
            ++i;
        }
    }
    return out;
}

// An integer the source decides, or unknown.
struct Value {
    bool known = false;
    std::int64_t v = 0;
};
Value known(std::int64_t v) { return {true, v}; }
Value unknown_value() { return {}; }
Value from_tri(Tri t) { return t == Tri::unknown ? unknown_value() : known(t == Tri::yes ? 1 : 0); }

class Condition {
public:
    Condition(const std::vector<Token>& tokens, const Macros& macros) : t_(tokens), macros_(macros) {}

    Tri evaluate() {
        const Value v = logical_or();
        if (failed_ || pos_ != t_.size() || !v.known) return Tri::unknown;
        return v.v != 0 ? Tri::yes : Tri::no;
    }

    static Tri is_defined(const Macros& macros, const std::string& name) {
        const auto it = macros.find(name);
        if (it == macros.end()) return name.compare(0, 3, "PX_") == 0 ? Tri::no : Tri::unknown;
        switch (it->second.state) {
            case Macro::State::defined: return Tri::yes;
            case Macro::State::undefined: return Tri::no;
            case Macro::State::unknown: return Tri::unknown;
        }
        return Tri::unknown;
    }

private:
    bool at(const char* punct) const {
        return pos_ < t_.size() && t_[pos_].kind == Token::Kind::punct && t_[pos_].text == punct;
    }
    bool accept(const char* punct) {
        if (!at(punct)) return false;
        ++pos_;
        return true;
    }

    // Kleene logic: a decided false (&&) or true (||) side decides the whole,
    // whatever the other side is.
    Value logical_or() {
        Value a = logical_and();
        while (accept("||")) {
            const Value b = logical_and();
            if ((a.known && a.v != 0) || (b.known && b.v != 0)) a = known(1);
            else if (a.known && b.known) a = known(0);
            else a = unknown_value();
        }
        return a;
    }
    Value logical_and() {
        Value a = equality();
        while (accept("&&")) {
            const Value b = equality();
            if ((a.known && a.v == 0) || (b.known && b.v == 0)) a = known(0);
            else if (a.known && b.known) a = known(1);
            else a = unknown_value();
        }
        return a;
    }
    Value equality() {
        Value a = relational();
        for (;;) {
            const bool eq = at("==");
            if (!eq && !at("!=")) return a;
            ++pos_;
            const Value b = relational();
            a = a.known && b.known ? known((a.v == b.v) == eq ? 1 : 0) : unknown_value();
        }
    }
    Value relational() {
        Value a = unary();
        for (;;) {
            std::string op;
            for (const char* p : {"<=", ">=", "<", ">"})
                if (at(p)) op = p;
            if (op.empty()) return a;
            ++pos_;
            const Value b = unary();
            if (!a.known || !b.known) {
                a = unknown_value();
                continue;
            }
            bool r = false;
            if (op == "<") r = a.v < b.v;
            else if (op == ">") r = a.v > b.v;
            else if (op == "<=") r = a.v <= b.v;
            else r = a.v >= b.v;
            a = known(r ? 1 : 0);
        }
    }
    Value unary() {
        if (accept("!")) {
            const Value v = unary();
            return v.known ? known(v.v == 0 ? 1 : 0) : v;
        }
        return primary();
    }
    Value primary() {
        if (pos_ >= t_.size()) return fail();
        const Token& tok = t_[pos_];
        if (accept("(")) {
            const Value v = logical_or();
            if (!accept(")")) return fail();
            return v;
        }
        if (tok.kind == Token::Kind::number) {
            ++pos_;
            const std::optional<std::int64_t> n = parse_integer(tok.text);
            return n ? known(*n) : fail();
        }
        if (tok.kind != Token::Kind::identifier) return fail();
        ++pos_;
        if (tok.text == "defined") {
            const bool paren = accept("(");
            if (pos_ >= t_.size() || t_[pos_].kind != Token::Kind::identifier) return fail();
            const std::string name = t_[pos_++].text;
            if (paren && !accept(")")) return fail();
            return from_tri(is_defined(macros_, name));
        }
        return macro_value(tok.text, 0);
    }

    // A name as a value: its definition when that is an integer (or a name
    // that is one). An undefined name is unknown, not 0: GLSL ES makes it an
    // error (1.00 and 3.00, section 3.4), which is the driver's to report.
    Value macro_value(const std::string& name, int depth) const {
        const auto it = macros_.find(name);
        if (it == macros_.end() || it->second.state != Macro::State::defined || it->second.function_like)
            return unknown_value();
        if (const std::optional<std::int64_t> n = parse_integer(it->second.value)) return known(*n);
        if (depth < 32 && is_identifier(it->second.value)) return macro_value(it->second.value, depth + 1);
        return unknown_value();
    }

    Value fail() {
        failed_ = true;
        return unknown_value();
    }

    const std::vector<Token>& t_;
    const Macros& macros_;
    size_t pos_ = 0;
    bool failed_ = false;
};

Tri evaluate(const std::string& expression, const Macros& macros) {
    const std::optional<std::vector<Token>> tokens = tokenize(expression);
    if (!tokens || tokens->empty()) return Tri::unknown;
    return Condition(*tokens, macros).evaluate();
}

// --- Lines ----------------------------------------------------------------------

// One logical line: physical lines joined where one ends in a backslash
// (GLSL ES 3.00 and C splice them before anything else).
struct LogicalLine {
    size_t first = 0;    // index of its first physical line
    std::string raw;     // as written, physical lines joined by '\n'
    std::string joined;  // the splices removed
};

std::vector<LogicalLine> logical_lines(const std::string& text) {
    std::vector<std::string> physical;
    size_t start = 0;
    while (start < text.size()) {
        size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        physical.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    std::vector<LogicalLine> out;
    for (size_t i = 0; i < physical.size(); ++i) {
        LogicalLine l;
        l.first = i;
        l.raw = physical[i];
        l.joined = physical[i];
        while (!l.joined.empty() && l.joined.back() == '\\' && i + 1 < physical.size()) {
            l.joined.pop_back();
            ++i;
            l.raw += '\n' + physical[i];
            l.joined += physical[i];
        }
        out.push_back(std::move(l));
    }
    return out;
}

// Comments replaced by a space (C translation phase 3). `in_block`: inside a
// block comment, at the start of the line on entry and at its end on return.
std::string strip_comments(const std::string& s, bool& in_block) {
    std::string out;
    for (size_t i = 0; i < s.size(); ++i) {
        if (in_block) {
            if (s.compare(i, 2, "*/") == 0) {
                in_block = false;
                ++i;
                out += ' ';
            }
        } else if (s.compare(i, 2, "//") == 0) {
            out += ' ';
            break;
        } else if (s.compare(i, 2, "/*") == 0) {
            in_block = true;
            ++i;
        } else {
            out += s[i];
        }
    }
    return out;
}

struct Directive {
    std::string name;  // "ifdef", "define", ...
    std::string rest;  // after the name, comments removed, trimmed
};

// A directive: '#' first on the line (after spaces), then its name.
std::optional<Directive> parse_directive(const std::string& code) {
    size_t i = 0;
    while (i < code.size() && is_space(code[i])) ++i;
    if (i == code.size() || code[i] != '#') return std::nullopt;
    ++i;
    while (i < code.size() && is_space(code[i])) ++i;
    const size_t name_start = i;
    while (i < code.size() && is_ident_char(code[i])) ++i;
    return Directive{code.substr(name_start, i - name_start), trim(code.substr(i))};
}

// #define NAME value / #define NAME(args) value / #undef NAME: the name, or "".
std::string directive_name(const std::string& rest, size_t& end) {
    end = 0;
    if (rest.empty() || !is_ident_start(rest[0])) return "";
    while (end < rest.size() && is_ident_char(rest[end])) ++end;
    return rest.substr(0, end);
}

// One #if ... #endif structure being read.
struct Frame {
    bool parent_emit = true;     // the enclosing branch is in the output
    bool parent_certain = true;  // ... and certainly compiled
    bool emit = false;           // the current branch is in the output
    bool certain = false;        // ... and certainly compiled
    bool taken = false;          // a branch certainly taken: those after it are dead
    bool kept = false;           // the driver decides: the structure's directives are in the output
    bool seen_else = false;
    size_t opened = 0;           // physical line of its #if
};

// One pass of resolve_conditionals: the macros as known so far, the
// #if structures open, the text kept and where each kept line came from.
class Resolver {
public:
    Resolver(const std::string& name, const std::vector<LineOrigin>& origins, std::vector<LineOrigin>* kept_origins)
        : name_(name), origins_(origins), kept_origins_(kept_origins) {}

    std::vector<Frame> frames;
    std::string out;
    size_t current = 0;  // physical line of the logical line being read

    std::string where(size_t physical) const {
        if (physical < origins_.size()) return origins_[physical].file + ":" + std::to_string(origins_[physical].line);
        return name_ + ":" + std::to_string(physical + 1);
    }

    void keep(const std::string& s) {
        out += s;
        out += '\n';
        if (!kept_origins_) return;
        // One entry per physical line written (a spliced line keeps its splices).
        const size_t lines = 1 + static_cast<size_t>(std::count(s.begin(), s.end(), '\n'));
        for (size_t i = 0; i < lines; ++i) kept_origins_->push_back(origin_of(current + i));
    }

    // #if, #ifdef, #ifndef, #elif or #else: which branch is in the output,
    // and which of their lines the driver still has to decide.
    Status branch(const Directive& d, const LogicalLine& line, bool emit, bool certain) {
        const std::string& dn = d.name;
        const bool opens = dn != "elif" && dn != "else";
        if (opens) {
            Frame f;
            f.parent_emit = emit;
            f.parent_certain = certain;
            f.opened = line.first;
            frames.push_back(f);
        } else {
            if (frames.empty()) return make_error(where(line.first) + ": #" + dn + " without #if");
            if (frames.back().seen_else)
                return make_error(where(line.first) + ": #" + dn + " after #else (the #if at " +
                                  where(frames.back().opened) + ")");
            if (dn == "else") frames.back().seen_else = true;
        }
        Frame& f = frames.back();
        if (!f.parent_emit || f.taken) {  // dead: not evaluated at all
            f.emit = false;
            return {};
        }
        Tri cond = Tri::yes;
        if (dn == "if" || dn == "elif") {
            cond = evaluate(d.rest, macros_);
        } else if (dn == "ifdef" || dn == "ifndef") {
            cond = is_identifier(d.rest) ? Condition::is_defined(macros_, d.rest) : Tri::unknown;
            if (dn == "ifndef") cond = negate(cond);
        }
        if (cond == Tri::no) {
            f.emit = false;
        } else if (cond == Tri::yes) {
            // Taken whenever it is reached; after a kept (driver-decided)
            // branch it is the remaining alternative: an #else.
            f.emit = true;
            f.certain = f.parent_certain && !f.kept;
            f.taken = true;
            if (f.kept) keep(dn == "else" ? line.raw : "#else");
        } else {
            f.emit = true;
            f.certain = false;
            // The first branch the driver decides opens the kept structure.
            if (!f.kept && dn == "elif") keep("#if " + d.rest);
            else keep(line.raw);
            f.kept = true;
        }
        return {};
    }

    // #define or #undef in the output: the macro's state from here on.
    void define(const Directive& d, bool certain) {
        size_t end = 0;
        const std::string macro = directive_name(d.rest, end);
        if (macro.empty()) return;
        Macro m;
        if (!certain) {
            // Defined or not as the driver decides the branch around it.
            m.state = Macro::State::unknown;
        } else if (d.name == "undef") {
            m.state = Macro::State::undefined;
        } else {
            m.state = Macro::State::defined;
            m.function_like = end < d.rest.size() && d.rest[end] == '(';
            m.value = trim(d.rest.substr(end));
        }
        macros_[macro] = m;
    }

private:
    const std::string& name_;
    const std::vector<LineOrigin>& origins_;
    std::vector<LineOrigin>* kept_origins_;
    Macros macros_;

    LineOrigin origin_of(size_t physical) const {
        if (physical < origins_.size()) return origins_[physical];
        return LineOrigin{name_, static_cast<int>(physical + 1)};
    }
};

}  // namespace

Result<std::string> resolve_conditionals(const std::string& text, const std::string& name,
                                         const std::vector<LineOrigin>& origins,
                                         std::vector<LineOrigin>* kept_origins) {
    Resolver r(name, origins, kept_origins);
    r.out.reserve(text.size());
    // Block comments are followed across lines: a '#' inside one starts no
    // directive. Dropping lines never splits a comment: a directive starts
    // outside any (else it is none) and must end outside (checked below), so
    // every run of dropped lines begins and ends outside a comment.
    bool in_block = false;

    for (const LogicalLine& line : logical_lines(text)) {
        r.current = line.first;
        const bool starts_in_comment = in_block;
        const std::string code = strip_comments(line.joined, in_block);
        const bool emit = r.frames.empty() || r.frames.back().emit;
        const bool certain = r.frames.empty() || r.frames.back().certain;
        const std::optional<Directive> d = starts_in_comment ? std::nullopt : parse_directive(code);
        if (!d) {
            if (emit) r.keep(line.raw);
            continue;
        }
        if (in_block)
            return make_error(r.where(line.first) + ": a block comment that begins on a directive line must end on it");

        const std::string& dn = d->name;
        if (dn == "if" || dn == "ifdef" || dn == "ifndef" || dn == "elif" || dn == "else") {
            if (Status s = r.branch(*d, line, emit, certain); !s) return s.error();
            continue;
        }
        if (dn == "endif") {
            if (r.frames.empty()) return make_error(r.where(line.first) + ": #endif without #if");
            if (r.frames.back().parent_emit && r.frames.back().kept) r.keep(line.raw);
            r.frames.pop_back();
            continue;
        }
        if (!emit) continue;
        if (dn == "define" || dn == "undef") r.define(*d, certain);
        r.keep(line.raw);
    }
    if (!r.frames.empty())
        return make_error(r.where(r.frames.back().opened) + ": #if without #endif");
    return std::move(r.out);
}

}  // namespace px
