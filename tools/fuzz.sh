#!/usr/bin/env bash
# fuzz.sh — builds the libFuzzer targets in build-fuzz (clang, ASan, UBSan; or in the build
# $PCNC_FUZZ_BUILD names, which tools/test.sh sets to its clang ASan build) and runs each for
# N seconds (default 60, or $PCNC_FUZZ_SECONDS): fuzz_gcode (the G-code front end, seeded from
# ../shared/gcode) and fuzz_protocol (the control protocol's parsing and dispatch against an
# in-process machine, seeded from fuzz/corpus_protocol). Exits non-zero on a crash, a hang or
# a leak; the input that caused it is left in build-fuzz/fuzz-out-TARGET (crash-*, timeout-*,
# leak-*). The targets run at the same time, one process each.
# Ends with one line per target: executions, exec/s, coverage (cov: edges, ft: features).
# Usage: tools/fuzz.sh [SECONDS] [gcode|protocol ...]   (no target: both)
set -euo pipefail
secs="${1:-${PCNC_FUZZ_SECONDS:-60}}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(gcode protocol)
root="$(cd "$(dirname "$0")/.." && pwd)"
shared="${PCNC_SHARED_DIR:-$root/../shared}"
build="${PCNC_FUZZ_BUILD:-$root/build-fuzz}"

if [ -n "${PCNC_FUZZ_BUILD:-}" ]; then
  # tools/test.sh's ASan+UBSan build, configured there with -DPCNC_FUZZ=ON: used as it is
  grep -q '^PCNC_FUZZ:BOOL=ON' "$build/CMakeCache.txt" 2>/dev/null ||
    { echo "fuzz.sh: $build is not a build configured with -DPCNC_FUZZ=ON" >&2; exit 2; }
else
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DPCNC_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_UNITY_BUILD=ON >/dev/null
  # (-g1: line tables, enough for a crash report; a unity build compiles the libraries in batches)
fi
cmake --build "$build" -j2 --target "${targets[@]/#/fuzz_}"

# The targets run side by side (one core each on CI's two), each in a directory of its own so
# that a crash-* file names its target; the reports follow in order once all have ended.
cd "$build"
pids=()
for t in "${targets[@]}"; do
  # New inputs go to the first (scratch) directory; the seed directories are only read.
  work="$build/fuzz-corpus-$t"
  mkdir -p "$work" "$build/fuzz-out-$t"
  seeds=()
  case "$t" in
    gcode)
      [ -d "$shared/gcode" ] && seeds+=("$shared/gcode")
      args=(-max_len=8192 -dict="$root/fuzz/gcode.dict")
      ;;
    protocol)
      seeds+=("$root/fuzz/corpus_protocol")
      args=(-max_len=4096 -dict="$root/fuzz/protocol.dict")
      ;;
    *) echo "fuzz.sh: unknown target '$t' (gcode, protocol)" >&2; exit 2 ;;
  esac
  echo "fuzzing $t for ${secs} s (seeds: ${seeds[*]:-none}; log: $build/fuzz-$t.log)"
  (cd "$build/fuzz-out-$t" &&  # crash-* files land here
    exec "$build/fuzz/fuzz_$t" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 "${args[@]}" \
      -print_final_stats=1 "$work" "${seeds[@]}" >"$build/fuzz-$t.log" 2>&1) &
  pids+=($!)
done

summary=()
failed=0
for i in "${!targets[@]}"; do
  t=${targets[$i]}
  log="$build/fuzz-$t.log"
  rc=0
  wait "${pids[$i]}" || rc=$?
  echo "---- fuzz_$t ----"
  tail -n 12 "$log"
  if [ "$rc" -ne 0 ]; then
    # The report's head (what failed and where) and the input, so a CI log alone reproduces it:
    # base64 -d > crash.bin; build-asan/fuzz/fuzz_gcode crash.bin
    echo "---- the report's first lines ----"
    sed -n '/ERROR: \|runtime error\|==[0-9]*==\|deadly signal/,$p' "$log" | head -n 60
    for f in "$build/fuzz-out-$t"/crash-* "$build/fuzz-out-$t"/timeout-* "$build/fuzz-out-$t"/leak-*; do
      [ -f "$f" ] || continue
      echo "---- $f ($(stat -c %s "$f") bytes), base64 ----"
      head -c 8192 "$f" | base64
    done
    echo "fuzz.sh: fuzz_$t failed (exit $rc); see $log and the crash-*/timeout-*/leak-* file in $build/fuzz-out-$t" >&2
    failed=$rc
    continue
  fi
  # The last status line ("#N DONE cov: C ft: F ... exec/s: E") and the final stats.
  last=$(grep -E '^#[0-9]+' "$log" | tail -n 1)
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  summary+=("fuzz_$t: ${secs} s, ${execs} executions, ${rate} exec/s, cov ${cov}, ft ${ft}")
done
[ "$failed" -ne 0 ] && exit "$failed"
printf '%s\n' "${summary[@]}"
