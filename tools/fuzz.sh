#!/usr/bin/env bash
# fuzz.sh — builds the G-code front end's libFuzzer target in build-fuzz (clang, ASan, UBSan)
# and runs it for N seconds (default 60), seeded from ../shared/gcode. Exits non-zero on a crash.
# Usage: tools/fuzz.sh [SECONDS]
set -euo pipefail
secs="${1:-60}"
root="$(cd "$(dirname "$0")/.." && pwd)"
shared="${PCNC_SHARED_DIR:-$root/../shared}"
build="$root/build-fuzz"

cmake -S "$root" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DPCNC_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" --target fuzz_gcode -j2

# New inputs go to the first (scratch) directory; the shared corpus is only read.
work="$build/fuzz-corpus"
mkdir -p "$work"
seeds=()
[ -d "$shared/gcode" ] && seeds+=("$shared/gcode")
echo "fuzzing the G-code front end for ${secs} s (seeds: ${seeds[*]:-none})"
cd "$build"  # crash-* files land here
"$build/fuzz/fuzz_gcode" -max_total_time="$secs" -max_len=8192 -timeout=10 -rss_limit_mb=2048 \
  -dict="$root/fuzz/gcode.dict" \
  -print_final_stats=1 "$work" "${seeds[@]}"
