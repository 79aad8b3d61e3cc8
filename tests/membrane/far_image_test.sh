#!/bin/sh
# A cell placed two box lengths away along x (centre 40 in a 16 box) is the same cell as one at its wrapped
# centre 8: its vertices are gathered unwrapped, about 2 L from the particles near them, and both the
# inner-fluid labelling and the bounce-back must find their nearest image however many periods away (a
# single minimum-image step missed them: no inner fluid and no bounce-back, so a cell that had travelled
# 1.5 box lengths in a flow leaked). Asserts the same number of particles inside, bounce-backs in both
# runs within 10 % of each other, and no particle on the wrong side. About 10 s.
# usage: far_image_test.sh MESODPD SOURCE_DIR WORK_DIR
set -e
app=$1; src=$2/tests/membrane; work=$3
rm -rf "$work"; mkdir -p "$work"
for c in 8.0 40.0; do
  sed -e "s/^center = \[8.0, 8.0, 8.0\]/center = [$c, 8.0, 8.0]/" -e 's/^steps = 2000/steps = 300/' \
      "$src/membrane_in_solvent.toml" > "$work/c$c.toml"
  "$app" run "$work/c$c.toml" --out "$work/c$c" --no-progress > "$work/c$c.log"
done
/usr/bin/python3 - "$work" <<'PY'
import csv, re, sys
work = sys.argv[1]
def summary(c):
    text = open(f"{work}/c{c}.log").read()
    m = re.search(r"membranes: (\d+) bounce-backs.*?; (\d+) particles inside cells, (\d+) of them", text)
    wrong = max(int(r["wrong_side"]) for r in csv.DictReader(open(f"{work}/c{c}/cells.csv")))
    return int(m.group(1)), int(m.group(2)), int(m.group(3)), wrong
near, far = summary("8.0"), summary("40.0")
print("centre 8: bounce-backs %d, inside %d, wrong side %d/%d; centre 40: %d, %d, %d/%d" % (near + far))
ok = near[1] > 0 and near[1] == far[1] and near[0] > 0 and abs(far[0] - near[0]) <= 0.1 * near[0] \
     and near[2] == far[2] == near[3] == far[3] == 0
sys.exit(0 if ok else 1)
PY
