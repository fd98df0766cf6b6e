// SGBEM performance: assembly of closed meshes, factorisation, crack Schur solves, and the gain
// of extending the Schur factor over refactoring it. Figures go to docs/performance.md.
#include "nodes/bem/solver.hpp"
#include "nodes/bem/test_meshes.hpp"

#include <benchmark/benchmark.h>

using namespace cf;
using namespace cf::bem;

namespace {
Material mat() {
    Material m;
    m.E = 1;
    m.nu = 0.3;
    return m;
}
// Icosphere levels give 320 / 1280 triangles; cubes with m x m faces give 12 m^2.
SurfaceMesh closed_mesh(int triangles) {
    int m = 1;
    while (12 * (m + 1) * (m + 1) <= triangles) ++m;
    return bem_cube_mesh(m, 1.0);
}
}  // namespace

static void BM_AssembleSurface(benchmark::State& st) {
    const SurfaceMesh mesh = closed_mesh(static_cast<int>(st.range(0)));
    AssemblyOptions opt;
    opt.memory_budget_bytes = 16e9;
    std::int64_t pairs = 0;
    for (auto _ : st) {
        auto ops = assemble_surface_operators(mesh, mat(), opt);
        pairs += ops->pairs_computed;
        benchmark::DoNotOptimize(ops);
    }
    st.counters["triangles"] = static_cast<double>(mesh.num_triangles());
    // Element-pair integrals (each a full quadrature of the three kernel families) per second.
    st.counters["pair_integrals_per_s"] = benchmark::Counter(static_cast<double>(pairs), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_AssembleSurface)->Arg(300)->Arg(1000)->Arg(2000)->Arg(4000)->Unit(benchmark::kMillisecond)->UseRealTime();

// Assemble + factorise a mixed problem (bottom clamped): the "1200 triangles in 1 s" target.
static void BM_AssembleAndFactorMixed(benchmark::State& st) {
    const SurfaceMesh mesh = closed_mesh(static_cast<int>(st.range(0)));
    const auto bcs = parse_boundary_conditions("z_min: displacement 0 0 0; z_max: traction 0 0 1; *: traction 0 0 0");
    for (auto _ : st) {
        const auto o = assemble_surface_operators(mesh, mat(), AssemblyOptions{});
        benchmark::DoNotOptimize(solve_sgbem(o, nullptr, resolve(bcs, mesh), {}, nullptr));
    }
    st.counters["triangles"] = static_cast<double>(mesh.num_triangles());
}
BENCHMARK(BM_AssembleAndFactorMixed)->Arg(1200)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_FactorMixed(benchmark::State& st) {
    const SurfaceMesh mesh = closed_mesh(static_cast<int>(st.range(0)));
    const auto o = assemble_surface_operators(mesh, mat(), AssemblyOptions{});
    const auto bc = resolve(parse_boundary_conditions("z_min: displacement 0 0 0; z_max: traction 0 0 1; *: traction 0 0 0"), mesh);
    for (auto _ : st) benchmark::DoNotOptimize(solve_sgbem(o, nullptr, bc, {}, nullptr));
}
BENCHMARK(BM_FactorMixed)->Arg(1200)->Unit(benchmark::kMillisecond)->UseRealTime();

// Crack with about n/3 interior nodes (n crack unknowns) in a 300-triangle cube: the Schur
// solve after the surface factorisation (previous solution reused).
static void BM_CrackSchurSolve(benchmark::State& st) {
    const int unknowns = static_cast<int>(st.range(0));
    int rings = 1;
    while (3 * (1 + 3 * rings * (rings - 1)) < unknowns) ++rings;
    const SurfaceMesh cube = bem_cube_mesh(5, 10.0);
    const auto o = assemble_surface_operators(cube, mat(), AssemblyOptions{});
    const auto bc = resolve(parse_boundary_conditions("z_min: displacement 0 0 0; z_max: traction 0 0 1; *: traction 0 0 0"), cube);
    const auto base = solve_sgbem(o, nullptr, bc, {}, nullptr);
    const auto cr = append_crack_elements(*o, nullptr, bem_disk_mesh(rings, 2.0));
    for (auto _ : st) benchmark::DoNotOptimize(solve_sgbem(o, cr, bc, {}, base.get()));
    st.counters["crack_unknowns"] = static_cast<double>(3 * (1 + 3 * rings * (rings - 1)));
}
BENCHMARK(BM_CrackSchurSolve)->Arg(200)->Arg(800)->Unit(benchmark::kMillisecond)->UseRealTime();

// One propagation step: a crack of R rings grows by one ring. Extend (arg 1) vs refactor (arg 0).
static void BM_CrackStepExtendVsRefactor(benchmark::State& st) {
    const bool extend = st.range(0) != 0;
    const int rings = static_cast<int>(st.range(1));
    const SurfaceMesh cube = bem_cube_mesh(5, 10.0);
    const auto o = assemble_surface_operators(cube, mat(), AssemblyOptions{});
    const auto bc = resolve(parse_boundary_conditions("z_min: displacement 0 0 0; z_max: traction 0 0 1; *: traction 0 0 0"), cube);
    const SurfaceMesh big = bem_disk_mesh(rings + 1, 2.0);
    SurfaceMesh small = big;
    small.triangles.resize(6 * rings * rings);
    small.region.resize(small.triangles.size());
    small.vertices.resize(1 + 3 * rings * (rings + 1));
    const auto c1 = append_crack_elements(*o, nullptr, small);
    const auto s1 = solve_sgbem(o, c1, bc, {}, nullptr);
    const auto c2 = append_crack_elements(*o, c1, big);
    SolveOptions so;
    so.extend_schur = extend;
    for (auto _ : st) benchmark::DoNotOptimize(solve_sgbem(o, c2, bc, {}, s1.get(), so));
    st.counters["crack_unknowns"] = static_cast<double>(3 * (1 + 3 * rings * (rings + 1)));
}
BENCHMARK(BM_CrackStepExtendVsRefactor)->Args({0, 12})->Args({1, 12})->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
