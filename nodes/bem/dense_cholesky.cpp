#include "nodes/bem/dense_cholesky.hpp"

#include <Eigen/Cholesky>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace cf::bem {

namespace {

// Panel width: big enough for Eigen's matrix-product kernels to run near peak, small enough to
// give two cores several chunks each on the 1000-4000 unknown systems of a BEM solve.
constexpr Eigen::Index chunk = 128;

// Polls `cancel` per chunk (one chunk of a trailing update is at most n x 128 x 128 flops).
template <class Fn>
void for_each_chunk(Eigen::Index begin, Eigen::Index end, Fn fn, const CancelToken& cancel = {}) {
    const Eigen::Index n = (end - begin + chunk - 1) / chunk;
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 1), [&](const tbb::blocked_range<Eigen::Index>& r) {
        for (Eigen::Index c = r.begin(); c != r.end(); ++c) {
            cancel.poll();
            const Eigen::Index b = begin + c * chunk;
            fn(b, std::min(chunk, end - b));
        }
    });
}

}  // namespace

bool DenseCholesky::compute(Eigen::MatrixXd A, const CancelToken& cancel) {
    ok_ = false;
    const Eigen::Index n = A.rows();
    if (A.cols() != n) return false;
    for (Eigen::Index k0 = 0; k0 < n; k0 += chunk) {
        cancel.poll();
        const Eigen::Index kb = std::min(chunk, n - k0), r0 = k0 + kb, nr = n - r0;
        Eigen::Ref<Eigen::MatrixXd> A11 = A.block(k0, k0, kb, kb);
        Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(A11);  // in place: A11 becomes L11
        if (llt.info() != Eigen::Success) {
            L_.resize(0, 0);
            return false;
        }
        if (nr == 0) break;
        // Panel: L21 = A21 L11^-T, by row chunks.
        for_each_chunk(r0, n, [&](Eigen::Index b, Eigen::Index m) {
            A.block(k0, k0, kb, kb).triangularView<Eigen::Lower>().transpose().solveInPlace<Eigen::OnTheRight>(
                A.block(b, k0, m, kb));
        }, cancel);
        // Trailing update of the lower triangle: A22 -= L21 L21^T, by column chunks.
        const auto L21 = A.block(r0, k0, nr, kb);
        for_each_chunk(r0, n, [&](Eigen::Index b, Eigen::Index m) {
            A.block(b, b, n - b, m).noalias() -= L21.bottomRows(n - b) * L21.middleRows(b - r0, m).transpose();
        }, cancel);
    }
    L_ = std::move(A);
    ok_ = true;
    return true;
}

void DenseCholesky::solve_lower_in_place(Eigen::MatrixXd& X) const {
    for_each_chunk(0, X.cols(), [&](Eigen::Index b, Eigen::Index m) {
        L_.triangularView<Eigen::Lower>().solveInPlace(X.middleCols(b, m));
    });
}

void DenseCholesky::solve_upper_in_place(Eigen::MatrixXd& X) const {
    for_each_chunk(0, X.cols(), [&](Eigen::Index b, Eigen::Index m) {
        L_.triangularView<Eigen::Lower>().transpose().solveInPlace(X.middleCols(b, m));
    });
}

Eigen::MatrixXd DenseCholesky::solve(const Eigen::MatrixXd& b) const {
    Eigen::MatrixXd x = b;
    solve_lower_in_place(x);
    solve_upper_in_place(x);
    return x;
}

void add_lower_gram(Eigen::MatrixXd& S, const Eigen::MatrixXd& W) {
    const Eigen::Index n = S.cols();
    for_each_chunk(0, n, [&](Eigen::Index b, Eigen::Index m) {
        S.block(b, b, n - b, m).noalias() += W.rightCols(n - b).transpose() * W.middleCols(b, m);
    });
}

}  // namespace cf::bem
