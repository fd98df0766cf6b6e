#pragma once
// CF_AVX2_CLONE: compile a hot function twice, for plain x86-64 and for AVX2, and pick one when the
// program loads (GCC function multiversioning: no -march flag, the binary still runs anywhere).
//
// The AVX2 clone runs the same IEEE operations in the same order, only on wider registers and with
// three-operand instructions: it does not enable FMA (contracting a*b+c changes rounding), so both
// clones give bit-identical results and a run's output does not depend on the machine's ISA level.
// (pair_integrals.cpp's kernel, older, uses the x86-64-v3/v4 levels, FMA included.)
//
// Not under ThreadSanitizer: the clone's resolver runs while the program is being relocated, before
// TSan's runtime is set up, and its instrumentation crashes the process at start.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && !defined(__SANITIZE_THREAD__)
#define CF_AVX2_CLONE __attribute__((target_clones("avx2", "default")))
#else
#define CF_AVX2_CLONE
#endif
