#!/usr/bin/env bash
# Installs the Debian packages pcnc needs to build, test and benchmark, and the test-only npm
# packages of the CNCjs end-to-end test (tests/e2e/README.md) into .cache/e2e (project-local;
# running pcnc never needs them; PCNC_SKIP_NPM=1 leaves them out).
# Safe to run twice: it installs only what is missing, and does nothing when all is there.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libboost-dev libcli11-dev libspdlog-dev libfmt-dev
  libgtest-dev libgmock-dev libtomlplusplus-dev nlohmann-json3-dev
  clang libclang-rt-14-dev lld stress-ng
  zlib1g-dev # the run report packs its 3D view's script and data (gzip)
  libjs-three # three.js, inlined into the run report's interactive 3D view
  chromium   # headless rendering test of the HTML run report (tests/test_report_html.cpp)
  nodejs     # node and npm: the CNCjs end-to-end test of the grbl port (tests/test_proc_grbl_cncjs.cpp)
)

# The npm packages of the CNCjs test, pinned; installed once into .cache/e2e.
install_e2e() {
  [ "${PCNC_SKIP_NPM:-0}" = 1 ] && return 0
  local dir
  dir="$(cd "$(dirname "$0")/.." && pwd)/.cache/e2e"
  if [ -x "$dir/node_modules/.bin/cncjs" ] && [ -d "$dir/node_modules/socket.io-client" ] && [ -d "$dir/node_modules/playwright-core" ]; then
    echo "install-deps: CNCjs test packages present in $dir"
    return 0
  fi
  mkdir -p "$dir"
  echo "install-deps: npm install cncjs, socket.io-client, playwright-core into $dir"
  (cd "$dir" && npm install --no-audit --no-fund --loglevel=error --prefix "$dir" \
     cncjs@1.11.5 socket.io-client@2.5.0 playwright-core@1.65.1) ||
    echo "install-deps: npm install failed: the CNCjs test will skip"
}
trap install_e2e EXIT

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
