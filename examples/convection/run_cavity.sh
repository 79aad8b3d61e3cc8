#!/usr/bin/env bash
# Runs a cavity config and keeps a copy of the binned fields each time the run rewrites them
# ([analysis.fields] write_every): OUT/snap_<step>.csv and .json, the cumulative averages up to that
# step, from which check_cavity.py forms block averages for its error bars.
# usage: examples/convection/run_cavity.sh CONFIG OUT [mesodpd binary, default build/mesodpd]
set -euo pipefail
config=$1 out=$2 bin=${3:-build/mesodpd}
mkdir -p "$out"
OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} "$bin" run "$config" --out "$out" > "$out.log" 2>&1 &
run=$!
snap() {
  if [ -f "$out/cavity.json" ]; then
    step=$(/usr/bin/python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['last_step'])" "$out/cavity.json" 2>/dev/null || true)
    if [ -n "$step" ] && [ ! -f "$out/snap_$step.csv" ]; then
      cp "$out/cavity.csv" "$out/snap_$step.csv"
      cp "$out/cavity.json" "$out/snap_$step.json"
    fi
  fi
}
while kill -0 "$run" 2>/dev/null; do
  snap
  sleep 5
done
wait "$run"
snap
tail -2 "$out.log"
