#include "graph/node_context.hpp"

#include <cstdio>

namespace cf::graph {

const Value& NodeContext::input_value(std::string_view port) const {
    auto it = inputs_.find(std::string(port));
    if (it == inputs_.end()) {
        if (!type_.find_input(port)) throw std::logic_error("node type " + type_.name() + " has no input '" + std::string(port) + "'");
        throw NodeError("input '" + std::string(port) + "' is not connected");
    }
    return it->second;
}

void NodeContext::set_output(std::string_view port, Value v) {
    const PortDecl* p = type_.find_output(port);
    if (!p) throw std::logic_error("node type " + type_.name() + " has no output '" + std::string(port) + "'");
    if (v.type() != p->type)
        throw std::logic_error("node type " + type_.name() + ": output '" + std::string(port) + "' expects " +
                               p->type.name + ", got " + v.type().name);
    outputs_[std::string(port)] = std::move(v);
}

std::filesystem::path NodeContext::output_path(const std::string& pattern) const {
    std::string path = pattern;
    const std::string tag = "{iteration}";
    for (auto pos = path.find(tag); pos != std::string::npos; pos = path.find(tag)) {
        char buf[16];
        std::snprintf(buf, sizeof buf, "%04d", iteration_ < 0 ? 0 : iteration_);
        path.replace(pos, tag.size(), buf);
    }
    std::filesystem::path p = path;
    if (!p.is_relative()) {
        if (!options_.allow_absolute_paths)
            fail("output path '" + pattern + "' is absolute; outputs go inside the output directory (" +
                 options_.output_dir.string() + "): use a relative name, or run with --allow-absolute-paths");
        return p;
    }
    // A relative output path stays inside the output directory, and the run's own report is not
    // an output name a node may take (it would be overwritten when the run ends).
    const std::filesystem::path rel = p.lexically_normal();
    if (rel.empty() || *rel.begin() == "..")
        fail("output path '" + pattern + "' leaves the output directory (" + options_.output_dir.string() +
             "); use a name inside it (or an absolute path with --allow-absolute-paths)");
    if (rel == "report.json")
        fail("output path '" + pattern + "' is the run's report.json, which the run writes last; choose another name");
    return options_.output_dir / rel;
}

const ParamValue& NodeContext::param(std::string_view n) const {
    auto it = params_.find(std::string(n));
    if (it == params_.end()) throw std::logic_error("node type " + type_.name() + " has no parameter '" + std::string(n) + "'");
    return it->second;
}

}  // namespace cf::graph
