#pragma once
// The pipeline loader's internals (graph/pipeline.cpp: the passes; graph/subpipeline.cpp: `use`
// nodes; graph/pipeline_overrides.cpp: fast:, --set and input paths). Not a public interface:
// everything outside graph/ goes through graph/pipeline.hpp.
#include "graph/loop_type.hpp"
#include "graph/pipeline.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace cf::graph::detail {

inline constexpr const char* kLoopType = kLoopTypeName;
inline constexpr const char* kUseType = "use";
// Inside a sub-pipeline, `input.PORT` reads what the using node connects to PORT.
inline constexpr const char* kInputNode = "input";

// One pipeline file as read: the top file (scope 0) or one use of a sub-pipeline. Node names of a
// used file get the use node's name and '/' in front (`fracture/solve0`), so a file can be used
// twice and every node keeps one global name (report.json, --set, the executor).
struct Scope {
    std::string file;                  // as given (the top file) or as resolved from the using file
    std::filesystem::path dir;         // the file's directory: relative input paths start here
    std::string prefix;                // "" or "NAME/" ("OUTER/NAME/" when nested)
    int parent = -1;
    std::string via;                   // "used at FILE:LINE:COL (node 'NAME')" chain, for diagnostics
    // Declared interface (sub-pipelines only).
    bool is_sub = false;
    struct Param {
        std::vector<std::pair<std::string, std::string>> targets;  // (node, param) in this file's names
        std::string doc;
        SourceLoc loc;
    };
    std::map<std::string, Param> params;
    std::vector<std::string> param_order;
    std::map<std::string, std::string> input_types;  // declared input -> type name
    std::set<std::string> optional_inputs;           // may stay unconnected: input.NAME is then left out
    std::vector<std::string> input_order;
    std::map<std::string, std::pair<YAML::Node, SourceLoc>> outputs;  // name -> (NODE.PORT in this file, where)
    std::vector<std::string> output_order;
    // What the using node connects to each declared input: the source text in the parent's names.
    std::map<std::string, YAML::Node> wired;
    YAML::Node fast;  // the file's own fast: section (applied before the using file's with --fast)
};

// A `use` node: expanded into its file's nodes, kept for references to its outputs and overrides
// of its parameters.
struct UseNode {
    std::string name;  // global
    SourceLoc loc;
    int scope = -1;    // the used file's scope
    int parent = -1;   // the scope the use node is written in
};

// A node entry as written, before type checking.
struct RawNode {
    std::string name;
    SourceLoc loc;
    std::string type;
    SourceLoc type_loc;
    int scope = 0;  // the file it is written in
    struct Param {
        std::string name;
        YAML::Node value;
        SourceLoc key_loc, value_loc;  // overrides carry their own (--set or the fast: entry)
        int scope = 0;                 // where the value was written (-1: the command line), for input paths
    };
    std::vector<Param> params;  // in file order; overrides replace
    std::vector<std::pair<std::string, YAML::Node>> inputs;
    std::vector<std::pair<std::string, YAML::Node>> next;
    YAML::Node while_node;
    bool has_while = false;
    int body_of = -1;  // raw index of the loop holding this node
};

class Loader {
public:
    Loader(std::string file, const NodeRegistry& reg, std::vector<Diagnostic>& diags);

    SourceLoc loc(const YAML::Node& n) const { return loc_in(n, scope_); }
    SourceLoc loc_in(const YAML::Node& n, int scope) const;
    void error(const SourceLoc& l, std::string msg, std::string hint = "") {
        diags_.push_back({l, std::move(msg), std::move(hint)});
    }

    Plan load(const YAML::Node& root, const LoadOptions& options);

private:
    // The steps of load(), in order.
    bool read_top_level(const YAML::Node& root, YAML::Node& nodes, YAML::Node& fast, bool& has_fast, int scope);  // false: fatal
    void apply_overrides(const YAML::Node& fast, bool has_fast, const LoadOptions& options);
    void plan_types_and_params();
    void resolve_input_paths();
    void resolve_loop_variables();
    void resolve_inputs();
    void resolve_loop_next_and_while();
    // Every body node must depend on a per-iteration value, or it would never know when to run.
    void check_body_nodes_vary();
    // Topological order, file order among ready nodes; empty after reporting a cycle.
    std::vector<int> dependency_order();
    // A node fed by LOOP.each runs once per iteration; so do its consumers.
    void mark_streamed_nodes(const std::vector<int>& order);
    // Stable plan indices: reorder the nodes and remap every reference.
    void emit_in_order(const std::vector<int>& order, Plan& plan);
    void read_nodes(const YAML::Node& map, int body_of);
    // read_nodes' steps: the keys of one node's mapping, and the checks of the entry as a whole
    // (false: the node is not kept).
    void read_node_keys(const YAML::Node& v, RawNode& n, YAML::Node& body, bool& has_body, bool& has_type);
    bool check_node_entry(const RawNode& n, bool has_type, bool has_body, int body_of);
    // Overrides: `fast:` entries (YAML values), --set (text for text parameters), a use node's
    // parameters. A value shared through a YAML anchor is replaced in every node sharing it.
    // value_scope: the file the value is written in (-1: the command line), for input paths.
    void apply_override(const Override& o, int value_scope);
    // NODE.PARAM = value, where NODE is a node or a use node (then each of the parameter's targets).
    void assign(const std::string& node, const std::string& param, const YAML::Node& value, const SourceLoc& l,
                int value_scope);
    void set_param(int node, const std::string& param, const YAML::Node& value, const SourceLoc& l, int value_scope);
    std::optional<YAML::Node> override_value(const Override& o, const ParamDecl* decl);
    const ParamDecl* find_decl(int node, const std::string& param) const;
    // The declaration a parameter of a node or use node ends at (the first target's), or null.
    const ParamDecl* target_decl(const std::string& node, const std::string& param, int depth = 0) const;
    std::optional<ParamValue> convert(const ParamDecl& d, const YAML::Node& v, const std::string& node, const SourceLoc& l);
    // The type's declared parameter/input rules (NodeType::input_needed_when) for node i.
    void check_input_rules(std::size_t i);
    // A node's parameters converted by its type's declarations, defaults for the rest.
    void read_params(const NodeType& t, const RawNode& r, std::map<std::string, ParamValue>& out);
    // scope: the loop whose body the reader sits in (-1 outside); -2 means the consumer's own.
    std::optional<PlanInput> resolve_source(const YAML::Node& src, int consumer, const std::string& what, int scope = -2);
    // resolve_source's two kinds of source `text` (at l, node index s): a loop's variables, a node's output.
    std::optional<PlanInput> resolve_loop_source(const SourceLoc& l, int consumer, const std::string& what, int scope, int s,
                                                 const std::string& text);
    std::optional<PlanInput> resolve_node_output(const SourceLoc& l, int consumer, const std::string& what, int scope, int s,
                                                 const std::string& text);

    // Sub-pipelines (graph/subpipeline.cpp).
    // Reads the `use` node `name` (its mapping v) of the current scope: its file's nodes join raw_.
    void expand_use(const std::string& name, const SourceLoc& name_loc, const YAML::Node& v, int body_of);
    // The file's declared parameters, inputs and outputs (top-level `parameters:`, `inputs:`, `outputs:`).
    void read_interface(const YAML::Node& root, int scope);
    // NODE.PORT as written in `scope` -> the global source text (through `input.` and use nodes'
    // outputs); nullopt after reporting why not at l.
    std::optional<std::string> globalize(const std::string& text, int scope, const SourceLoc& l, int depth = 0);
    int find_use(const std::string& global_name) const;
    // `input.NAME` of an optional input the using node leaves unconnected: the consumer's port is
    // then left unconnected too.
    bool unwired_optional(const YAML::Node& src, int scope) const;
    // After a used file's nodes are read: its parameters' targets and outputs name what it has.
    void check_interface(int scope);
    // The file's fast: entries as overrides (NODE.PARAM in the file's names).
    void fast_overrides(const YAML::Node& fast, int scope, std::vector<Override>& out);

    std::vector<std::string> all_names() const {
        std::vector<std::string> r;
        for (const auto& n : raw_) r.push_back(n.name);
        for (const auto& u : uses_) r.push_back(u.name);
        return r;
    }
    int find_raw(const std::string& name) const {
        for (std::size_t i = 0; i < raw_.size(); ++i)
            if (raw_[i].name == name) return static_cast<int>(i);
        return -1;
    }
    bool is_loop(int i) const { return raw_[i].type == kLoopType; }

    std::string file_;
    const NodeRegistry& reg_;
    std::vector<Diagnostic>& diags_;
    std::vector<RawNode> raw_;
    std::vector<PlanNode> plan_;  // same indices as raw_
    std::vector<Scope> scopes_;
    std::vector<UseNode> uses_;
    int scope_ = 0;  // the scope whose YAML loc() describes
    bool fast_ = false;
    bool require_input_files_ = true;
    std::set<std::pair<int, std::string>> input_type_reported_;
};

// Reads a pipeline file's text with the size limit (false after reporting at `at`).
bool read_pipeline_text(const std::string& path, std::string& text, std::vector<Diagnostic>& diags, const SourceLoc& at);
// Parses one YAML document (false after reporting a syntax error or several documents).
bool parse_pipeline_yaml(const std::string& text, const std::string& file_name, const std::string& via, YAML::Node& root,
                         std::vector<Diagnostic>& diags);

}  // namespace cf::graph::detail
