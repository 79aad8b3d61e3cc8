#!/bin/sh
# Short asserted version of examples/rbc_flow (issue 28, a cell in Poiseuille flow): tube.toml at the
# sweep's lowest and highest mean speeds (0.25 and 2 mm/s), 3,000 steps each (about 25 s each), shapes
# averaged over the second half: the first minutes of the example's runs, where a disc facing the flow
# cups into a parachute the faster the flow. Asserts that the cup deepens with the flow (depth / D rises
# by more than 0.05), that the fast cell is a cup (depth / D > 0.1) and that no fluid particle crossed the
# membrane.
# usage: flow_test.sh MESODPD SOURCE_DIR WORK_DIR
set -e
app=$1; src=$2/examples/rbc_flow; work=$3
rm -rf "$work"; mkdir -p "$work"
for g in 0.1218 0.9747; do
  sed -e "s/^body_force = \[0\.487,/body_force = [$g,/" "$src/tube.toml" > "$work/tube_$g.toml"
  "$app" run "$work/tube_$g.toml" --out "$work/g$g" --steps 3000 --no-progress > /dev/null
done
/usr/bin/python3 "$src/check_flow.py" "$work/g0.1218" "$work/g0.9747" --start-fraction 0.5 --rising depth 0.05 --min-depth 0.1
