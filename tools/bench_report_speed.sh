#!/usr/bin/env bash
# bench_report_speed.sh — figures, not tests: how fast `pcnc run --clock virtual` replays with
# and without `--report` (docs/replay.md, "Replay speed with a report"). For each program it
# runs `pcnc run FILE --fit --clock virtual` plainly, with `--report R.html` (the compact
# trace), and with `--report R.html --trace T.csv` (the full CSV, as every report was made
# before the compact trace), N times each, and prints for the fastest run: machine time / wall
# time of the whole command (both processes' start, the check, the replay, the report), the
# CPU time of all three processes (user + system: less sensitive to a busy machine than the
# wall time), the report's size and the CSV's size. The runs use the surfacing bench's settings
# (tools/bench_surfacing.sh: --contouring on --tolerance 0.005, smoothing on), not the programs'
# own G64 P0.1.
# Usage: tools/bench_report_speed.sh [BUILD_DIR] [RUNS] [PROGRAM...]
#   default: build 3 linuxcnc-tp/LHchips4.ngc linuxcnc-tp/blur_torus.ngc fusion360/Key_Pockets.nc
#   (programs relative to ../shared/gcode/cam)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
RUNS=${2:-3}
shift $(( $# < 2 ? $# : 2 ))
PROGRAMS=("$@")
[ ${#PROGRAMS[@]} -gt 0 ] || PROGRAMS=(linuxcnc-tp/LHchips4.ngc linuxcnc-tp/blur_torus.ngc fusion360/Key_Pockets.nc)
PCNC=$BUILD/tools/pcnc
SHARED=$(cd .. && pwd)/shared
[ -x "$PCNC" ] || { echo "bench_report_speed: $PCNC not built (cmake --build $BUILD --target pcnc pcnc-rt pcnc-host)"; exit 2; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# a private segment, socket and state directory, so a running pcnc elsewhere is not disturbed,
# and 2 s heartbeat timeouts (tools/private_config.sh)
source tools/private_config.sh
private_config configs/desktop-mill.toml benchrep "$TMP" >"$TMP/mill.toml"

# timed OUT ARGS... : runs pcnc run ARGS RUNS times; prints "WALL CPU" of the fastest run
timed() {
  local out=$1
  shift
  python3 - "$RUNS" "$out" "$PCNC" run "$@" --config "$TMP/mill.toml" -q <<'EOF'
import resource, subprocess, sys, time
runs, out, argv = int(sys.argv[1]), sys.argv[2], sys.argv[3:]
best = None
for _ in range(runs):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    with open(out, "w") as o, open(out + ".err", "w") as e:
        rc = subprocess.run(argv, stdout=o, stderr=e).returncode
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if rc != 0:  # a busy machine can starve a heartbeat: say so, keep the other runs
        print(f"bench_report_speed: exit {rc} (run left out): {' '.join(argv)}\n" + open(out + ".err").read()[-400:],
              file=sys.stderr)
        continue
    if best is None or wall < best[0]:
        best = (wall, cpu)
        with open(out) as o, open(out + ".best", "w") as b:
            b.write(o.read())
if best is None:
    sys.exit("bench_report_speed: every run failed")
print(f"{best[0]:.3f} {best[1]:.3f}")
EOF
}

OPTS=(--fit --clock virtual --contouring on --tolerance 0.005)

mb() { [ -f "$1" ] && python3 -c "import os,sys; print(f'{os.path.getsize(sys.argv[1])/1e6:.2f} MB')" "$1" || echo "-"; }

echo "== pcnc replay speed with and without --report ($(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg) at the start; fastest of $RUNS)"
printf "   %-28s %9s  %-15s %8s %7s %8s %10s %10s\n" program machine run wall speed cpu report csv
for p in "${PROGRAMS[@]}"; do
  f=$SHARED/gcode/cam/$p
  rm -f "$TMP"/*.html "$TMP"/*.csv
  read -r w0 c0 < <(timed "$TMP/o0" "$f" "${OPTS[@]}")
  machine=$(sed -n 's/^  program time *\([0-9.]*\) s machine time.*/\1/p' "$TMP/o0.best")
  read -r w1 c1 < <(timed "$TMP/o1" "$f" "${OPTS[@]}" --report "$TMP/r1.html")
  read -r w2 c2 < <(timed "$TMP/o2" "$f" "${OPTS[@]}" --report "$TMP/r2.html" --trace "$TMP/t2.csv")
  for row in "plain|$w0|$c0|-|-" "--report|$w1|$c1|$TMP/r1.html|-" "--report --trace|$w2|$c2|$TMP/r2.html|$TMP/t2.csv"; do
    IFS='|' read -r kind w c r t <<<"$row"
    speed=$(python3 -c "print(f'{$machine / $w:.0f}x')")
    printf "   %-28s %8ss  %-15s %7.3fs %7s %7.3fs %10s %10s\n" "$p" "$machine" "$kind" "$w" "$speed" "$c" "$(mb "$r")" "$(mb "$t")"
  done
done
