#include "runtime/report.hpp"

#include "graph/json_writer.hpp"
#include "runtime/heap_description.hpp"
#include "runtime/run_profile.hpp"

#include <Eigen/Core>
#include <openvdb/version.h>
#include <tbb/version.h>

#include <algorithm>
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

// The counts of run r of a node (per-iteration nodes keep one set per run).
static const std::map<std::string, double>& run_counts(const graph::NodeStats& s, std::size_t r) {
    return s.iteration_counts.empty() ? s.counts : s.iteration_counts[std::min(r, s.iteration_counts.size() - 1)];
}

static double count_or(const std::map<std::string, double>& c, const std::string& k) {
    auto it = c.find(k);
    return it == c.end() ? 0.0 : it->second;
}

// A digest for people and scripts: seconds per node type, iterations per loop and, for fracture
// pipelines, the figures of a thesis table row (BEM steps, elements at the first and last
// assembly, cracks initiated, fragments) and the markers stopped by each test of fig. 27. Taken
// from the nodes' own counts.
static void write_summary(graph::JsonWriter& w, const graph::Plan& plan, const graph::ExecutionResult& result,
                          const std::vector<std::string>& notes) {
    std::map<std::string, double> stage_seconds;
    std::map<std::string, int> loops;
    int steps = 0;
    double cracks = -1, fragments = -1;
    // Markers stopped by each geometry test of fig. 27, summed over all propagate runs: where a
    // run stalls, these say why (surface reached, another crack, self-intersection eq. 6.2).
    std::map<std::string, double> stops;
    // First and last assembly in time: (start of the run, elements), (end of the run, elements).
    double first_t = 1e300, last_t = -1, first_n = 0, last_n = 0;
    // BEM step at which crack growth became estimated (assemble.sgbem method estimator / hybrid), -1: never.
    double switch_step = -1;
    // Rigid-body scenes: Table 3's figures, from export.animation (the runs are in fracture_runs.json).
    const std::map<std::string, double>* scene = nullptr;
    for (std::size_t i = 0; i < plan.nodes.size(); ++i) {
        const graph::NodeStats& s = result.stats[i];
        if (plan.nodes[i].is_loop()) {
            loops[plan.nodes[i].name] = s.runs;
            continue;
        }
        stage_seconds[s.type] += s.wall_seconds;
        for (std::size_t r = 0; r < std::size_t(s.runs); ++r) {
            const auto& c = run_counts(s, r);
            if (c.count("cracks_initiated")) cracks = std::max(cracks, c.at("cracks_initiated"));
            if (s.type == "assemble.sgbem" && c.count("switched_to_estimator")) switch_step = count_or(c, "switch_step");
            if (s.type == "assemble.sgbem" && r < s.intervals.size()) {
                const double n = count_or(c, "triangles") + count_or(c, "crack_triangles");
                if (s.intervals[r].first < first_t) first_t = s.intervals[r].first, first_n = n;
                if (s.intervals[r].second > last_t) last_t = s.intervals[r].second, last_n = n;
            }
        }
        if (s.type == "propagate.fronts") {
            steps += s.runs;
            for (std::size_t r = 0; r < std::size_t(s.runs); ++r) {
                const auto& c = run_counts(s, r);
                stops["left_object"] += count_or(c, "hits_left_object");
                stops["crossed_crack"] += count_or(c, "hits_crossed_crack");
                stops["self_intersection"] += count_or(c, "hits_self_intersection");
            }
        }
        if (s.type == "segment.fragments" && s.runs > 0) fragments = count_or(s.counts, "fragments");
        if (s.type == "export.animation" && s.runs > 0) scene = &s.counts;
    }
    w.key("summary").begin_object();
    w.key("stage_seconds");
    write_counts(w, stage_seconds);
    w.key("loop_iterations").begin_object();
    for (const auto& [k, v] : loops) w.key(k).value(static_cast<long long>(v));
    w.end_object();
    if (last_t >= 0 || steps > 0 || fragments >= 0) {
        w.key("fracture").begin_object();
        w.key("bem_steps").value(static_cast<long long>(steps));
        if (last_t >= 0) {
            w.key("elements_start").value(static_cast<long long>(first_n));
            w.key("elements_end").value(static_cast<long long>(last_n));
        }
        if (cracks >= 0) w.key("cracks_initiated").value(static_cast<long long>(cracks));
        if (switch_step >= 0) w.key("switch_step").value(static_cast<long long>(switch_step));
        if (fragments >= 0) w.key("fragments").value(static_cast<long long>(fragments));
        if (!stops.empty()) {
            w.key("markers_stopped").begin_object();
            for (const auto& [k, v] : stops) w.key(k).value(static_cast<long long>(v));
            w.end_object();
        }
        w.end_object();
    }
    // What the counts suggest changing (runtime/run_notes; crackflow run prints the same lines).
    w.key("notes").begin_array();
    for (const std::string& n : notes) w.value(n);
    w.end_array();
    // What bounded the wall time (crackflow run --profile prints it with the split per type).
    const RunProfile profile = run_profile(plan, result);
    w.key("critical_path_seconds").value(profile.critical_seconds);
    w.key("critical_path").begin_array();
    for (const CriticalNode& c : profile.critical_path) {
        w.begin_object();
        w.key("node").value(c.node);
        w.key("type").value(c.type);
        w.key("runs").value(static_cast<long long>(c.runs));
        w.key("seconds").value(c.seconds);
        w.end_object();
    }
    w.end_array();
    if (scene) {
        w.key("scene").begin_object();
        for (const char* k : {"frames", "pieces", "fracture_runs", "breaks", "failed_runs", "largest_bem_triangles",
                              "rigid_seconds", "fracture_seconds"}) {
            const double v = count_or(*scene, k);
            if (std::string(k).find("seconds") != std::string::npos) w.key(k).value(v);
            else w.key(k).value(static_cast<long long>(v));
        }
        w.key("pieces_by_class").begin_object();
        for (const char* k : {"original", "hull", "mesh", "breakable", "large"})
            w.key(k).value(static_cast<long long>(count_or(*scene, std::string("pieces_") + k)));
        w.end_object();
        w.end_object();
    }
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
    w.key("allocator").value(heap_description());
    w.end_object();
    w.key("wall_seconds").value(result.wall_seconds);
    if (result.stats.size() == plan.nodes.size()) write_summary(w, plan, result, ctx.notes);
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
