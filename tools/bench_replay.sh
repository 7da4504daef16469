#!/usr/bin/env bash
# bench_replay.sh — figures, not tests: how fast and how well `pcnc run` replays real CAM
# programs (docs/replay.md explains each figure). Prints:
#   1. virtual-clock replay speed on the largest program in ../shared/gcode/cam
#      (simulated machine time / wall time; the job alone and the whole command);
#   2. real-clock replay of that program at its programmed feed: ring underruns, the host's
#      slot-refill latency, the rt's wake-up latency and overruns;
#   3. peak memory (VmHWM) of pcnc-rt and pcnc-host in both runs;
#   4. program time with contouring on (M21) and off (M22) for every corpus program;
#   5. square.ngc and tiny.ngc (../shared/bench) on configs/bench-peers.toml, next to the
#      machine times LinuxCNC, Klipper, grbl and grblHAL take.
# Usage: tools/bench_replay.sh [BUILD_DIR] [--quick]   (--quick skips the real-clock run,
# which takes as long as the program: about 160 s)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=build
QUICK=0
for a in "$@"; do
  case "$a" in
    --quick) QUICK=1 ;;
    *) BUILD=$a ;;
  esac
done
PCNC=$BUILD/tools/pcnc
SHARED=$(cd .. && pwd)/shared
[ -x "$PCNC" ] || { echo "bench_replay: $PCNC not built (cmake --build $BUILD --target pcnc pcnc-rt pcnc-host)"; exit 2; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

# a private segment, socket and state directory (the socket in our own mktemp directory, as
# docs/protocol.md allows), so a running pcnc elsewhere is not disturbed
mkconfig() {  # mkconfig SRC NAME -> path
  sed -e "s#^shm_name = .*#shm_name = \"/pcnc-bench-$$-$2\"#" -e "s#^\# socket_path = .*#socket_path = \"$TMP/$2.sock\"#" \
      -e "s#^\# state_dir = .*#state_dir = \"$TMP/$2.state\"#" "$1" >"$TMP/$2.toml"
  echo "$TMP/$2.toml"
}
MILL=$(mkconfig configs/desktop-mill.toml mill)
PEERS=$(mkconfig configs/bench-peers.toml peers)

field() {  # field SUMMARY.json python-expression-over-j
  python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"
}

# Runs pcnc run in the background, samples VmHWM of its two children every 20 ms.
# run_sampled OUT_PREFIX ARGS... -> OUT_PREFIX.{out,err,mem}; returns pcnc's status
run_sampled() {
  local out=$1
  shift
  local t0 t1
  t0=$(date +%s.%N)
  "$PCNC" run "$@" >"$out.out" 2>"$out.err" &
  local pid=$! rt_hwm=0 host_hwm=0
  while kill -0 "$pid" 2>/dev/null; do
    for c in $(pgrep -P "$pid" 2>/dev/null); do
      local name hwm
      name=$(cat "/proc/$c/comm" 2>/dev/null || true)
      hwm=$(awk '/^VmHWM/ {print $2}' "/proc/$c/status" 2>/dev/null || true)
      [ -n "$hwm" ] || continue
      if [ "$name" = "pcnc-rt" ] && [ "$hwm" -gt "$rt_hwm" ]; then rt_hwm=$hwm; fi
      if [ "$name" = "pcnc-host" ] && [ "$hwm" -gt "$host_hwm" ]; then host_hwm=$hwm; fi
    done
    sleep 0.02
  done
  local rc=0
  wait "$pid" || rc=$?
  t1=$(date +%s.%N)
  echo "$rt_hwm $host_hwm $(echo "$t1 - $t0" | bc)" >"$out.mem"
  return $rc
}

needs_fit() {  # needs_fit FILE CONFIG -> "--fit" or ""
  if "$PCNC" check "$1" --config "$2" -q >/dev/null 2>&1; then echo ""; else echo "--fit"; fi
}

LARGEST=$(find "$SHARED/gcode/cam" -type f -printf '%s %p\n' | sort -n | tail -1 | cut -d' ' -f2-)
FIT=$(needs_fit "$LARGEST" "$MILL")
echo "== pcnc replay figures ($(date -u +%Y-%m-%d), $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
echo "largest CAM program: ${LARGEST#$SHARED/} ($(stat -c %s "$LARGEST") bytes, $(wc -l <"$LARGEST") lines) $FIT"
echo

echo "-- 1. virtual-clock replay speed (contouring on; best of 5; memory is sampled in a separate run)"
best=""
for i in 1 2 3 4 5; do
  t0=$(date +%s.%N)
  "$PCNC" run "$LARGEST" --clock virtual --contouring on $FIT --config "$MILL" --summary "$TMP/v$i.json" \
    >"$TMP/v$i.out" 2>"$TMP/v$i.err" || true
  t1=$(date +%s.%N)
  m=$(field "$TMP/v$i.json" "j['status']['program_time_s']")
  w=$(field "$TMP/v$i.json" "j['job']['wall_time_s']")
  total=$(echo "$t1 - $t0" | bc)
  printf '   run %d: machine %.3f s, job wall %.3f s (%.0fx), whole command %.3f s (%.0fx)\n' "$i" "$m" "$w" \
    "$(echo "$m / $w" | bc -l)" "$total" "$(echo "$m / $total" | bc -l)"
  if [ -z "$best" ] || (($(echo "$w < $(cut -d' ' -f2 <<<"$best")" | bc))); then best="$i $w"; fi
done
b=${best%% *}
echo "   rt compute per cycle: $(field "$TMP/v$b.json" "'mean %.2f us, p99 %.2f us, over %d cycles' % (j['status']['timing']['compute_mean_us'], j['status']['timing']['compute_p99_us'], j['status']['program_cycles'])")"
run_sampled "$TMP/vmem" "$LARGEST" --clock virtual --contouring on $FIT --config "$MILL" || true
read -r vrt vhost _ <"$TMP/vmem.mem"
echo

if [ "$QUICK" = 0 ]; then
  echo "-- 2. real-clock replay at the programmed feed (takes the program's machine time)"
  run_sampled "$TMP/real" "$LARGEST" --clock real --contouring on $FIT --config "$MILL" --summary "$TMP/real.json" || true
  echo "   $(field "$TMP/real.json" "'%s: machine %.3f s, wall %.3f s' % (j['job']['end'], j['status']['program_time_s'], j['job']['wall_time_s'])")"
  echo "   ring underruns: $(field "$TMP/real.json" "j['status']['underruns']")"
  echo "   host slot refill: $(field "$TMP/real.json" "'p50 %.1f us, p99 %.1f us, max %.1f us over %d refills' % (j['job']['refill_p50_us'], j['job']['refill_p99_us'], j['job']['refill_max_us'], j['job']['refill_count'])")"
  echo "   rt wake-up: $(field "$TMP/real.json" "'p99 %.1f us, max %.1f us; compute p99 %.2f us, max %.1f us; %d overruns' % (j['status']['timing']['wake_p99_us'], j['status']['timing']['wake_max_us'], j['status']['timing']['compute_p99_us'], j['status']['timing']['compute_max_us'], j['status']['timing']['overruns'])")"
  read -r rrt rhost _ <"$TMP/real.mem"
  echo
fi

echo "-- 3. peak memory (VmHWM, sampled every 20 ms)"
echo "   virtual run: pcnc-rt $((vrt / 1024)) MiB ($vrt kB), pcnc-host $((vhost / 1024)) MiB ($vhost kB)"
[ "$QUICK" = 0 ] && echo "   real run:    pcnc-rt $((rrt / 1024)) MiB ($rrt kB), pcnc-host $((rhost / 1024)) MiB ($rhost kB)"
echo

echo "-- 4. program time with contouring on (M21) and off (M22), virtual clock, default config"
printf '   %-42s %7s %10s %10s %8s %11s  %s\n' program scale "M22 [s]" "M21 [s]" saved "L/F [s]" "mode words in the program"
find "$SHARED/gcode/cam" -type f | sort | while read -r f; do
  rel=${f#$SHARED/gcode/cam/}
  fit=$(needs_fit "$f" "$MILL")
  if ! "$PCNC" check "$f" --config "$MILL" $fit -q >/dev/null 2>&1; then
    printf '   %-42s refused by the front end: %s\n' "$rel" "$("$PCNC" check "$f" --config "$MILL" $fit 2>&1 | grep -m1 error: | sed 's/.*error: //' | cut -c1-60)"
    continue
  fi
  rm -f "$TMP/off.json" "$TMP/on.json"
  "$PCNC" run "$f" --clock virtual --contouring off $fit --config "$MILL" --summary "$TMP/off.json" >/dev/null 2>"$TMP/off.err" || true
  "$PCNC" run "$f" --clock virtual --contouring on $fit --config "$MILL" --summary "$TMP/on.json" >/dev/null 2>"$TMP/on.err" || true
  for m in off on; do
    if [ ! -f "$TMP/$m.json" ] || [ "$(field "$TMP/$m.json" "j['job']['end']")" != completed ]; then
      printf '   %-42s contouring %s: did not complete: %s\n' "$rel" "$m" "$(tail -1 "$TMP/$m.err")"
      continue 2
    fi
  done
  off=$(field "$TMP/off.json" "j['status']['program_time_s']")
  on=$(field "$TMP/on.json" "j['status']['program_time_s']")
  modes=$(sed -e 's/([^)]*)//g' -e 's/;.*//' "$f" | grep -oiE '(G61(\.1)?|G64|M2[12])([^0-9]|$)' | grep -oiE 'G61(\.1)?|G64|M2[12]' | tr a-z A-Z | sort -u | tr '\n' ' ' || true)
  lf=$(field "$TMP/on.json" "j['check']['feed_length_time_s']")
  sc=$(field "$TMP/on.json" "j['check']['scale']")
  printf '   %-42s %7.4f %10.3f %10.3f %7.1f%% %11.3f  %s\n' "$rel" "$sc" "$off" "$on" "$(echo "100 * ($off - $on) / $off" | bc -l)" "$lf" "${modes:--}"
done
echo

echo "-- 5. side by side with other controllers (configs/bench-peers.toml, virtual clock, contouring on)"
(cd "$TMP" && python3 "$SHARED/bench/gen_peer_programs.py")
for p in square tiny; do
  "$PCNC" run "$TMP/$p.ngc" --clock virtual --contouring on --config "$PEERS" --summary "$TMP/$p.json" >/dev/null 2>&1 || true
done
sq=$(field "$TMP/square.json" "'%.2f' % j['status']['program_time_s']")
ti=$(field "$TMP/tiny.json" "'%.2f' % j['status']['program_time_s']")
printf '   %-58s %10s %10s\n' controller square.ngc tiny.ngc
printf '   %-58s %10s %10s\n' "pcnc (this build), 2 kHz, 4-slot ring" "$sq" "$ti"
printf '   %-58s %10s %10s\n' "LinuxCNC 2.10-pre, G64 P0.01" 31.48 39.22
printf '   %-58s %10s %10s\n' "Klipper, batch mode" 31.49 46.81
printf '   %-58s %10s %10s\n' "grbl 1.1h, grbl-sim (serial-limited on tiny)" 31.80 50.51
printf '   %-58s %10s %10s\n' "grblHAL simulator (serial-limited on tiny)" 31.33 "53.2-53.5"
printf '   %-58s %10s %10s\n' "length / feed alone" "$(field "$TMP/square.json" "'%.2f' % j['check']['feed_length_time_s']")" \
  "$(field "$TMP/tiny.json" "'%.2f' % j['check']['feed_length_time_s']")"
for p in square tiny; do
  echo "   pcnc $p.ngc: $(field "$TMP/$p.json" "'%s, %d junctions flowed, %d stops, %d underruns, max following error %.2f/%.2f/%.2f um' % (j['job']['end'], j['status']['junction_flows'], j['status']['junction_stops'], j['status']['underruns'], *[1000*x for x in j['status']['max_following_error']])")"
done
