// tcp_fit.cpp — --fit of a tool-centre-point program: bisection on the scale, a linear program
// for the offset. See tcp_fit.hpp.
#include "geometry/tcp_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "geometry/axis_slerp.hpp"
#include "geometry/minmax_lp.hpp"
#include "geometry/tcp_path.hpp"

namespace pcnc {
namespace {

// One sampled pose with its angles fixed: machine x, y, z = M·tip + b, M's rows in `rows`.
struct AffineSample {
  Vec3 p{};                  // tip, program coordinates
  std::array<Vec3, 3> rows{};
  Vec3 b{};
};

AffineSample affine_at(const Kinematics& kin, const Vec3& p, const Vec3& axis, const Joints& q, const RotaryTravel& rt) {
  AffineSample s;
  s.p = p;
  auto xyz = [&](const Vec3& tip) {
    const Joints j = inverse(kin, ToolPose{tip, axis}, q, rt);
    return Vec3{j[0], j[1], j[2]};
  };
  s.b = xyz({0.0, 0.0, 0.0});
  for (int c = 0; c < 3; ++c) {
    Vec3 e{0.0, 0.0, 0.0};
    e[static_cast<std::size_t>(c)] = 1.0;
    const Vec3 col = xyz(e) - s.b;
    for (int r = 0; r < 3; ++r) s.rows[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)] = col[static_cast<std::size_t>(r)];
  }
  return s;
}

std::string deg(double rad) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", rad * 180.0 / std::numbers::pi);
  return buf;
}

// An angle outside the travel: the message, else empty.
std::string angle_outside(const Joints& q, const RotaryTravel& t, int line) {
  const double slack = 1e-9;
  const std::string at = "line " + std::to_string(line) + ": ";
  if (q[kTilt] < t.tilt_min - slack || q[kTilt] > t.tilt_max + slack)
    return at + "the tool axis needs the tilt joint at " + deg(q[kTilt]) + " deg, outside its travel " +
           deg(t.tilt_min) + " .. " + deg(t.tilt_max) + " deg; --fit scales and moves X Y Z, never the angles";
  if (q[kRotary] < t.rotary_min - slack || q[kRotary] > t.rotary_max + slack)
    return at + "the tool axis needs the rotary joint at " + deg(q[kRotary]) + " deg, outside its travel " +
           deg(t.rotary_min) + " .. " + deg(t.rotary_max) + " deg; --fit scales and moves X Y Z, never the angles";
  return {};
}

MinMaxResult best_offset(const std::vector<AffineSample>& samples, const JointTravel& travel, double s,
                         std::vector<MinMaxRow>& rows) {
  rows.clear();
  for (const AffineSample& a : samples) {
    for (std::size_t r = 0; r < 3; ++r) {
      const double fixed = a.b[r] + s * dot(a.rows[r], a.p);
      rows.push_back({a.rows[r], travel.max[r] - fixed});
      rows.push_back({-1.0 * a.rows[r], fixed - travel.min[r]});
    }
  }
  return minimize_max_affine(rows);
}

}  // namespace

TcpFitResult fit_tcp_program(const std::vector<FitPose>& poses, const Kinematics& kin, const JointTravel& travel,
                             const Joints& start, int samples_per_move, double tolerance) {
  TcpFitResult out;
  if (poses.empty()) {
    out.error = "no moves to fit";
    return out;
  }
  for (const FitPose& f : poses) {
    if (!f.tcp && !f.turn_only && kin.kind != KinematicsKind::kTrivial && (f.tilt != 0.0 || f.rotary != 0.0)) {
      out.error_line = f.line;
      out.error = "line " + std::to_string(f.line) +
                  ": a move with tool-centre-point control off (M429) turns a rotary joint; its joint values do "
                  "not scale: --fit takes a 5-axis program only under tool-centre-point control (M428), or run "
                  "it without --fit";
      return out;
    }
  }
  // the angles along the program (they depend on the tool axes alone): every `dense`-th sample
  // is one of the coarse samples the linear programs start from; the rest check the result
  const int coarse_n = std::max(2, samples_per_move);
  const int dense_factor = 8;
  std::vector<AffineSample> dense;
  std::vector<char> is_coarse;
  Joints q = start;
  auto axis_of = [&](const FitPose& f) { return f.tcp || f.turn_only ? f.pose.axis : Vec3{0.0, 0.0, 1.0}; };
  // a turn-only pose: its angles as written, its linear joints the point itself (x = s·p + o)
  auto turn_only_sample = [&](const FitPose& f) {
    q[kTilt] = f.tilt;
    q[kRotary] = f.rotary;
    AffineSample a;
    a.p = f.joint_xyz;
    a.rows = {Vec3{1.0, 0.0, 0.0}, Vec3{0.0, 1.0, 0.0}, Vec3{0.0, 0.0, 1.0}};
    dense.push_back(a);
    is_coarse.push_back(1);
    return angle_outside(q, travel.rotary, f.line);
  };
  if (poses.front().turn_only) {
    if (std::string why = turn_only_sample(poses.front()); !why.empty()) {
      out.error = why;
      out.error_line = poses.front().line;
      return out;
    }
  } else {
    const FitPose& f = poses.front();
    q = inverse(kin, ToolPose{f.pose.tip, axis_of(f)}, q, travel.rotary);
    if (std::string why = angle_outside(q, travel.rotary, f.line); !why.empty()) {
      out.error = why;
      out.error_line = f.line;
      return out;
    }
    dense.push_back(affine_at(kin, f.pose.tip, axis_of(f), q, travel.rotary));
    is_coarse.push_back(1);
  }
  for (std::size_t i = 1; i < poses.size(); ++i) {
    const FitPose& a = poses[i - 1];
    const FitPose& b = poses[i];
    if (b.turn_only) {  // the linear joints stand still, the angles run linearly: its end alone
      if (std::string why = turn_only_sample(b); !why.empty()) {
        out.error = why;
        out.error_line = b.line;
        return out;
      }
      continue;
    }
    const TcpMove move{{a.pose.tip, axis_of(a)}, {b.pose.tip, axis_of(b)}};
    const double length = norm(move.end.tip - move.start.tip);
    const AxisSlerp axes = make_axis_slerp(move.start.axis, move.end.axis);
    if (length <= 1e-12 && axes.angle <= 1e-12) continue;
    const double param = length > 1e-12 ? length : axes.angle;
    const int n = (coarse_n - 1) * dense_factor + 1;
    for (const JointSample& js : sample_tcp_move(kin, move, param, q, n, travel.rotary)) {
      const double u = js.s / param;
      if (std::string why = angle_outside(js.q, travel.rotary, b.line); !why.empty()) {
        out.error = why;
        out.error_line = b.line;
        return out;
      }
      const ToolPose at = tcp_pose(move, axes, u);
      dense.push_back(affine_at(kin, at.tip, at.axis, js.q, travel.rotary));
      const double k = u * (n - 1);
      is_coarse.push_back(std::abs(k - std::round(k)) < 1e-9 && static_cast<long>(std::lround(k)) % dense_factor == 0 ? 1 : 0);
      q = js.q;
    }
  }
  std::vector<AffineSample> active;
  for (std::size_t i = 0; i < dense.size(); ++i)
    if (is_coarse[i]) active.push_back(dense[i]);
  out.samples = static_cast<int>(dense.size());

  std::vector<MinMaxRow> rows;
  bool unsolved = false;  // a linear program that did not converge: no answer rather than a wrong one
  auto fits = [&](double s, MinMaxResult& r) {
    r = best_offset(active, travel, s, rows);
    unsolved |= !r.ok;
    return r.ok && r.value <= 1e-12;
  };
  // the smallest margin over every dense sample at (s, o); the samples below 0 join `active`
  auto verify = [&](double s, const Vec3& o) {
    double margin = 1e300;
    for (std::size_t i = 0; i < dense.size(); ++i) {
      const AffineSample& a = dense[i];
      double m = 1e300;
      for (std::size_t r = 0; r < 3; ++r) {
        const double x = a.b[r] + dot(a.rows[r], s * a.p + o);
        m = std::min({m, x - travel.min[r], travel.max[r] - x});
      }
      if (m < -1e-12 && !is_coarse[i]) {
        active.push_back(a);
        is_coarse[i] = 1;
      }
      margin = std::min(margin, m);
    }
    return margin;
  };
  double hi = 1.0;
  for (int round = 0; round < 8; ++round) {
    MinMaxResult at_hi, at_lo;
    double lo = 0.0;
    if (fits(hi, at_hi)) {
      lo = hi;
      at_lo = at_hi;
    } else {
      if (!fits(0.0, at_lo) && !unsolved) {
        // the scales that fit are an interval that does not start at 0: its lowest violation
        // (convex in s) by golden section, then the interval's upper end as below
        MinMaxResult r1, r2;
        double a = 0.0, b = hi;
        constexpr double kG = 0.6180339887498949;
        double s1 = b - kG * (b - a), s2 = a + kG * (b - a);
        fits(s1, r1);
        fits(s2, r2);
        while (b - a > tolerance && !unsolved) {
          if (r1.value <= 1e-12 || r2.value <= 1e-12) break;
          if (r1.value < r2.value) {
            b = s2, s2 = s1, r2 = r1;
            s1 = b - kG * (b - a);
            fits(s1, r1);
          } else {
            a = s1, s1 = s2, r1 = r2;
            s2 = a + kG * (b - a);
            fits(s2, r2);
          }
        }
        const bool first = r1.value <= r2.value;
        if (unsolved || (first ? r1.value : r2.value) > 1e-12) {
          if (!unsolved) {
            out.error = "no offset puts the program's tool axes within the joints' travel at any scale: at some "
                        "two poses the tilt and rotary joints need the tip in places the X, Y, Z travel cannot both reach";
            return out;
          }
        } else {
          lo = first ? s1 : s2;
          at_lo = first ? r1 : r2;
        }
      }
      MinMaxResult trial;
      while (hi - lo > tolerance) {
        const double mid = 0.5 * (lo + hi);
        if (fits(mid, trial)) {
          lo = mid;
          at_lo = trial;
        } else {
          hi = mid;
        }
      }
    }
    if (unsolved) {
      out.error = "the offset's linear program did not converge (geometry/minmax_lp.hpp); --fit found no scale";
      return out;
    }
    const std::size_t before = active.size();
    const double margin = verify(lo, at_lo.x);
    if (active.size() == before) {
      out.ok = true;
      out.scale = lo;
      out.offset = at_lo.x;
      out.margin_mm = margin;
      return out;
    }
    hi = lo + tolerance;  // more samples can only lower the scale (just above: lo itself may still fit)
    hi = std::min(hi, 1.0);
  }
  out.error = "the fit did not settle between its samples along the moves; expected shorter moves";
  return out;
}

}  // namespace pcnc
