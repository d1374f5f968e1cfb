#!/usr/bin/env bash
# Installs, builds and runs squint's main job: 45 simulated minutes of closed-loop exploration of
# the built-in `default` building, writing explore-out/summary.json, map.png and trace.csv.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh --target squint
./build/squint explore --world default --minutes 45 --seed 1 --out explore-out "$@"
echo "map of the run: $(pwd)/explore-out/map.png"
