#!/usr/bin/env bash
# What moving rigid bodies cost (issue 26's benchmark): 100 spheres of radius 2 on a 5 x 5 x 4 lattice in
# a 33^3 box of the standard fluid (about 10^5 solvent particles), three ways, runs alternating:
#   bodies: every sphere a free [[body]] (bounce-back, force sums, contacts, particle placement);
#   fixed:  the same spheres as fixed [[solid]] walls (layer reflections);
#   fluid:  the same box without spheres;
#   sp-DPD: 100 single-particle DPD colloids (pair.style = "spdpd") in the same box of solvent.
# Rates count all particles (particle-steps/s = particles x steps / seconds of the step loop); the cost
# columns are each run's time over the fluid's, minus 1, and the bodies' time over the fixed spheres'.
# Usage: bench/bodies_cost.sh BUILD_DIR [REPS=2] [STEPS=300] [THREADS=1]   (an idle machine, please)
set -euo pipefail
build=$1
reps=${2:-2}
steps=${3:-300}
threads=${4:-1}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
/usr/bin/python3 - "$work" "$steps" <<'PY'
import sys
work, steps = sys.argv[1], int(sys.argv[2])
head = f"""[system]
box = [33, 33, 33]
kT = 1.0
seed = 100
[[species]]
name = "S"
density = 3
[[species]]
name = "W"
frozen = true
[pair]
a = 25.0
gamma = 4.5
[integrator]
dt = 0.02
[run]
steps = {steps}
[output]
thermo_every = 100
progress = false
"""
solids, bodies = "", ""
k = 0
for i in range(5):
    for j in range(5):
        for l in range(4):
            c = [3.3 + 6.6 * i, 3.3 + 6.6 * j, 4.125 + 8.25 * l]
            solids += f'[[solid]]\nname = "c{k}"\nspecies = "W"\nshape = "sphere"\ncenter = {c}\nradius = 2.0\n'
            bodies += f'[[body]]\nsolid = "c{k}"\noutput_every = 0\n'
            k += 1
open(f"{work}/fluid.toml", "w").write(head)
# Single-particle DPD colloids instead (the parameters of examples/colloids/brownian.toml: radius 1.5,
# colloid-solvent pairs to r = 2; hydrodynamic radius ~1.5 there, against ~2 for the frozen spheres),
# 100 of them placed at random in the same box of solvent.
sp = head.replace('[[species]]\nname = "S"\ndensity = 3\n[[species]]\nname = "W"\nfrozen = true\n',
                  '[[species]]\nname = "S"\nradius = 0.5\ndensity = 3\n[[species]]\nname = "C"\nradius = 1.5\nmass = 42.4\ncount = 100\n')
sp = sp.replace('[pair]\na = 25.0\ngamma = 4.5\n', '[pair]\nstyle = "spdpd"\na = 25.0\ngamma = 4.5\ngamma_perp = 4.5\n'
                '[[pair.override]]\nspecies = ["C", "S"]\na = 150.0\nrc = 2.0\ngamma = 15.0\ngamma_perp = 15.0\ns = 0.5\n'
                '[[pair.override]]\nspecies = ["C", "C"]\na = 200.0\nrc = 2.0\ngamma = 0.0\ngamma_perp = 0.0\n')
assert "spdpd" in sp and "count = 100" in sp
open(f"{work}/spdpd.toml", "w").write(sp)
open(f"{work}/fixed.toml", "w").write(head + solids)
open(f"{work}/bodies.toml", "w").write(head + solids + bodies)
PY
run() {  # prints "particles seconds" of one run
  "$build/mesodpd" run "$1" --out "$work/out" --threads "$threads" 2>/dev/null |
    sed -n -e 's/^mesodpd [^:]*: \([0-9]*\) particles.*/\1/p' -e 's/^done: [0-9]* steps in \([0-9.e+]*\) s.*/\1/p' | tr '\n' ' '
  echo
}
echo "# $steps steps, $threads thread(s); M particle-steps/s of bodies, fixed, fluid, sp-DPD; cost vs fluid; bodies vs fixed; sp-DPD vs bodies"
for rep in $(seq 1 "$reps"); do
  read -r nb tb < <(run "$work/bodies.toml")
  read -r nf tf < <(run "$work/fixed.toml")
  read -r nl tl < <(run "$work/fluid.toml")
  read -r ns ts < <(run "$work/spdpd.toml")
  awk -v rep="$rep" -v nb="$nb" -v tb="$tb" -v nf="$nf" -v tf="$tf" -v nl="$nl" -v tl="$tl" -v ns="$ns" -v ts="$ts" -v s="$steps" 'BEGIN {
    printf "%d  %.3g %.3g %.3g %.3g  bodies %+.1f%% fixed %+.1f%%  bodies/fixed %+.1f%%  step time sp-DPD/bodies %.2f  (N = %d, %d, %d, %d)\n", rep,
      nb * s / tb / 1e6, nf * s / tf / 1e6, nl * s / tl / 1e6, ns * s / ts / 1e6, 100 * (tb / tl - 1), 100 * (tf / tl - 1),
      100 * (tb / tf - 1), ts / tb, nb, nf, nl, ns }'
done
