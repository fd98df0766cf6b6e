// The loader's overrides (fast:, --set, a use node's parameters) and input paths.
#include "graph/input_paths.hpp"
#include "graph/pipeline_loader.hpp"

namespace cf::graph::detail {

void Loader::fast_overrides(const YAML::Node& fast, int scope, std::vector<Override>& out) {
    if (!fast.IsMap()) {
        error(loc_in(fast, scope), "'fast:' must be a mapping of NODE.PARAM: value");
        return;
    }
    for (auto it = fast.begin(); it != fast.end(); ++it) {
        const std::string key = it->first.Scalar();
        auto dot = key.find('.');
        if (dot == std::string::npos) {
            error(loc_in(it->first, scope), "fast override '" + key + "' must be NODE.PARAM");
            continue;
        }
        YAML::Emitter e;
        e << YAML::Flow << it->second;
        out.push_back({scopes_[scope].prefix + key.substr(0, dot), key.substr(dot + 1), e.c_str(), loc_in(it->first, scope), true});
    }
}

void Loader::apply_overrides(const YAML::Node& fast, bool has_fast, const LoadOptions& options) {
    std::vector<Override> fast_entries;
    if (options.fast && has_fast) fast_overrides(fast, 0, fast_entries);
    for (const auto& o : fast_entries) apply_override(o, 0);
    for (const auto& o : options.overrides) apply_override(o, -1);
}

const ParamDecl* Loader::find_decl(int node, const std::string& param) const {
    const NodeType* t = reg_.find(raw_[node].type);
    return t ? t->find_param(param) : nullptr;
}

const ParamDecl* Loader::target_decl(const std::string& node, const std::string& param, int depth) const {
    if (const int i = find_raw(node); i >= 0) return find_decl(i, param);
    const int u = find_use(node);
    if (u < 0 || depth > 32) return nullptr;
    const Scope& s = scopes_[uses_[u].scope];
    const auto it = s.params.find(param);
    if (it == s.params.end() || it->second.targets.empty()) return nullptr;
    return target_decl(s.prefix + it->second.targets.front().first, it->second.targets.front().second, depth + 1);
}

std::optional<YAML::Node> Loader::override_value(const Override& o, const ParamDecl* decl) {
    // Text parameters take the text as it is: a boundary condition 'z_max: traction 0 0 1' is not a
    // YAML mapping. Quoted text is still read as YAML (what --set needed before, and what a batch
    // manifest hands on for text it had to quote).
    if (!o.yaml && decl && (decl->kind == ParamKind::String || decl->kind == ParamKind::Choice)) {
        const std::string& t = o.value;
        const bool quoted = t.size() >= 2 && (t.front() == '"' || t.front() == '\'') && t.back() == t.front();
        if (quoted) {
            try {
                YAML::Node n = YAML::Load(t);
                if (n.IsScalar()) return n;
            } catch (const YAML::Exception&) {
            }
        }
        return YAML::Node(t);
    }
    try {
        return YAML::Load(o.value);
    } catch (const YAML::Exception& e) {
        error(o.loc, "override '" + o.node + "." + o.param + "': value '" + o.value + "' is not valid YAML: " + e.msg);
        return std::nullopt;
    }
}

void Loader::apply_override(const Override& o, int value_scope) {
    const int i = find_raw(o.node);
    const int u = find_use(o.node);
    if (i < 0 && u < 0) {
        error(o.loc, "override '" + o.node + "." + o.param + "' names no node", did_you_mean(o.node, all_names()));
        return;
    }
    if (const auto dot = o.param.find('.'); dot != std::string::npos && find_raw(o.param.substr(0, dot)) >= 0) {
        // LOOP.NODE.PARAM: names are global, so a body node is addressed on its own.
        error(o.loc, "override '" + o.node + "." + o.param + "' names node '" + o.param.substr(0, dot) + "' through '" +
                         o.node + "'",
              "write " + o.param + ": every node, also inside a loop body, is addressed by its own name");
        return;
    }
    if (u >= 0) {
        const Scope& s = scopes_[uses_[u].scope];
        if (!s.params.count(o.param)) {
            error(o.loc, "override '" + o.node + "." + o.param + "': sub-pipeline " + s.file + " (node '" + o.node +
                             "') has no parameter '" + o.param + "'",
                  did_you_mean(o.param, s.param_order) + "; a parameter of one of its nodes is " + o.node + "/NODE.PARAM");
            return;
        }
    }
    const std::optional<YAML::Node> value = override_value(o, target_decl(o.node, o.param));
    if (!value) return;
    assign(o.node, o.param, *value, o.loc, value_scope);
}

void Loader::assign(const std::string& node, const std::string& param, const YAML::Node& value, const SourceLoc& l,
                    int value_scope) {
    if (const int i = find_raw(node); i >= 0) {
        set_param(i, param, value, l, value_scope);
        return;
    }
    const int u = find_use(node);
    if (u < 0) return;  // a target the interface check reported
    const Scope& s = scopes_[uses_[u].scope];
    const auto it = s.params.find(param);
    if (it == s.params.end()) return;
    for (const auto& [n, p] : it->second.targets) assign(s.prefix + n, p, value, l, value_scope);
}

void Loader::set_param(int node, const std::string& param, const YAML::Node& value, const SourceLoc& l, int value_scope) {
    RawNode& r = raw_[node];
    for (auto& p : r.params) {
        if (p.name != param) continue;
        // A value the file shares between nodes through a YAML anchor (&pull ... *pull) is one
        // value: overriding it in one node overrides it in all (docs/pipelines.md, "Overrides").
        const YAML::Node shared = p.value;
        for (std::size_t j = 0; j < raw_.size(); ++j) {
            if (static_cast<int>(j) == node) continue;
            for (auto& q : raw_[j].params)
                if (q.name == param && q.value.IsDefined() && shared.IsDefined() && q.value.is(shared)) {
                    q.value.reset(value);  // rebinds; operator= would write through to the shared node
                    q.key_loc = q.value_loc = l;
                    q.scope = value_scope;
                }
        }
        p.value.reset(value);
        p.key_loc = p.value_loc = l;
        p.scope = value_scope;
        return;
    }
    r.params.push_back({param, value, l, l, value_scope});
}

void Loader::resolve_input_paths() {
    std::error_code ec;
    const std::filesystem::path cwd = std::filesystem::current_path(ec);
    for (std::size_t i = 0; i < raw_.size(); ++i) {
        const NodeType* t = plan_[i].type;
        if (!t) continue;
        for (const auto& prm : raw_[i].params) {
            const ParamDecl* d = t->find_param(prm.name);
            auto v = plan_[i].params.find(prm.name);
            if (!d || !d->input_file || v == plan_[i].params.end()) continue;
            const auto* text = std::get_if<std::string>(&v->second);
            if (!text || text->empty()) continue;
            const std::filesystem::path base = prm.scope >= 0 ? scopes_[static_cast<std::size_t>(prm.scope)].dir : cwd;
            const InputFileSearch found = find_input_file(*text, base);
            if (!found.found.empty() || !require_input_files_) {
                v->second = found.found.empty() ? found.tried.front() : found.found;
                continue;
            }
            std::string tried;
            for (const auto& p : found.tried) tried += "\n    " + p;
            error(prm.value_loc,
                  "input file '" + *text + "' of node '" + raw_[i].name + "' (" + t->name() + ", parameter '" + prm.name +
                      "') not found; tried:" + tried,
                  std::string("a relative path is looked up beside the file that gives it (the working directory for --set), "
                              "then in each directory of ") +
                      kDataPathVariable + " (':'-separated), then in the build's data directory (libcgal-demo's meshes: "
                      "install the Debian package libcgal-demo and re-run cmake, e.g. ./setup.sh demo)");
        }
    }
}

}  // namespace cf::graph::detail
