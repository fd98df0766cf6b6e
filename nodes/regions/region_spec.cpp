#include "nodes/regions/region_spec.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>

namespace cf {
namespace {

enum class Kind { Name, Number, Compare, Symbol, Bad, End };

struct Token {
    Kind kind;
    std::string text;  // as written ("the end of the text" for End)
    std::size_t pos;   // offset into the spec
    double number = 0;
};

bool name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

std::vector<Token> tokenize(const std::string& s) {
    std::vector<Token> out;
    std::size_t i = 0;
    while (true) {
        while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
        if (i == s.size()) break;
        const std::size_t start = i;
        const char c = s[i];
        if (name_start(c)) {
            while (i < s.size() && name_char(s[i])) ++i;
            out.push_back({Kind::Name, s.substr(start, i - start), start});
        } else if (digit(c) || (c == '.' && i + 1 < s.size() && digit(s[i + 1]))) {
            // digits [. digits] [e [+-] digits]: scanned here so strtod never sees hex, inf or nan.
            while (i < s.size() && digit(s[i])) ++i;
            if (i < s.size() && s[i] == '.') ++i;
            while (i < s.size() && digit(s[i])) ++i;
            if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
                std::size_t j = i + 1;
                if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
                if (j < s.size() && digit(s[j])) {
                    i = j;
                    while (i < s.size() && digit(s[i])) ++i;
                }
            }
            const std::string text = s.substr(start, i - start);
            out.push_back({Kind::Number, text, start, std::strtod(text.c_str(), nullptr)});
        } else if (c == '>' || c == '<' || c == '=') {
            ++i;
            if (i < s.size() && (s[i] == '=' || s[i] == '<' || s[i] == '>')) ++i;
            out.push_back({Kind::Compare, s.substr(start, i - start), start});
        } else if (c == '&') {
            ++i;
            if (i < s.size() && s[i] == '&') ++i;  // '&&' reads as '&'
            out.push_back({Kind::Symbol, "&", start});
        } else if (c == ':' || c == ';' || c == '+' || c == '-' || c == '*' || c == '/') {
            ++i;
            out.push_back({Kind::Symbol, std::string(1, c), start});
        } else {
            ++i;
            out.push_back({Kind::Bad, std::string(1, c), start});
        }
    }
    out.push_back({Kind::End, "the end of the text", s.size()});
    return out;
}

// A linear function a . p + b.
struct Linear {
    Vec3 a = Vec3::Zero();
    double b = 0;
};

class Parser {
public:
    explicit Parser(const std::string& spec) : spec_(spec), tokens_(tokenize(spec)) {}

    std::vector<RegionDefinition> parse() {
        std::vector<RegionDefinition> regions;
        std::map<std::string, std::size_t> first_pos;
        while (true) {
            while (is(";")) ++at_;
            if (peek().kind == Kind::End) break;
            region_.clear();
            const Token& name = peek();
            if (name.kind != Kind::Name)
                fail(name.pos, "expected a region name (a letter or '_', then letters, digits or '_'), found " +
                                   quoted(name));
            ++at_;
            region_ = name.text;
            if (auto [it, inserted] = first_pos.emplace(name.text, name.pos); !inserted) {
                region_.clear();
                throw RegionSpecError("region '" + name.text + "' is defined twice (at " + where(it->second) +
                                      " and " + where(name.pos) + "); give each region its own name");
            }
            if (!is(":"))
                fail(peek().pos, "expected ':' after the region name '" + name.text + "', found " + quoted(peek()));
            ++at_;
            RegionDefinition r{name.text, {}};
            r.conditions.push_back(condition());
            while (is("&")) {
                ++at_;
                r.conditions.push_back(condition());
            }
            if (!is(";") && peek().kind != Kind::End)
                fail(peek().pos, "expected '&' (and), ';' (next region) or the end after the condition, found " +
                                     quoted(peek()) + "; separate regions with ';'");
            regions.push_back(std::move(r));
        }
        if (regions.empty())
            throw RegionSpecError("the region list is empty; write regions like 'top: z >= 0.49; bottom: z <= -0.49'");
        return regions;
    }

private:
    const Token& peek() const { return tokens_[at_]; }
    const Token& previous() const { return tokens_[at_ - 1]; }
    bool is(const char* symbol) const { return peek().kind == Kind::Symbol && peek().text == symbol; }

    static std::string quoted(const Token& t) { return t.kind == Kind::End ? t.text : "'" + t.text + "'"; }

    std::string where(std::size_t pos) const {
        std::size_t line = 1, column = 1;
        for (std::size_t i = 0; i < pos && i < spec_.size(); ++i) {
            if (spec_[i] == '\n') ++line, column = 1;
            else ++column;
        }
        const bool multiline = spec_.find('\n') != std::string::npos;
        return (multiline ? "line " + std::to_string(line) + ", " : std::string()) + "column " + std::to_string(column);
    }

    [[noreturn]] void fail(std::size_t pos, const std::string& what) const {
        if (peek().kind == Kind::Bad && peek().pos == pos)
            throw RegionSpecError((region_.empty() ? "" : "region '" + region_ + "', ") + where(pos) +
                                  ": unexpected character '" + peek().text +
                                  "'; conditions use numbers, x, y, z, + - * /, >= <= > <, '&' and ';'");
        throw RegionSpecError((region_.empty() ? "" : "region '" + region_ + "', ") + where(pos) + ": " + what);
    }

    HalfSpace condition() {
        const std::size_t start = peek().pos;
        const Linear lhs = linear();
        const Token& op = peek();
        if (op.kind != Kind::Compare) {
            fail(op.pos, "expected a comparison (>=, <=, >, <) after '" + previous().text + "', found " + quoted(op));
        }
        if (op.text == "=" || op.text == "==")
            fail(op.pos, "'" + op.text + "' cannot select triangles (no centroid lies exactly on a plane); use '>=' or '<='");
        if (op.text == "=>" || op.text == "=<")
            fail(op.pos, "write '" + std::string{op.text[1], '='} + "' instead of '" + op.text + "'");
        if (op.text != ">=" && op.text != "<=" && op.text != ">" && op.text != "<")
            fail(op.pos, "'" + op.text + "' is not a comparison; use >=, <=, > or <");
        ++at_;
        const Linear rhs = linear();
        const bool greater = op.text[0] == '>';
        // lhs >= rhs  <=>  (lhs - rhs) >= 0;  lhs <= rhs  <=>  (rhs - lhs) >= 0.
        HalfSpace h;
        h.normal = greater ? Vec3(lhs.a - rhs.a) : Vec3(rhs.a - lhs.a);
        h.offset = greater ? lhs.b - rhs.b : rhs.b - lhs.b;
        h.strict = op.text.size() == 1;
        if (h.normal.isZero(0)) {
            std::string text = spec_.substr(start, previous().pos + previous().text.size() - start);
            fail(start, "the condition '" + text +
                            "' does not depend on x, y or z, so it would hold everywhere or nowhere");
        }
        return h;
    }

    Linear linear() {
        Linear sum;
        bool first = true;
        while (true) {
            double sign = 1;
            if (is("+") || is("-")) {
                sign = peek().text == "-" ? -1 : 1;
                ++at_;
            } else if (!first) {
                return sum;
            }
            first = false;
            term(sign, sum);
        }
    }

    // Adds sign * term to sum.
    void term(double sign, Linear& sum) {
        double coefficient = sign;
        std::optional<int> variable;
        std::string variable_name;
        factor(coefficient, variable, variable_name, false);
        while (true) {
            if (is("*") || is("/")) {
                const bool divide = peek().text == "/";
                ++at_;
                factor(coefficient, variable, variable_name, divide);
            } else if (peek().kind == Kind::Name && previous().kind == Kind::Number &&
                       peek().pos == previous().pos + previous().text.size()) {
                factor(coefficient, variable, variable_name, false);  // 2x reads as 2*x
            } else {
                break;
            }
        }
        if (variable) sum.a[*variable] += coefficient;
        else sum.b += coefficient;
    }

    void factor(double& coefficient, std::optional<int>& variable, std::string& variable_name, bool divide) {
        const Token& t = peek();
        const std::string after = at_ > 0 ? " after '" + previous().text + "'" : "";
        if (t.kind == Kind::Number) {
            if (!std::isfinite(t.number)) fail(t.pos, "the number '" + t.text + "' is too large");
            if (divide && t.number == 0) fail(t.pos, "division by zero");
            coefficient = divide ? coefficient / t.number : coefficient * t.number;
        } else if (t.kind == Kind::Name) {
            if (t.text != "x" && t.text != "y" && t.text != "z")
                fail(t.pos, "unknown variable '" + t.text + "'; conditions use x, y and z (metres)");
            if (divide) fail(t.pos, "'/" + t.text + "' is not linear; only divide by numbers");
            if (variable)
                fail(t.pos, "'" + variable_name + "*" + t.text + "' is not linear; multiply a variable only by numbers");
            variable = t.text[0] - 'x';
            variable_name = t.text;
        } else {
            fail(t.pos, "expected a number or x, y, z" + after + ", found " + quoted(t));
        }
        ++at_;
    }

    const std::string& spec_;
    std::vector<Token> tokens_;
    std::size_t at_ = 0;
    std::string region_;  // the region being parsed, for messages
};

}  // namespace

std::vector<RegionDefinition> parse_region_spec(const std::string& spec) { return Parser(spec).parse(); }

}  // namespace cf
