// Mesh writers (nodes/export): a fragment-sized mesh written as OBJ into memory. docs/performance.md.
#include "nodes/export/mesh_writers.hpp"
#include "nodes/shape/box.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <sstream>

namespace {

// A box of 2 * 6 * n^2 triangles whose vertices are moved off the grid (float-rounded, as meshes
// from OpenVDB's mesher are: their shortest decimals are long), with two regions.
cf::SurfaceMesh fragment_like(int n) {
    cf::BoxSpec box;
    box.size = cf::Vec3(0.1, 0.1, 0.1);
    box.subdivisions = n;
    cf::SurfaceMesh m = cf::make_box(box);
    for (std::size_t i = 0; i < m.vertices.size(); ++i) {
        cf::Vec3& p = m.vertices[i];
        for (int a = 0; a < 3; ++a) p[a] = double(float(p[a] + 1e-4 * std::sin(0.37 * double(i) + a)));
    }
    m.region_names = {"outside", "fracture"};
    m.region.assign(m.triangles.size(), 0);
    for (std::size_t t = m.triangles.size() / 2; t < m.triangles.size(); ++t) m.region[t] = 1;
    return m;
}

void BM_WriteObj(benchmark::State& state) {
    const cf::SurfaceMesh m = fragment_like(int(state.range(0)));
    std::size_t bytes = 0;
    for (auto _ : state) {
        std::ostringstream os;
        cf::write_obj(os, m, "fragments.mtl");
        bytes = os.str().size();
        benchmark::DoNotOptimize(bytes);
    }
    state.counters["triangles"] = double(m.num_triangles());
    state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(bytes));
}
BENCHMARK(BM_WriteObj)->Arg(200)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
