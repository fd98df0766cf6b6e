// Cost of one BEM time step of crack growth against the front length (thesis ch. 5.3): the
// estimator path (SIF estimator at every front edge + integrating the new row's estimated openings
// + one solve with the stored factorisation) against the full-BEM path (crack blocks of the new row
// + extended Schur factor + solve), on a fixed surface (a 1 m cube of 432 triangles) and a square
// crack sheet of k x k cells grown by one row of cells at its front. The front has 4 k edges; the
// sheet 2 k^2 triangles. Figures and the fitted exponents go to docs/performance.md.
#include "nodes/bem/assembly_step.hpp"
#include "nodes/bem/boundary_conditions.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "nodes/estimate/sif_estimator.hpp"

#include <benchmark/benchmark.h>

using namespace cf;

namespace {

// k columns of k cells, column-major so that the last column's triangles come last.
SurfaceMesh sheet(int columns, int k) {
    SurfaceMesh m;
    const double w = 0.4;
    for (int i = 0; i <= columns; ++i)
        for (int j = 0; j <= k; ++j) m.vertices.push_back(Vec3(-0.2 + w * i / k, -0.2 + w * j / k, 0.013));
    auto id = [&](int i, int j) { return i * (k + 1) + j; };
    for (int i = 0; i < columns; ++i)
        for (int j = 0; j < k; ++j) {
            m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    m.region.assign(m.triangles.size(), 0);
    return m;
}

struct Scene {
    std::shared_ptr<const bem::SurfaceOperators> surface;
    bem::ResolvedConditions bc;
    SurfaceMesh before, after;  // k - 1 columns, k columns
    Scene(int k) {
        const SurfaceMesh cube = bem::bem_cube_mesh(6, 1.0);
        Material mat;
        bem::AssemblyOptions opt;
        opt.memory_budget_bytes = 16e9;
        surface = bem::assemble_surface_operators(cube, mat, opt);
        bc = bem::resolve(bem::parse_boundary_conditions("z_max: traction 0 0 1e6; z_min: displacement 0 0 0; *: traction 0 0 0"), cube);
        before = sheet(k - 1, k);
        after = sheet(k, k);
    }
};

void BM_EstimatorStep(benchmark::State& st) {
    const int k = static_cast<int>(st.range(0));
    const Scene s(k);
    // The previous step's state: growth estimated since the start, the solution of that step.
    bem::CrackOpeningEstimate none;
    auto g0 = bem::update_estimated_growth(*s.surface, nullptr, s.before, 0, 0, none, 0);
    const auto sol0 = bem::solve_sgbem(s.surface, nullptr, s.bc, {}, nullptr, {}, g0);
    // The column of nodes the front left behind carries openings now.
    bem::CrackOpeningEstimate est;
    est.opening.assign(s.after.num_vertices(), Vec3::Zero());
    est.known.assign(s.after.num_vertices(), 0);
    for (int j = 1; j < k; ++j) {
        est.known[(k - 1) * (k + 1) + j] = 1;
        est.opening[(k - 1) * (k + 1) + j] = Vec3(0, 0, 1e-6);
    }
    for (auto _ : st) {
        const auto sifs = estimate::estimate_sifs(*sol0, s.before, {});
        const auto g1 = bem::update_estimated_growth(*s.surface, g0, s.after, 0, 0, est, 1);
        const auto sol1 = bem::solve_sgbem(s.surface, nullptr, s.bc, {}, sol0.get(), {}, g1);
        benchmark::DoNotOptimize(sifs);
        benchmark::DoNotOptimize(sol1);
    }
    st.counters["front_edges"] = 4.0 * k;
    st.counters["crack_triangles"] = static_cast<double>(s.after.num_triangles());
    st.SetComplexityN(4 * k);
}

void BM_FullBemStep(benchmark::State& st) {
    const int k = static_cast<int>(st.range(0));
    const Scene s(k);
    const auto ops0 = bem::append_crack_elements(*s.surface, nullptr, s.before);
    const auto sol0 = bem::solve_sgbem(s.surface, ops0, s.bc, {}, nullptr);
    for (auto _ : st) {
        const auto sifs = bem::displacement_correlation_sifs(sol0->cracks->cracks, sol0->crack_opening, 3.1e9, 0.327);
        const auto ops1 = bem::append_crack_elements(*s.surface, ops0, s.after);
        const auto sol1 = bem::solve_sgbem(s.surface, ops1, s.bc, {}, sol0.get());
        benchmark::DoNotOptimize(sifs);
        benchmark::DoNotOptimize(sol1);
    }
    st.counters["front_edges"] = 4.0 * k;
    st.counters["crack_triangles"] = static_cast<double>(s.after.num_triangles());
    st.SetComplexityN(4 * k);
}

}  // namespace

BENCHMARK(BM_EstimatorStep)->Arg(4)->Arg(8)->Arg(16)->Arg(32)->Arg(48)->Unit(benchmark::kMillisecond)->UseRealTime()->Complexity();
BENCHMARK(BM_FullBemStep)->Arg(4)->Arg(8)->Arg(16)->Arg(32)->Arg(48)->Unit(benchmark::kMillisecond)->UseRealTime()->Complexity();

BENCHMARK_MAIN();
