#include "nodes/bem/rigid_motion_rows.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace cf::bem {

RigidMotionRows impose_rigid_motion_rows(Eigen::MatrixXd& K, const std::vector<Vec3>& vertices,
                                         const std::vector<ElementGeometry>& geometry, bool closed_oriented, double limit) {
    const std::size_t M = geometry.size(), N = vertices.size();
    // Row a's residual of the three translations: sum_j K[a, j] + 1/2 |a| I (M01[a, vertex] = |a|/3 I).
    std::vector<Mat3> residual(M);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, M), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t a = range.begin(); a != range.end(); ++a) {
            Mat3 res = 0.5 * geometry[a].area * Mat3::Identity();
            for (std::size_t j = 0; j < N; ++j) res += K.block<3, 3>(3 * a, 3 * j);
            residual[a] = res;
        }
    });
    RigidMotionRows out;
    for (std::size_t a = 0; a < M; ++a) out.max_residual = std::max(out.max_residual, residual[a].norm() / geometry[a].area);
    if (!closed_oriented || !(out.max_residual < limit)) return out;
    // The same third of the residual off each vertex block: the change's first moment,
    // sum_v C_v (x_v - centroid), is zero, so a linear field's row sees no change beyond its value at the
    // centroid (the rotations' and strains' own quadrature errors are neither corrected nor made worse;
    // a minimum-norm change fitted to all six rigid motions made a uniform strain's displacement worse
    // on a coarse slab, 9.1e-4 against 6.2e-4 |eps| L without it).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, M), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t a = range.begin(); a != range.end(); ++a)
            for (int v : geometry[a].nodes) K.block<3, 3>(3 * a, 3 * v) -= residual[a] / 3;
    });
    out.applied = true;
    return out;
}

}  // namespace cf::bem
