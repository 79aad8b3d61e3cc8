#!/usr/bin/env bash
# Side-by-side throughput of two or more builds in one sitting: the standard fluid (rho = 3, a = 25,
# gamma = 4.5, dt = 0.04) at N = 98,304 on 1 and 2 threads, builds alternating, repeated. A build may
# carry a SIMD cap for the run-time dispatched pair loop as DIR@avx2 (MESODPD_SIMD=avx2).
# Usage: bench/side_by_side.sh REPS BUILD_DIR[@simd] BUILD_DIR[@simd] ...   (an idle machine, please)
# Prints one line per run: build, simd cap, repetition, threads, particle-steps/s.
set -euo pipefail
reps=$1
shift
n=${BENCH_N:-98304}
for rep in $(seq 1 "$reps"); do
  for spec in "$@"; do
    dir=${spec%@*}
    simd=best
    [[ $spec == *@* ]] && simd=${spec#*@}
    for t in 1 2; do
      rate=$(MESODPD_SIMD=$simd "$dir/bench/bench_fluid" --n "$n" --threads "$t" --steps 300 --warmup 50 |
             awk '!/^#/ && $1 ~ /^[0-9]+$/ {print $5}')
      echo "$dir $simd $rep $t $rate"
    done
  done
done
