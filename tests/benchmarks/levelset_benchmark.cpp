// Level-set benchmarks (issue 4): crack recording throughput against OpenVDB's
// meshToUnsignedDistanceField on the same strips, segmentation of ~1e7 active voxels, and
// remeshing the armadillo to 1000 triangles, each parallel one at 1 and 2 threads. Figures go
// to docs/performance.md.
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/segment/fragments.hpp"
#include "nodes/shape/box.hpp"
#include "nodes/simplify/remesh.hpp"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace {

using namespace cf;

constexpr double kRf = 0.005;

// A closed front of 256 markers on a circle of radius r, slightly out of plane so the strips are
// not axis-aligned.
std::vector<Vec3> ring(double r) {
    std::vector<Vec3> p;
    for (int i = 0; i < 256; ++i) {
        const double a = 2 * M_PI * i / 256;
        p.emplace_back(r * std::cos(a), r * std::sin(a), 0.1 * r * std::sin(3 * a));
    }
    return p;
}

// The ring front growing from radius 0.05 m by `advance` per sub-step.
std::vector<FrontMotion> growing_front(int substeps, double advance = 2 * kRf) {
    std::vector<FrontMotion> steps;
    for (int s = 0; s < substeps; ++s)
        steps.push_back(FrontMotion{ring(0.05 + advance * s), ring(0.05 + advance * (s + 1)), true});
    return steps;
}

// Voxels within the band of each strip, as OpenVDB's meshToUnsignedDistanceField activates them:
// the common work unit of the two recording benchmarks below, so their voxels_per_s compare
// directly (the ratio equals the ratio of strips per second).
std::size_t strip_voxels(const std::vector<FrontMotion>& steps) {
    std::size_t n = 0;
    for (const FrontMotion& m : steps) n += active_voxel_count(reference_strip_level_set(strip_triangles(m), kRf));
    return n;
}

// Recording 20 strips into one growing crack grid (union with what is there), with the
// benchmark argument as the number of threads.
void BM_RecordGrowingCrack(benchmark::State& state) {
    const auto steps = growing_front(20);
    const std::size_t per_run = strip_voxels(steps);
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, std::size_t(state.range(0)));
    std::size_t band = 0;
    for (auto _ : state) {
        CrackRecorder rec(kRf);
        rec.add_crack();
        for (const FrontMotion& m : steps) {
            std::size_t w = 0;
            rec.record_substep({m}, nullptr, &w);
            band += w;
        }
        benchmark::DoNotOptimize(rec.num_cracks());
    }
    state.counters["voxels_per_s"] = benchmark::Counter(double(per_run * state.iterations()), benchmark::Counter::kIsRate);
    state.counters["band_voxels_per_s"] = benchmark::Counter(double(band), benchmark::Counter::kIsRate);
    state.counters["strips_per_s"] = benchmark::Counter(double(steps.size() * state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RecordGrowingCrack)->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();

// The same strips voxelised one by one by OpenVDB (no union): the reference cost per strip.
// What deferring the recording could save (issue 17's lead): 48 sub-steps of a front advancing
// half a voxel each (a BEM step's worth at r_c = 24 r_f), recorded into one crack grid in
// batches of m sub-steps (one add_triangles call per batch; m = 1 is today's recorder). The
// grids are the same for every m (CrackGrid.IncrementalRecordingEqualsRecordingEverythingAtOnce);
// what differs is how often a voxel ahead of the front is re-lowered and the per-call set-up.
void BM_RecordHalfVoxelSubstepsInBatches(benchmark::State& state) {
    const int m = int(state.range(0));
    const std::vector<FrontMotion> steps = growing_front(48, 0.5 * kRf);
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
    for (auto _ : state) {
        CrackRecorder rec(kRf, 2);  // fracture.start's default crack_band
        rec.add_crack();
        for (std::size_t s = 0; s < steps.size(); s += std::size_t(m)) {
            std::vector<Triangle3> tris;
            for (std::size_t k = s; k < std::min(steps.size(), s + std::size_t(m)); ++k) {
                const std::vector<Triangle3> t = strip_triangles(steps[k]);
                tris.insert(tris.end(), t.begin(), t.end());
            }
            rec.add_triangles(0, tris);
        }
        benchmark::DoNotOptimize(rec.num_cracks());
    }
    state.counters["substeps_per_s"] = benchmark::Counter(double(steps.size() * state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RecordHalfVoxelSubstepsInBatches)->Arg(1)->Arg(4)->Arg(16)->Arg(48)->ArgName("m")->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_MeshToVolumeSameStrips(benchmark::State& state) {
    const auto steps = growing_front(20);
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, std::size_t(state.range(0)));
    std::size_t voxels = 0;
    for (auto _ : state) {
        for (const FrontMotion& m : steps) {
            const LevelSet ls = reference_strip_level_set(strip_triangles(m), kRf);
            voxels += active_voxel_count(ls);
        }
    }
    state.counters["voxels_per_s"] = benchmark::Counter(double(voxels), benchmark::Counter::kIsRate);
    state.counters["strips_per_s"] = benchmark::Counter(double(steps.size() * state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_MeshToVolumeSameStrips)->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();

// The object level set of the thesis' edge-cracked cube (issue 17): a 10 cm box of 300 triangles at
// r_f = L / 339, 4.1 M active voxels in the 3-voxel band; by meshToLevelSet or by the exact band
// rasteriser (levelset.from_mesh band: exact).
template <LevelSet (*Build)(const SurfaceMesh&, double, double, double, const CancelToken&)>
void object_level_set_box(benchmark::State& state) {
    BoxSpec spec;
    spec.size = Vec3(0.1, 0.1, 0.1);
    spec.subdivisions = 5;
    const SurfaceMesh box = make_box(spec);
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, std::size_t(state.range(0)));
    std::size_t voxels = 0;
    for (auto _ : state) voxels = active_voxel_count(Build(box, 2.9499e-4, 3, 2e8, CancelToken::current()));
    state.counters["active_voxels"] = double(voxels);
}
void BM_ObjectLevelSetBox(benchmark::State& state) { object_level_set_box<level_set_from_mesh>(state); }
BENCHMARK(BM_ObjectLevelSetBox)->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();
void BM_ExactObjectLevelSetBox(benchmark::State& state) { object_level_set_box<exact_level_set_from_mesh>(state); }
BENCHMARK(BM_ExactObjectLevelSetBox)->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();

// A 1 m cube at r_f = 2 mm (~1e7 active voxels) cut by one oblique plane.
void BM_SegmentTenMillionVoxels(benchmark::State& state) {
    BoxSpec spec;
    spec.size = Vec3(1, 1, 1);
    spec.subdivisions = 2;
    const double r_f = 0.002;
    const LevelSet cube = level_set_from_mesh(make_box(spec), r_f);
    const LevelSet broken =
        broken_object(cube, CrackLevelSets{r_f, 3, {planar_disk_crack(Vec3(0.05, 0, 0), Vec3(1, 0.4, 0.2), 2, r_f)}});
    std::size_t fragments = 0;
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, std::size_t(state.range(0)));
    for (auto _ : state) fragments = find_fragments(broken).fragments.size();
    state.counters["active_voxels"] = double(active_voxel_count(broken));
    state.counters["fragments"] = double(fragments);
    state.counters["voxels_per_s"] =
        benchmark::Counter(double(active_voxel_count(broken) * state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SegmentTenMillionVoxels)->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

SurfaceMesh read_off(const std::filesystem::path& p) {
    std::ifstream f(p);
    std::string magic;
    std::size_t nv = 0, nf = 0, ne = 0;
    f >> magic >> nv >> nf >> ne;
    SurfaceMesh m;
    m.vertices.resize(nv);
    for (auto& v : m.vertices) f >> v.x() >> v.y() >> v.z();
    for (std::size_t i = 0; i < nf; ++i) {
        int n;
        Tri t;
        f >> n >> t[0] >> t[1] >> t[2];
        m.triangles.push_back(t);
    }
    return m;
}

void BM_RemeshArmadillo1000(benchmark::State& state) {
    const std::filesystem::path file = std::filesystem::path(CF_REMESH_DATA_DIR) / "armadillo.off";
    if (!std::filesystem::exists(file)) {
        state.SkipWithError("armadillo.off not found (install libcgal-demo and re-run cmake)");
        return;
    }
    const SurfaceMesh input = read_off(file);
    const LevelSet ls = level_set_from_mesh(input, bounding_box(input).extent().maxCoeff() / 160);
    RemeshOptions opt;
    opt.target_triangles = 1000;
    std::size_t tris = 0, dense = 0;
    for (auto _ : state) {
        const RemeshResult r = remesh(ls, opt);
        tris = r.mesh.num_triangles();
        dense = r.dense_triangles;
    }
    state.counters["dense_triangles"] = double(dense);
    state.counters["triangles"] = double(tris);
}
BENCHMARK(BM_RemeshArmadillo1000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
