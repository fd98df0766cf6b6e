#include "graph/pipeline.hpp"

#include "graph/pipeline_loader.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <tuple>

namespace cf::graph {

int Plan::find(const std::string& name) const {
    for (std::size_t i = 0; i < nodes.size(); ++i)
        if (nodes[i].name == name) return static_cast<int>(i);
    return -1;
}

namespace detail {

Loader::Loader(std::string file, const NodeRegistry& reg, std::vector<Diagnostic>& diags)
    : file_(std::move(file)), reg_(reg), diags_(diags) {
    Scope top;
    top.file = file_;
    std::error_code ec;
    top.dir = std::filesystem::absolute(std::filesystem::path(file_), ec).parent_path();
    scopes_.push_back(std::move(top));
}

SourceLoc Loader::loc_in(const YAML::Node& n, int scope) const {
    const Scope& s = scopes_[static_cast<std::size_t>(scope < 0 ? 0 : scope)];
    YAML::Mark m = n.Mark();
    if (m.is_null()) return {s.file, 0, 0, s.via};
    return {s.file, m.line + 1, m.column + 1, s.via};
}

void Loader::read_nodes(const YAML::Node& map, int body_of) {
    for (auto it = map.begin(); it != map.end(); ++it) {
        RawNode n;
        n.name = it->first.Scalar();
        n.loc = loc(it->first);
        n.body_of = body_of;
        n.scope = scope_;
        const YAML::Node v = it->second;
        if (n.name.empty() || n.name.find('.') != std::string::npos) {
            error(n.loc, "node name '" + n.name + "' must be non-empty and contain no '.'",
                  "node names are referred to as NAME.port, so use letters, digits and '_'");
            continue;
        }
        if (scopes_[scope_].is_sub && n.name == kInputNode) {
            error(n.loc, "node name 'input' is reserved in a sub-pipeline (input.PORT reads its declared inputs)",
                  "rename the node");
            continue;
        }
        n.name = scopes_[scope_].prefix + n.name;
        if (find_raw(n.name) >= 0 || find_use(n.name) >= 0) {
            error(n.loc, "node name '" + n.name + "' is used twice", "give every node, also inside loop bodies, its own name");
            continue;
        }
        if (!v.IsMap()) {
            error(loc(v).line ? loc(v) : n.loc, "node '" + n.name + "' must be a mapping with at least 'type:'",
                  "e.g. " + n.name + ": {type: shape.box}");
            continue;
        }
        if (const YAML::Node t = v["type"]; t && t.IsScalar() && t.Scalar() == kUseType) {
            expand_use(n.name, n.loc, v, body_of);
            continue;
        }
        YAML::Node body;
        bool has_body = false, has_type = false;
        read_node_keys(v, n, body, has_body, has_type);
        if (!check_node_entry(n, has_type, has_body, body_of)) continue;
        const bool loop = n.type == kLoopType;
        raw_.push_back(std::move(n));
        int self = static_cast<int>(raw_.size()) - 1;
        if (loop) {
            if (!has_body || !body.IsMap() || body.size() == 0)
                error(raw_[self].loc, "loop '" + raw_[self].name + "' needs a non-empty 'body:' mapping of nodes");
            else
                read_nodes(body, self);
        }
    }
}

void Loader::read_node_keys(const YAML::Node& v, RawNode& n, YAML::Node& body, bool& has_body, bool& has_type) {
    for (auto f = v.begin(); f != v.end(); ++f) {
        const std::string key = f->first.Scalar();
        const YAML::Node val = f->second;
        auto need_map = [&](const char* what) {
            if (val.IsNull()) return false;
            if (!val.IsMap()) {
                error(loc(val), "'" + std::string(what) + "' of node '" + n.name + "' must be a mapping",
                      std::string(what) + ": {name: value, ...}");
                return false;
            }
            return true;
        };
        if (key == "type") {
            has_type = true;
            n.type = val.IsScalar() ? val.Scalar() : "";
            n.type_loc = loc(val);
        } else if (key == "params") {
            if (need_map("params"))
                for (auto p = val.begin(); p != val.end(); ++p)
                    n.params.push_back({p->first.Scalar(), p->second, loc(p->first), loc(p->second), scope_});
        } else if (key == "inputs") {
            if (need_map("inputs"))
                for (auto p = val.begin(); p != val.end(); ++p) n.inputs.emplace_back(p->first.Scalar(), p->second);
        } else if (key == "body") {
            body = val;
            has_body = true;
        } else if (key == "next") {
            if (need_map("next"))
                for (auto p = val.begin(); p != val.end(); ++p) n.next.emplace_back(p->first.Scalar(), p->second);
        } else if (key == "while") {
            n.while_node = val;
            n.has_while = true;
        } else {
            error(loc(f->first), "unknown key '" + key + "' in node '" + n.name + "'",
                  did_you_mean(key, {"type", "params", "inputs", "body", "next", "while"}));
        }
    }
}

bool Loader::check_node_entry(const RawNode& n, bool has_type, bool has_body, int body_of) {
    if (!has_type) {
        error(n.loc, "node '" + n.name + "' has no 'type:'", "add e.g. 'type: shape.box'; `crackflow nodes` lists the types");
        return false;
    }
    const bool loop = n.type == kLoopType;
    if (!loop && (has_body || !n.next.empty() || n.has_while)) {
        error(n.loc, "only loop nodes may have 'body', 'next' or 'while' (node '" + n.name + "' has type '" + n.type + "')");
    }
    if (loop && body_of >= 0) {
        error(n.loc, "loop '" + n.name + "' is nested inside loop '" + raw_[body_of].name + "'",
              "nested loops are not supported; put the inner iteration inside one node (as propagate does with sub-steps)");
        return false;
    }
    return true;
}

void Loader::check_input_rules(std::size_t i) {
    const NodeType& t = *plan_[i].type;
    for (const InputRule& rule : t.input_rules()) {
        bool mentioned = false;
        for (auto& [port, src] : raw_[i].inputs) mentioned = mentioned || (port == rule.input && !unwired_optional(src, raw_[i].scope));
        const auto value = plan_[i].params.find(rule.param);
        if (mentioned || value == plan_[i].params.end()) continue;
        const std::string text = format_param_value(value->second);
        if (std::find(rule.values.begin(), rule.values.end(), text) == rule.values.end()) continue;
        SourceLoc where = raw_[i].loc;  // the parameter's value when the file (or --set) gives it
        for (const auto& prm : raw_[i].params)
            if (prm.name == rule.param) where = prm.value_loc;
        error(where,
              "parameter '" + rule.param + "' = " + text + " of node '" + raw_[i].name + "' (" + t.name() + ") needs the input '" +
                  rule.input + "' (" + t.find_input(rule.input)->type.name + "), which is not connected",
              "connect it: inputs: {" + rule.input + ": NODE.PORT} (" + rule.why + "), or change '" + rule.param + "'");
    }
}

void Loader::read_params(const NodeType& t, const RawNode& r, std::map<std::string, ParamValue>& out) {
    for (const auto& prm : r.params) {
        const ParamDecl* d = t.find_param(prm.name);
        if (!d) {
            std::vector<std::string> names;
            for (const auto& pd : t.params()) names.push_back(pd.name);
            error(prm.key_loc, "unknown parameter '" + prm.name + "' for node '" + r.name + "' (" + r.type + ")",
                  did_you_mean(prm.name, names));
            continue;
        }
        if (auto val = convert(*d, prm.value, r.name, prm.value_loc)) out[prm.name] = *val;
    }
    for (const auto& d : t.params()) {
        bool given = false;
        for (const auto& prm : r.params) given = given || prm.name == d.name;
        if (given) continue;
        if (d.default_value) out[d.name] = *d.default_value;
        else error(r.loc, "node '" + r.name + "' (" + r.type + ") is missing required parameter '" + d.name + "'",
                   d.doc + (d.unit.empty() ? "" : " [" + d.unit + "]"));
    }
}

std::optional<ParamValue> Loader::convert(const ParamDecl& d, const YAML::Node& v, const std::string& node,
                                          const SourceLoc& l) {
    const std::string where = "parameter '" + d.name + "' of node '" + node + "'";
    auto fail = [&](const std::string& why) -> std::optional<ParamValue> {
        std::string hint = d.doc;
        std::string r = d.describe_range();
        if (!r.empty()) hint += (hint.empty() ? "" : "; ") + std::string("allowed: ") + r;
        if (!d.unit.empty()) hint += " [" + d.unit + "]";
        error(l, where + " " + why, hint);
        return std::nullopt;
    };
    auto parse_real = [](const std::string& s, double& out) {
        if (s.empty()) return false;
        char* end = nullptr;
        errno = 0;
        out = std::strtod(s.c_str(), &end);
        return end && *end == '\0' && errno == 0;
    };
    if (!v || v.IsNull()) return fail("has no value");
    ParamValue value;
    switch (d.kind) {
        case ParamKind::Bool: {
            bool b;
            if (!v.IsScalar() || !YAML::convert<bool>::decode(v, b)) return fail("expects true or false, got '" + (v.IsScalar() ? v.Scalar() : std::string("a collection")) + "'");
            value = b;
            break;
        }
        case ParamKind::Int: {
            if (!v.IsScalar()) return fail("expects an integer");
            const std::string& s = v.Scalar();
            char* end = nullptr;
            errno = 0;
            long long x = std::strtoll(s.c_str(), &end, 10);
            if (s.empty() || *end != '\0' || errno != 0) return fail("expects an integer, got '" + s + "'");
            value = x;
            break;
        }
        case ParamKind::Real: {
            double x;
            if (!v.IsScalar() || !parse_real(v.Scalar(), x))
                return fail("expects a number, got '" + (v.IsScalar() ? v.Scalar() : std::string("a collection")) + "'");
            value = x;
            break;
        }
        case ParamKind::String:
        case ParamKind::Choice:
            if (!v.IsScalar()) return fail("expects a string");
            value = v.Scalar();
            break;
        case ParamKind::RealList: {
            std::vector<double> list;
            if (v.IsScalar()) {
                double x;
                if (!parse_real(v.Scalar(), x)) return fail("expects a list of numbers, e.g. [1, 2, 3], got '" + v.Scalar() + "'");
                list.push_back(x);
            } else if (v.IsSequence()) {
                for (const auto& e : v) {
                    double x;
                    if (!e.IsScalar() || !parse_real(e.Scalar(), x))
                        return fail("expects a list of numbers, e.g. [1, 2, 3]; element '" + (e.IsScalar() ? e.Scalar() : std::string("?")) + "' is not a number");
                    list.push_back(x);
                }
            } else {
                return fail("expects a list of numbers, e.g. [1, 2, 3]");
            }
            value = list;
            break;
        }
    }
    std::string why = d.check(value);
    if (!why.empty()) return fail(why);
    return value;
}

// Resolves "node.port" (or "loop.each.var", "loop.final.var", "loop.var", "loop.iteration").
std::optional<PlanInput> Loader::resolve_source(const YAML::Node& src, int consumer, const std::string& what, int scope) {
    const SourceLoc l = loc_in(src, raw_[consumer].scope);
    const RawNode& c = raw_[consumer];
    if (scope == -2) scope = c.body_of;
    if (!src.IsScalar() || src.Scalar().find('.') == std::string::npos) {
        error(l, what + " of node '" + c.name + "' must be written NODE.PORT",
              "e.g. " + std::string("mesh: box.mesh"));
        return std::nullopt;
    }
    // In a sub-pipeline's names: input.PORT, a use node's outputs and the file's own nodes.
    const std::optional<std::string> global = globalize(src.Scalar(), c.scope, l);
    if (!global) return std::nullopt;
    const std::string text = *global;
    const std::string node = text.substr(0, text.find('.'));
    int s = find_raw(node);
    if (s < 0) {
        error(l, what + " of node '" + c.name + "' refers to unknown node '" + node + "'", did_you_mean(node, all_names()));
        return std::nullopt;
    }
    if (s == consumer) {
        error(l, what + " of node '" + c.name + "' refers to the node itself", "a node cannot consume its own output; use a loop");
        return std::nullopt;
    }
    std::optional<PlanInput> in = is_loop(s) ? resolve_loop_source(l, consumer, what, scope, s, text)
                                             : resolve_node_output(l, consumer, what, scope, s, text);
    // input.PORT of a sub-pipeline: what the using node connects must be of the declared type
    // (reported once, where the using file connects it).
    const Scope& sc = scopes_[c.scope];
    const std::string written = src.Scalar();
    if (in && sc.is_sub && written.rfind(std::string(kInputNode) + ".", 0) == 0) {
        const std::string port = written.substr(std::string(kInputNode).size() + 1);
        const auto declared = sc.input_types.find(port);
        if (declared != sc.input_types.end() && declared->second != in->type.name &&
            input_type_reported_.insert({c.scope, port}).second)
            error(loc_in(sc.wired.at(port), sc.parent),
                  "input '" + port + "' of sub-pipeline " + sc.file + " (node '" + sc.prefix.substr(0, sc.prefix.size() - 1) +
                      "') is " + declared->second + ", but '" + sc.wired.at(port).Scalar() + "' is " + in->type.name);
    }
    return in;
}

std::optional<PlanInput> Loader::resolve_loop_source(const SourceLoc& l, int consumer, const std::string& what, int scope,
                                                     int s, const std::string& text) {
    const RawNode& c = raw_[consumer];
    const std::string node = text.substr(0, text.find('.'));
    const std::string rest = text.substr(text.find('.') + 1);
    PlanInput in;
    in.source = s;
    const PlanNode& lp = plan_[s];
    const bool inside = scope == s;
    auto var_type = [&](const std::string& var) -> std::optional<TypeId> {
        auto it = lp.loop_var_types.find(var);
        if (it == lp.loop_var_types.end()) {
            error(l, what + " of node '" + c.name + "': loop '" + node + "' has no variable '" + var + "'",
                  did_you_mean(var, lp.loop_vars));
            return std::nullopt;
        }
        return it->second;
    };
    std::string var;
    if (rest == "iteration") {
        in.kind = SourceKind::LoopIteration;
        in.type = type_id<long long>();
    } else if (rest.rfind("each.", 0) == 0 || rest.rfind("final.", 0) == 0) {
        const bool each = rest[0] == 'e';
        in.kind = each ? SourceKind::LoopEach : SourceKind::LoopFinal;
        var = rest.substr(rest.find('.') + 1);
    } else {
        in.kind = SourceKind::LoopVariable;
        var = rest;
    }
    const bool needs_inside = in.kind == SourceKind::LoopIteration || in.kind == SourceKind::LoopVariable;
    if (needs_inside && !inside) {
        error(l, what + " of node '" + c.name + "' reads '" + text + "', which exists only inside the body of loop '" + node + "'",
              "outside the loop use " + node + ".each.VAR (every iteration) or " + node + ".final.VAR (after the last)");
        return std::nullopt;
    }
    if (!needs_inside && inside) {
        error(l, what + " of node '" + c.name + "' reads '" + text + "' from inside the loop's own body",
              "inside the body use " + node + ".VAR for the current value");
        return std::nullopt;
    }
    if (in.kind != SourceKind::LoopIteration) {
        auto t = var_type(var);
        if (!t) return std::nullopt;
        in.type = *t;
    }
    in.source_port = var;
    return in;
}

std::optional<PlanInput> Loader::resolve_node_output(const SourceLoc& l, int consumer, const std::string& what, int scope,
                                                     int s, const std::string& text) {
    const RawNode& c = raw_[consumer];
    const std::string node = text.substr(0, text.find('.'));
    const std::string rest = text.substr(text.find('.') + 1);
    const RawNode& sn = raw_[s];
    const NodeType* st = plan_[s].type;
    if (!st) return std::nullopt;  // the source had its own error
    const PortDecl* out = st->find_output(rest);
    if (!out) {
        std::vector<std::string> names;
        for (const auto& p : st->outputs()) names.push_back(p.name);
        error(l, what + " of node '" + c.name + "': node '" + node + "' (" + st->name() + ") has no output '" + rest + "'",
              did_you_mean(rest, names));
        return std::nullopt;
    }
    if (sn.body_of >= 0 && sn.body_of != scope) {
        const std::string& ln = raw_[sn.body_of].name;
        error(l, what + " of node '" + c.name + "' reads '" + text + "', but '" + node + "' is inside the body of loop '" + ln + "'",
              "pass the value out through the loop: add it to " + ln + ".next and read " + ln + ".each.VAR or " + ln + ".final.VAR");
        return std::nullopt;
    }
    PlanInput in;
    in.source = s;
    in.source_port = rest;
    in.type = out->type;
    return in;
}

bool Loader::read_top_level(const YAML::Node& root, YAML::Node& nodes, YAML::Node& fast, bool& has_fast, int scope) {
    const int saved = scope_;
    scope_ = scope;
    struct Restore {
        int& s;
        int v;
        ~Restore() { s = v; }
    } restore{scope_, saved};
    if (!root.IsMap()) {
        error(loc(root), "a pipeline file must be a mapping with a top-level 'nodes:' key");
        return false;
    }
    bool has_nodes = false, interface = false;
    for (auto it = root.begin(); it != root.end(); ++it) {
        const std::string key = it->first.Scalar();
        if (key == "nodes") nodes = it->second, has_nodes = true;
        else if (key == "fast") fast = it->second, has_fast = true;
        else if (key == "parameters" || key == "inputs" || key == "outputs") {
            if (scope == 0 && !interface)
                error(loc(it->first), "'" + key + "' declares a sub-pipeline's interface; this file is run on its own",
                      "validate or run a pipeline that uses this file (a node with type: use, use: FILE)");
            interface = true;
        } else if (key != "description")
            error(loc(it->first), "unknown top-level key '" + key + "'",
                  did_you_mean(key, {"nodes", "fast", "description", "parameters", "inputs", "outputs"}));
    }
    if (!has_nodes || !nodes.IsMap()) {
        error(loc(root), "missing top-level 'nodes:' mapping", "nodes:\n    box: {type: shape.box}");
        return false;
    }
    return !(scope == 0 && interface);  // its input.PORT references would only repeat the point
}

void Loader::plan_types_and_params() {
    plan_.resize(raw_.size());
    for (std::size_t i = 0; i < raw_.size(); ++i) {
        RawNode& r = raw_[i];
        PlanNode& p = plan_[i];
        p.name = r.name;
        p.loc = r.loc;
        p.body_of = r.body_of;
        for (const auto& prm : r.params) p.param_locs[prm.name] = prm.value_loc;  // messages and run notes name them
        if (r.type == kLoopType) {
            // Declared in the registry like every node type (graph/loop_type.cpp); the plan keeps
            // max_iterations apart from params, where the executor and the scene runner read it.
            std::map<std::string, ParamValue> params;
            read_params(*reg_.find(kLoopType), r, params);
            if (auto it = params.find(kMaxIterationsParam); it != params.end()) p.max_iterations = std::get<long long>(it->second);
            continue;
        }
        p.type = reg_.find(r.type);
        if (!p.type) {
            error(r.type_loc, "unknown node type '" + r.type + "' (node '" + r.name + "')",
                  did_you_mean(r.type, reg_.names()) + " (`crackflow nodes` lists all types)");
            continue;
        }
        read_params(*p.type, r, p.params);
    }
}

void Loader::resolve_loop_variables() {
    for (std::size_t i = 0; i < raw_.size(); ++i) {
        if (!is_loop(static_cast<int>(i))) continue;
        scope_ = raw_[i].scope;
        for (auto& [var, src] : raw_[i].inputs) {
            if (var == "iteration" || var == "each" || var == "final") {
                error(loc(src), "loop variable name '" + var + "' is reserved", "choose another name, e.g. state");
                continue;
            }
            auto in = resolve_source(src, static_cast<int>(i), "initial value of loop variable '" + var + "'");
            plan_[i].loop_vars.push_back(var);
            if (!in) continue;
            in->port = var;
            plan_[i].loop_var_types[var] = in->type;
            plan_[i].loop_init.push_back(*in);
        }
        if (raw_[i].inputs.empty())
            error(raw_[i].loc, "loop '" + raw_[i].name + "' has no variables", "add inputs: {VAR: node.port} with the initial value of each");
    }
}

void Loader::resolve_inputs() {
    for (std::size_t i = 0; i < raw_.size(); ++i) {
        if (is_loop(static_cast<int>(i)) || !plan_[i].type) continue;
        scope_ = raw_[i].scope;
        const NodeType& t = *plan_[i].type;
        std::set<std::string> connected, left_out;
        for (auto& [port, src] : raw_[i].inputs) {
            if (unwired_optional(src, raw_[i].scope)) {
                left_out.insert(port);
                continue;
            }
            const PortDecl* pd = t.find_input(port);
            if (!pd) {
                std::vector<std::string> names;
                for (const auto& d : t.inputs()) names.push_back(d.name);
                error(loc(src), "node '" + raw_[i].name + "' (" + t.name() + ") has no input '" + port + "'",
                      names.empty() ? "this node type takes no inputs" : did_you_mean(port, names));
                continue;
            }
            auto in = resolve_source(src, static_cast<int>(i), "input '" + port + "'");
            if (!in) continue;
            in->port = port;
            if (in->type != pd->type) {
                error(loc(src), "type mismatch: input '" + port + "' of node '" + raw_[i].name + "' expects " + pd->type.name +
                                    ", but '" + src.Scalar() + "' is " + in->type.name);
                continue;
            }
            connected.insert(port);
            plan_[i].inputs.push_back(*in);
        }
        for (const auto& d : t.inputs())
            if (!d.optional && !connected.count(d.name)) {
                bool mentioned = false;
                for (auto& [port, src] : raw_[i].inputs) mentioned = mentioned || (port == d.name && !left_out.count(port));
                if (!mentioned)
                    error(raw_[i].loc, "required input '" + d.name + "' (" + d.type.name + ") of node '" + raw_[i].name + "' is not connected",
                          "add inputs: {" + d.name + ": NODE.PORT}; " + d.doc);
            }
        check_input_rules(i);
    }
}

void Loader::resolve_loop_next_and_while() {
    for (std::size_t i = 0; i < raw_.size(); ++i) {
        if (!is_loop(static_cast<int>(i))) continue;
        scope_ = raw_[i].scope;
        PlanNode& lp = plan_[i];
        std::set<std::string> given;
        for (auto& [var, src] : raw_[i].next) {
            if (!lp.loop_var_types.count(var)) {
                error(loc(src), "loop '" + lp.name + "': 'next' names '" + var + "', which is not a loop variable", did_you_mean(var, lp.loop_vars));
                continue;
            }
            // 'next' is read from inside the body.
            auto in = resolve_source(src, static_cast<int>(i), "next value of '" + var + "'", static_cast<int>(i));
            if (!in) continue;
            if (in->kind != SourceKind::NodeOutput || raw_[in->source].body_of != static_cast<int>(i)) {
                error(loc(src), "loop '" + lp.name + "': next value of '" + var + "' must come from a node in its body");
                continue;
            }
            if (in->type != lp.loop_var_types[var]) {
                error(loc(src), "type mismatch: loop variable '" + var + "' of '" + lp.name + "' is " + lp.loop_var_types[var].name +
                                    ", but its next value '" + src.Scalar() + "' is " + in->type.name);
                continue;
            }
            in->port = var;
            given.insert(var);
            lp.loop_next.push_back(*in);
        }
        for (const auto& var : lp.loop_vars)
            if (lp.loop_var_types.count(var) && !given.count(var))
                error(lp.loc, "loop '" + lp.name + "' gives no next value for variable '" + var + "'",
                      "add next: {" + var + ": BODYNODE.PORT}");
        if (raw_[i].has_while) {
            auto in = resolve_source(raw_[i].while_node, static_cast<int>(i), "'while'", static_cast<int>(i));
            if (in) {
                if (in->kind != SourceKind::NodeOutput || raw_[in->source].body_of != static_cast<int>(i))
                    error(loc(raw_[i].while_node), "loop '" + lp.name + "': 'while' must come from a node in its body");
                else if (in->type != type_id<bool>())
                    error(loc(raw_[i].while_node), "loop '" + lp.name + "': 'while' must be Bool, got " + in->type.name);
                else
                    lp.loop_while = *in;
            }
        }
    }
}

void Loader::check_body_nodes_vary() {
    std::vector<char> varies(raw_.size(), 0);
    for (bool changed = true; changed;) {
        changed = false;
        for (std::size_t v = 0; v < raw_.size(); ++v) {
            if (varies[v] || plan_[v].body_of < 0) continue;
            for (const auto& in : plan_[v].inputs)
                if (in.kind == SourceKind::LoopVariable || in.kind == SourceKind::LoopIteration ||
                    (in.kind == SourceKind::NodeOutput && varies[in.source]))
                    varies[v] = 1, changed = true;
        }
    }
    for (std::size_t v = 0; v < raw_.size(); ++v)
        if (plan_[v].body_of >= 0 && plan_[v].type && !varies[v])
            error(plan_[v].loc, "node '" + plan_[v].name + "' is in the body of loop '" + raw_[plan_[v].body_of].name + "' but uses no loop value",
                  "move it out of the body, or connect it to " + raw_[plan_[v].body_of].name + ".VAR or .iteration");
}

std::vector<int> Loader::dependency_order() {
    const int n = static_cast<int>(raw_.size());
    std::vector<std::vector<int>> succ(n);
    std::vector<int> indeg(n, 0);
    auto edge = [&](int a, int b) { succ[a].push_back(b); ++indeg[b]; };
    for (int i = 0; i < n; ++i) {
        for (const auto& in : plan_[i].inputs) edge(in.source, i);
        for (const auto& in : plan_[i].loop_init) edge(in.source, i);
    }
    std::vector<int> order;
    std::vector<int> ready;
    for (int i = 0; i < n; ++i) if (indeg[i] == 0) ready.push_back(i);
    while (!ready.empty()) {
        std::sort(ready.begin(), ready.end(), std::greater<int>());  // file order among ready nodes
        int v = ready.back();
        ready.pop_back();
        order.push_back(v);
        for (int s : succ[v]) if (--indeg[s] == 0) ready.push_back(s);
    }
    if (static_cast<int>(order.size()) != n) {
        // Walk predecessors among the remaining nodes until one repeats: that is a cycle.
        std::vector<char> done(n, 0);
        for (int v : order) done[v] = 1;
        int start = 0;
        while (done[start]) ++start;
        std::vector<int> path{start};
        std::vector<int> pos(n, -1);
        pos[start] = 0;
        for (;;) {
            int v = path.back(), next = -1;
            for (const auto& in : plan_[v].inputs) if (!done[in.source]) { next = in.source; break; }
            if (next < 0) for (const auto& in : plan_[v].loop_init) if (!done[in.source]) { next = in.source; break; }
            if (next < 0 || pos[next] >= 0) {
                std::string cyc;
                int from = next < 0 ? 0 : pos[next];
                for (int k = static_cast<int>(path.size()) - 1; k >= from; --k) cyc += raw_[path[k]].name + " -> ";
                cyc += raw_[path[next < 0 ? path.size() - 1 : from]].name;
                error(raw_[start].loc, "illegal cycle: " + cyc,
                      "a pipeline is acyclic; express iteration with a loop node (type: loop) and its 'next:' values");
                return {};
            }
            pos[next] = static_cast<int>(path.size());
            path.push_back(next);
        }
    }
    return order;
}

void Loader::mark_streamed_nodes(const std::vector<int>& order) {
    for (int v : order) {
        PlanNode& p = plan_[v];
        if (p.body_of >= 0 || p.is_loop()) continue;
        for (const auto& in : p.inputs) {
            int s = -1;
            if (in.kind == SourceKind::LoopEach) s = in.source;
            else if (in.kind == SourceKind::NodeOutput && plan_[in.source].streamed_by >= 0) s = plan_[in.source].streamed_by;
            if (s < 0) continue;
            if (p.streamed_by >= 0 && p.streamed_by != s)
                error(p.loc, "node '" + p.name + "' mixes per-iteration values of loops '" + plan_[p.streamed_by].name + "' and '" +
                                 plan_[s].name + "'", "use one loop's .final value instead");
            p.streamed_by = s;
        }
    }
}

void Loader::emit_in_order(const std::vector<int>& order, Plan& plan) {
    const int n = static_cast<int>(raw_.size());
    std::vector<int> new_index(n);
    for (int k = 0; k < n; ++k) new_index[order[k]] = k;
    auto remap = [&](PlanInput& in) { in.source = new_index[in.source]; };
    for (auto& p : plan_) {
        for (auto& in : p.inputs) remap(in);
        for (auto& in : p.loop_init) remap(in);
        for (auto& in : p.loop_next) remap(in);
        if (p.loop_while) remap(*p.loop_while);
        if (p.body_of >= 0) p.body_of = new_index[p.body_of];
        if (p.streamed_by >= 0) p.streamed_by = new_index[p.streamed_by];
    }
    for (int k = 0; k < n; ++k) plan.nodes.push_back(std::move(plan_[order[k]]));
}

// The passes, in order; each reports every problem it finds, and the plan is built only when
// none was found.
Plan Loader::load(const YAML::Node& root, const LoadOptions& options) {
    Plan plan;
    plan.file = file_;
    YAML::Node nodes, fast;
    bool has_fast = false;
    fast_ = options.fast;
    require_input_files_ = options.require_input_files;
    if (!read_top_level(root, nodes, fast, has_fast, 0)) return plan;
    read_nodes(nodes, -1);  // sub-pipelines (use nodes) are read in place, with their parameters
    apply_overrides(fast, has_fast, options);  // fast: (with --fast, the used files' first) and --set
    plan_types_and_params();
    resolve_input_paths();
    resolve_loop_variables();  // first: their types come from the initial values
    resolve_inputs();
    resolve_loop_next_and_while();
    check_body_nodes_vary();
    for (const auto& u : uses_) plan.uses.push_back({u.name, scopes_[u.scope].file, u.loc});
    if (!diags_.empty()) return plan;
    const std::vector<int> order = dependency_order();  // loop back-edges 'next'/'while' are not edges
    if (!diags_.empty()) return plan;                   // a cycle
    mark_streamed_nodes(order);
    emit_in_order(order, plan);
    // Checks across nodes that only the stages understand (e.g. boundary conditions naming the
    // regions of an upstream mesh): registered with the registry, run on the finished plan.
    for (const PlanCheck& check : reg_.plan_checks()) check(plan, diags_);
    return plan;
}

}  // namespace detail

std::optional<Override> parse_override(const std::string& text, std::vector<Diagnostic>& diags) {
    auto eq = text.find('=');
    auto dot = text.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq || dot == 0 || dot + 1 == eq) {
        diags.push_back({{"--set", 0, 0}, "override '" + text + "' must be NODE.PARAM=VALUE", "e.g. --set box.size=[1,2,3]"});
        return std::nullopt;
    }
    return Override{text.substr(0, dot), text.substr(dot + 1, eq - dot - 1), text.substr(eq + 1), {"--set", 0, 0}};
}

namespace detail {

bool parse_pipeline_yaml(const std::string& text, const std::string& file_name, const std::string& via, YAML::Node& root,
                         std::vector<Diagnostic>& diags) {
    try {
        // A file with several YAML documents ('---') is one pipeline only if it has one document;
        // silently running the first would hide the rest.
        const std::vector<YAML::Node> docs = YAML::LoadAll(text);
        if (docs.size() > 1) {
            const YAML::Mark m = docs[1].Mark();
            diags.push_back({{file_name, m.line >= 0 ? m.line + 1 : 0, m.column >= 0 ? m.column + 1 : 0, via},
                             "the file holds " + std::to_string(docs.size()) + " YAML documents; a pipeline file holds one",
                             "remove the '---' separators, or split the documents into one file each"});
            return false;
        }
        root = docs.empty() ? YAML::Node() : docs.front();
    } catch (const YAML::ParserException& e) {
        diags.push_back({{file_name, e.mark.line + 1, e.mark.column + 1, via}, "YAML syntax error: " + e.msg,
                         "check indentation and that every 'key: value' has a space after the colon"});
        return false;
    }
    return true;
}

bool read_pipeline_text(const std::string& path, std::string& text, std::vector<Diagnostic>& diags, const SourceLoc& at) {
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        std::error_code ec;
        const std::string abs = std::filesystem::absolute(path, ec).lexically_normal().string();
        diags.push_back({at, "cannot open pipeline file '" + path + "' (" + abs + ")",
                         "check the path; pipelines/ has the shipped ones"});
        return false;
    }
    // Read at most the limit and one byte more: a pipeline is a few kilobytes, and /dev/zero or a
    // mesh given by mistake must not be read into memory whole (validate /dev/zero read 4.2 GB).
    // Read in 64 KiB chunks: a 16 MiB buffer zero-filled per file cost ~10 ms of page faults per
    // pipeline and sub-pipeline file at every start (issue 17).
    constexpr std::size_t limit = std::size_t(16) << 20, chunk = std::size_t(64) << 10;
    text.clear();
    while (f && text.size() <= limit) {
        const std::size_t have = text.size();
        text.resize(have + chunk);
        f.read(text.data() + have, static_cast<std::streamsize>(chunk));
        text.resize(have + static_cast<std::size_t>(f.gcount()));
    }
    if (text.size() > limit) {
        diags.push_back({at, "pipeline file '" + path + "' is larger than 16 MiB (a pipeline is a few kilobytes); not read",
                         "check that this is the pipeline YAML file and not a mesh, a device or a generated file"});
        return false;
    }
    return true;
}

}  // namespace detail

Plan load_pipeline_text(const std::string& text, const std::string& file_name, const NodeRegistry& registry,
                        const LoadOptions& options, std::vector<Diagnostic>& diags) {
    YAML::Node root;
    if (!detail::parse_pipeline_yaml(text, file_name, "", root, diags)) return {};
    const std::size_t first = diags.size();
    detail::Loader loader(file_name, registry, diags);
    Plan plan = loader.load(root, options);
    plan.registry = &registry;
    // The file's own problems by line, then those inside each used file (after the using line's).
    std::stable_sort(diags.begin() + first, diags.end(), [](const Diagnostic& a, const Diagnostic& b) {
        return std::tie(a.loc.via, a.loc.line, a.loc.column) < std::tie(b.loc.via, b.loc.line, b.loc.column);
    });
    return plan;
}

Plan load_pipeline_file(const std::string& path, const NodeRegistry& registry, const LoadOptions& options,
                        std::vector<Diagnostic>& diags) {
    std::string text;
    if (!detail::read_pipeline_text(path, text, diags, {path, 0, 0})) return {};
    return load_pipeline_text(text, path, registry, options, diags);
}

namespace {

// The use node directly holding `name` among `uses` below `prefix` ("" at the top), or -1.
int owning_use(const Plan& plan, const std::string& name, const std::string& prefix) {
    int best = -1;
    for (std::size_t u = 0; u < plan.uses.size(); ++u) {
        const std::string up = plan.uses[u].name + "/";
        if (name.rfind(up, 0) != 0 || up.size() <= prefix.size() || up.rfind(prefix, 0) != 0) continue;
        if (best < 0 || up.size() < plan.uses[static_cast<std::size_t>(best)].name.size() + 1) best = static_cast<int>(u);
    }
    return best;
}

// The nodes outside loop bodies whose innermost scope is `prefix`; each use below it as a cluster.
void dot_scope(std::ostringstream& o, const Plan& plan, const std::string& prefix, const std::string& indent) {
    auto id = [](const std::string& s) { return "\"" + s + "\""; };
    for (std::size_t u = 0; u < plan.uses.size(); ++u) {
        const PlanUse& use = plan.uses[u];
        if (use.name.rfind(prefix, 0) != 0 || owning_use(plan, use.name + "/", prefix) != static_cast<int>(u)) continue;
        o << indent << "subgraph " << id("cluster_use_" + use.name) << " {\n" << indent << "  label=" << id("use " + use.name + " (" + use.file + ")")
          << ";\n" << indent << "  style=dashed;\n";
        dot_scope(o, plan, use.name + "/", indent + "  ");
        o << indent << "}\n";
    }
    for (std::size_t i = 0; i < plan.nodes.size(); ++i) {
        const PlanNode& p = plan.nodes[i];
        if (p.body_of >= 0 || p.name.rfind(prefix, 0) != 0 || owning_use(plan, p.name, prefix) >= 0) continue;
        if (p.is_loop()) {
            o << indent << "subgraph " << id("cluster_" + p.name) << " {\n" << indent << "  label=" << id("loop " + p.name + " (max " + std::to_string(p.max_iterations) + ")") << ";\n" << indent << "  style=rounded;\n";
            o << indent << "  " << id(p.name) << " [shape=diamond, label=" << id(p.name) << "];\n";
            for (const auto& q : plan.nodes)
                if (q.body_of == static_cast<int>(i)) o << indent << "  " << id(q.name) << " [label=" << id(q.name + "\\n" + q.type->name()) << "];\n";
            o << indent << "}\n";
        } else {
            o << indent << id(p.name) << " [label=" << id(p.name + "\\n" + p.type->name()) << (p.streamed_by >= 0 ? ", style=dashed" : "") << "];\n";
        }
    }
}

}  // namespace

std::string to_dot(const Plan& plan) {
    std::ostringstream o;
    auto id = [](const std::string& s) { return "\"" + s + "\""; };
    o << "digraph pipeline {\n  rankdir=LR;\n  node [shape=box, fontname=\"Helvetica\"];\n";
    dot_scope(o, plan, "", "  ");
    for (const auto& p : plan.nodes) {
        for (const auto& in : p.inputs) {
            std::string label = in.source_port + " -> " + in.port;
            if (in.kind == SourceKind::LoopEach) label = "each." + label;
            if (in.kind == SourceKind::LoopFinal) label = "final." + label;
            o << "  " << id(plan.nodes[in.source].name) << " -> " << id(p.name) << " [label=" << id(label) << "];\n";
        }
        for (const auto& in : p.loop_init)
            o << "  " << id(plan.nodes[in.source].name) << " -> " << id(p.name) << " [label=" << id("init " + in.port) << "];\n";
        for (const auto& in : p.loop_next)
            o << "  " << id(plan.nodes[in.source].name) << " -> " << id(p.name) << " [label=" << id("next " + in.port) << ", style=dotted, constraint=false];\n";
        if (p.loop_while)
            o << "  " << id(plan.nodes[p.loop_while->source].name) << " -> " << id(p.name) << " [label=\"while\", style=dotted, constraint=false];\n";
    }
    o << "}\n";
    return o.str();
}

}  // namespace cf::graph
