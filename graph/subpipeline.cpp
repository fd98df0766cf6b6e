// Sub-pipelines: a node `{type: use, use: FILE, params: {...}, inputs: {...}}` reads another
// pipeline file in its place (in the spirit of Gaffer's Reference or a Houdini digital asset). The
// used file declares its interface at the top level:
//   parameters: {NAME: {to: [NODE.PARAM, ...], doc: ...}}   # promoted: set on every target
//   inputs:     {NAME: {type: TypeName, doc: ...}}           # read inside as input.NAME
//   outputs:    {NAME: NODE.PORT}                            # read outside as USE.NAME
// Its nodes join the plan as USE/NODE (so a file can be used twice), with the using node's
// parameters applied over the file's own values; errors inside name the used file's line and the
// using file's line (SourceLoc::via).
#include "graph/input_paths.hpp"
#include "graph/pipeline_loader.hpp"

#include <filesystem>

namespace cf::graph::detail {

namespace {

constexpr int kMaxUseDepth = 16;

std::string where(const SourceLoc& l) {
    std::string s = l.file;
    if (l.line > 0) s += ":" + std::to_string(l.line) + ":" + std::to_string(l.column);
    return s;
}

// "NODE.PARAM" -> (NODE, PARAM); false when malformed.
bool split_target(const std::string& t, std::pair<std::string, std::string>& out) {
    const auto dot = t.find('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 == t.size()) return false;
    out = {t.substr(0, dot), t.substr(dot + 1)};
    return true;
}

}  // namespace

bool Loader::unwired_optional(const YAML::Node& src, int scope) const {
    const Scope& sc = scopes_[static_cast<std::size_t>(scope)];
    if (!sc.is_sub || !src.IsScalar()) return false;
    const std::string prefix = std::string(kInputNode) + ".";
    if (src.Scalar().rfind(prefix, 0) != 0) return false;
    const std::string port = src.Scalar().substr(prefix.size());
    return sc.optional_inputs.count(port) && !sc.wired.count(port);
}

int Loader::find_use(const std::string& global_name) const {
    for (std::size_t i = 0; i < uses_.size(); ++i)
        if (uses_[i].name == global_name) return static_cast<int>(i);
    return -1;
}

void Loader::expand_use(const std::string& name, const SourceLoc& name_loc, const YAML::Node& v, int body_of) {
    const int parent = scope_;
    if (body_of >= 0) {
        error(name_loc, "use node '" + name + "' is inside the body of loop '" + raw_[body_of].name + "'",
              "use sub-pipelines outside loop bodies (a used file may hold a loop itself)");
        return;
    }
    YAML::Node file_node, params, inputs;
    for (auto f = v.begin(); f != v.end(); ++f) {
        const std::string key = f->first.Scalar();
        if (key == "type") continue;
        if (key == "use") file_node.reset(f->second);
        else if (key == "params" || key == "inputs") {
            if (!f->second.IsNull() && !f->second.IsMap()) {
                error(loc(f->second), "'" + key + "' of use node '" + name + "' must be a mapping", key + ": {name: value, ...}");
                continue;
            }
            (key == "params" ? params : inputs).reset(f->second);
        } else {
            error(loc(f->first), "unknown key '" + key + "' in use node '" + name + "'",
                  did_you_mean(key, {"type", "use", "params", "inputs"}));
        }
    }
    if (!file_node || !file_node.IsScalar() || file_node.Scalar().empty()) {
        error(name_loc, "use node '" + name + "' needs 'use: FILE', the sub-pipeline file (relative to this file)",
              "e.g. use: lib/fracture.yaml");
        return;
    }
    const std::string written = file_node.Scalar();
    const SourceLoc use_loc = loc(file_node);
    // The file beside the using file, shown as the using file's path names it; else on the
    // pipeline search path (CRACKFLOW_PIPELINE_PATH, then crackflow's own pipelines/), shown absolute.
    const InputFileSearch search = find_pipeline_file(written, scopes_[parent].dir);
    if (search.found.empty()) {
        std::string tried;
        for (const std::string& t : search.tried) tried += (tried.empty() ? "" : ", ") + t;
        error(use_loc, "sub-pipeline file '" + written + "' of use node '" + name + "' not found: " + tried,
              "a sub-pipeline is looked up beside the file that uses it, then in each directory of " +
                  std::string(kPipelinePathVariable) + " (':'-separated), then in crackflow's own pipelines directory "
                  "(lib/fracture.yaml, lib/surface.yaml)");
        return;
    }
    const std::filesystem::path abs(search.found);
    std::filesystem::path shown(written);
    if (shown.is_relative())
        shown = search.found == search.tried.front()
                    ? (std::filesystem::path(scopes_[parent].file).parent_path() / shown).lexically_normal()
                    : abs;
    std::error_code ec;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(abs, ec);
    int depth = 0;
    std::string chain = shown.string();
    for (int s = parent; s >= 0; s = scopes_[s].parent, ++depth) {
        chain = scopes_[s].file + " -> " + chain;
        std::error_code e2;
        if (std::filesystem::weakly_canonical(std::filesystem::absolute(scopes_[s].file, e2), e2) == canonical) {
            error(use_loc, "sub-pipeline " + shown.string() + " uses itself: " + chain, "a file cannot use itself, directly or not");
            return;
        }
    }
    if (depth > kMaxUseDepth) {
        error(use_loc, "sub-pipelines nested more than " + std::to_string(kMaxUseDepth) + " deep: " + chain);
        return;
    }
    Scope sc;
    sc.file = shown.string();
    sc.dir = std::filesystem::absolute(abs, ec).parent_path();
    sc.prefix = name + "/";
    sc.parent = parent;
    sc.via = where(name_loc) + " (node '" + name + "')" + (scopes_[parent].via.empty() ? "" : ", used at " + scopes_[parent].via);
    sc.is_sub = true;
    std::string text;
    YAML::Node root;
    if (!read_pipeline_text(abs.string(), text, diags_, use_loc) || !parse_pipeline_yaml(text, sc.file, sc.via, root, diags_))
        return;
    scopes_.push_back(std::move(sc));
    const int s = static_cast<int>(scopes_.size()) - 1;
    uses_.push_back({name, name_loc, s, parent});
    YAML::Node nodes, fast;
    bool has_fast = false;
    if (!read_top_level(root, nodes, fast, has_fast, s)) return;
    read_interface(root, s);
    scope_ = s;
    read_nodes(nodes, -1);
    scope_ = parent;
    check_interface(s);
    // The used file's own fast: entries, then the using node's parameters over them (the using
    // file's fast: and --set come later, over both).
    if (fast_ && has_fast) {
        std::vector<Override> entries;
        fast_overrides(fast, s, entries);
        for (const auto& o : entries) apply_override(o, s);
    }
    if (params)
        for (auto p = params.begin(); p != params.end(); ++p) {
            const std::string key = p->first.Scalar();
            if (!scopes_[s].params.count(key)) {
                error(loc(p->first), "sub-pipeline " + scopes_[s].file + " (node '" + name + "') has no parameter '" + key + "'",
                      did_you_mean(key, scopes_[s].param_order));
                continue;
            }
            assign(name, key, p->second, loc(p->second), parent);
        }
    if (inputs)
        for (auto p = inputs.begin(); p != inputs.end(); ++p) {
            const std::string key = p->first.Scalar();
            if (!scopes_[s].input_types.count(key)) {
                error(loc(p->first), "sub-pipeline " + scopes_[s].file + " (node '" + name + "') has no input '" + key + "'",
                      did_you_mean(key, scopes_[s].input_order));
                continue;
            }
            scopes_[s].wired[key] = p->second;
        }
    for (const auto& in : scopes_[s].input_order)
        if (!scopes_[s].wired.count(in) && !scopes_[s].optional_inputs.count(in))
            error(name_loc, "input '" + in + "' (" + scopes_[s].input_types[in] + ") of sub-pipeline " + scopes_[s].file +
                                " (node '" + name + "') is not connected",
                  "add inputs: {" + in + ": NODE.PORT}");
}

void Loader::read_interface(const YAML::Node& root, int s) {
    const int saved = scope_;
    scope_ = s;
    Scope& sc = scopes_[s];
    auto mapping = [&](const char* key) {
        const YAML::Node n = root[key];
        if (n && !n.IsNull() && !n.IsMap()) {
            error(loc(n), std::string("'") + key + "' of a sub-pipeline must be a mapping");
            return YAML::Node();
        }
        return n;
    };
    if (const YAML::Node ps = mapping("parameters"))
        for (auto it = ps.begin(); it != ps.end(); ++it) {
            const std::string name = it->first.Scalar();
            Scope::Param p;
            p.loc = loc(it->first);
            const YAML::Node to = it->second.IsMap() ? it->second["to"] : it->second;
            if (it->second.IsMap()) {
                if (it->second["doc"]) p.doc = it->second["doc"].as<std::string>("");
                for (auto k = it->second.begin(); k != it->second.end(); ++k)
                    if (k->first.Scalar() != "to" && k->first.Scalar() != "doc")
                        error(loc(k->first), "unknown key '" + k->first.Scalar() + "' in parameter '" + name + "'",
                              did_you_mean(k->first.Scalar(), {"to", "doc"}));
            }
            std::vector<YAML::Node> targets;
            if (to && to.IsScalar()) targets.push_back(to);
            else if (to && to.IsSequence())
                for (const auto& t : to) targets.push_back(t);
            for (const auto& t : targets) {
                std::pair<std::string, std::string> nt;
                if (!t.IsScalar() || !split_target(t.Scalar(), nt)) {
                    error(loc(t), "target of parameter '" + name + "' must be NODE.PARAM", "e.g. to: [solve0.boundary_conditions]");
                    continue;
                }
                p.targets.push_back(nt);
            }
            if (targets.empty())
                error(p.loc, "parameter '" + name + "' of the sub-pipeline names no target",
                      name + ": {to: [NODE.PARAM, ...], doc: ...}  (or " + name + ": NODE.PARAM)");
            if (sc.params.emplace(name, std::move(p)).second) sc.param_order.push_back(name);
        }
    if (const YAML::Node ins = mapping("inputs"))
        for (auto it = ins.begin(); it != ins.end(); ++it) {
            const std::string name = it->first.Scalar();
            std::string type = it->second.IsScalar() ? it->second.Scalar()
                               : it->second.IsMap() && it->second["type"] ? it->second["type"].as<std::string>("")
                                                                          : "";
            if (it->second.IsMap()) {
                if (it->second["optional"] && it->second["optional"].as<std::string>("") == "true") sc.optional_inputs.insert(name);
                for (auto k = it->second.begin(); k != it->second.end(); ++k)
                    if (k->first.Scalar() != "type" && k->first.Scalar() != "doc" && k->first.Scalar() != "optional")
                        error(loc(k->first), "unknown key '" + k->first.Scalar() + "' in input '" + name + "'",
                              did_you_mean(k->first.Scalar(), {"type", "doc", "optional"}));
            }
            if (type.empty())
                error(loc(it->first), "input '" + name + "' of the sub-pipeline needs a type", name + ": {type: SurfaceMesh, doc: ...}");
            if (sc.input_types.emplace(name, type).second) sc.input_order.push_back(name);
        }
    if (const YAML::Node outs = mapping("outputs"))
        for (auto it = outs.begin(); it != outs.end(); ++it) {
            const std::string name = it->first.Scalar();
            YAML::Node src = it->second.IsMap() ? it->second["from"] : it->second;
            if (!src || !src.IsScalar() || src.Scalar().find('.') == std::string::npos) {
                error(loc(it->second), "output '" + name + "' of the sub-pipeline must be NODE.PORT", name + ": fragments.fragments");
                continue;
            }
            if (sc.outputs.emplace(name, std::make_pair(src, loc(src))).second) sc.output_order.push_back(name);
        }
    scope_ = saved;
}

void Loader::check_interface(int s) {
    const Scope& sc = scopes_[s];
    for (const auto& name : sc.param_order) {
        const Scope::Param& p = sc.params.at(name);
        for (const auto& [node, param] : p.targets) {
            const std::string g = sc.prefix + node;
            if (const int i = find_raw(g); i >= 0) {
                const NodeType* t = reg_.find(raw_[i].type);
                if (t && !t->find_param(param)) {
                    std::vector<std::string> names;
                    for (const auto& d : t->params()) names.push_back(d.name);
                    error(p.loc, "parameter '" + name + "' targets '" + node + "." + param + "', but node '" + node + "' (" +
                                     t->name() + ") has no parameter '" + param + "'",
                          did_you_mean(param, names));
                }
            } else if (const int u = find_use(g); u >= 0) {
                if (!scopes_[uses_[u].scope].params.count(param))
                    error(p.loc, "parameter '" + name + "' targets '" + node + "." + param + "', but sub-pipeline node '" + node +
                                     "' declares no parameter '" + param + "'",
                          did_you_mean(param, scopes_[uses_[u].scope].param_order));
            } else {
                std::vector<std::string> names;
                for (const auto& r : raw_)
                    if (r.scope == s) names.push_back(r.name.substr(sc.prefix.size()));
                error(p.loc, "parameter '" + name + "' targets '" + node + "." + param + "', but the file has no node '" + node + "'",
                      did_you_mean(node, names));
            }
        }
    }
    for (const auto& name : sc.output_order) {
        const auto& [src, l] = sc.outputs.at(name);
        const std::string node = src.Scalar().substr(0, src.Scalar().find('.'));
        if (node == kInputNode) continue;
        const std::string g = sc.prefix + node;
        if (find_raw(g) < 0 && find_use(g) < 0)
            error(l, "output '" + name + "' reads '" + src.Scalar() + "', but the file has no node '" + node + "'");
    }
}

std::optional<std::string> Loader::globalize(const std::string& text, int s, const SourceLoc& l, int depth) {
    const Scope& sc = scopes_[s];
    const auto dot = text.find('.');
    if (dot == std::string::npos || depth > 4 * kMaxUseDepth) return text;  // reported by the caller's checks
    const std::string node = text.substr(0, dot), rest = text.substr(dot + 1);
    if (sc.is_sub && node == kInputNode) {
        const auto it = sc.wired.find(rest);
        if (it == sc.wired.end()) {
            if (!sc.input_types.count(rest))
                error(l, "'" + text + "': the sub-pipeline declares no input '" + rest + "'",
                      sc.input_order.empty() ? "declare it: inputs: {" + rest + ": {type: TYPE}}" : did_you_mean(rest, sc.input_order));
            return std::nullopt;  // an unconnected declared input is reported at the use node
        }
        const YAML::Node& src = it->second;
        const SourceLoc ol = loc_in(src, sc.parent);
        if (!src.IsScalar() || src.Scalar().find('.') == std::string::npos) {
            error(ol, "input '" + rest + "' of use node '" + sc.prefix.substr(0, sc.prefix.size() - 1) + "' must be written NODE.PORT",
                  "e.g. mesh: box.mesh");
            return std::nullopt;
        }
        return globalize(src.Scalar(), sc.parent, ol, depth + 1);
    }
    const std::string g = sc.prefix + node;
    if (const int u = find_use(g); u >= 0) {
        const Scope& us = scopes_[uses_[u].scope];
        const auto it = us.outputs.find(rest);
        if (it == us.outputs.end()) {
            error(l, "'" + text + "': sub-pipeline " + us.file + " (node '" + g + "') has no output '" + rest + "'",
                  us.output_order.empty() ? "the file declares no outputs" : did_you_mean(rest, us.output_order));
            return std::nullopt;
        }
        return globalize(it->second.first.Scalar(), uses_[u].scope, it->second.second, depth + 1);
    }
    return g + "." + rest;
}

}  // namespace cf::graph::detail
