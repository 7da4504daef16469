#!/usr/bin/env bash
# bench_report_phase.sh — figures, not tests: how long the report phase of `pcnc run --report`
# takes (docs/replay.md, "Replay speed with a report"): the time from the moment the front
# `pcnc` process has reaped both pcnc-rt and pcnc-host to its exit, in which it reads the
# summary and the compact trace and writes the HTML page. Measured with strace on the front
# process alone (its wait4 and exit_group timestamps; the two children are not traced). For each
# program it runs `pcnc run FILE --fit --clock virtual --contouring on --tolerance 0.005
# --report R.html` N times (as tools/bench_report_speed.sh) and prints the fastest and the
# median report phase, and the page's size. A busy machine stretches the phase: compare builds
# in alternation, on the same machine state.
# Usage: tools/bench_report_phase.sh [BUILD_DIR] [RUNS] [PROGRAM...]
#   default: build 5 linuxcnc-tp/blur_torus.ngc linuxcnc-tp/LHchips4.ngc fusion360/Key_Pockets.nc
#   (programs relative to ../shared/gcode/cam)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
RUNS=${2:-5}
shift $(( $# < 2 ? $# : 2 ))
PROGRAMS=("$@")
[ ${#PROGRAMS[@]} -gt 0 ] || PROGRAMS=(linuxcnc-tp/blur_torus.ngc linuxcnc-tp/LHchips4.ngc fusion360/Key_Pockets.nc)
PCNC=$BUILD/tools/pcnc
SHARED=$(cd .. && pwd)/shared
[ -x "$PCNC" ] || { echo "bench_report_phase: $PCNC not built"; exit 2; }
command -v strace >/dev/null || { echo "bench_report_phase: needs strace"; exit 2; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# a private segment, socket and state directory, 2 s heartbeat timeouts (tools/private_config.sh)
source tools/private_config.sh
private_config configs/desktop-mill.toml benchphase "$TMP" >"$TMP/mill.toml"

echo "== report phase of pcnc run --report ($PCNC, $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg) at the start; $RUNS runs)"
printf "   %-28s %10s %10s %10s\n" program fastest median report
for p in "${PROGRAMS[@]}"; do
  phases=()
  for _ in $(seq "$RUNS"); do
    rm -f "$TMP/r.html" "$TMP/st.txt"
    strace -tt -e trace=wait4,exit_group -o "$TMP/st.txt" "$PCNC" run "$SHARED/gcode/cam/$p" --fit --clock virtual \
      --contouring on --tolerance 0.005 -q --config "$TMP/mill.toml" --report "$TMP/r.html" >/dev/null 2>"$TMP/err" ||
      { echo "bench_report_phase: run failed: $p"; tail -3 "$TMP/err"; continue; }
    size=$(python3 -c "import os,sys; print(f'{os.path.getsize(sys.argv[1])/1e6:.2f} MB')" "$TMP/r.html")
    # the last wait4 that reaped a child, to exit_group
    phases+=("$(python3 - "$TMP/st.txt" <<'EOF'
import re, sys
def secs(line):
    h, m, s = line.split()[0].split(":")
    return int(h) * 3600 + int(m) * 60 + float(s)
reaped = end = None
for line in open(sys.argv[1]):
    if re.search(r"wait4\(.*\) = [1-9][0-9]*$", line):
        reaped = secs(line)
    elif "exit_group(" in line:
        end = secs(line)
print(f"{(end - reaped) * 1e3:.1f}")
EOF
)")
  done
  [ ${#phases[@]} -gt 0 ] || continue
  read -r fastest median < <(printf "%s\n" "${phases[@]}" | sort -g | awk '{v[NR]=$1} END {print v[1], v[int((NR+1)/2)]}')
  printf "   %-28s %8s ms %7s ms %10s\n" "$p" "$fastest" "$median" "$size"
done
