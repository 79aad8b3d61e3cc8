#!/bin/sh
# Many cells (issue 28): the haematocrit lattice and the cells_file, and their bad input.
# usage: placement_test.sh MESODPD SOURCE_DIR WORK_DIR
set -e
app=$1; src=$2/tests/membrane; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work"
fail() { echo "FAIL: $*"; exit 1; }
refused() {  # refused TOML PATTERN...: `check` exits non-zero and its error names every pattern
  if "$app" check "$1" 2> err.txt; then fail "$1 was accepted"; fi
  shift
  for p in "$@"; do grep -q -- "$p" err.txt || { cat err.txt; fail "the error does not name '$p'"; }; done
}
# 1. The lattice: 21 cells, 15 % of the box within one cell's share, none leaking, after 200 steps.
"$app" run "$src/cells_at_haematocrit.toml" --out hct > /dev/null
/usr/bin/python3 - <<'PY'
import csv, sys
rows = list(csv.DictReader(open("hct/cells.csv")))
last = [r for r in rows if r["step"] == "200"]
vol = sum(float(r["volume"]) for r in last)
print(f"{len(last)} cells, volume fraction {vol / 18**3:.4f}, wrong side {max(int(r['wrong_side']) for r in rows)}")
if len(last) != 21: sys.exit("expected 21 cells (round(0.15 x 5832 / 41.3))")
if abs(vol / 18**3 - 0.15) > vol / len(last) / 18**3: sys.exit("volume fraction off by more than one cell")
if any(int(r["wrong_side"]) for r in rows): sys.exit("particles on the wrong side")
PY
# cells.gsd: a frame per output step with every vertex, the edges as bonds (3 V - 6 per closed cell), and
# the picture drawn from it finds each cell's 2 V - 4 triangles again.
/usr/bin/python3 "$src/check_cells_gsd.py" hct/cells.gsd --steps 50 100 150 200 --vertices $((21 * 162)) --edges $((21 * 480))
/usr/bin/python3 "$2/tools/render_cells.py" hct/cells.gsd --frames 0 -1 --out hct/cells.png 2> render.err | grep -q '21 cells' \
  || { cat render.err; fail "render_cells.py"; }
if grep -q "not its 2 V - 4 faces" render.err; then fail "render_cells.py did not find the faces"; fi
# 2. A cells_file with turned cells: after one step each centroid is where its line puts it (within 0.05); the axial diameter (along x)
# of a cell turned onto x is its thickness.
sed -e 's/^haematocrit = 0.15/cells_file = "cells.txt"/' -e 's/^steps = 200/steps = 1/' -e 's/^output_every = 50/output_every = 1/' \
    "$src/cells_at_haematocrit.toml" > file.toml
printf '# x y z [axis]\n4 4 4\n12 5 6  1 0 0\n\n5 13 12 0 1 1  # tilted\n' > cells.txt
"$app" run file.toml --out fromfile > /dev/null
/usr/bin/python3 - <<'PY'
import csv, sys
rows = list(csv.DictReader(open("fromfile/cells.csv")))
want = [(4, 4, 4), (12, 5, 6), (5, 13, 12)]
if len(rows) != 3: sys.exit(f"{len(rows)} rows, expected 3")
for r, w in zip(rows, want):
    c = (float(r["cx"]), float(r["cy"]), float(r["cz"]))
    if max(abs(a - b) for a, b in zip(c, w)) > 0.05: sys.exit(f"centroid {c}, expected {w}")
print("axial (x) diameters:", [r["axial"] for r in rows])
if not (float(rows[1]["axial"]) < 3 < 5.5 < float(rows[0]["axial"])): sys.exit("the cell turned onto x is not thin along x")
PY
# 3. Bad input, each refused naming the key (and the file's line).
printf '4 4 4\n7 4 4\n' > overlap.txt
sed 's/cells.txt/overlap.txt/' file.toml > overlap.toml
refused overlap.toml 'membrane\[0\].cells_file' 'line 1 of' 'line 2 of' 'overlap'
printf '4 4 4\n12 5 x6\n' > word.txt
sed 's/cells.txt/word.txt/' file.toml > word.toml
refused word.toml 'word.txt:2' 'x6'
printf '4 4 4 0 0 0\n' > zero.txt
sed 's/cells.txt/zero.txt/' file.toml > zero.toml
refused zero.toml 'zero.txt:1' 'zero vector'
sed 's/^haematocrit = 0.15/haematocrit = 0.5/' "$src/cells_at_haematocrit.toml" > dense.toml
refused dense.toml 'membrane\[0\].haematocrit = 0.5' 'lattice'
sed 's/^haematocrit = 0.15/haematocrit = 0.15\ncenter = [9, 9, 9]/' "$src/cells_at_haematocrit.toml" > both.toml
refused both.toml 'membrane\[0\].haematocrit' 'one of center, cells_file and haematocrit'
sed 's/^haematocrit = 0.15//' "$src/cells_at_haematocrit.toml" > none.toml
refused none.toml 'membrane\[0\].center'
printf '9 9 9\n' > big.txt
sed -e 's/cells.txt/big.txt/' -e 's/^diameter = 6.0/diameter = 17.5/' file.toml > big.toml
refused big.toml 'membrane\[0\].cells_file' 'more than the box'
echo PASS
