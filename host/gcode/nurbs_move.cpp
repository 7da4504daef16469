// nurbs_move.cpp — extreme points, control-polygon refinement and ring blocks of a NURBS move.
#include "gcode/nurbs_move.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gcode/nurbs_plan_memo.hpp"
#include "gcode/nurbs_schedule.hpp"
#include "gcode/arc_packing.hpp"

namespace pcnc {
namespace {

constexpr int kSamplesPerSpan = 16;  // dense sampling of each knot span for the extremes
constexpr int kBisections = 60;      // parameter bisections per extreme (to double precision)
constexpr int kRefineRounds = 30;    // knot-insertion rounds of refine_into_travel

// The feed schedule's sampling of a smoothed curve (Move::smoothed): half the 128 per span of a
// programmed curve. A smoothing fit is a C2 cubic within the path tolerance of G1 moves turning
// at most the smoothing angle, its spans refined where the path bends (down to 1 um): its
// curvature varies smoothly inside a span; the 128 are for programmed curves' cusps
// (nurbs_move.hpp). Half the front end's time (docs/smoothing.md, "Front-end cost"). At 32 the
// rt's setpoints on blur_torus passed an axis's velocity limit by more than 1e-9
// (tests/test_surfacing_limits.cpp), at 48 too; at 64 they keep it.
constexpr int kSmoothedSamplesPerSpan = 64;

bool outside(const Vec3& p, const MachineConfig& c, double tol) {
  for (int i = 0; i < kAxes; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!(p[k] >= c.axes[k].travel_min_mm - tol && p[k] <= c.axes[k].travel_max_mm + tol)) return true;
  }
  return false;
}

// The source line of the curve at parameter u: a smoothed run's blocks carry the line of the
// programmed move each starts in; a programmed curve its own line.
int line_at(const Move& m, double u) {
  int line = m.line;
  if (m.line_marks) {
    for (const LineMark& k : *m.line_marks) {
      if (k.u > u) break;
      line = k.line;
    }
  }
  return line > 0 ? line : 0;
}
}  // namespace

void nurbs_extreme_points(const NurbsCurve& curve, std::vector<Vec3>& out) {
  out.clear();
  const NurbsView v = curve.view();
  out.push_back(nurbs_point(v, v.u_min()));
  out.push_back(nurbs_point(v, v.u_max()));
  for (int j = v.degree; j < v.count; ++j) {
    const double a = v.knots[j], b = v.knots[j + 1];
    if (!(a < b)) continue;
    int span = j;  // every sample and bisection point of this span lies in it
    NurbsEval prev = nurbs_eval(v, a, span);
    double u_prev = a;
    // the last sample of a span sits just inside it: at b the derivative is the next span's
    auto sample_u = [&](int s) { return s == kSamplesPerSpan ? std::nextafter(b, a) : a + (b - a) * s / kSamplesPerSpan; };
    NurbsEval e, next;  // two samples at a time (nurbs_eval_pair; C'' is not needed): e at s, next at s + 1
    for (int s = 1; s <= kSamplesPerSpan; ++s) {
      const double u = sample_u(s);
      if (s % 2 == 0) {
        e = next;
      } else if (s + 1 <= kSamplesPerSpan) {
        nurbs_eval_pair(v, u, sample_u(s + 1), span, e, next, false);
      } else {
        e = nurbs_eval(v, u, span);
      }
      out.push_back(e.p);
      for (std::size_t i = 0; i < 3; ++i) {
        if (!((prev.d1[i] < 0.0 && e.d1[i] > 0.0) || (prev.d1[i] > 0.0 && e.d1[i] < 0.0))) continue;
        double lo = u_prev, hi = u;
        const bool rising = prev.d1[i] < 0.0;  // d1 goes from - to + : a minimum
        for (int k = 0; k < kBisections && lo < hi; ++k) {
          const double mid = 0.5 * (lo + hi);
          if (mid <= lo || mid >= hi) break;
          const double d = nurbs_derivative(v, mid, span)[i];  // nurbs_eval's d1, bit for bit
          if ((d < 0.0) == rising) {
            lo = mid;
          } else {
            hi = mid;
          }
        }
        out.push_back(nurbs_point(v, 0.5 * (lo + hi)));
      }
      prev = e;
      u_prev = u;
    }
  }
}

int schedule_samples_per_span(const NurbsCurve& curve) {
  const std::size_t spans = curve.points.size() > static_cast<std::size_t>(curve.degree)
                                ? curve.points.size() - static_cast<std::size_t>(curve.degree)
                                : 1;
  const std::size_t fit = kMaxScheduleSamples / spans;
  return static_cast<int>(std::clamp<std::size_t>(fit, kMinSamplesPerSpan, kMaxSamplesPerSpan));
}

double nurbs_travel_margin(const MachineConfig& config) { return 0.5 * config.motion.block_tolerance_mm; }

std::string refine_into_travel(NurbsCurve& curve, const MachineConfig& config, double tol) {
  const std::size_t budget = 4 * static_cast<std::size_t>(kMaxNurbsCurvePoints);
  for (int round = 0; round <= kRefineRounds; ++round) {
    const NurbsView v = curve.view();
    const int p = v.degree;
    std::vector<double> cuts;  // mid-parameters of spans whose control points leave the travel
    for (int j = p; j < v.count; ++j) {
      const double a = v.knots[j], b = v.knots[j + 1];
      if (!(a < b)) continue;
      bool out_here = false;
      for (int i = j - p; i <= j && !out_here; ++i) out_here = outside(v.points[i], config, tol);
      if (out_here) cuts.push_back(0.5 * (a + b));
    }
    if (cuts.empty()) return {};
    if (round == kRefineRounds || curve.points.size() + cuts.size() > budget) break;
    for (const double u : cuts) curve = insert_knot(curve, u);
  }
  return "the NURBS curve runs so close to the travel limit that its control polygon cannot be brought inside "
         "the travel by knot insertion; expected a curve at least " +
         std::to_string(tol) + " mm inside the travel";
}

NurbsMoveBlocks plan_nurbs_move(const Move& m, const MachineConfig& config) {
  NurbsMoveBlocks out;
  if (!m.nurbs) {
    out.error = "NURBS move without its curve";
    return out;
  }
  NurbsCurve curve = *m.nurbs;
  out.error = refine_into_travel(curve, config, nurbs_travel_margin(config));
  if (!out.error.empty()) return out;
  NurbsLimits lim = nurbs_limits(config, m.feed_mm_s);
  lim.samples_per_span = schedule_samples_per_span(curve);
  if (m.smoothed) lim.samples_per_span = std::min(lim.samples_per_span, kSmoothedSamplesPerSpan);
  // Packed arcs (arc_packing.hpp) are circles: their curvature is constant between the knots,
  // where the schedule takes the smaller limit of the two sides.
  if (m.packed_arcs) lim.normal_accel_share = kPackedArcNormalShare;
  NurbsBlocks nb = plan_nurbs_blocks_memo(curve, lim);  // the check's plan, when the stream asks again
  if (!nb.error.empty()) {
    out.error = nb.error;
    return out;
  }
  const std::size_t n = nb.blocks.size();
  out.blocks.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    Block& b = nb.blocks[i];
    b.seq = 0;
    b.line = static_cast<std::uint32_t>(line_at(m, b.nurbs.knots[b.nurbs.degree]));
    b.path_tolerance_mm = m.contouring ? static_cast<float>(m.path_tolerance_mm) : 0.0f;
    // Pieces of one curve join with its own continuity: they flow unless the curve has a
    // corner there; the last piece joins the next move under the program's M21/M22.
    const bool inner_smooth = i + 1 < n && !nb.corner_after[i];
    b.contouring = inner_smooth || m.contouring ? 1 : 0;
    out.blocks.push_back(b);
  }
  return out;
}

}  // namespace pcnc
