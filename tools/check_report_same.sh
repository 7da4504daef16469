#!/usr/bin/env bash
# check_report_same.sh — a check, not a test: do two builds write the same run report from the
# same run? Two runs of one program do not give the same page (the figures measured on this
# computer differ, and so, slightly, does the motion the trace records), so the check keeps one
# run's files and draws the page from them with each build's report code:
#   1. build A's pcnc runs each program (`pcnc run FILE --fit --clock virtual --contouring on
#      --tolerance 0.005 --summary S.json --report R.html`, the surfacing bench's settings)
#      with a wrapper around pcnc-rt that keeps the compact trace it writes for the report;
#   2. a small driver calling build_report_file(S.json, trace, out.html) (the report phase of
#      `pcnc run --report`, host/report/run_outputs.hpp) is compiled against each build's
#      libraries and headers (the source tree is the build directory's parent);
#   3. the two pages are compared byte for byte, and with the page of the run itself.
# Prints one line per program with both builds' report time (fastest of 5, wall and CPU ms of
# the driver: a busy machine stretches them); exits 1 if any page differs and keeps both pages
# of the first difference in /tmp/check_report_same.{a,b}.html.
# Usage: tools/check_report_same.sh BUILD_A BUILD_B [PROGRAM...]
#   e.g. tools/check_report_same.sh /work/main/build build
#   default programs (relative to ../shared/gcode/cam): linuxcnc-tp/blur_torus.ngc
#   linuxcnc-tp/LHchips4.ngc fusion360/Key_Pockets.nc ugs/arc_rword_test.gcode
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: $0 BUILD_A BUILD_B [PROGRAM...]"; exit 2; }
A=$(readlink -f "$1")
B=$(readlink -f "$2")
shift 2
PROGRAMS=("$@")
[ ${#PROGRAMS[@]} -gt 0 ] ||
  PROGRAMS=(linuxcnc-tp/blur_torus.ngc linuxcnc-tp/LHchips4.ngc fusion360/Key_Pockets.nc ugs/arc_rword_test.gcode)
SHARED=$(cd .. && pwd)/shared
for b in "$A" "$B"; do
  for f in tools/pcnc rt/pcnc-rt host/pcnc-host host/libpcnc_host.a shared/libpcnc_shared.a; do
    [ -e "$b/$f" ] || { echo "check_report_same: $b/$f not built"; exit 2; }
  done
done
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# a private segment, socket and state directory, 2 s heartbeat timeouts (tools/private_config.sh)
source tools/private_config.sh
private_config configs/desktop-mill.toml samerep "$TMP" >"$TMP/mill.toml"

# 1. build A's programs side by side (pcnc looks for pcnc-rt and pcnc-host next to itself), the rt wrapped
mkdir -p "$TMP/bin"
cp "$A/tools/pcnc" "$TMP/bin/pcnc"
ln -s "$A/host/pcnc-host" "$TMP/bin/pcnc-host"
cat >"$TMP/bin/pcnc-rt" <<EOF
#!/usr/bin/env bash
# pcnc-rt, keeping the compact trace it writes (--trace-digest FILE) as \$KEEP_TRACE
prev=; out=
for a in "\$@"; do [ "\$prev" = --trace-digest ] && out=\$a; prev=\$a; done
"$A/rt/pcnc-rt" "\$@" &
child=\$!
trap 'kill -TERM \$child' TERM
trap 'kill -INT \$child' INT
rc=0
while kill -0 \$child 2>/dev/null; do wait \$child; rc=\$?; done
[ -n "\$out" ] && [ -n "\${KEEP_TRACE:-}" ] && cp "\$out" "\$KEEP_TRACE"
exit \$rc
EOF
chmod +x "$TMP/bin/pcnc-rt"

# 2. the driver, against each build
cat >"$TMP/report_from_files.cpp" <<'EOF'
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include "report/run_outputs.hpp"
int main(int argc, char** argv) {  // SUMMARY TRACE OUT.html RUNS: prints the fastest "wall cpu" ms
  double wall = 1e300, cpu = 1e300;
  for (int i = 0; i < std::atoi(argv[4]); ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    pcnc::build_report_file(argv[1], argv[2], argv[3]);
    wall = std::min(wall, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    cpu = std::min(cpu, 1e3 * static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
  }
  std::printf("%.1f %.1f\n", wall, cpu);
}
EOF
for side in a b; do
  b=$A
  [ $side = b ] && b=$B
  src=$(dirname "$b")
  c++ -std=c++20 -O2 -DSPDLOG_SHARED_LIB -DSPDLOG_COMPILED_LIB -DSPDLOG_FMT_EXTERNAL -DFMT_SHARED -I"$src/host" -I"$src/shared" \
    "$TMP/report_from_files.cpp" -o "$TMP/report_$side" "$b/host/libpcnc_host.a" "$b/host/libpcnc_rt_link.a" \
    "$b/shared/libpcnc_shared.a" "$b/shared/libpcnc_geometry.a" -ltomlplusplus -lspdlog -lfmt -lz -lrt -lpthread
done

# 3. each program: one run, both pages from its files
status=0
printf "   %-28s %-10s %22s %22s\n" program page "A: wall / cpu ms" "B: wall / cpu ms"
for p in "${PROGRAMS[@]}"; do
  KEEP_TRACE="$TMP/trace.pcct" "$TMP/bin/pcnc" run "$SHARED/gcode/cam/$p" --fit --clock virtual --contouring on \
    --tolerance 0.005 -q --config "$TMP/mill.toml" --summary "$TMP/summary.json" --report "$TMP/run.html" >/dev/null 2>"$TMP/err" ||
    { echo "check_report_same: the run of $p failed:"; tail -3 "$TMP/err"; status=1; continue; }
  read -r wa ca < <("$TMP/report_a" "$TMP/summary.json" "$TMP/trace.pcct" "$TMP/a.html" 5)
  read -r wb cb < <("$TMP/report_b" "$TMP/summary.json" "$TMP/trace.pcct" "$TMP/b.html" 5)
  if cmp -s "$TMP/a.html" "$TMP/b.html" && cmp -s "$TMP/a.html" "$TMP/run.html"; then
    verdict=same
  else
    verdict=DIFFERENT
    if [ $status = 0 ]; then
      cp "$TMP/a.html" /tmp/check_report_same.a.html
      cp "$TMP/b.html" /tmp/check_report_same.b.html
    fi
    status=1
  fi
  printf "   %-28s %-10s %13s / %6s %13s / %6s\n" "$p" "$verdict" "$wa" "$ca" "$wb" "$cb"
done
exit $status
