#!/usr/bin/env bash
# Installs squint's build and test dependencies from Debian 12's package archive.
set -euo pipefail
pkgs=(build-essential cmake pkg-config
      libopencv-dev libeigen3-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
      libspdlog-dev libfmt-dev libgtest-dev libgmock-dev libbenchmark-dev)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
