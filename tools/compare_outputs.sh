#!/usr/bin/env bash
# Runs every example config (examples/*/*.toml) for a few steps with two builds of mesodpd and compares
# every output file byte for byte (cmp): the check that a refactoring changed no result.
# Usage: tools/compare_outputs.sh OLD_MESODPD NEW_MESODPD [STEPS=20] [THREADS=2]
# Prints one line per example (same / DIFFERENT: files) and exits 1 if any output differs.
set -uo pipefail
old=$1 new=$2 steps=${3:-20} threads=${4:-2}
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
for cfg in examples/*/*.toml; do
  name=$(echo "${cfg#examples/}" | tr / _)
  name=${name%.toml}
  for which in old new; do
    bin=$old; [[ $which == new ]] && bin=$new
    mkdir -p "$work/$which"
    # The same output path for both builds, since messages name it.
    "$bin" run "$cfg" --steps "$steps" --threads "$threads" --no-progress --out "$work/run" \
      >"$work/$which/$name.stdout" 2>&1
    echo $? >"$work/$which/$name.rc"
    mv "$work/run" "$work/$which/$name"
    # The timing line differs from run to run.
    sed -i '/^done: /d; /particle-steps\/s/d; /^bonded forces: .* s of /d' "$work/$which/$name.stdout"
  done
  diffs=""
  cmp -s "$work/old/$name.rc" "$work/new/$name.rc" || diffs+=" exit-code"
  cmp -s "$work/old/$name.stdout" "$work/new/$name.stdout" || diffs+=" stdout"
  for f in $(cd "$work/old/$name" && find . -type f | sort) $(cd "$work/new/$name" && find . -type f | sort); do
    cmp -s "$work/old/$name/$f" "$work/new/$name/$f" || diffs+=" ${f#./}"
  done
  if [[ -z $diffs ]]; then
    echo "same       $cfg ($(ls "$work/new/$name" | wc -l) files, exit $(cat "$work/new/$name.rc"))"
  else
    echo "DIFFERENT  $cfg:$(echo "$diffs" | tr ' ' '\n' | sort -u | tr '\n' ' ')"
    status=1
  fi
done
exit $status
