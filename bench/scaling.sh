#!/usr/bin/env bash
# The performance table of docs/performance.md: particle-steps/s for N = 10^4 .. 10^6 on 1 and 2 threads,
# for the default (double) build in build/ and, if present, the single-precision build in build-single/
# (cmake -S . -B build-single -DMESODPD_SINGLE=ON). Builds alternate and repeat (noisy machines);
# bench/plot_scaling.py plots the best repetition. Usage: bench/scaling.sh [repetitions] > results.txt
set -euo pipefail
cd "$(dirname "$0")/.."
reps=${1:-2}
# The default OpenMP wait policy (threads spin briefly at barriers): with OMP_WAIT_POLICY=passive every
# parallel loop pays a thread wake-up, which on an idle machine costs most of the two-thread speed-up of
# the short loops of a step (docs/performance.md). Run on an otherwise idle machine.
builds=(build)
[[ -x build-single/bench/bench_fluid ]] && builds+=(build-single)
for rep in $(seq 1 "$reps"); do
  for b in "${builds[@]}"; do
    for n in 10000 98304 400000; do
      "$b/bench/bench_fluid" --n "$n" --threads 1 2 --steps 300 --warmup 50 | grep -v -e '^#' -e ' N ' | sed "s|^|$b $rep |"
    done
    # Largest N in its own process, so that its peak RSS is its own.
    "$b/bench/bench_fluid" --n 1000000 --threads 1 2 --steps 60 --warmup 10 | grep -v -e '^#' -e ' N ' | sed "s|^|$b $rep |"
  done
done
