#!/usr/bin/env bash
# check_report_same.sh — a check, not a test: do two builds write the same run report? For
# each program it runs `pcnc run FILE --fit --clock virtual --report R.html` with each build's
# pcnc (the surfacing bench's settings, as tools/bench_report_speed.sh), masks the figures that
# are measured on this computer and differ from run to run (the wall time and replay speed,
# the rt's compute and wake-up times, the host's refill times and count), and compares the two
# pages byte for byte. Run it after changing how the page is written (docs/replay.md, "Replay
# speed with a report"). Prints one line per program; exits 1 if any page differs, and keeps
# the masked pages of the first difference in /tmp/check_report_same.{a,b}.html.
# Usage: tools/check_report_same.sh BUILD_A BUILD_B [PROGRAM...]
#   default programs (relative to ../shared/gcode/cam): linuxcnc-tp/blur_torus.ngc
#   linuxcnc-tp/LHchips4.ngc fusion360/Key_Pockets.nc ugs/arc_rword_test.gcode
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: $0 BUILD_A BUILD_B [PROGRAM...]"; exit 2; }
A=$1
B=$2
shift 2
PROGRAMS=("$@")
[ ${#PROGRAMS[@]} -gt 0 ] ||
  PROGRAMS=(linuxcnc-tp/blur_torus.ngc linuxcnc-tp/LHchips4.ngc fusion360/Key_Pockets.nc ugs/arc_rword_test.gcode)
SHARED=$(cd .. && pwd)/shared
for b in "$A" "$B"; do
  [ -x "$b/tools/pcnc" ] || { echo "check_report_same: $b/tools/pcnc not built"; exit 2; }
done
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# a private segment, socket and state directory (as bench_report_speed.sh)
sed -e "s#^shm_name = .*#shm_name = \"/pcnc-samerep-$$\"#" -e "s#^\# socket_path = .*#socket_path = \"$TMP/s.sock\"#" \
    -e "s#^\# state_dir = .*#state_dir = \"$TMP/state\"#" \
    -e "s#^host_timeout_s = .*#host_timeout_s = 2.0#" -e "s#^rt_timeout_s = .*#rt_timeout_s = 2.0#" \
    configs/desktop-mill.toml >"$TMP/mill.toml"

# mask FILE: the page with the figures measured on this computer replaced by "#"
mask() {
  sed -E -e 's#(id="(wall-time|replay-speed|rt-compute-p99|rt-compute-max|rt-wake-p99|rt-wake-max|refill-p50|refill-p99|refill-max)">)[^<]*<#\1\#<#g' \
         -e 's#filling it, [0-9]+ refills#filling it, \# refills#' "$1"
}

status=0
for p in "${PROGRAMS[@]}"; do
  for side in a b; do
    build=$A
    [ $side = b ] && build=$B
    "$build/tools/pcnc" run "$SHARED/gcode/cam/$p" --fit --clock virtual --contouring on --tolerance 0.005 -q \
      --config "$TMP/mill.toml" --report "$TMP/$side.html" >/dev/null
    mask "$TMP/$side.html" >"$TMP/$side.masked.html"
  done
  size=$(stat -c %s "$TMP/a.html")
  if cmp -s "$TMP/a.masked.html" "$TMP/b.masked.html"; then
    echo "same       $p ($size bytes)"
  else
    echo "DIFFERENT  $p: $(cmp "$TMP/a.masked.html" "$TMP/b.masked.html" | head -1)"
    if [ $status = 0 ]; then
      cp "$TMP/a.masked.html" /tmp/check_report_same.a.html
      cp "$TMP/b.masked.html" /tmp/check_report_same.b.html
    fi
    status=1
  fi
done
exit $status
