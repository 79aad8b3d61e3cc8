#!/usr/bin/env bash
# Side-by-side throughput of mesodpd and LAMMPS (Debian's lammps package, pair_style dpd) on the
# standard DPD fluid, same machine, same run. Usage: bench/compare_lammps.sh [N] [STEPS] [THREADS]
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-98304}; steps=${2:-200}; threads=${3:-1}
len=$(/usr/bin/python3 -c "print(($n/3.0)**(1/3))")
lmp=$(command -v lmp || command -v lmp_serial || command -v lmp_openmpi || true)
[[ -n "$lmp" ]] || { echo "compare_lammps: LAMMPS not installed (apt-get install lammps)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rate_lammps() {  # skin, sort interval
  OMP_NUM_THREADS=$threads "$lmp" -in bench/lammps/in.dpd -log "$work/log.lammps" -screen none \
    -var L "$len" -var N "$n" -var STEPS "$steps" -var SKIN "$1" -var SORT "$2" >/dev/null || true
  if grep -q "^ERROR" "$work/log.lammps"; then
    echo "compare_lammps: LAMMPS failed: $(grep -m1 '^ERROR' "$work/log.lammps")" >&2
    echo "(Debian 12's lammps package lacks the DPD-BASIC package; use a LAMMPS built with it)" >&2
    exit 1
  fi
  # "Loop time of T on P procs for S steps with N atoms": the second run is the timed one.
  awk -v n="$n" '/^Loop time of/ {t=$4; s=$9} END {printf "%.4g", n*s/t}' "$work/log.lammps"
}
mesodpd_rate=$(build/bench/bench_fluid --n "$n" --threads "$threads" --steps "$steps" --warmup 50 | tail -1 | awk '{print $5}')
lammps_default=$(rate_lammps 0.3 1000) || exit 1
lammps_tuned=$(rate_lammps 0.5 20) || exit 1
echo "N=$n threads=$threads steps=$steps"
echo "mesodpd                         $mesodpd_rate particle-steps/s"
echo "LAMMPS dpd (skin 0.3, sort 1000) $lammps_default particle-steps/s"
echo "LAMMPS dpd (skin 0.5, sort 20)   $lammps_tuned particle-steps/s"
/usr/bin/python3 -c "print(f'ratio mesodpd / LAMMPS: {$mesodpd_rate/$lammps_default:.2f}x (default), {$mesodpd_rate/$lammps_tuned:.2f}x (tuned)')"
