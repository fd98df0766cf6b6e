#pragma once
// Dense products and triangular solves of the crack Schur complement (solver.cpp) split into column
// chunks on oneTBB tasks, each chunk the same Eigen call restricted to its columns of the result:
// bit for bit the single call (tests/bem/column_chunks_test.cpp). Why that holds: Eigen's product
// blocks the summed dimension by a size that depends on that dimension and the L1 cache only, its
// kernels treat a column by its place in a panel of 4 (or 8) columns, and matrix-vector or
// coefficient-wise paths are taken only for results one column or a few entries wide. Chunks
// therefore start at multiples of 32 columns and none is narrower than 32 (the last takes the rest);
// chunks of 10 or 30 columns do change the last bits.
#include <Eigen/Core>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace cf::bem {

constexpr Eigen::Index kColumnChunk = 32;

// f(first column, number of columns) for each chunk of [0, n), in parallel.
template <class F>
void for_column_chunks(Eigen::Index n, F&& f) {
    const Eigen::Index chunks = std::max<Eigen::Index>(1, n / kColumnChunk);
    tbb::parallel_for(Eigen::Index(0), chunks, [&](Eigen::Index i) {
        const Eigen::Index c0 = i * kColumnChunk;
        f(c0, i + 1 == chunks ? n - c0 : kColumnChunk);
    });
}

}  // namespace cf::bem
