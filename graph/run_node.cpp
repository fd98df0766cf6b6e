#include "graph/run_node.hpp"

namespace cf::graph {

std::map<std::string, ParamValue> resolve_params(const NodeType& type, const std::map<std::string, ParamValue>& given,
                                                 std::vector<std::string>& errors) {
    std::map<std::string, ParamValue> out;
    for (const auto& [name, v] : given) {
        const ParamDecl* d = type.find_param(name);
        if (!d) {
            errors.push_back("unknown parameter '" + name + "' for node type " + type.name());
            continue;
        }
        ParamValue value = v;
        // An integer literal is a fine real.
        if (d->kind == ParamKind::Real && std::holds_alternative<long long>(v))
            value = static_cast<double>(std::get<long long>(v));
        if (d->kind == ParamKind::RealList && std::holds_alternative<double>(v))
            value = std::vector<double>{std::get<double>(v)};
        std::string why = d->check(value);
        if (!why.empty()) {
            errors.push_back("parameter '" + name + "' " + why);
            continue;
        }
        out[name] = value;
    }
    for (const auto& d : type.params()) {
        if (out.count(d.name) || given.count(d.name)) continue;
        if (d.default_value) out[d.name] = *d.default_value;
        else errors.push_back("missing required parameter '" + d.name + "' (" + d.doc + ")");
    }
    return out;
}

NodeResult run_node(const NodeType& type, const std::map<std::string, ParamValue>& params,
                    const std::map<std::string, Value>& inputs, const RunOptions& options,
                    const std::string& node_name, int iteration) {
    std::vector<std::string> errors;
    auto resolved = resolve_params(type, params, errors);
    for (const auto& [port, v] : inputs) {
        const PortDecl* p = type.find_input(port);
        if (!p) errors.push_back("unknown input '" + port + "'");
        else if (v.type() != p->type) errors.push_back("input '" + port + "' expects " + p->type.name + ", got " + v.type().name);
    }
    for (const auto& p : type.inputs())
        if (!p.optional && !inputs.count(p.name)) errors.push_back("required input '" + p.name + "' is not connected");
    if (!errors.empty()) {
        std::string msg;
        for (const auto& e : errors) msg += (msg.empty() ? "" : "; ") + e;
        throw NodeError(msg);
    }
    NodeContext ctx(type, node_name.empty() ? type.name() : node_name, std::move(resolved), inputs, options, iteration);
    type.run_fn()(ctx);
    for (const auto& p : type.outputs())
        if (!ctx.outputs().count(p.name))
            throw std::logic_error("node type " + type.name() + " did not set its output '" + p.name + "'");
    return NodeResult{ctx.outputs(), ctx.counts()};
}

}  // namespace cf::graph
