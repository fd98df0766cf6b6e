// Verification cases of the whole fracture loop (docs/verification.md case 8). They run a
// pipeline through the same executor as `crackflow run`, so they check the wiring (loop state,
// SIFs, propagation, recording, BEM growth, segmentation) as well as the mechanics.
#include "graph/executor.hpp"
#include "graph/pipeline.hpp"
#include "nodes/register_all.hpp"
#include "nodes/registration.hpp"
#include "nodes/segment/fragments.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace cf {
namespace {

// Edge-cracked cube under mode I as pipelines/edge_crack_mode1.yaml, at the resolution of its
// `fast:` section (r_f = L/100, r_c = 15 r_f) so the case runs in seconds; no files written.
const char* edge_crack_mode1_pipeline = R"(
nodes:
  material:
    type: material.brittle
    params: {E: 3.1e9, nu: 0.327, rho: 1200, tensile_strength: 7.6e7, toughness: 1.0e6, compressive_factor: 2}
  toughness: {type: fields.homogeneous, params: {value: 1.0e6, compressive_factor: 2}}
  cube: {type: shape.box, params: {size: [0.1, 0.1, 0.1], subdivisions: 5}}
  object: {type: levelset.from_mesh, inputs: {mesh: cube.mesh}, params: {voxel_size: 1.0e-3}}
  start: {type: fracture.start, inputs: {mesh: cube.mesh, object: object.level_set}, params: {r_c: 1.5e-2}}
  initial_crack:
    type: initiate.user_crack
    inputs: {state: start.state, mesh: cube.mesh, object: object.level_set}
    params: {centre: [-0.05, 0, 0], normal: [0, 0, 1], front_direction: [1, 0, 0], radius: 0.03}
  initial_cracks: {type: fracture.geometry, inputs: {state: initial_crack.state}}
  assemble0:
    type: assemble.sgbem
    inputs: {mesh: cube.mesh, cracks: initial_cracks.cracks, material: material.material}
  solve0:
    type: solve.sgbem
    inputs: {operators: assemble0.operators}
    params: &pull {boundary_conditions: "z_max: displacement 0 0 3e-4; z_min: displacement 0 0 -3e-4; *: traction 0 0 0"}
  fracture:
    type: loop
    params: {max_iterations: 14}
    inputs: {state: initial_crack.state, operators: assemble0.operators, solution: solve0.solution}
    body:
      sifs: {type: sif.displacement_correlation, inputs: {solution: fracture.solution}}
      propagate:
        type: propagate.fronts
        inputs: {state: fracture.state, sifs: sifs.sifs, toughness: toughness.field, material: material.material,
                 object: object.level_set}
      cracks: {type: fracture.geometry, inputs: {state: propagate.state}}
      assemble:
        type: assemble.sgbem
        inputs: {mesh: cube.mesh, cracks: cracks.cracks, previous: fracture.operators, material: material.material}
      solve:
        type: solve.sgbem
        inputs: {operators: assemble.operators, previous: fracture.solution}
        params: *pull
    next: {state: propagate.state, operators: assemble.operators, solution: solve.solution}
    while: propagate.continue
  final: {type: fracture.geometry, inputs: {state: fracture.final.state}}
  fragments:
    type: segment.fragments
    inputs: {object: object.level_set, cracks: final.grids}
    params: {write_listing: false}
)";

VerificationResult edge_crack_mode1_planar() {
    VerificationResult r;
    const double r_c = 1.5e-2;
    r.tolerance = 0.05;  // out-of-plane deviation / r_c (verification.md case 8)
    std::vector<graph::Diagnostic> diags;
    const graph::Plan plan = graph::load_pipeline_text(edge_crack_mode1_pipeline, "edge_crack_mode1_planar (built in)",
                                                       node_registry(), {}, diags);
    if (!diags.empty()) {
        r.details = "pipeline does not load: " + graph::format(diags.front());
        return r;
    }
    graph::RunOptions run;
    run.output_dir = std::filesystem::temp_directory_path() / "crackflow-verify-edge-crack";
    std::filesystem::create_directories(run.output_dir);
    const graph::ExecutionResult res = graph::execute(plan, run);
    if (!res.ok) {
        r.details = "pipeline failed: " + res.error;
        return r;
    }
    const SurfaceMesh& cracks = res.outputs.at("final").at("cracks").get<SurfaceMesh>();
    const Fragments& frags = res.outputs.at("fragments").at("fragments").get<Fragments>();
    double deviation = 0;
    for (const Vec3& v : cracks.vertices) deviation = std::max(deviation, std::abs(v.z()));
    r.error = deviation / r_c;
    const std::size_t n = frags.fragments.size();
    double volume_ratio = 0;
    if (n == 2) volume_ratio = frags.fragments[1].volume / frags.fragments[0].volume;
    // Two fragments, the halves above and below the crack plane (equal volumes within 2 %).
    r.passed = r.error <= r.tolerance && n == 2 && volume_ratio > 0.98;
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "max |z| of %zu crack nodes = %.3g r_c; %zu fragments (volume ratio %.4f); %zu crack elements; "
                  "r_f = L/100, r_c = 15 r_f",
                  cracks.num_vertices(), r.error, n, volume_ratio, cracks.num_triangles());
    r.details = buf;
    return r;
}

}  // namespace

void add_fracture_verification_cases(std::vector<VerificationCase>& cases) {
    cases.push_back({"edge_crack_mode1_planar",
                     "case 8: edge-cracked cube under mode I stays planar (< 0.05 r_c) and splits in two",
                     edge_crack_mode1_planar});
}

}  // namespace cf
