#include "graph/param.hpp"

#include <cmath>
#include <sstream>

namespace cf::graph {

const char* to_string(ParamKind k) {
    switch (k) {
        case ParamKind::Bool: return "bool";
        case ParamKind::Int: return "int";
        case ParamKind::Real: return "real";
        case ParamKind::String: return "string";
        case ParamKind::Choice: return "choice";
        case ParamKind::RealList: return "real list";
    }
    return "?";
}

static std::string fmt_num(double v) {
    std::ostringstream s;
    s.precision(10);
    s << v;
    return s.str();
}

std::string format_param_value(const ParamValue& v) {
    struct {
        std::string operator()(bool b) const { return b ? "true" : "false"; }
        std::string operator()(long long i) const { return std::to_string(i); }
        std::string operator()(double d) const { return fmt_num(d); }
        std::string operator()(const std::string& s) const { return s; }
        std::string operator()(const std::vector<double>& l) const {
            std::string r = "[";
            for (std::size_t i = 0; i < l.size(); ++i) r += (i ? ", " : "") + fmt_num(l[i]);
            return r + "]";
        }
    } f;
    return std::visit(f, v);
}

std::string ParamDecl::describe_range() const {
    if (kind == ParamKind::Choice) {
        std::string r = "one of: ";
        for (std::size_t i = 0; i < choices.size(); ++i) r += (i ? ", " : "") + choices[i];
        return r;
    }
    if (!min && !max) return "";
    std::string r;
    r += min ? (min_exclusive ? "(" : "[") + fmt_num(*min) : std::string("(-inf");
    r += ", ";
    r += max ? fmt_num(*max) + (max_exclusive ? ")" : "]") : std::string("inf)");
    return r;
}

std::string ParamDecl::check(const ParamValue& v) const {
    auto in_range = [&](double x) -> std::string {
        if (!std::isfinite(x)) return "must be a finite number";
        bool ok = true;
        if (min) ok = ok && (min_exclusive ? x > *min : x >= *min);
        if (max) ok = ok && (max_exclusive ? x < *max : x <= *max);
        return ok ? "" : "value " + fmt_num(x) + " is outside the allowed range " + describe_range();
    };
    switch (kind) {
        case ParamKind::Bool:
            if (!std::holds_alternative<bool>(v)) return "expects a bool (true/false)";
            return "";
        case ParamKind::Int:
            if (!std::holds_alternative<long long>(v)) return "expects an integer";
            return in_range(static_cast<double>(std::get<long long>(v)));
        case ParamKind::Real:
            if (!std::holds_alternative<double>(v)) return "expects a number";
            return in_range(std::get<double>(v));
        case ParamKind::String:
            if (!std::holds_alternative<std::string>(v)) return "expects a string";
            return text_check ? text_check(std::get<std::string>(v)) : "";
        case ParamKind::Choice: {
            if (!std::holds_alternative<std::string>(v)) return "expects a string, " + describe_range();
            const auto& s = std::get<std::string>(v);
            for (const auto& c : choices)
                if (c == s) return "";
            return "'" + s + "' is not allowed; expected " + describe_range();
        }
        case ParamKind::RealList: {
            if (!std::holds_alternative<std::vector<double>>(v)) return "expects a list of numbers, e.g. [1, 2, 3]";
            const auto& l = std::get<std::vector<double>>(v);
            if (list_size && l.size() != *list_size)
                return "expects exactly " + std::to_string(*list_size) + " numbers, got " + std::to_string(l.size());
            for (double x : l) {
                std::string e = in_range(x);
                if (!e.empty()) return e;
            }
            return "";
        }
    }
    return "";
}

}  // namespace cf::graph
