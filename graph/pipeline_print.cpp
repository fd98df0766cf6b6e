// `crackflow run --print-pipeline`: the plan written back as a pipeline file.
#include "graph/diagnostics.hpp"
#include "graph/pipeline.hpp"

#include <yaml-cpp/yaml.h>

namespace cf::graph {

namespace {

void emit_value(YAML::Emitter& e, const ParamValue& v) {
    if (const auto* b = std::get_if<bool>(&v)) e << (*b ? "true" : "false");
    else if (const auto* i = std::get_if<long long>(&v)) e << *i;
    else if (const auto* d = std::get_if<double>(&v)) e << format_number(*d);  // reads back as the same double
    else if (const auto* s = std::get_if<std::string>(&v)) e << YAML::DoubleQuoted << *s;
    else if (const auto* l = std::get_if<std::vector<double>>(&v)) {
        e << YAML::Flow << YAML::BeginSeq;
        for (double x : *l) e << format_number(x);
        e << YAML::EndSeq;
    }
}

std::string source_text(const Plan& plan, const PlanInput& in) {
    const std::string& n = plan.nodes[static_cast<std::size_t>(in.source)].name;
    switch (in.kind) {
        case SourceKind::NodeOutput: return n + "." + in.source_port;
        case SourceKind::LoopVariable: return n + "." + in.source_port;
        case SourceKind::LoopIteration: return n + ".iteration";
        case SourceKind::LoopEach: return n + ".each." + in.source_port;
        case SourceKind::LoopFinal: return n + ".final." + in.source_port;
    }
    return n;
}

void emit_node(YAML::Emitter& e, const Plan& plan, std::size_t i) {
    const PlanNode& p = plan.nodes[i];
    e << YAML::Key << p.name << YAML::Value << YAML::BeginMap;
    e << YAML::Key << "type" << YAML::Value << (p.is_loop() ? std::string("loop") : p.type->name());
    // The parameters a file or an override gave (param_locs), after every override; the rest
    // take their defaults.
    if (p.is_loop()) {
        e << YAML::Key << "params" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "max_iterations"
          << YAML::Value << p.max_iterations << YAML::EndMap;
    } else if (!p.param_locs.empty()) {
        e << YAML::Key << "params" << YAML::Value << YAML::BeginMap;
        for (const auto& [name, l] : p.param_locs) {
            const auto v = p.params.find(name);
            if (v == p.params.end()) continue;
            e << YAML::Key << name << YAML::Value;
            emit_value(e, v->second);
        }
        e << YAML::EndMap;
    }
    const auto& inputs = p.is_loop() ? p.loop_init : p.inputs;
    if (!inputs.empty()) {
        e << YAML::Key << "inputs" << YAML::Value << YAML::BeginMap;
        for (const auto& in : inputs) e << YAML::Key << in.port << YAML::Value << source_text(plan, in);
        e << YAML::EndMap;
    }
    if (p.is_loop()) {
        e << YAML::Key << "body" << YAML::Value << YAML::BeginMap;
        for (std::size_t k = 0; k < plan.nodes.size(); ++k)
            if (plan.nodes[k].body_of == static_cast<int>(i)) emit_node(e, plan, k);
        e << YAML::EndMap;
        e << YAML::Key << "next" << YAML::Value << YAML::BeginMap;
        for (const auto& in : p.loop_next) e << YAML::Key << in.port << YAML::Value << source_text(plan, in);
        e << YAML::EndMap;
        if (p.loop_while) e << YAML::Key << "while" << YAML::Value << source_text(plan, *p.loop_while);
    }
    e << YAML::EndMap;
}

}  // namespace

std::string to_yaml(const Plan& plan) {
    YAML::Emitter e;
    e.SetIndent(2);
    std::string used;
    for (const auto& u : plan.uses) used += "\n  " + u.name + ": " + u.file;
    e << YAML::BeginMap;
    e << YAML::Key << "description" << YAML::Value << YAML::Literal
      << "The pipeline " + plan.file + " as it runs: sub-pipelines expanded (their nodes named USE/NODE), fast: and --set "
         "overrides applied, input paths resolved; parameters not listed take their defaults." +
             (used.empty() ? std::string() : "\nSub-pipelines:" + used) + "\n";
    e << YAML::Key << "nodes" << YAML::Value << YAML::BeginMap;
    for (std::size_t i = 0; i < plan.nodes.size(); ++i)
        if (plan.nodes[i].body_of < 0) emit_node(e, plan, i);
    e << YAML::EndMap << YAML::EndMap;
    return std::string(e.c_str()) + "\n";
}

}  // namespace cf::graph
