#!/usr/bin/env bash
# bench_rt_latency.sh — real-clock figures of pcnc-rt's 2 kHz loop (benchmark, never a test):
# wake-up latency p50/p99/p99.9/max, compute time and overruns, over SECONDS idle and over
# SECONDS with both cores loaded by stress-ng. Usage: tools/bench_rt_latency.sh [SECONDS] [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-60}
build=${2:-build}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
sed -e "s|shm_name = \"/pcnc-desktop-mill\"|shm_name = \"/pcnc-bench-lat-$$\"|" \
    -e "s|^# socket_path = .*|socket_path = \"$tmp/s.sock\"|" \
    -e "s|^# state_dir = .*|state_dir = \"$tmp/state\"|" \
    configs/desktop-mill.toml > "$tmp/bench.toml"

measure() {
  local label=$1
  "$build/rt/pcnc-rt" --config "$tmp/bench.toml" --clock real 2> "$tmp/rt.log" &
  local pid=$!
  sleep "$secs"
  kill -TERM "$pid"
  wait "$pid" || true
  echo "$label ($secs s):"
  grep -E "SCHED_FIFO|mlockall|memory locked" "$tmp/rt.log" | sed 's/^.*\] /  /'
  grep "stopped after" "$tmp/rt.log" | sed 's/^.*\] /  /'
}

echo "kernel: $(uname -r) $(uname -v | cut -c1-40); $(nproc) cores"
measure "idle"
if command -v stress-ng >/dev/null; then
  stress-ng --cpu "$(nproc)" --timeout "$((secs + 5))s" --quiet &
  spid=$!
  sleep 1
  measure "both cores loaded (stress-ng --cpu $(nproc))"
  kill "$spid" 2>/dev/null || true
  wait "$spid" 2>/dev/null || true
else
  echo "stress-ng not installed: skipped the loaded run (apt-get install stress-ng)"
fi
