#!/usr/bin/env bash
# bench_report_view.sh — the run report's size and its interactive 3D view's load time in
# headless Chromium (software WebGL): for each program, `pcnc run --fit --clock virtual
# --report`, then the page loaded three times; prints the report's size, the points the view
# draws and the view's load time (unpacking three.js and the path, building the scene, first
# frame; the page's own performance.now()), median of three. Figures, never pass/fail.
#   tools/bench_report_view.sh [BUILD_DIR] [PROGRAM...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
shift || true
programs=("$@")
if [ ${#programs[@]} -eq 0 ]; then
  programs=("$root/examples/demo.ngc" "$root/../shared/gcode/cam/linuxcnc-tp/LHchips4.ngc"
            "$root/../shared/gcode/cam/linuxcnc-tp/blur_torus.ngc")
fi
chromium=$(command -v chromium || command -v chromium-browser || true)
[ -n "$chromium" ] || { echo "bench_report_view: chromium is not installed (tools/install-deps.sh)"; exit 1; }
dir=$(mktemp -d /tmp/pcnc-bench-view.XXXXXX)
trap 'rm -rf "$dir"' EXIT
printf '%-22s %10s %8s %12s\n' program "report MB" points "load ms"
for p in "${programs[@]}"; do
  name=$(basename "$p")
  "$build/tools/pcnc" run "$p" --fit --clock virtual --report "$dir/r.html" --quiet > /dev/null 2>&1 || true
  [ -f "$dir/r.html" ] || { printf '%-22s %s\n' "$name" "no report"; continue; }
  size=$(stat -c %s "$dir/r.html")
  times=()
  points=-
  for i in 1 2 3; do
    dom=$("$chromium" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking \
          --disable-component-update --disable-sync --user-data-dir="$dir/profile$i" --virtual-time-budget=15000 \
          --window-size=1200,1000 --dump-dom "file://$dir/r.html" 2>/dev/null || true)
    tag=$(grep -o '<div class="view3d"[^>]*>' <<< "$dom" || true)
    points=$(sed -n 's/.*data-points="\([0-9]*\)".*/\1/p' <<< "$tag")
    ms=$(sed -n 's/.*data-load-ms="\([0-9]*\)".*/\1/p' <<< "$tag")
    [ -n "$ms" ] && times+=("$ms")
  done
  median=$(printf '%s\n' "${times[@]:-}" | sort -n | sed -n 2p)
  printf '%-22s %10.2f %8s %12s\n' "$name" "$(echo "$size / 1048576" | bc -l)" "${points:--}" "${median:-failed}"
  rm -f "$dir/r.html"
done
