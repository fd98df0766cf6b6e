#pragma once
// Dense symmetric positive definite factorisation for the SGBEM solves, parallel with oneTBB.
// Blocked right-looking Cholesky: each diagonal block by Eigen's LLT in place, the panel below it
// and the trailing update in fixed-size chunks run in parallel. Chunk boundaries depend only on
// the matrix size, and every entry is computed by one task, so results are bit-identical for any
// thread count.
#include "graph/cancel_token.hpp"

#include <Eigen/Core>

namespace cf::bem {

class DenseCholesky {
public:
    DenseCholesky() = default;
    // Factorises the symmetric matrix whose LOWER triangle is given (the upper part is ignored).
    explicit DenseCholesky(Eigen::MatrixXd lower) { compute(std::move(lower)); }
    // Returns false (and keeps no factor) when the matrix is not numerically positive definite.
    // Throws cf::Cancelled between block columns once `cancel` is set.
    bool compute(Eigen::MatrixXd lower, const CancelToken& cancel = CancelToken::current());
    bool ok() const { return ok_; }
    Eigen::Index size() const { return L_.rows(); }
    // Lower factor L with A = L L^T; only the lower triangle is meaningful.
    const Eigen::MatrixXd& factor() const { return L_; }
    // In place: X <- L^-1 X and X <- L^-T X (columns of X in parallel chunks).
    void solve_lower_in_place(Eigen::MatrixXd& X) const;
    void solve_upper_in_place(Eigen::MatrixXd& X) const;
    Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const;  // A^-1 b

private:
    Eigen::MatrixXd L_;
    bool ok_ = false;
};

// S (lower triangle) += W^T W, in parallel over fixed column chunks of S.
void add_lower_gram(Eigen::MatrixXd& S, const Eigen::MatrixXd& W);

}  // namespace cf::bem
