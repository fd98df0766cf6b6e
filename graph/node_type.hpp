#pragma once
// A node type: typed ports, parameters, and a run function. Declared as data in the style of
// Blender's node declarations; the run function is a thin adapter around a plain algorithm.
#include "graph/param.hpp"
#include "graph/value.hpp"

#include <functional>
#include <string>
#include <vector>

namespace cf::graph {

class NodeContext;

// A dependency between a parameter and an optional input, declared beside the ports: the input is
// needed when the parameter has one of `values` (as format_param_value prints them: "true", a
// choice). The pipeline loader checks it, so `crackflow validate` names FILE:LINE before a run
// instead of the node failing at the end of it; docs/nodes.md lists it.
struct InputRule {
    std::string input;                // an optional input of the node type
    std::string param;                // the parameter that decides
    std::vector<std::string> values;  // the parameter's values that need the input
    std::string why;                  // what the input is used for, one line
};

// A file a node writes under a name of its own, not one a parameter gives (object.vdb,
// fragments.csv): `crackflow validate` checks these names against each other and against the
// names parameters give, so one output cannot silently replace another. In `name`, '<param>'
// stands for that parameter's value and '*' for a number the run decides (an index, a step).
struct FixedOutput {
    std::string name;
    std::string when;  // a Bool parameter that must be true for the file to be written; empty: always
};

struct PortDecl {
    std::string name;
    TypeId type;
    std::string doc;
    bool optional = false;  // inputs only: may stay unconnected
};

class NodeType {
public:
    using RunFn = std::function<void(NodeContext&)>;

    NodeType(std::string name, std::string doc) : name_(std::move(name)), doc_(std::move(doc)) {}

    template <class T>
    NodeType& input(std::string name, std::string doc) {
        inputs_.push_back({std::move(name), type_id<T>(), std::move(doc), false});
        return *this;
    }
    template <class T>
    NodeType& optional_input(std::string name, std::string doc) {
        inputs_.push_back({std::move(name), type_id<T>(), std::move(doc), true});
        return *this;
    }
    template <class T>
    NodeType& output(std::string name, std::string doc) {
        outputs_.push_back({std::move(name), type_id<T>(), std::move(doc), false});
        return *this;
    }

    ParamDecl& param_bool(std::string name, bool def, std::string doc);
    ParamDecl& param_int(std::string name, long long def, std::string doc);
    ParamDecl& param_real(std::string name, double def, std::string unit, std::string doc);
    ParamDecl& param_string(std::string name, std::string def, std::string doc);
    ParamDecl& param_choice(std::string name, std::string def, std::vector<std::string> choices, std::string doc);
    ParamDecl& param_reals(std::string name, std::vector<double> def, std::string unit, std::string doc);

    // Declares that `input` (an optional input) must be connected when parameter `param` has one
    // of `values`. Throws std::logic_error naming the type when the input, parameter or a value
    // does not exist.
    NodeType& input_needed_when(std::string input, std::string param, std::vector<std::string> values, std::string why);

    // Declares a file written under a fixed name (see FixedOutput). Throws std::logic_error naming
    // the type when `when` or a '<param>' in `name` is not one of its parameters.
    NodeType& writes_fixed(std::string name, std::string when = "");
    NodeType& run(RunFn fn) { run_ = std::move(fn); return *this; }
    // A construct the executor runs itself (only `loop`, graph/loop_type.hpp): no run function, and
    // its ports are patterns named by each pipeline. Declared so that validation and docs use it.
    NodeType& executor_construct() { construct_ = true; return *this; }
    bool is_executor_construct() const { return construct_; }

    const std::string& name() const { return name_; }
    const std::string& doc() const { return doc_; }
    const std::vector<PortDecl>& inputs() const { return inputs_; }
    const std::vector<PortDecl>& outputs() const { return outputs_; }
    const std::vector<ParamDecl>& params() const { return params_; }
    const std::vector<InputRule>& input_rules() const { return input_rules_; }
    const std::vector<FixedOutput>& fixed_outputs() const { return fixed_outputs_; }
    const RunFn& run_fn() const { return run_; }

    const PortDecl* find_input(std::string_view n) const;
    const PortDecl* find_output(std::string_view n) const;
    const ParamDecl* find_param(std::string_view n) const;

private:
    ParamDecl& add_param(ParamDecl p);
    std::string name_, doc_;
    std::vector<PortDecl> inputs_, outputs_;
    std::vector<ParamDecl> params_;
    std::vector<InputRule> input_rules_;
    std::vector<FixedOutput> fixed_outputs_;
    RunFn run_;
    bool construct_ = false;
};

}  // namespace cf::graph
