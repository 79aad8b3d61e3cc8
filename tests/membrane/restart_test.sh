#!/bin/sh
# A restart of a run with cells (cells_at_haematocrit.toml) continues it bit for bit: thermo.csv and
# cells.csv equal to an uninterrupted run's, after a restart from a checkpoint that the first run went
# past (its rows after the checkpoint's step are dropped, not repeated), and cells.gsd has one frame per
# output step.
# usage: restart_test.sh MESODPD SOURCE_DIR WORK_DIR
set -e
app=$1; toml=$2/tests/membrane/cells_at_haematocrit.toml; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work"
"$app" run "$toml" --out whole --steps 200 > /dev/null
"$app" run "$toml" --out split --steps 100 > /dev/null
cp split/checkpoint.mdpd at100.mdpd
"$app" run "$toml" --out split --steps 150 --restart split/checkpoint.mdpd > /dev/null
"$app" run "$toml" --out split --steps 200 --restart at100.mdpd > /dev/null
cmp whole/thermo.csv split/thermo.csv
cmp whole/cells.csv split/cells.csv
/usr/bin/python3 "$2/tests/membrane/check_cells_gsd.py" split/cells.gsd --steps 50 100 150 200
echo PASS
