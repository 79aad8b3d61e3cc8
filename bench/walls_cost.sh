#!/usr/bin/env bash
# What walls cost: seed 004's single pillar between two plates (examples/pillar/pillar.toml: frozen
# walls, Maxwellian reflection, drag sampling; its binned fields left out) against a periodic box of the
# same fluid holding the same number of fluid particles, runs alternating. Both rates count fluid
# particles only (particle-steps/s = fluid particles x steps / seconds of the step loop).
# Usage: bench/walls_cost.sh BUILD_DIR [REPS=3] [STEPS=1500] [THREADS=1]   (an idle machine, please)
# Prints one line per repetition: walls rate, periodic rate, walls time / periodic time - 1 (the cost).
set -euo pipefail
build=$1
reps=${2:-3}
steps=${3:-1500}
threads=${4:-1}
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The pillar case without [analysis.fields] (the last section of the file) and with short runs.
sed -e '/^\[analysis.fields\]/,$d' -e "s/^steps = .*/steps = $steps/" -e 's/^progress = .*/progress = false/' \
    -e "s/^drag_start = .*/drag_start = 0/" -e "s/^equilibrate = .*/equilibrate = 0/" "$root/examples/pillar/pillar.toml" > "$work/walls.toml"
# Its fluid particle count, from the engine's own initial state.
nfluid=$(PYTHONPATH="$build/python" /usr/bin/python3 -c "
import mesodpd
s = mesodpd.Simulation(mesodpd.Spec.from_toml('$work/walls.toml'))
print(int((s.snapshot()['species'] == 0).sum()))")
# The same fluid, periodic, same count, at the same density (60 x 4 x Lz with 4 Lz x 240 = N), with the
# same body force (the whole fluid then accelerates uniformly: the cost per step is the same).
g=$(sed -n 's/^body_force = \[\([0-9.e+-]*\),.*/\1/p' "$work/walls.toml" | head -n 1)
lz=$(awk -v n="$nfluid" 'BEGIN { printf "%.6f", n / (4.0 * 240.0) }')
cat > "$work/periodic.toml" <<TOML
[system]
box = [60, 4, $lz]
kT = 1.0
seed = 4
[[species]]
name = "fluid"
count = $nfluid
body_force = [$g, 0, 0]
[pair]
a = 18.75
gamma = 4.5
sigma = 3.0
s = 0.25
[integrator]
dt = 0.02
[run]
steps = $steps
[output]
thermo_every = 1000
progress = false
TOML
rate() {  # fluid particle-steps/s of one run
  local secs
  secs=$("$build/mesodpd" run "$1" --out "$work/out" --threads "$threads" 2>/dev/null | sed -n 's/^done: [0-9]* steps in \([0-9.e+]*\) s.*/\1/p')
  awk -v n="$nfluid" -v s="$steps" -v t="$secs" 'BEGIN { printf "%.4g", n * s / t }'
}
echo "# $nfluid fluid particles, $steps steps, $threads thread(s); columns: rep walls periodic cost"
for rep in $(seq 1 "$reps"); do
  w=$(rate "$work/walls.toml")
  p=$(rate "$work/periodic.toml")
  echo "$rep $w $p $(awk -v w="$w" -v p="$p" 'BEGIN { printf "%+.1f%%", 100 * (p / w - 1) }')"
done
