#!/usr/bin/env python3
# junction_turns.py — figures, not a test: every junction between two motion blocks of a program
# as `pcnc check --print-blocks` makes them, with the kinds on both sides, the turn (angle
# between the end tangent of one and the start tangent of the next) and the junction-deviation
# speed the rt allows there for the path tolerance (rt/motion/junction.hpp; the desktop mill's
# axis accelerations 2000/2000/1000 mm/s² unless --accel says otherwise). Prints a table per
# pair of kinds and turn band; --list prints every junction (source lines, turn, speed, lengths).
# Usage: pcnc check FILE --fit --contouring on --tolerance 0.005 --print-blocks -q > B.txt
#        tools/junction_turns.py B.txt [--tolerance 0.005] [--accel 2000,2000,1000] [--list]
import argparse
import collections
import math
import re

ap = argparse.ArgumentParser()
ap.add_argument("blocks")
ap.add_argument("--tolerance", type=float, default=0.005)
ap.add_argument("--accel", default="2000,2000,1000")
ap.add_argument("--list", action="store_true")
a = ap.parse_args()
A = [float(x) for x in a.accel.split(",")]
pat = re.compile(r"(\d+) L(\d+) (\w+) \(([^)]*)\)->\(([^)]*)\) len=(\S+).*t0=\(([^)]*)\) t1=\(([^)]*)\) m21=(\d)")
vec = lambda s: [float(x) for x in s.split(",")]
rows = []
for line in open(a.blocks):
    m = pat.match(line)
    if m:
        rows.append(dict(line=int(m[2]), kind=m[3], len=float(m[6]), t0=vec(m[7]), t1=vec(m[8]), m21=m[9] == "1"))


def jd_speed(d0, d1):  # junction_deviation_speed
    c = -sum(x * y for x, y in zip(d0, d1))
    if c <= -1 + 1e-12:
        return math.inf
    if c >= 1 - 1e-12:
        return 0.0
    sh = math.sqrt(0.5 * (1 - c))
    r = a.tolerance * sh / (1 - sh)
    ch = [y - x for x, y in zip(d0, d1)]
    n = math.sqrt(sum(x * x for x in ch))
    acc = min(A[i] / abs(ch[i] / n) if abs(ch[i]) > 1e-15 else math.inf for i in range(3))
    return math.sqrt(acc * r)


bands = [(0.5, "<0.5"), (10, "0.5-10"), (20, "10-20"), (45, "20-45"), (90, "45-90"), (179, "90-179"), (181, ">=179")]
table = collections.defaultdict(list)
for p, q in zip(rows, rows[1:]):
    turn = math.degrees(math.acos(max(-1.0, min(1.0, sum(x * y for x, y in zip(p["t1"], q["t0"]))))))
    v = jd_speed(p["t1"], q["t0"])
    band = next(name for lim, name in bands if turn < lim)
    table[(p["kind"], q["kind"], band)].append(v)
    if a.list:
        print(f"L{p['line']}->L{q['line']} {p['kind']}->{q['kind']} turn {turn:6.1f} deg  v_jd {v:8.2f} mm/s  "
              f"lengths {p['len']:.3f} {q['len']:.3f} mm")
print(f"{'from':6} {'to':6} {'turn deg':>9} {'count':>6} {'v_jd min':>9} {'v_jd max':>9}  (mm/s, tolerance {a.tolerance} mm)")
for (k0, k1, band), vs in sorted(table.items(), key=lambda kv: (kv[0][0], kv[0][1], [n for _, n in bands].index(kv[0][2]))):
    fin = [v for v in vs if math.isfinite(v)]
    lo = f"{min(fin):9.2f}" if fin else f"{'inf':>9}"
    hi = f"{max(fin):9.2f}" if fin else f"{'inf':>9}"
    print(f"{k0:6} {k1:6} {band:>9} {len(vs):6d} {lo} {hi}")
print(f"{len(rows) - 1} junctions between {len(rows)} motion blocks")
