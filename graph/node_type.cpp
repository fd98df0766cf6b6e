#include "graph/node_type.hpp"

#include <algorithm>
#include <stdexcept>

namespace cf::graph {

NodeType& NodeType::input_needed_when(std::string input, std::string param, std::vector<std::string> values,
                                       std::string why) {
    const PortDecl* in = find_input(input);
    if (!in || !in->optional)
        throw std::logic_error("node type " + name_ + ": rule for '" + input + "', which is not an optional input");
    const ParamDecl* p = find_param(param);
    if (!p) throw std::logic_error("node type " + name_ + ": rule for '" + input + "' names no parameter '" + param + "'");
    if (p->kind != ParamKind::Bool && p->kind != ParamKind::Choice)
        throw std::logic_error("node type " + name_ + ": rule for '" + input + "': '" + param + "' is not a Bool or Choice parameter");
    for (const std::string& v : values) {
        const bool ok = p->kind == ParamKind::Bool ? v == "true" || v == "false"
                                                   : std::find(p->choices.begin(), p->choices.end(), v) != p->choices.end();
        if (!ok) throw std::logic_error("node type " + name_ + ": rule for '" + input + "': '" + v + "' is no value of '" + param + "'");
    }
    input_rules_.push_back({std::move(input), std::move(param), std::move(values), std::move(why)});
    return *this;
}

NodeType& NodeType::writes_fixed(std::string name, std::string when) {
    if (!when.empty()) {
        const ParamDecl* p = find_param(when);
        if (!p || p->kind != ParamKind::Bool)
            throw std::logic_error("node type " + name_ + ": fixed output '" + name + "' depends on '" + when +
                                   "', which is not a Bool parameter");
    }
    for (std::size_t open = name.find('<'); open != std::string::npos; open = name.find('<', open + 1)) {
        const std::size_t close = name.find('>', open);
        if (close == std::string::npos || !find_param(std::string_view(name).substr(open + 1, close - open - 1)))
            throw std::logic_error("node type " + name_ + ": fixed output '" + name + "' names no parameter at column " +
                                   std::to_string(open + 1));
    }
    fixed_outputs_.push_back({std::move(name), std::move(when)});
    return *this;
}

ParamDecl& NodeType::add_param(ParamDecl p) {
    if (find_param(p.name)) throw std::logic_error("node type " + name_ + ": duplicate parameter " + p.name);
    params_.push_back(std::move(p));
    return params_.back();
}

ParamDecl& NodeType::param_bool(std::string name, bool def, std::string doc) {
    ParamDecl p;
    p.name = std::move(name); p.kind = ParamKind::Bool; p.default_value = def; p.doc = std::move(doc);
    return add_param(std::move(p));
}
ParamDecl& NodeType::param_int(std::string name, long long def, std::string doc) {
    ParamDecl p;
    p.name = std::move(name); p.kind = ParamKind::Int; p.default_value = def; p.doc = std::move(doc);
    return add_param(std::move(p));
}
ParamDecl& NodeType::param_real(std::string name, double def, std::string unit, std::string doc) {
    ParamDecl p;
    p.name = std::move(name); p.kind = ParamKind::Real; p.default_value = def; p.unit = std::move(unit);
    p.doc = std::move(doc);
    return add_param(std::move(p));
}
ParamDecl& NodeType::param_string(std::string name, std::string def, std::string doc) {
    ParamDecl p;
    p.name = std::move(name); p.kind = ParamKind::String; p.default_value = std::move(def); p.doc = std::move(doc);
    return add_param(std::move(p));
}
ParamDecl& NodeType::param_choice(std::string name, std::string def, std::vector<std::string> choices,
                                  std::string doc) {
    ParamDecl p;
    p.name = std::move(name); p.kind = ParamKind::Choice; p.default_value = std::move(def);
    p.choices = std::move(choices); p.doc = std::move(doc);
    return add_param(std::move(p));
}
ParamDecl& NodeType::param_reals(std::string name, std::vector<double> def, std::string unit, std::string doc) {
    ParamDecl p;
    p.name = std::move(name); p.kind = ParamKind::RealList; p.default_value = std::move(def);
    p.unit = std::move(unit); p.doc = std::move(doc);
    return add_param(std::move(p));
}

const PortDecl* NodeType::find_input(std::string_view n) const {
    for (const auto& p : inputs_) if (p.name == n) return &p;
    return nullptr;
}
const PortDecl* NodeType::find_output(std::string_view n) const {
    for (const auto& p : outputs_) if (p.name == n) return &p;
    return nullptr;
}
const ParamDecl* NodeType::find_param(std::string_view n) const {
    for (const auto& p : params_) if (p.name == n) return &p;
    return nullptr;
}

}  // namespace cf::graph
