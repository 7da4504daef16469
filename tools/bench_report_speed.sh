#!/usr/bin/env bash
# bench_report_speed.sh — figures, not tests: how fast `pcnc run --clock virtual` replays with
# and without `--report` (docs/replay.md, "Replay speed with a report"). For each program it
# runs `pcnc run FILE --fit --clock virtual` plainly, with `--report R.html`, and with
# `--report R.html --trace T.csv` (the full CSV, as every report was made before the compact
# trace), best wall time of N runs each, and prints machine time / wall time of the whole
# command (both processes' start, the check, the replay and the report), the report's size
# and the trace's size.
# Usage: tools/bench_report_speed.sh [BUILD_DIR] [RUNS]    (default: build 3)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
RUNS=${2:-3}
PCNC=$BUILD/tools/pcnc
SHARED=$(cd .. && pwd)/shared
[ -x "$PCNC" ] || { echo "bench_report_speed: $PCNC not built (cmake --build $BUILD --target pcnc pcnc-rt pcnc-host)"; exit 2; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# a private segment, socket and state directory, so a running pcnc elsewhere is not disturbed
sed -e "s#^shm_name = .*#shm_name = \"/pcnc-benchrep-$$\"#" -e "s#^\# socket_path = .*#socket_path = \"$TMP/s.sock\"#" \
    -e "s#^\# state_dir = .*#state_dir = \"$TMP/state\"#" configs/desktop-mill.toml >"$TMP/mill.toml"

PROGRAMS=(linuxcnc-tp/LHchips4.ngc linuxcnc-tp/blur_torus.ngc fusion360/Key_Pockets.nc)

# best_run OUT ARGS... : prints "WALL_S" (best of RUNS), leaves the last run's stdout in OUT
best_run() {
  local out=$1 best=""
  shift
  for _ in $(seq "$RUNS"); do
    local t0 t1 w
    t0=$(date +%s.%N)
    "$PCNC" run "$@" --config "$TMP/mill.toml" -q >"$out" 2>"$out.err" || { echo "failed: $* (see below)" >&2; cat "$out.err" >&2; exit 1; }
    t1=$(date +%s.%N)
    w=$(python3 -c "print($t1 - $t0)")
    if [ -z "$best" ] || python3 -c "import sys; sys.exit(0 if $w < $best else 1)"; then best=$w; fi
  done
  echo "$best"
}

echo "== pcnc replay speed with and without --report ($(date -u +%Y-%m-%d), $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg) at the start; best of $RUNS)"
printf "   %-28s %9s  %-22s %9s %9s %10s %10s\n" program machine run wall speed report trace
for p in "${PROGRAMS[@]}"; do
  f=$SHARED/gcode/cam/$p
  w0=$(best_run "$TMP/o0" "$f" --fit --clock virtual)
  machine=$(sed -n 's/^  program time *\([0-9.]*\) s machine time.*/\1/p' "$TMP/o0")
  w1=$(best_run "$TMP/o1" "$f" --fit --clock virtual --report "$TMP/r1.html")
  w2=$(best_run "$TMP/o2" "$f" --fit --clock virtual --report "$TMP/r2.html" --trace "$TMP/t2.csv")
  for row in "plain|$w0|-|-" "--report|$w1|$(stat -c %s "$TMP/r1.html")|-" \
             "--report --trace (CSV)|$w2|$(stat -c %s "$TMP/r2.html")|$(stat -c %s "$TMP/t2.csv")"; do
    IFS='|' read -r kind w rsize tsize <<<"$row"
    speed=$(python3 -c "print(f'{$machine / $w:.0f}x')")
    fmt() { [ "$1" = "-" ] && echo "-" || python3 -c "print(f'{$1/1e6:.2f} MB')"; }
    printf "   %-28s %8ss  %-22s %8.3fs %9s %10s %10s\n" "$p" "$machine" "$kind" "$w" "$speed" "$(fmt "$rsize")" "$(fmt "$tsize")"
  done
done
