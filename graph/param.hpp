#pragma once
// Parameter declarations: the data from which YAML validation, defaults, `crackflow nodes`,
// docs/nodes.md and error messages all come.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace cf::graph {

enum class ParamKind { Bool, Int, Real, String, Choice, RealList };
const char* to_string(ParamKind k);

using ParamValue = std::variant<bool, long long, double, std::string, std::vector<double>>;
std::string format_param_value(const ParamValue& v);

struct ParamDecl {
    std::string name;
    ParamKind kind = ParamKind::Real;
    std::optional<ParamValue> default_value;  // no default: the parameter is required
    std::string unit;                          // SI unit ("m", "Pa", "Pa*sqrt(m)"), empty if none
    std::string doc;                           // one line
    std::optional<double> min, max;            // numeric range (also each element of a RealList)
    bool min_exclusive = false, max_exclusive = false;
    std::vector<std::string> choices;          // for Choice
    std::optional<std::size_t> list_size;      // for RealList with a fixed length
    bool output_file = false;                  // names a file the node writes (checked by validate)
    bool input_file = false;                   // names a file the node reads (resolved by the loader)
    // For String parameters with a syntax of their own (e.g. boundary conditions): returns why the
    // text is not acceptable, empty when it is. Run by check(), so `validate` reports it at FILE:LINE.
    std::function<std::string(const std::string&)> text_check;

    // Builder-style refinements, chained after NodeType::param_*.
    ParamDecl& with_unit(std::string u) { unit = std::move(u); return *this; }
    ParamDecl& range(double lo, double hi) { min = lo; max = hi; return *this; }
    ParamDecl& above(double lo) { min = lo; min_exclusive = true; return *this; }
    ParamDecl& at_least(double lo) { min = lo; return *this; }
    ParamDecl& below(double hi) { max = hi; max_exclusive = true; return *this; }
    ParamDecl& at_most(double hi) { max = hi; return *this; }
    ParamDecl& size(std::size_t n) { list_size = n; return *this; }
    ParamDecl& required() { default_value.reset(); return *this; }
    // A String naming an output file, relative to the run's output directory: `validate` and `run`
    // refuse absolute paths (unless allowed), paths leaving --out, report.json and two nodes
    // naming the same file (graph/output_paths.hpp).
    ParamDecl& writes_file() { output_file = true; return *this; }
    // A String naming a file the node reads: the loader resolves a relative path beside the
    // pipeline file, then on the data search path, and hands the node an absolute path
    // (graph/input_paths.hpp); validate reports a file that is not found, with every path tried.
    ParamDecl& reads_file() { input_file = true; return *this; }
    ParamDecl& checked_by(std::function<std::string(const std::string&)> f) { text_check = std::move(f); return *this; }

    bool is_required() const { return !default_value.has_value(); }
    // Human-readable allowed range, e.g. "(0, 0.5)" or "one of: obj, ply".
    std::string describe_range() const;
    // Empty when v is acceptable, otherwise why not (without the parameter name).
    std::string check(const ParamValue& v) const;
};

}  // namespace cf::graph
