// Column chunks of the crack Schur complement's dense work (nodes/bem/column_chunks.hpp): each chunk
// the same Eigen call on its columns, on its own task; the results must be those of the single call
// bit for bit (the solver's outputs, and through them the fragments, depend on the last bits).
#include "nodes/bem/column_chunks.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <algorithm>
#include <mutex>
#include <vector>

using namespace cf::bem;
using Matrix = Eigen::MatrixXd;

namespace {

bool same_bits(const Matrix& a, const Matrix& b) {
    return a.rows() == b.rows() && a.cols() == b.cols() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

Matrix random_matrix(Eigen::Index r, Eigen::Index c, std::mt19937& rng) {
    std::normal_distribution<double> nd;
    Matrix m(r, c);
    for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = nd(rng);
    return m;
}

TEST(ColumnChunks, CoverEveryColumnOnceNoneNarrowerThanAChunk) {
    for (Eigen::Index n : {0, 1, 31, 32, 63, 64, 65, 97, 1000}) {
        std::vector<std::pair<Eigen::Index, Eigen::Index>> seen;
        std::mutex m;
        for_column_chunks(n, [&](Eigen::Index c0, Eigen::Index w) {
            std::lock_guard<std::mutex> lock(m);
            seen.push_back({c0, w});
        });
        std::sort(seen.begin(), seen.end());
        Eigen::Index next = 0;
        for (const auto& [c0, w] : seen) {
            EXPECT_EQ(c0, next);
            EXPECT_EQ(c0 % kColumnChunk, 0);
            if (n >= kColumnChunk) EXPECT_GE(w, kColumnChunk) << "n " << n;
            EXPECT_LT(w, 2 * kColumnChunk + (n < kColumnChunk ? kColumnChunk : 0));
            next = c0 + w;
        }
        EXPECT_EQ(next, n);
    }
}

// The solver's three kinds of chunked work (solver.cpp, extend_schur_by), at the crack Schur
// complement's sizes: k x k factors of 48..700 unknowns (several blocks of the summed dimension), 3..340 new columns, widths whose last
// chunk is 1..31 columns wider than the others.
TEST(ColumnChunks, ProductsAndTriangularSolvesGiveTheSingleCallsBits) {
    std::mt19937 rng(11);
    int cases = 0;
    for (Eigen::Index ko : {48, 201, 700})
        for (Eigen::Index kn : {3, 33, 65, 97, 130, 337}) {
            const Matrix A = random_matrix(ko, ko, rng);
            const Matrix S = A * A.transpose() + double(ko) * Matrix::Identity(ko, ko);
            const Matrix L = S.llt().matrixL();
            const Matrix B = random_matrix(ko, kn, rng), C = random_matrix(kn, ko, rng), Y = random_matrix(kn, ko, rng);
            // Triangular solve L^-1 B.
            const Matrix X1 = L.triangularView<Eigen::Lower>().solve(B);
            Matrix X2(ko, kn);
            for_column_chunks(kn, [&](Eigen::Index c0, Eigen::Index w) {
                X2.middleCols(c0, w) = L.triangularView<Eigen::Lower>().solve(B.middleCols(c0, w));
            });
            EXPECT_TRUE(same_bits(X1, X2)) << "solve, k " << ko << ", columns " << kn;
            // Y - C Z.
            const Matrix P1 = Y - C * L;
            Matrix P2(kn, ko);
            for_column_chunks(ko, [&](Eigen::Index c0, Eigen::Index w) { P2.middleCols(c0, w) = Y.middleCols(c0, w) - C * L.middleCols(c0, w); });
            EXPECT_TRUE(same_bits(P1, P2)) << "difference, k " << ko << ", columns " << kn;
            // S -= X^T X.
            Matrix R1 = random_matrix(kn, kn, rng), R2 = R1;
            R1.noalias() -= X1.transpose() * X1;
            for_column_chunks(kn, [&](Eigen::Index c0, Eigen::Index w) { R2.middleCols(c0, w).noalias() -= X1.transpose() * X1.middleCols(c0, w); });
            EXPECT_TRUE(same_bits(R1, R2)) << "update, k " << ko << ", columns " << kn;
            ++cases;
        }
    EXPECT_EQ(cases, 18);
}

}  // namespace
