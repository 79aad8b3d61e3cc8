#!/usr/bin/env bash
# What each integrator costs against Groot-Warren (issue 27): the standard fluid (rho = 3, a = 25,
# gamma = Gamma = 4.5; Stoyanov-Groot Gamma = 0.5, alpha = 4.5; dt = 0.04) in a 16^3 box, N = 12,288,
# on 1 and 2 threads, every scheme in one sitting and alternating, so that a drift of the machine's
# speed hits them all alike. The rate is the command's own (particle-steps/s of the step loop); thermo
# rows only at the end.
# Usage: examples/thermostats/cost.sh [BUILD_DIR=build] [REPS=3] [STEPS=1000]   (an idle machine, please)
set -euo pipefail
build=${1:-build}
reps=${2:-3}
steps=${3:-1000}
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
schemes="groot_warren lowe_andersen shardlow peters stoyanov_groot"
for s in $schemes; do
  sed -e 's/^box = .*/box = [16.0, 16.0, 16.0]/' -e "s/^steps = .*/steps = $steps/" \
      -e "s/^thermo_every = .*/thermo_every = $steps/" "$here/$s.toml" > "$work/$s.toml"
done
echo "# $(lscpu | sed -n 's/^Model name: *//p'); $(nproc) CPUs; load: $(uptime | sed 's/.*load average: //')"
simd=$("$build/mesodpd" run "$work/groot_warren.toml" --out "$work/probe" --threads 1 --steps 1 2>/dev/null |
       sed -n 's/.*SIMD \([^,]*\),.*/\1/p')
echo "# SIMD $simd; $(grep -q 'MESODPD_SINGLE:BOOL=ON' "$build/CMakeCache.txt" 2>/dev/null && echo single || echo double) precision"
echo "# N = 12288, $steps steps per run; columns: rep threads scheme particle-steps/s"
for rep in $(seq 1 "$reps"); do
  for threads in 1 2; do
    for s in $schemes; do
      rate=$("$build/mesodpd" run "$work/$s.toml" --out "$work/out_$s" --threads "$threads" 2>/dev/null |
             sed -n 's/^done: .*(\([0-9.e+]*\) particle-steps\/s)/\1/p')
      echo "$rep $threads $s $rate"
    done
  done
done
echo "# load after: $(uptime | sed 's/.*load average: //')"
