#include "runtime/report.hpp"

#include "graph/json_writer.hpp"

#include <Eigen/Core>
#include <openvdb/version.h>
#include <tbb/version.h>

#include <ctime>
#include <sys/resource.h>

#ifndef CRACKFLOW_VERSION
#define CRACKFLOW_VERSION "dev"
#endif

namespace cf::runtime {

static void write_param(graph::JsonWriter& w, const graph::ParamValue& v) {
    if (auto b = std::get_if<bool>(&v)) w.value(*b);
    else if (auto i = std::get_if<long long>(&v)) w.value(*i);
    else if (auto d = std::get_if<double>(&v)) w.value(*d);
    else if (auto s = std::get_if<std::string>(&v)) w.value(*s);
    else {
        w.begin_array();
        for (double x : std::get<std::vector<double>>(v)) w.value(x);
        w.end_array();
    }
}

static void write_counts(graph::JsonWriter& w, const std::map<std::string, double>& counts) {
    w.begin_object();
    for (const auto& [k, v] : counts) w.key(k).value(v);
    w.end_object();
}

std::string report_json(const graph::Plan& plan, const graph::ExecutionResult& result, const ReportContext& ctx) {
    graph::JsonWriter w;
    char when[32];
    std::time_t now = std::time(nullptr);
    std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    w.begin_object();
    w.key("crackflow_version").value(CRACKFLOW_VERSION);
    w.key("pipeline").value(ctx.pipeline_file);
    w.key("finished_utc").value(when);
    w.key("status").value(result.ok ? "ok" : result.cancelled ? "cancelled" : "failed");
    if (!result.error.empty()) w.key("error").value(result.error);
    w.key("fast").value(ctx.fast);
    w.key("threads").value(ctx.threads);
    w.key("overrides").begin_array();
    for (const auto& o : ctx.overrides) w.value(o);
    w.end_array();
    w.key("versions").begin_object();
    w.key("eigen").value(std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
                         std::to_string(EIGEN_MINOR_VERSION));
    w.key("onetbb").value(TBB_VERSION_STRING);
    w.key("openvdb").value(OPENVDB_LIBRARY_VERSION_STRING);
    w.end_object();
    w.key("wall_seconds").value(result.wall_seconds);
    w.key("peak_rss_bytes").value(static_cast<long long>(u.ru_maxrss) * 1024);
    w.key("nodes").begin_array();
    for (std::size_t i = 0; i < plan.nodes.size(); ++i) {
        const auto& p = plan.nodes[i];
        const auto& s = result.stats[i];
        w.begin_object();
        w.key("name").value(p.name);
        w.key("type").value(s.type);
        if (p.body_of >= 0) w.key("loop").value(plan.nodes[p.body_of].name);
        w.key("params").begin_object();
        if (p.is_loop()) w.key("max_iterations").value(p.max_iterations);
        for (const auto& [k, v] : p.params) {
            w.key(k);
            write_param(w, v);
        }
        w.end_object();
        w.key("runs").value(s.runs);
        w.key("wall_seconds").value(s.wall_seconds);
        w.key("peak_rss_bytes").value(s.peak_rss_bytes);
        w.key("counts");
        write_counts(w, s.counts);
        if (!s.iteration_counts.empty()) {
            w.key("iteration_counts").begin_array();
            for (const auto& c : s.iteration_counts) write_counts(w, c);
            w.end_array();
        }
        w.end_object();
    }
    w.end_array();
    w.end_object();
    return w.str() + "\n";
}

}  // namespace cf::runtime
