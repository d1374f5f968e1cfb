#!/usr/bin/env bash
# Configures and builds squint (Release) into ./build after installing its Debian packages.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" "$@"
