#include "graph/executor.hpp"

#include "graph/run_node.hpp"

#include <tbb/flow_graph.h>
#include <tbb/task_group.h>

#include <chrono>
#include <exception>
#include <memory>
#include <mutex>
#include <sys/resource.h>

namespace cf::graph {

namespace {

using Clock = std::chrono::steady_clock;

struct Packet {
    int slot = -1;       // consumer's input slot; -1 starts a node with no inputs
    Value value;
    int iteration = -1;  // -1: a value that holds for the whole run
};

struct Route {
    int consumer;
    int slot;
};

long long peak_rss_bytes() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<long long>(u.ru_maxrss) * 1024;
}

class Execution {
public:
    Execution(const Plan& plan, const RunOptions& options, ExecutionObserver* observer)
        : plan_(plan), options_(options), observer_(observer), n_(static_cast<int>(plan.nodes.size())) {
        cancel_ = options.cancel_flag ? options.cancel_flag : &own_cancel_;
        node_options_ = options;
        node_options_.cancel_flag = cancel_;
        if (node_options_.pipeline_dir.empty() && !plan.file.empty())
            node_options_.pipeline_dir = std::filesystem::absolute(std::filesystem::path(plan.file)).parent_path();
        if (!node_options_.registry) node_options_.registry = plan.registry;
        result_.stats.resize(n_);
        state_.resize(n_);
        routes_.resize(n_);
        loop_var_routes_.resize(n_);
        for (int i = 0; i < n_; ++i) build_routes(i);
        for (int i = 0; i < n_; ++i) {
            const PlanNode& p = plan_.nodes[i];
            result_.stats[i].name = p.name;
            result_.stats[i].type = p.is_loop() ? "loop" : p.type->name();
            NodeState& s = state_[i];
            const std::size_t slots = p.is_loop() ? 2 * p.loop_vars.size() + 1 : p.inputs.size();
            s.constants.resize(slots);
            s.have_constant.assign(slots, 0);
            s.per_iteration_slot.assign(slots, 0);
            if (p.is_loop()) {
                for (std::size_t k = p.loop_vars.size(); k < slots; ++k) s.per_iteration_slot[k] = 1;
                if (!p.loop_while) s.have_constant[slots - 1] = 1;  // no 'while': always continue
            } else {
                for (std::size_t k = 0; k < p.inputs.size(); ++k) s.per_iteration_slot[k] = is_per_iteration(p.inputs[k]);
            }
            nodes_.push_back(std::make_unique<tbb::flow::function_node<Packet, tbb::flow::continue_msg>>(
                graph_, tbb::flow::serial, [this, i](const Packet& pk) {
                    receive(i, pk);
                    return tbb::flow::continue_msg();
                }));
        }
    }

    ExecutionResult run() {
        start_ = Clock::now();
        for (int i = 0; i < n_; ++i)
            if (!plan_.nodes[i].is_loop() && plan_.nodes[i].inputs.empty()) nodes_[i]->try_put(Packet{});
        graph_.wait_for_all();
        result_.wall_seconds = seconds_since_start();
        if (!result_.error.empty()) {
            result_.ok = false;
        } else if (cancelled()) {
            result_.cancelled = true;
            result_.ok = false;
        } else {
            result_.ok = true;
        }
        return std::move(result_);
    }

private:
    struct NodeState {
        std::vector<Value> constants;
        std::vector<char> have_constant;
        std::vector<char> per_iteration_slot;
        std::map<int, std::vector<Value>> iteration_values;
        std::map<int, std::vector<char>> iteration_have;
        bool done_once = false;  // constant-scope node ran / loop started
    };

    bool is_per_iteration(const PlanInput& in) const {
        switch (in.kind) {
            case SourceKind::LoopVariable:
            case SourceKind::LoopIteration:
            case SourceKind::LoopEach: return true;
            case SourceKind::LoopFinal: return false;
            case SourceKind::NodeOutput: return plan_.nodes[in.source].per_iteration();
        }
        return false;
    }

    // routes_[source][port] -> consumers of an ordinary node's output;
    // loop_var_routes_[loop][kind:var] -> consumers of the loop's values.
    void build_routes(int i) {
        const PlanNode& p = plan_.nodes[i];
        auto add = [&](const PlanInput& in, int slot) {
            if (in.kind == SourceKind::NodeOutput) routes_[in.source][in.source_port].push_back({i, slot});
            else loop_var_routes_[in.source][key(in.kind, in.source_port)].push_back({i, slot});
        };
        if (p.is_loop()) {
            const int v = static_cast<int>(p.loop_vars.size());
            for (const auto& in : p.loop_init) add(in, var_index(p, in.port));
            for (const auto& in : p.loop_next) add(in, v + var_index(p, in.port));
            if (p.loop_while) add(*p.loop_while, 2 * v);
        } else {
            for (std::size_t k = 0; k < p.inputs.size(); ++k) add(p.inputs[k], static_cast<int>(k));
        }
    }
    static int var_index(const PlanNode& loop, const std::string& var) {
        for (std::size_t k = 0; k < loop.loop_vars.size(); ++k)
            if (loop.loop_vars[k] == var) return static_cast<int>(k);
        return -1;
    }
    static std::string key(SourceKind kind, const std::string& var) {
        switch (kind) {
            case SourceKind::LoopVariable: return "var:" + var;
            case SourceKind::LoopIteration: return "iteration";
            case SourceKind::LoopEach: return "each:" + var;
            case SourceKind::LoopFinal: return "final:" + var;
            default: return var;
        }
    }

    double seconds_since_start() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

    void send(const std::vector<Route>& routes, const Value& v, int iteration) {
        for (const Route& r : routes) nodes_[r.consumer]->try_put(Packet{r.slot, v, iteration});
    }

    void fail(int i, const std::string& message) {
        std::lock_guard<std::mutex> lock(error_mutex_);
        if (result_.error.empty()) {
            const PlanNode& p = plan_.nodes[i];
            result_.failed_node = p.name;
            result_.error = "node '" + p.name + "' (" + (p.is_loop() ? std::string("loop") : p.type->name()) + "): " + message;
        }
        cancel_->store(true);
        graph_.cancel();
    }

    // Called serially per node.
    void receive(int i, const Packet& pk) {
        if (cancelled()) return;
        NodeState& s = state_[i];
        const PlanNode& p = plan_.nodes[i];
        if (pk.slot >= 0) {
            if (pk.iteration < 0) {
                s.constants[pk.slot] = pk.value;
                s.have_constant[pk.slot] = 1;
            } else {
                auto& vals = s.iteration_values[pk.iteration];
                auto& have = s.iteration_have[pk.iteration];
                if (vals.empty()) vals.resize(s.constants.size()), have.assign(s.constants.size(), 0);
                vals[pk.slot] = pk.value;
                have[pk.slot] = 1;
            }
        }
        if (p.is_loop()) return loop_step(i);
        if (!p.per_iteration()) {
            if (s.done_once) return;
            for (std::size_t k = 0; k < s.constants.size(); ++k) if (!s.have_constant[k]) return;
            s.done_once = true;
            run_plain(i, s.constants, -1);
            return;
        }
        for (std::size_t k = 0; k < s.constants.size(); ++k)
            if (!s.per_iteration_slot[k] && !s.have_constant[k]) return;
        for (auto it = s.iteration_have.begin(); it != s.iteration_have.end();) {
            bool complete = true;
            for (std::size_t k = 0; k < s.constants.size(); ++k)
                if (s.per_iteration_slot[k] && !it->second[k]) complete = false;
            if (!complete) { ++it; continue; }
            const int iteration = it->first;
            std::vector<Value> inputs = s.iteration_values[iteration];
            for (std::size_t k = 0; k < s.constants.size(); ++k)
                if (!s.per_iteration_slot[k]) inputs[k] = s.constants[k];
            s.iteration_values.erase(iteration);
            it = s.iteration_have.erase(it);
            run_plain(i, inputs, iteration);
            if (cancelled()) return;
        }
    }

    void run_plain(int i, const std::vector<Value>& values, int iteration) {
        const PlanNode& p = plan_.nodes[i];
        std::map<std::string, Value> inputs;
        for (std::size_t k = 0; k < p.inputs.size(); ++k) inputs[p.inputs[k].port] = values[k];
        if (observer_) observer_->node_started(p.name, iteration);
        const double t0 = seconds_since_start();
        NodeResult r;
        try {
            // The node's own parallel loops run in an isolated context: cancelling the flow graph
            // (another node failed, or Ctrl-C) must not cut a running node's parallel_for short, which
            // would leave its arrays half computed while it goes on using them. A long node notices
            // the cancellation through check_cancelled() and stops cleanly instead.
            tbb::task_group_context isolated(tbb::task_group_context::isolated);
            tbb::task_group group(isolated);
            std::exception_ptr error;
            group.run_and_wait([&] {
                try {
                    // Algorithms the node calls poll this token (graph/cancel_token.hpp).
                    const CancelScope scope(CancelToken(node_options_.cancel_flag, node_options_.outer_cancel_flag));
                    r = run_node(*p.type, p.params, inputs, node_options_, p.name, iteration);
                } catch (...) {
                    error = std::current_exception();
                }
            });
            if (error) std::rethrow_exception(error);
        } catch (const Cancelled&) {
            cancel_->store(true);
            graph_.cancel();
            return;
        } catch (const std::exception& e) {
            // A node that wraps every exception into its own message turns a Cancelled thrown in its
            // algorithm into a failure "...: cancelled"; once the run is cancelled, it is a stop.
            if (!cancelled()) fail(i, e.what());
            else graph_.cancel();
            return;
        }
        const double t1 = seconds_since_start();
        NodeStats& st = result_.stats[i];
        st.runs++;
        st.wall_seconds += t1 - t0;
        // Per-run records are kept for the first kMaxRecordedRuns runs only, so a loop with
        // max_iterations 1e9 does not grow by ~170 bytes per iteration; later runs are counted
        // in runs and wall_seconds.
        const bool record = st.runs <= kMaxRecordedRuns;
        if (record) st.intervals.emplace_back(t0, t1);
        st.counts = r.counts;
        if (record && p.per_iteration()) {  // per-step figures of a loop (e.g. a fracture step's time split)
            auto counts = r.counts;
            counts["wall_seconds"] = t1 - t0;
            st.iteration_counts.push_back(std::move(counts));
        }
        st.peak_rss_bytes = peak_rss_bytes();
        if (options_.keep_outputs) {
            std::lock_guard<std::mutex> lock(outputs_mutex_);
            for (const auto& [port, v] : r.outputs) result_.outputs[p.name][port] = v;
        }
        if (observer_) observer_->node_finished(p.name, iteration, t1 - t0);
        if (cancelled()) return;
        const int out_iteration = p.per_iteration() ? iteration : -1;
        for (const auto& [port, v] : r.outputs) {
            auto it = routes_[i].find(port);
            if (it != routes_[i].end()) send(it->second, v, out_iteration);
        }
    }

    void emit_iteration(int i, const std::vector<Value>& vars, int iteration) {
        const PlanNode& p = plan_.nodes[i];
        auto& lr = loop_var_routes_[i];
        for (std::size_t k = 0; k < p.loop_vars.size(); ++k) {
            auto it = lr.find(key(SourceKind::LoopVariable, p.loop_vars[k]));
            if (it != lr.end()) send(it->second, vars[k], iteration);
        }
        auto it = lr.find("iteration");
        if (it != lr.end()) send(it->second, Value::of<long long>(iteration), iteration);
        if (observer_) observer_->node_started(p.name, iteration);
    }

    void loop_step(int i) {
        NodeState& s = state_[i];
        const PlanNode& p = plan_.nodes[i];
        const std::size_t v = p.loop_vars.size();
        if (!s.done_once) {
            for (std::size_t k = 0; k < v; ++k) if (!s.have_constant[k]) return;
            s.done_once = true;
            result_.stats[i].intervals.emplace_back(seconds_since_start(), 0);
            emit_iteration(i, std::vector<Value>(s.constants.begin(), s.constants.begin() + v), 0);
        }
        for (auto it = s.iteration_have.begin(); it != s.iteration_have.end();) {
            bool complete = true;
            for (std::size_t k = v; k < 2 * v + 1; ++k)
                if (!it->second[k] && !(k == 2 * v && !p.loop_while)) complete = false;
            if (!complete) { ++it; continue; }
            const int iteration = it->first;
            const auto& vals = s.iteration_values[iteration];
            std::vector<Value> next(vals.begin() + v, vals.begin() + 2 * v);
            const bool go_on = p.loop_while ? vals[2 * v].get<bool>() : true;
            NodeStats& st = result_.stats[i];
            st.runs = iteration + 1;
            auto& lr = loop_var_routes_[i];
            for (std::size_t k = 0; k < v; ++k) {
                auto e = lr.find(key(SourceKind::LoopEach, p.loop_vars[k]));
                if (e != lr.end()) send(e->second, next[k], iteration);
                if (options_.keep_outputs) {
                    std::lock_guard<std::mutex> lock(outputs_mutex_);
                    result_.outputs[p.name][p.loop_vars[k]] = next[k];
                }
            }
            if (observer_) observer_->node_finished(p.name, iteration, 0);
            const bool last = !go_on || iteration + 1 >= p.max_iterations;
            s.iteration_values.erase(iteration);
            it = s.iteration_have.erase(it);
            if (last) {
                st.counts["iterations"] = iteration + 1;
                st.peak_rss_bytes = peak_rss_bytes();
                st.counts["stopped_by_while"] = go_on ? 0 : 1;
                if (!st.intervals.empty()) {
                    st.intervals.back().second = seconds_since_start();
                    st.wall_seconds = st.intervals.back().second - st.intervals.back().first;
                }
                for (std::size_t k = 0; k < v; ++k) {
                    auto f = lr.find(key(SourceKind::LoopFinal, p.loop_vars[k]));
                    if (f != lr.end()) send(f->second, next[k], -1);
                }
            } else {
                emit_iteration(i, next, iteration + 1);
            }
        }
    }

    const Plan& plan_;
    RunOptions options_;
    RunOptions node_options_;
    ExecutionObserver* observer_;
    const int n_;
    // Cancelled by a failure or Ctrl-C here, or by the run that started this one (a sub-pipeline
    // stops with its caller, but its own failure does not cancel the caller).
    bool cancelled() const {
        return cancel_->load() || (options_.outer_cancel_flag && options_.outer_cancel_flag->load());
    }
    std::atomic<bool> own_cancel_{false};
    std::atomic<bool>* cancel_;
    tbb::flow::graph graph_;
    std::vector<std::unique_ptr<tbb::flow::function_node<Packet, tbb::flow::continue_msg>>> nodes_;
    std::vector<NodeState> state_;
    std::vector<std::map<std::string, std::vector<Route>>> routes_;
    std::vector<std::map<std::string, std::vector<Route>>> loop_var_routes_;
    ExecutionResult result_;
    std::mutex error_mutex_, outputs_mutex_;
    Clock::time_point start_;
};

}  // namespace

ExecutionResult execute(const Plan& plan, const RunOptions& options, ExecutionObserver* observer) {
    Execution e(plan, options, observer);
    return e.run();
}

}  // namespace cf::graph
