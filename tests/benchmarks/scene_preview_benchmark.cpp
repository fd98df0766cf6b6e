// Scene preview rendering (nodes/rigid/scene_preview): one 640 x 480 frame of 400 pieces of 2028
// triangles each (811k triangles) with the ground, for 1 and 2 threads. docs/performance.md.
#include "nodes/rigid/scene_preview.hpp"
#include "nodes/shape/box.hpp"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <memory>

namespace {

cf::rigid::Animation crowd(int pieces) {
    cf::BoxSpec box;
    box.size = cf::Vec3(0.25, 0.18, 0.12);
    box.subdivisions = 13;
    const auto mesh = std::make_shared<const cf::SurfaceMesh>(cf::make_box(box));
    cf::rigid::Animation a;
    a.frames.resize(1);
    for (int i = 0; i < pieces; ++i) {
        cf::rigid::AnimationPiece p;
        p.parent = i >= 10 ? i % 10 : -1;  // 10 bodies and their fragments
        p.name = p.parent < 0 ? "body" + std::to_string(i) : a.pieces[std::size_t(p.parent)].name + "." + std::to_string(i);
        p.rest_mesh = mesh;
        a.pieces.push_back(p);
        // Low-discrepancy placement in a 3 m x 3 m x 1.2 m block, each piece turned its own way.
        const double u = std::fmod(0.5 + i * 0.7548776662466927, 1.0), v = std::fmod(0.5 + i * 0.5698402909980532, 1.0);
        const double w = std::fmod(0.5 + i * 0.6180339887498949, 1.0);
        cf::rigid::PiecePose pose;
        pose.position = cf::Vec3(3 * u - 1.5, 3 * v - 1.5, 1.2 * w);
        pose.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(6.283 * w, cf::Vec3(u, v, 1 - w).normalized()));
        a.frames[0].poses.emplace_back(i, pose);
    }
    return a;
}

void BM_ScenePreview400Pieces(benchmark::State& state) {
    const cf::rigid::Animation a = crowd(400);
    const cf::rigid::SceneCamera camera;
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
    for (auto _ : state)
        benchmark::DoNotOptimize(cf::rigid::render_scene_image(a, 0, camera, cf::Vec3::Zero(), cf::Vec3::UnitZ(), true));
}
BENCHMARK(BM_ScenePreview400Pieces)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
