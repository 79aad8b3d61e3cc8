#!/usr/bin/env bash
# eDPD and tDPD throughput of mesodpd and LAMMPS (pair_style edpd and tdpd, DPD-MESO package) on one
# core, side by side, in alternation: bench/edpd/README.md. Usage (an idle machine, please):
#   bench/edpd/side_by_side.sh LMP MESODPD [REPS] [STEPS]
# LMP: a LAMMPS binary built with DPD-MESO (and MPI); MESODPD: build/mesodpd. The data file
# bench/edpd/init.lammps_data must exist (LMP -in in.init, run in bench/edpd); the tDPD cases b10
# (solute cutoff 1) and b14 (1.4) run where tdpd.lammps_data exists (LMP -in in.tdpd_init).
# CASES=edpd or CASES=tdpd runs only those. Prints one line per run:
# code, case, settings, repetition, particle-steps/s. Cases: a (edpd.toml), a2 (edpd_const_s.toml), and
# mesodpd's isothermal fluid at the same cutoff (dpd_rc15.toml, s = 0.41 and s = 2).
set -euo pipefail
lmp=$(realpath "$1"); mesodpd=$(realpath "$2"); reps=${3:-3}; steps=${4:-400}
cd "$(dirname "$0")"
[[ -f init.lammps_data || ${CASES:-all} == tdpd ]] ||
  { echo "side_by_side: init.lammps_data missing (run: $lmp -in in.init)" >&2; exit 1; }
n=0
[[ -f init.lammps_data ]] && n=$(awk '/ atoms$/ {print $1; exit}' init.lammps_data)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
lammps() {  # case, poly, s, a
  mpirun --allow-run-as-root -np 1 "$lmp" -in in.run -log "$work/log" -screen none -var steps "$steps" \
    -var skin 0.5 -var sort 20 -var poly "$2" -var s "$3" -var a "$4" > /dev/null
  awk -v n="$n" -v c="$1" -v r="$rep" '/^Loop time of/ {t=$4; s=$9} END {printf "lammps %s skin0.5-sort20 %s %.4g\n", c, r, n*s/t}' "$work/log"
}
mesodpd() {  # case, config, noise
  sed "s/^\[run\]/[run]\nnoise = \"$3\"/" "$2" > "$work/run.toml"
  [[ -f init.lammps_data ]] && cp init.lammps_data "$work/"
  OMP_NUM_THREADS=1 "$mesodpd" run "$work/run.toml" --out "$work/out" --threads 1 --steps "$steps" --no-progress |
    awk -v c="$1" -v z="$3" -v r="$rep" '/particle-steps\/s/ {gsub(/[(]/, "", $(NF-1)); printf "mesodpd %s %s %s %s\n", c, z, r, $(NF-1)}'
}
lammps_tdpd() {  # case, rcc
  mpirun --allow-run-as-root -np 1 "$lmp" -in in.tdpd_run -log "$work/log" -screen none -var steps "$steps" \
    -var rcc "$2" > /dev/null
  awk -v n="$nt" -v c="$1" -v r="$rep" '/^Loop time of/ {t=$4; s=$9} END {printf "lammps %s skin0.5-sort20 %s %.4g\n", c, r, n*s/t}' "$work/log"
}
nt=0
[[ -f tdpd.lammps_data ]] && nt=$(awk '/ atoms$/ {print $1; exit}' tdpd.lammps_data)
for rep in $(seq 1 "$reps"); do
  if [[ $nt -gt 0 && ${CASES:-all} != edpd ]]; then  # tDPD, when in.tdpd_init has written its data file
    cp tdpd.lammps_data "$work/"
    lammps_tdpd b10 1.0
    mesodpd b10 tdpd.toml uniform
    mesodpd b10 tdpd.toml gaussian
    lammps_tdpd b14 1.4
    sed 's/^rcc = 1.0/rcc = 1.4/' tdpd.toml > "$work/tdpd14.toml"
    mesodpd b14 "$work/tdpd14.toml" uniform
  fi
  [[ ${CASES:-all} == tdpd ]] && continue
  lammps a 1 0.41 18.75
  mesodpd a edpd.toml uniform
  mesodpd a edpd.toml gaussian
  lammps a2 0 2.0 25.0
  mesodpd a2 edpd_const_s.toml uniform
  mesodpd a2 edpd_const_s.toml gaussian
  mesodpd dpd-s0.41 dpd_rc15.toml uniform
  sed 's/^s = 0.41/s = 2.0/' dpd_rc15.toml > "$work/dpd_s2.toml"
  mesodpd dpd-s2 "$work/dpd_s2.toml" uniform
done
