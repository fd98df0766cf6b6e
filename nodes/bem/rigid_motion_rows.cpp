#include "nodes/bem/rigid_motion_rows.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace cf::bem {

RigidMotionRows impose_rigid_motion_rows(Eigen::MatrixXd& K, const std::vector<ElementGeometry>& geometry,
                                         bool closed_oriented, double limit) {
    const Eigen::Index M = static_cast<Eigen::Index>(geometry.size()), N = K.cols() / 3;
    // Row a's residual of the three translations: sum_j K[a, j] + 1/2 |a| I (M01[a, vertex] = |a|/3 I),
    // summed column block by column block (K is column-major), rows in parallel.
    Eigen::MatrixXd residual = Eigen::MatrixXd::Zero(3 * M, 3);
    for (Eigen::Index a = 0; a < M; ++a) residual.block<3, 3>(3 * a, 0).diagonal().setConstant(0.5 * geometry[a].area);
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, M, 64), [&](const tbb::blocked_range<Eigen::Index>& r) {
        const Eigen::Index row = 3 * r.begin(), rows = 3 * (r.end() - r.begin());
        for (Eigen::Index j = 0; j < N; ++j) residual.block(row, 0, rows, 3) += K.block(row, 3 * j, rows, 3);
    });
    RigidMotionRows out;
    for (Eigen::Index a = 0; a < M; ++a) {
        const double r = residual.block<3, 3>(3 * a, 0).norm() / geometry[a].area;
        if (r > out.max_residual) {
            out.max_residual = r;
            out.worst_element = static_cast<int>(a);
        }
    }
    if (!closed_oriented || !(out.max_residual < limit)) return out;
    // The same third of the residual off each vertex block: the change's first moment,
    // sum_v C_v (x_v - centroid), is zero, so a linear field's row sees no change beyond its value at the
    // centroid (the rotations' and strains' own quadrature errors are neither corrected nor made worse;
    // a minimum-norm change fitted to all six rigid motions made a uniform strain's displacement worse
    // on a coarse slab, 9.1e-4 against 6.2e-4 |eps| L without it).
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, M), [&](const tbb::blocked_range<Eigen::Index>& r) {
        for (Eigen::Index a = r.begin(); a != r.end(); ++a)
            for (int v : geometry[a].nodes) K.block<3, 3>(3 * a, 3 * v) -= residual.block<3, 3>(3 * a, 0) / 3;
    });
    out.applied = true;
    return out;
}

}  // namespace cf::bem
