#pragma once
// What a node's run function sees: its typed inputs, validated parameters, and ways to emit
// outputs, report counts, show progress and notice cancellation.
#include "graph/cancel_token.hpp"
#include "graph/node_type.hpp"
#include "graph/registry.hpp"

#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>

namespace cf::graph {

// Thrown by a node for bad input; the executor reports it once, prefixed with the node name.
struct NodeError : std::runtime_error {
    using std::runtime_error::runtime_error;
};
// Thrown when the run was cancelled (Ctrl-C or another node failed); see graph/cancel_token.hpp.
using Cancelled = cf::Cancelled;

struct RunOptions {
    std::filesystem::path output_dir = ".";
    bool fast = false;  // reduced resolution for tests (nodes may lower their defaults)
    std::atomic<bool>* cancel_flag = nullptr;  // set by Ctrl-C handlers; the executor sets it on failure too
    const std::atomic<bool>* outer_cancel_flag = nullptr;  // read only: the calling run's flag (sub-pipelines)
    std::function<void(const std::string& node, double fraction)> on_progress;
    // Keep the last value of every output port in ExecutionResult::outputs (tests and verification
    // cases read them). `crackflow run` turns it off so a value is freed once its consumers are done
    // (the last BEM step's dense blocks during segmentation, for instance).
    bool keep_outputs = true;
    // Absolute output paths are accepted (library callers, tests); `crackflow run` refuses them
    // unless given --allow-absolute-paths, so that every output lands inside --out.
    bool allow_absolute_paths = true;
    // Set by the executor from the plan when empty: the directory of the pipeline file (relative
    // paths of sub-pipelines resolve against it) and the registry the plan was loaded with.
    std::filesystem::path pipeline_dir;
    const NodeRegistry* registry = nullptr;
    // Values a calling node hands to a pipeline it runs (a sub-pipeline), by name; nodes of that
    // pipeline read them with NodeContext::pipeline_input (the rigid-body scene passes each
    // collision's body and loads to its fracture pipeline this way).
    std::map<std::string, Value> pipeline_inputs;
};

class NodeContext {
public:
    NodeContext(const NodeType& type, std::string node_name, std::map<std::string, ParamValue> params,
                std::map<std::string, Value> inputs, const RunOptions& options, int iteration = -1)
        : type_(type), name_(std::move(node_name)), params_(std::move(params)), inputs_(std::move(inputs)),
          options_(options), iteration_(iteration) {}

    // Inputs.
    bool has(std::string_view port) const { return inputs_.count(std::string(port)) > 0; }
    template <class T>
    const T& in(std::string_view port) const { return input_value(port).get<T>(); }
    template <class T>
    std::shared_ptr<const T> in_ptr(std::string_view port) const { return input_value(port).ptr<T>(); }
    const Value& input_value(std::string_view port) const;

    // Outputs (every declared output must be set before run returns).
    template <class T>
    void out(std::string_view port, T value) { set_output(port, Value::of<T>(std::move(value))); }
    template <class T>
    void out_shared(std::string_view port, std::shared_ptr<const T> p) { set_output(port, Value::shared<T>(std::move(p))); }
    void set_output(std::string_view port, Value v);

    // Parameters (already validated against their declarations; defaults filled in).
    bool boolean(std::string_view n) const { return std::get<bool>(param(n)); }
    long long integer(std::string_view n) const { return std::get<long long>(param(n)); }
    double real(std::string_view n) const { return std::get<double>(param(n)); }
    const std::string& string(std::string_view n) const { return std::get<std::string>(param(n)); }
    const std::vector<double>& reals(std::string_view n) const { return std::get<std::vector<double>>(param(n)); }
    const ParamValue& param(std::string_view n) const;

    // Reporting: counts go into report.json under this node.
    void count(const std::string& key, double value) { counts_[key] = value; }
    void progress(double fraction) const {
        if (options_.on_progress) options_.on_progress(name_, fraction);
    }
    // Long loops call this now and then; throws Cancelled after Ctrl-C or a failure elsewhere.
    void check_cancelled() const { cancel_token().poll(); }
    // The same check for plain algorithms (they take the token, not the context).
    CancelToken cancel_token() const { return CancelToken(options_.cancel_flag, options_.outer_cancel_flag); }
    // Throws NodeError with the message; the executor prefixes the node name.
    [[noreturn]] void fail(const std::string& message) const { throw NodeError(message); }

    const std::string& node_name() const { return name_; }
    const NodeType& type() const { return type_; }
    const std::filesystem::path& output_dir() const { return options_.output_dir; }
    const RunOptions& run_options() const { return options_; }
    // A value handed in by the node that runs this pipeline; null when there is none.
    const Value* pipeline_input(const std::string& name) const {
        const auto it = options_.pipeline_inputs.find(name);
        return it == options_.pipeline_inputs.end() ? nullptr : &it->second;
    }
    bool fast() const { return options_.fast; }
    int iteration() const { return iteration_; }  // loop iteration, -1 outside loops
    // A path parameter with '{iteration}' replaced by the loop iteration (4 digits, 0 outside
    // loops) and made absolute against the output directory; per-step files land side by side.
    std::filesystem::path output_path(const std::string& pattern) const;

    const std::map<std::string, Value>& outputs() const { return outputs_; }
    const std::map<std::string, double>& counts() const { return counts_; }

private:
    const NodeType& type_;
    std::string name_;
    std::map<std::string, ParamValue> params_;
    std::map<std::string, Value> inputs_;
    std::map<std::string, Value> outputs_;
    std::map<std::string, double> counts_;
    const RunOptions& options_;
    int iteration_;
};

}  // namespace cf::graph
