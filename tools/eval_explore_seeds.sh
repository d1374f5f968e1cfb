#!/usr/bin/env bash
# Seeded starts over several seeds: `squint eval explore --starts 10 --minutes 3 --seed S` for each
# seed, two at a time, then one line per seed and the total of runs without collision.
#
# Usage: tools/eval_explore_seeds.sh SQUINT OUT_DIR FIRST_SEED LAST_SEED [extra eval options...]
#   e.g. tools/eval_explore_seeds.sh build/squint /tmp/seeds 1 8
# Writes OUT_DIR/seed-S/{table.md,runs.csv,map-*.png} and OUT_DIR/summary.txt. A closed loop's
# outcome is chaotic (any change to the explorer reshuffles which starts fail), so compare
# variants over many seeds, and judge on seeds that were not used to tune them (docs/explore.md,
# session 9); `squint eval compare-explore BASE_DIR VARIANT_DIR` compares two such folders run by
# run. Not part of CI: about 2.5 CPU minutes per seed.
set -euo pipefail
. "$(dirname "$0")/seed_runs.sh"
seed_args "SQUINT OUT_DIR FIRST_SEED LAST_SEED [extra eval options...]" "$@"
one_seed() {
  "$squint" eval explore --starts 10 --minutes 3 --seed "$1" --out "$out/seed-$1" "${extra[@]}" > "$out/seed-$1.log" 2>&1
}
seed_runs one_seed
total=0 runs=0
{
  for s in $(seq "$first" "$last"); do
    csv="$out/seed-$s/runs.csv"
    clean=$(awk -F, 'NR > 1 && $11 == 0' "$csv" | wc -l)
    n=$(awk -F, 'NR > 1' "$csv" | wc -l)
    failed=$(awk -F, 'NR > 1 && $11 > 0 {printf "%s %s; ", $1, $2}' "$csv")
    echo "seed $s: $clean of $n without collision${failed:+ (failed: ${failed%; })}"
    total=$((total + clean)) runs=$((runs + n))
  done
  echo "seeds $first-$last: $total of $runs runs without collision"
} | tee "$out/summary.txt"
