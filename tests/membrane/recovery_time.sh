#!/bin/sh
# Short asserted version of examples/rbc_stretch/recovery.toml + release.toml (issue 28, recovery): the
# same cell at a heavier vertex mass (1e5) and dt = 0.05 ms, stretched for 400 ms and released for 400 ms,
# at eta_m = 0.5 uN s/m and at twice that. Asserts that the 1/e recovery time of the first lies in
# 60-160 ms (Kelvin-Voigt eta_m / mu0 = 79 ms; the example measures ~95 ms) and that doubling eta_m
# doubles it within 15 %. About 40 s.
# usage: recovery_time.sh MESODPD SOURCE_DIR WORK_DIR
set -e
app=$1; src=$2/examples/rbc_stretch; work=$3
rm -rf "$work"; mkdir -p "$work"
short() {  # short FILE VISCOSITY STEPS > toml
  sed -e 's/^mass = .*/mass = 1.0e5/' -e 's/^dt = .*/dt = 0.05/' -e 's/^tweezers_ramp = .*/tweezers_ramp = 1000/' \
      -e "s/^viscosity = .*/viscosity = $2/" -e "s/^steps = .*/steps = $3/" "$1"
}
for v in 116820.0 233640.0; do
  short "$src/recovery.toml" $v 8000 > "$work/stretch_$v.toml"
  short "$src/release.toml" $v 16000 > "$work/release_$v.toml"
  "$app" run "$work/stretch_$v.toml" --out "$work/eta_$v" > /dev/null
  "$app" run "$work/release_$v.toml" --out "$work/eta_$v" --restart "$work/eta_$v/checkpoint.mdpd" > /dev/null
done
/usr/bin/python3 "$src/check_recovery.py" --release 8000 --dt 0.05 --ratio 2 0.15 --band 60 160 "$work/eta_116820.0" "$work/eta_233640.0"
