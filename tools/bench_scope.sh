#!/usr/bin/env bash
# bench_scope.sh — the rt's cycle timing over examples/demo.ngc on the real clock, once without
# and once with scope captures running back to back (six of 2 s, six signals), each under a
# fresh `pcnc serve` on a private copy of the default config. Prints the rt's compute and
# wake-up figures of both runs (whole rt life: start, program, end). Figures, never pass/fail;
# on a shared or virtual machine the wake-up figures are the machine's, not pcnc's.
#   tools/bench_scope.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
dir=$(mktemp -d /tmp/pcnc-bench-scope.XXXXXX)
chmod 700 "$dir"
trap 'rm -rf "$dir"' EXIT
sed -e "s|^shm_name = .*|shm_name = \"/pcnc-bench-scope-$$\"|" \
    -e "s|^# socket_path = .*|socket_path = \"$dir/control.sock\"|" \
    -e "s|^# state_dir = .*|state_dir = \"$dir/state\"|" "$root/configs/desktop-mill.toml" > "$dir/mill.toml"
ctl() { "$build/tools/pcnc" ctl --config "$dir/mill.toml" "$@"; }
for mode in without with; do
  "$build/tools/pcnc" serve --config "$dir/mill.toml" --clock real > "$dir/serve-$mode.log" 2>&1 &
  sp=$!
  for _ in $(seq 50); do ctl status > /dev/null 2>&1 && break; sleep 0.1; done
  cp=
  if [ "$mode" = with ]; then
    (for i in 1 2 3 4 5 6; do
       ctl capture --signals cmd_x,act_x,ferr_x,cmd_y,act_y,ferr_y --seconds 2 -o "$dir/c$i.html" > /dev/null || echo "capture $i failed"
     done) &
    cp=$!
  fi
  ctl run --wait "$root/examples/demo.ngc" | tail -1
  [ -n "$cp" ] && wait "$cp"
  echo "$mode captures: $(ctl status --json | python3 -c "import json,sys; t=json.load(sys.stdin)['result']['timing']; print('compute mean %.2f us p99 %.2f us max %.1f us; wake-up p99 %.1f us max %.1f us; %d overruns' % (t['compute_mean_us'], t['compute_p99_us'], t['compute_max_us'], t['wake_p99_us'], t['wake_max_us'], t['overruns']))")"
  kill "$sp"
  wait "$sp" 2> /dev/null || true
done
