#pragma once
// Hot functions compiled for several x86-64 ISA levels, one picked when the program loads (GCC
// function multiversioning, target_clones): no -march flag, the binary still runs anywhere.
//
// CF_AVX2_CLONE: plain x86-64 and AVX2. The AVX2 clone runs the same IEEE operations in the same
// order, only on wider registers and with three-operand instructions: it does not enable FMA
// (contracting a*b+c changes rounding), so both clones give bit-identical results and a run's output
// does not depend on the machine's ISA level.
// CF_AVX512_CLONE: the same with an x86-64-v4 (AVX-512) clone beside them. That level has FMA, so a file
// using it must be compiled with -ffp-contract=off (its CMakeLists says so): then no clone contracts,
// and the three give the same bits.
// CF_ISA_LEVEL_CLONES: the x86-64-v4, v3 and baseline levels, FMA included from v3 on (results may
// differ in the last bits between machines; pair_integrals.cpp's kernel, older, uses it).
//
// Neither under ThreadSanitizer: the clone's resolver runs while the program is being relocated,
// before TSan's runtime is set up, and its instrumentation crashes the process at start.
// The double-precision vectors those clones compute in (GCC vector extensions, lowered to SSE2,
// AVX2 or AVX-512 registers by each clone; element-wise IEEE operations, so every clone gives the
// same bits). Pass them by reference: by value their ABI differs between clones (-Wpsabi).
namespace cf {
typedef double Lanes4 __attribute__((vector_size(4 * sizeof(double))));
typedef double Lanes8 __attribute__((vector_size(8 * sizeof(double))));
}  // namespace cf

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && !defined(__SANITIZE_THREAD__)
#define CF_AVX2_CLONE __attribute__((target_clones("avx2", "default")))
#define CF_AVX512_CLONE __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#define CF_ISA_LEVEL_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define CF_AVX2_CLONE
#define CF_AVX512_CLONE
#define CF_ISA_LEVEL_CLONES
#endif
