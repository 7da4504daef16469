#!/usr/bin/env bash
# bench_surfacing.sh — figures, not tests (issue 14, docs/smoothing.md): 3D surfacing programs
# on the default desktop mill with --fit --contouring on --clock virtual, side by side:
#   M22      every junction an exact stop (the program's G64 made G61 in a copy);
#   M21 t=0  the seed's rule: --tolerance 0 (junctions under the contouring angle flow);
#   smooth   --tolerance 0.005: runs of G1 moves smoothed into curves, corners at the
#            junction-deviation speed;
# and for the smoothed run: moves -> blocks, the host's own measure of the path's distance from
# the programmed moves, the traced commanded and measured positions' distance from the
# programmed path (bench_path_deviation), the host CPU of `pcnc check` (the whole front end
# with the fit) against the machine time, and with --real the ring underruns at real clock.
# The ideal planner's time is bench_ideal_planner's (report/ideal_planner.hpp: grbl's junction
# deviation for 0.005 mm with unlimited look-ahead, arcs whole at sqrt(A·r) as LinuxCNC runs
# them); "issue" is the figure issue 14 gives for the program (LHchips4 62.8 s, blur_torus
# 78.5 s), "-" for others.
# Usage: tools/bench_surfacing.sh [BUILD_DIR] [--real] [FILES...]
#   (default files: cam/linuxcnc-tp/LHchips4.ngc and blur_torus.ngc of ../shared/gcode)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=build
REAL=0
FILES=()
for a in "$@"; do
  case "$a" in
    --real) REAL=1 ;;
    *.ngc | *.nc | *.tap | *.gcode) FILES+=("$a") ;;
    *) BUILD=$a ;;
  esac
done
PCNC=$BUILD/tools/pcnc
DEV=$BUILD/bench/bench_path_deviation
IDEAL=$BUILD/bench/bench_ideal_planner
SHARED=$(cd .. && pwd)/shared
[ -x "$PCNC" ] && [ -x "$DEV" ] && [ -x "$IDEAL" ] || {
  echo "bench_surfacing: build first: cmake --build $BUILD --target pcnc pcnc-rt pcnc-host bench_path_deviation bench_ideal_planner"
  exit 2
}
[ ${#FILES[@]} -gt 0 ] || FILES=("$SHARED/gcode/cam/linuxcnc-tp/LHchips4.ngc" "$SHARED/gcode/cam/linuxcnc-tp/blur_torus.ngc")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# heartbeat timeouts of 2 s instead of 0.1 s: on a busy machine a starved process would end a
# run early as "host lost" (a shorter machine time); they change no figure of a run that completes.
# A state directory of its own: the work offsets a program run before left in the user's state
# (G10 L2, G92 ...: docs/gcode.md) would move --fit's transform and every figure
sed -e "s#^shm_name = .*#shm_name = \"/pcnc-bench-surf-$$\"#" -e "s#^host_timeout_s = .*#host_timeout_s = 2.0#" \
    -e "s#^\# state_dir = .*#state_dir = \"$TMP/state\"#" \
    -e "s#^rt_timeout_s = .*#rt_timeout_s = 2.0#" configs/desktop-mill.toml >"$TMP/mill.toml"
MILL=$TMP/mill.toml
TOL=0.005

issue_ideal() {
  case "$(basename "$1")" in
    LHchips4.ngc) echo 62.8 ;;
    blur_torus.ngc) echo 78.5 ;;
    *) echo - ;;
  esac
}
# the machine time of a run that completed without a fault, else "fail"
DONE="'%.1f' % j['status']['program_time_s'] if j['status']['program_done'] == 1 and j['status']['fault'] == 'none' else 'fail'"
field() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"; }
run_time() {  # run_time FILE ARGS... -> machine time (s) of a virtual-clock run
  local f=$1
  shift
  "$PCNC" run "$f" --config "$MILL" --fit --clock virtual -q --summary "$TMP/s.json" "$@" >/dev/null 2>&1 || {
    echo fail
    return
  }
  field "$TMP/s.json" "$DONE"
}

echo "== smoothing bench ($(date -u +%Y-%m-%d), $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg)); desktop mill, --fit --contouring on, tolerance $TOL mm"
printf '%-16s %7s %7s %6s %8s %8s %8s %6s %13s %8s %8s %8s %8s %7s\n' program "L/F s" "ideal" "issue" "M22 s" "M21 t=0" "smooth" "/ideal" \
  "moves>blocks" "host um" "cmd um" "act um" "check s" "cpu %"
for f in "${FILES[@]}"; do
  name=$(basename "$f")
  sed -e 's/G64\( *[PQ] *[-0-9.]*\)*/G61/g' "$f" >"$TMP/m22.ngc"
  t22=$(run_time "$TMP/m22.ngc" --contouring off --tolerance 0)
  t0=$(run_time "$f" --contouring on --tolerance 0)
  "$PCNC" run "$f" --config "$MILL" --fit --clock virtual -q --contouring on --tolerance $TOL --summary "$TMP/s.json" \
    --trace "$TMP/t.csv" >/dev/null 2>&1 || true
  ts=$(field "$TMP/s.json" "$DONE")
  lf=$(field "$TMP/s.json" "'%.1f' % j['check']['feed_length_time_s']")
  mb=$(field "$TMP/s.json" "'%d>%d' % (j['check']['smoothed_moves'], j['check']['smoothed_blocks'])")
  hd=$(field "$TMP/s.json" "'%.2f' % (1000 * j['check']['max_path_deviation_mm'])")
  read -r cd ad _ < <("$DEV" "$f" "$TMP/t.csv" --config "$MILL" --fit --contouring on)
  /usr/bin/time -o "$TMP/cpu" -f '%U %S' "$PCNC" check "$f" --config "$MILL" --fit --contouring on --tolerance $TOL -q \
    >/dev/null 2>&1 || true
  cpu=$(awk '{print $1 + $2}' "$TMP/cpu")
  id=$("$IDEAL" "$f" --config "$MILL" --fit --contouring on --tolerance $TOL 2>/dev/null | awk '{print $2}')
  [ -n "$id" ] || id=-
  iss=$(issue_ideal "$f")
  ratio=$( [ "$id" = - ] || [ "$ts" = fail ] && echo - || python3 -c "print('%.2f' % ($ts / $id))")
  pct=$( [ "$ts" = fail ] && echo - || python3 -c "print('%.1f' % (100 * $cpu / $ts))")
  printf '%-16s %7s %7s %6s %8s %8s %8s %6s %13s %8s %8s %8s %8s %7s\n' "$name" "$lf" "$id" "$iss" "$t22" "$t0" "$ts" "$ratio" "$mb" "$hd" "$cd" \
    "$ad" "$cpu" "$pct"
done
echo "(host um: the host's measure of the curves against the programmed moves; cmd/act um: the traced commanded and"
echo " measured positions against the programmed path; check s: CPU of 'pcnc check' with smoothing, the whole front end)"
if [ $REAL = 1 ]; then
  echo
  echo "== real clock, smoothed (takes the machine time of each program)"
  for f in "${FILES[@]}"; do
    "$PCNC" run "$f" --config "$MILL" --fit --clock real -q --contouring on --tolerance $TOL --summary "$TMP/r.json" >/dev/null 2>&1 || true
    echo "$(basename "$f"): $(field "$TMP/r.json" "'machine time %.1f s, ring underruns %d, host refill p99 %.0f us' % (j['status']['program_time_s'], j['status']['underruns'], j['job']['refill_p99_us'])")"
  done
fi
