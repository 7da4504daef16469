#!/usr/bin/env python3
# feed_bound.py — figures, not a test: an estimate of the shortest machine time of a program's
# programmed polyline (lines; arcs taken as their chords) for a planner with unlimited look-ahead
# that KEEPS the axis limits, to set beside issue 14's ideal planner (which passes every junction
# at its junction-deviation speed as if isolated, and so exceeds the axes' acceleration on the
# fillets that CAM output draws with many small turns). Rules:
#  * at a junction turning by less than --angle (10°, the smoothing angle) the path is taken as
#    a curve through the three points: speed <= sqrt(share · a_n · rho), rho the circumradius of
#    the point and its neighbours, a_n the axes' acceleration along the velocity change;
#  * at a real corner (--angle or more) the junction-deviation speed for --tolerance;
#  * every move at most F (the machine's 100 mm/s) and the axes' velocities projected on it;
#    forward and backward passes at the move's projected axis acceleration; trapezoids.
# It ignores the rt's 2 kHz cycle, the 4-slot ring, the jerk of the servo and the time the
# tangential acceleration loses to the normal one on a bend: an estimate, not a bound to quote
# to the millisecond.
# Usage: pcnc check FILE --fit --contouring on --tolerance 0 --print-moves -q > M.txt
#        tools/feed_bound.py M.txt --scale 0.218413 [--share 1.0] [--tolerance 0.005]
import argparse
import math
import re

ap = argparse.ArgumentParser()
ap.add_argument("moves")
ap.add_argument("--scale", type=float, default=1.0, help="--fit's scale (the run report states it)")
ap.add_argument("--share", type=float, default=1.0, help="share of a_n the bends may use")
ap.add_argument("--tolerance", type=float, default=0.005)
ap.add_argument("--angle", type=float, default=10.0)
ap.add_argument("--accel", default="2000,2000,1000")
ap.add_argument("--velocity", default="100,100,50")
ap.add_argument("--feed", type=float, default=100.0)
a = ap.parse_args()
A = [float(x) for x in a.accel.split(",")]
V = [float(x) for x in a.velocity.split(",")]
pts = []
for line in open(a.moves):
    m = re.match(r"L\d+ (\w+) \(([^)]*)\)->\(([^)]*)\)", line)
    if not m:
        continue
    p0 = [float(x) * a.scale for x in m[2].split(",")]
    p1 = [float(x) * a.scale for x in m[3].split(",")]
    if not pts:
        pts.append(p0)
    if math.dist(p0, p1) > 1e-9:
        pts.append(p1)
n = len(pts)
L = [math.dist(pts[i], pts[i + 1]) for i in range(n - 1)]
U = [[(pts[i + 1][k] - pts[i][k]) / L[i] for k in range(3)] for i in range(n - 1)]


def cap(u, lim):
    return min(lim[k] / abs(u[k]) if abs(u[k]) > 1e-12 else math.inf for k in range(3))


vmove = [min(a.feed, cap(u, V)) for u in U]
amove = [cap(u, A) for u in U]
v = [0.0] * n
for i in range(1, n - 1):
    d0, d1 = U[i - 1], U[i]
    c = max(-1.0, min(1.0, sum(x * y for x, y in zip(d0, d1))))
    ch = [y - x for x, y in zip(d0, d1)]
    nn = math.sqrt(sum(x * x for x in ch))
    if nn < 1e-12:
        v[i] = min(vmove[i - 1], vmove[i])
        continue
    an = cap([x / nn for x in ch], A)
    if math.degrees(math.acos(c)) < a.angle:
        p, q, r = pts[i - 1], pts[i], pts[i + 1]
        u1 = [q[k] - p[k] for k in range(3)]
        u2 = [r[k] - p[k] for k in range(3)]
        cr = [u1[1] * u2[2] - u1[2] * u2[1], u1[2] * u2[0] - u1[0] * u2[2], u1[0] * u2[1] - u1[1] * u2[0]]
        area2 = math.sqrt(sum(x * x for x in cr))
        rho = math.dist(p, q) * math.dist(q, r) * math.dist(p, r) / (2 * area2) if area2 > 1e-15 else math.inf
        vi = math.sqrt(a.share * an * rho)
    else:
        sh = math.sqrt(0.5 * (1 + c))  # sin of half the enclosed angle
        vi = math.sqrt(an * a.tolerance * sh / (1 - sh)) if sh < 1 else 0.0
    v[i] = min(vi, vmove[i - 1], vmove[i])
for i in range(n - 1):
    v[i + 1] = min(v[i + 1], math.sqrt(v[i] ** 2 + 2 * amove[i] * L[i]))
for i in range(n - 2, -1, -1):
    v[i] = min(v[i], math.sqrt(v[i + 1] ** 2 + 2 * amove[i] * L[i]))
t = 0.0
for i in range(n - 1):
    v0, v1, acc, l = v[i], v[i + 1], amove[i], L[i]
    vp = min(vmove[i], math.sqrt((2 * acc * l + v0 * v0 + v1 * v1) / 2))
    d0 = (vp * vp - v0 * v0) / (2 * acc)
    d1 = (vp * vp - v1 * v1) / (2 * acc)
    t += (vp - v0) / acc + (vp - v1) / acc + max(0.0, l - d0 - d1) / vp
print(f"{n - 1} moves: {t:.1f} s (bends at {a.share} of a_n, corners from {a.angle} deg at the junction-deviation speed for {a.tolerance} mm)")
