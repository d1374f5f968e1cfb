#!/usr/bin/env bash
# Installs, builds and runs every test (unit, end-to-end CLI, benchmark smoke run) with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
cd build
ctest --output-on-failure -j"$(nproc)" --timeout 600
