#!/usr/bin/env bash
# What red cells cost (issue 28's performance targets): 492-vertex red cells (D = 8) in 98,304 solvent
# particles (32^3 at rho = 3, the fluid of tests/membrane/membrane_in_solvent.toml): CASE `single`, one
# cell in the middle; CASE `suspension`, 66 cells at a haematocrit of 20 % (the lattice of [[membrane]]
# haematocrit). Run three ways in alternation: the whole model, the model without the bounce-back
# (`bounce = false`), and the solvent alone (no [[membrane]]; the same species). The membrane's share of
# a step is 1 - t(solvent alone) / t(whole), the bounce-back's 1 - t(no bounce) / t(whole). The times
# include the start-up's inside/outside test (about 0.5 s for the suspension): use 300 steps or more.
# Usage: bench/membrane_cost.sh BUILD_DIR [REPS=3] [STEPS=300] [THREADS=1] [CASE=single]   (an idle machine, please)
set -euo pipefail
build=$1
reps=${2:-3}
steps=${3:-300}
threads=${4:-1}
case=${5:-single}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat > "$work/whole.toml" <<TOML
[system]
box = [32.0, 32.0, 32.0]
kT = 1.0
seed = 11
[[species]]
name = "S"
density = 3.0
[[species]]
name = "I"
count = 0
[[species]]
name = "M"
count = 0
[pair]
a = 25.0
gamma = 4.5
rc = 1.0
[[pair.override]]
species = ["M", "M"]
a = 0.0
gamma = 0.0
[integrator]
dt = 0.01
[run]
steps = $steps
[output]
thermo_every = 100
progress = false
[[membrane]]
species = "M"
inner_species = "I"
mesh = "red_cell"
vertices = 500
diameter = 8.0
center = [16.0, 16.0, 16.0]
shear_modulus = 100.0
bending = "juelicher"
kappa = 20.0
ka = 5000.0
kd = 100.0
kv = 5000.0
viscosity = 20.0
TOML
if [ "$case" = suspension ]; then
  sed -i 's/^center = .*/haematocrit = 0.2/' "$work/whole.toml"
elif [ "$case" != single ]; then
  echo "CASE is single or suspension, not $case" >&2; exit 2
fi
sed -e '/^\[\[membrane\]\]/a bounce = false' "$work/whole.toml" > "$work/nobounce.toml"
sed -e '/^\[\[membrane\]\]/,$d' "$work/whole.toml" > "$work/solvent.toml"
secs() {  # seconds of the step loop of one run
  "$build/mesodpd" run "$1" --out "$work/out" --threads "$threads" 2>/dev/null | sed -n 's/^done: [0-9]* steps in \([0-9.e+]*\) s.*/\1/p'
}
echo "# $case: red cells of 492 vertices in 98,304 solvent, $steps steps, $threads thread(s); seconds and shares of the step"
echo "# rep whole no_bounce solvent_alone membrane_share bounce_share"
for rep in $(seq 1 "$reps"); do
  w=$(secs "$work/whole.toml")
  b=$(secs "$work/nobounce.toml")
  s=$(secs "$work/solvent.toml")
  echo "$rep $w $b $s $(awk -v w="$w" -v b="$b" -v s="$s" 'BEGIN { printf "%.1f%% %.1f%%", 100 * (1 - s / w), 100 * (1 - b / w) }')"
done
