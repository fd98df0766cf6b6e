#include "nodes/rigid/impact_pipeline.hpp"

#include "graph/atomic_write.hpp"
#include "graph/json_writer.hpp"
#include "nodes/bem/bem_types.hpp"
#include "nodes/rigid/scene_state.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace cf::rigid {

std::shared_ptr<const graph::Plan> load_impact_pipeline(const std::filesystem::path& file,
                                                        const graph::NodeRegistry& registry) {
    std::vector<graph::Diagnostic> diags;
    auto plan = std::make_shared<graph::Plan>(
        file.empty() ? graph::load_pipeline_text(builtin_fracture_pipeline_text(), builtin_fracture_pipeline_name, registry, {}, diags)
                     : graph::load_pipeline_file(file.string(), registry, {}, diags));
    std::ostringstream problems;
    for (const graph::Diagnostic& d : diags) problems << "\n  " << graph::format(d);
    if (diags.empty()) {
        int impacts = 0, results = 0;
        for (const graph::PlanNode& n : plan->nodes) {
            if (n.is_loop()) continue;
            impacts += n.type->name() == "rigid.impact" ? 1 : 0;
            results += n.type->name() == "rigid.fragments" ? 1 : 0;
        }
        if (impacts != 1 || results != 1)
            problems << "\n  " << file.string() << ": a fracture pipeline needs exactly one rigid.impact node (the body and "
                     << "its collision loads) and one rigid.fragments node (its result); found " << impacts << " and "
                     << results;
    }
    if (!problems.str().empty())
        throw std::invalid_argument("fracture pipeline " + (file.empty() ? std::string(builtin_fracture_pipeline_name) : file.string()) +
                                    ":" + problems.str());
    return plan;
}

graph::Plan impact_plan(const graph::Plan& plan, const BreakableModel& model, long long max_steps) {
    const FractureSettings& s = *model.settings;
    graph::Plan p = plan;
    for (graph::PlanNode& n : p.nodes) {
        if (n.is_loop()) {
            n.max_iterations = std::min(n.max_iterations, max_steps);
            continue;
        }
        if (n.type->name() == "fracture.start") n.params["r_c"] = s.r_c;
        // Hexagons below the object's surface wherever the BEM surface stands off it by its remesh
        // offset and chords (a little more: sampled at element centroids, not everywhere).
        if (n.type->name() == "initiate.cracks")
            n.params["snap_distance"] = std::max(0.25 * s.r_c, 1.25 * model.bem_standoff);
        if (n.type->name() == "assemble.sgbem") {
            bool has_previous = false;
            for (const graph::PlanInput& in : n.inputs) has_previous = has_previous || in.port == "previous";
            if (!has_previous) {
                n.params["method"] = s.method;
                n.params["switch_elements"] = s.switch_elements;
            }
        }
    }
    return p;
}

namespace {

// What each node of the run counted (cracks, steps, fragments), beside the run's fragment listing.
void write_run_summary(const std::filesystem::path& path, const ImpactRun& run, const graph::ExecutionResult& r) {
    graph::JsonWriter w;
    w.begin_object().key("body").value(run.body).key("frame").value(run.frame).key("max_steps").value(run.max_steps);
    w.key("ok").value(r.ok).key("wall_seconds").value(r.wall_seconds).key("nodes").begin_object();
    for (const graph::NodeStats& st : r.stats) {
        w.key(st.name).begin_object().key("type").value(st.type).key("runs").value(st.runs);
        for (const auto& [k, v] : st.counts) w.key(k).value(v);
        w.end_object();
    }
    w.end_object().end_object();
    const std::string text = w.str() + "\n";
    graph::write_atomically(path, [&](std::ostream& os) { os << text; });
}

}  // namespace

FractureRunner pipeline_runner(const graph::RunOptions& options,
                               std::function<std::shared_ptr<const graph::Plan>(const ImpactRun&)> pipeline_of) {
    graph::RunOptions base = options;
    base.on_progress = nullptr;  // the scene's progress line stays the scene's
    base.keep_outputs = true;    // the fragments are read from the outputs
    base.pipeline_inputs.clear();
    // The run has a flag of its own (its failure must not cancel the scene) and follows the scene's.
    base.outer_cancel_flag = options.cancel_flag;
    base.cancel_flag = nullptr;
    return [base, pipeline_of](const ImpactRun& run) -> ImpactOutcome {
        const std::shared_ptr<const graph::Plan> file_plan = pipeline_of(run);
        const graph::Plan plan = impact_plan(*file_plan, *run.model, run.max_steps);
        graph::RunOptions o = base;
        o.output_dir = base.output_dir / run.output_dir;
        if (!run.model->settings->fracture_pipeline.empty())
            o.pipeline_dir = std::filesystem::path(plan.file).parent_path();
        o.registry = plan.registry;
        o.pipeline_inputs["impact"] = graph::Value::of(run);
        const graph::ExecutionResult r = graph::execute(plan, o);
        if (r.cancelled) throw graph::Cancelled();
        write_run_summary(o.output_dir / "run.json", run, r);
        if (!r.ok)
            throw std::runtime_error("fracture run of body '" + run.body + "' at frame " + std::to_string(run.frame) +
                                     " (" + plan.file + "): " + r.error);
        ImpactOutcome outcome;
        bool found = false;
        for (const graph::PlanNode& n : plan.nodes) {
            if (n.is_loop()) continue;
            auto out = r.outputs.find(n.name);
            if (out == r.outputs.end()) continue;
            if (n.type->name() == "rigid.fragments") {
                outcome.fragments = out->second.at("fragments").get<Fragments>();
                outcome.state = out->second.at("state").ptr<propagate::FractureState>();
                found = true;
            }
            // The surface blocks and factor of the run's first assembly and solve (those without
            // 'previous'), kept with the body for its next runs (ch. 7.3).
            bool has_previous = false;
            for (const graph::PlanInput& in : n.inputs) has_previous = has_previous || in.port == "previous";
            if (has_previous) continue;
            if (n.type->name() == "assemble.sgbem" && !outcome.surface_blocks)
                outcome.surface_blocks = out->second.at("operators").get<bem::BemOperators>().surface;
            if (n.type->name() == "solve.sgbem" && !outcome.surface_factor)
                outcome.surface_factor = out->second.at("solution").get<bem::BemSolution>().system;
        }
        if (!found) throw std::logic_error("fracture pipeline without rigid.fragments");
        // A factor of other operators (a pipeline whose first solve is not on its first assembly) is no use.
        if (outcome.surface_factor && outcome.surface_factor->ops != outcome.surface_blocks) outcome.surface_factor = nullptr;
        return outcome;
    };
}

}  // namespace cf::rigid
