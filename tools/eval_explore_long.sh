#!/usr/bin/env bash
# The main job over several noise seeds: `squint explore --seed S` (the world's own start, 45
# simulated minutes unless the extra options say otherwise) for each seed, two at a time, then one
# line per seed and the totals: runs without collision, runs without a contact felt, runs covering
# 0.95 or more (the main job's targets).
#
# Usage: tools/eval_explore_long.sh SQUINT OUT_DIR FIRST_SEED LAST_SEED [extra explore options...]
#   e.g. tools/eval_explore_long.sh build/squint /tmp/long 1 32
#        tools/eval_explore_long.sh build/squint /tmp/long-w 1 8 --world corridor-2 --minutes 10
# Writes OUT_DIR/seed-S/{summary.json,map.png,trace.csv,events.csv}, OUT_DIR/seed-S.log and
# OUT_DIR/summary.txt. Not part of CI: about a minute of CPU per seed at 45 minutes.
set -euo pipefail
. "$(dirname "$0")/seed_runs.sh"
seed_args "SQUINT OUT_DIR FIRST_SEED LAST_SEED [extra explore options...]" "$@"
command -v python3 > /dev/null || { echo "$0: python3 is needed to read summary.json" >&2; exit 2; }
one_seed() {
  "$squint" explore --seed "$1" --out "$out/seed-$1" "${extra[@]}" > "$out/seed-$1.log" 2>&1
}
seed_runs one_seed
python3 - "$out" "$first" "$last" << 'EOF' | tee "$out/summary.txt"
import json, sys
out, first, last = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
print("seed  coverage  collisions  contacts  distance_m  ends  turns  wall_s")
clean = untouched = covered = 0
for s in range(first, last + 1):
    d = json.load(open(f"{out}/seed-{s}/summary.json"))
    contacts = d.get("contacts_felt", 0)
    print(f"{s:4d}  {d['coverage']:8.3f}  {d['collisions']:10d}  {contacts:8d}  {d['distance_m']:10.0f}  "
          f"{d['ends_detected']:4d}  {d['turns']:5d}  {d['wall_seconds']:6.1f}")
    clean += d["collisions"] == 0
    untouched += d["collisions"] == 0 and contacts == 0
    covered += d["coverage"] >= 0.95
n = last - first + 1
print(f"seeds {first}-{last}: {clean} of {n} without collision, {untouched} without a contact, "
      f"{covered} covering 0.95 or more")
EOF
