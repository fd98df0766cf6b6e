#pragma once
// Running a breakable body's fracture pipeline for one collision (thesis ch. 7.2): the same nodes
// as a single-object fracture pipeline, loaded from a YAML file once per file and executed per
// run with the run's body and loads handed in (rigid.impact reads them) and its fragments read back
// from the pipeline's rigid.fragments node. The body's settings reach the pipeline as parameters:
// r_c of every fracture.start, method and switch_elements of every assemble.sgbem without
// 'previous', and every loop's max_iterations lowered to the run's step bound.
#include "graph/executor.hpp"
#include "graph/pipeline.hpp"
#include "nodes/rigid/scene_simulation.hpp"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace cf::rigid {

// The default fracture pipeline (pipelines/impact/fracture.yaml, compiled in).
const char* builtin_fracture_pipeline_text();
constexpr const char* builtin_fracture_pipeline_name = "built-in impact/fracture.yaml";

// Loads and checks a fracture pipeline (an empty `file`: the built-in one): it must hold exactly one rigid.impact and one rigid.fragments
// node. Throws std::invalid_argument with every problem (file and line) otherwise.
std::shared_ptr<const graph::Plan> load_impact_pipeline(const std::filesystem::path& file,
                                                        const graph::NodeRegistry& registry);

// The plan of one run: `plan` with the body's settings applied (see above), and initiate.cracks'
// snap_distance from the body's BEM standoff.
graph::Plan impact_plan(const graph::Plan& plan, const BreakableModel& model, long long max_steps);

// A runner that executes the pipeline file of each run's body (FractureSettings::fracture_pipeline
// is not here: the file comes with the body, `pipeline_of`), writing into
// options.output_dir / run.output_dir, cancelled with the scene's run.
FractureRunner pipeline_runner(const graph::RunOptions& options,
                               std::function<std::shared_ptr<const graph::Plan>(const ImpactRun&)> pipeline_of);

}  // namespace cf::rigid
