#!/bin/bash
# The AVX-512 clones of the functions marked CF_AVX512_CLONE (nodes/domain/isa_clones.hpp) give the
# bits of their baseline and AVX2 clones only if the compiler did not contract a*b+c into an FMA
# (x86-64-v4 has FMA; the files holding them are compiled with -ffp-contract=off). This disassembles
# every x86-64-v4 clone in the executable and fails on any FMA instruction, except in the functions
# that are documented to use FMA (CF_ISA_LEVEL_CLONES: the P1 pair kernel).
# usage: no_fma_in_exact_clones.sh CRACKFLOW_EXECUTABLE MIN_CLONES
set -euo pipefail
exe=$1
min=$2
allowed='pair_kernel'
checked=0
for sym in $(nm "$exe" | awk '$3 ~ /\.arch_x86_64_v4$/ {print $3}'); do
    if [[ $sym =~ $allowed ]]; then continue; fi
    fma=$(objdump -d --no-show-raw-insn --disassemble="$sym" "$exe" | grep -cE '\svfn?m(add|sub)' || true)
    echo "$sym: $fma FMA instructions"
    if [ "$fma" != 0 ]; then
        echo "FAIL: $sym contracts a*b+c into FMA; compile its file with -ffp-contract=off" >&2
        exit 1
    fi
    checked=$((checked + 1))
done
if [ "$checked" -lt "$min" ]; then
    echo "FAIL: found $checked AVX-512 clones to check, expected at least $min (were the clones dropped?)" >&2
    exit 1
fi
echo "OK: $checked AVX-512 clones without FMA"
