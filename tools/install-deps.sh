#!/usr/bin/env bash
# Installs the Debian packages pcnc needs to build, test and benchmark.
# Safe to run twice: it installs only what is missing, and does nothing when all is there.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libboost-dev libcli11-dev libspdlog-dev libfmt-dev
  libgtest-dev libgmock-dev libtomlplusplus-dev nlohmann-json3-dev
  clang libclang-rt-14-dev stress-ng
  zlib1g-dev # the run report packs its 3D view's script and data (gzip)
  libjs-three # three.js, inlined into the run report's interactive 3D view
  chromium   # headless rendering test of the HTML run report (tests/test_report_html.cpp)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
