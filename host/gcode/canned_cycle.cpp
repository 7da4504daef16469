// canned_cycle.cpp — one canned-cycle line into rapid, feed and dwell steps, the way LinuxCNC's
// rs274ngc does it: the words checked in its order (convert_cycle, convert_cycle_xy/yz/zx), the
// levels resolved for G90/G91 and G98/G99, the preliminary move up to R, the in-between moves
// of each repeat (CYCLE_MACRO) and the cycle bodies (convert_cycle_g73/g81/g82/g83/g85/g89).
// Every level is a coordinate along the drill axis (the plane's normal).
#include "gcode/canned_cycle.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gcode/interpreter_text.hpp"
#include "gcode/parser.hpp"

namespace pcnc {

namespace {

using interp::num;


bool uses_p(int code10) { return code10 == 820 || code10 == 890; }
bool uses_q(int code10) { return code10 == 730 || code10 == 830; }

CycleResult failure(char letter, std::string message) {
  CycleResult r;
  r.ok = false;
  r.error = std::move(message);
  r.error_letter = letter;
  return r;
}

// The values of one cycle line once its words are resolved.
struct Cycle {
  int code10 = 810;
  int n = 2;           // drill axis
  Vec3 hole{};         // the first hole before its increment (G91) or the hole (G90)
  Vec3 increment{};    // G91: added to the hole before each repeat (plane axes only)
  double d_radius = 0.0, d_angle = 0.0;  // G91 polar: added to the hole's before each repeat (mm, rad)
  bool polar_steps = false;
  double r = 0.0;      // R level
  double bottom = 0.0; // bottom level
  double p = 0.0;      // dwell, s
  double q = 0.0;      // peck depth, mm
  double clearance = kPeckClearanceMm;
  long repeats = 1;
};

// Appends steps and follows the tool. A move to where the tool already is stays in, as
// LinuxCNC emits it (pcnc check --print-moves compares with LinuxCNC's moves; the preflight
// drops null moves before blocks are made).
class StepWriter {
 public:
  StepWriter(std::vector<CycleStep>& out, const Vec3& from) : out_(out), at_(from) {}
  void rapid(const Vec3& p) { move(CycleStepKind::kRapid, p); }
  void feed(const Vec3& p) { move(CycleStepKind::kFeed, p); }
  void dwell(double s) { out_.push_back(CycleStep{CycleStepKind::kDwell, at_, s}); }
  const Vec3& at() const { return at_; }

 private:
  void move(CycleStepKind kind, const Vec3& p) {
    out_.push_back(CycleStep{kind, p, 0.0});
    at_ = p;
  }
  std::vector<CycleStep>& out_;
  Vec3 at_;
};

// The cycle proper at one hole; the tool is at the hole on the R level, and leaves on the
// clear level.
void cycle_body(const Cycle& c, const Vec3& hole, double clear, StepWriter& w) {
  auto level = [&](double v) {
    Vec3 p = hole;
    p[static_cast<std::size_t>(c.n)] = v;
    return p;
  };
  switch (c.code10) {
    case 810:  // drill: feed to the bottom, rapid out
      w.feed(level(c.bottom));
      w.rapid(level(clear));
      break;
    case 820:  // drill with a dwell at the bottom
      w.feed(level(c.bottom));
      w.dwell(c.p);
      w.rapid(level(clear));
      break;
    case 830:  // peck: after each peck rapid out to R, rapid back to just above the last depth
      for (double d = c.r - c.q; d > c.bottom; d -= c.q) {
        w.feed(level(d));
        w.rapid(level(c.r));
        w.rapid(level(d + c.clearance));
      }
      w.feed(level(c.bottom));
      w.rapid(level(clear));
      break;
    case 730:  // chip break: after each peck rapid up by the clearance only
      for (double d = c.r - c.q; d > c.bottom; d -= c.q) {
        w.feed(level(d));
        w.rapid(level(d + c.clearance));
      }
      w.feed(level(c.bottom));
      w.rapid(level(clear));
      break;
    case 850:  // bore: feed in, feed out to R, rapid to the clear level
      w.feed(level(c.bottom));
      w.feed(level(c.r));
      w.rapid(level(clear));
      break;
    case 890:  // bore with a dwell: feed in, dwell, feed out straight to the clear level
      w.feed(level(c.bottom));
      w.dwell(c.p);
      w.feed(level(clear));
      break;
    default:
      break;
  }
}

// An upper bound on the steps of the line (null moves are left out later, so it may be over).
double step_bound(const Cycle& c) {
  double pecks = 0.0;
  if (uses_q(c.code10)) pecks = std::floor((c.r - c.bottom) / c.q) + 1.0;
  double body = 0.0;
  switch (c.code10) {
    case 830: body = 3.0 * pecks + 2.0; break;
    case 730: body = 2.0 * pecks + 2.0; break;
    case 810: body = 2.0; break;
    default: body = 3.0; break;  // G82, G85, G89
  }
  return 1.0 + static_cast<double>(c.repeats) * (2.0 + body);
}

// The words of the line checked and resolved in LinuxCNC's order; `level` is the level the
// series started at (the G98 return level).
CycleResult resolve(const CycleInput& in, const CannedCycleModal& modal, double level, Cycle& c) {
  const std::string g = g_name(in.code10);
  const auto n = static_cast<std::size_t>(in.normal_axis);
  const char drill = axis_name(in.normal_axis);
  if (!in.has[0] && !in.has[1] && !in.has[2] && !in.has_radius && !in.has_angle) {
    return failure(0, g + " with no X, Y or Z word; expected the hole position or the " +
                          std::string(1, drill) + " bottom level on a canned-cycle line");
  }
  if (!in.has_r && (in.first_of_series || !modal.have_r)) {
    return failure(0, g + " without R (retract level) on the first line of the cycle; expected R, which later " +
                          g + " lines may leave out");
  }
  if (in.has_l && in.l <= 0) {
    return failure('L', "L" + std::to_string(in.l) + ": " + (in.l == 0 ? "zero" : "negative") +
                            " repeats of a canned cycle; expected L >= 1 (the number of holes)");
  }
  if (!in.has[n] && (in.first_of_series || !modal.have_z)) {
    return failure(0, g + " without " + std::string(1, drill) + " (bottom level) on the first line of the cycle; expected " +
                          std::string(1, drill) + ", which later " + g + " lines may leave out");
  }
  c.code10 = in.code10;
  c.n = in.normal_axis;
  c.repeats = in.has_l ? in.l : 1;
  c.clearance = in.peck_clearance;
  const double r_word = in.has_r ? in.r : modal.r;
  const double z_word = in.has[n] ? in.axis[n] : modal.z;
  c.hole = in.position;
  c.increment = Vec3{0.0, 0.0, 0.0};
  if (in.incremental) {  // R from the initial level, the bottom from R, X/Y per repeat
    c.r = level + r_word;
    c.bottom = c.r + z_word;
    for (std::size_t i = 0; i < 3; ++i) {
      if (i != n && in.has[i]) c.increment[i] = in.axis[i];
    }
  } else {
    c.r = r_word;
    c.bottom = z_word;
    for (std::size_t i = 0; i < 3; ++i) {
      if (i != n && in.has[i]) c.hole[i] = in.axis[i];
    }
  }
  if (in.has_radius || in.has_angle) {
    const double deg = std::numbers::pi / 180.0;
    const bool at_origin = std::hypot(c.hole[0], c.hole[1]) <= 1e-9;
    if (in.incremental) {
      if (at_origin) {
        return failure(in.has_radius ? '@' : '^', g + ": polar coordinates (@ ^) in G91 at the origin: the current "
                                                      "point has no angle; expected G90, or a hole off the origin first");
      }
      c.polar_steps = true;
      c.d_radius = in.has_radius ? in.radius : 0.0;
      c.d_angle = in.has_angle ? in.angle_deg * deg : 0.0;
    } else {
      if (at_origin && !in.has_angle) {
        return failure('@', g + ": @ without ^ at the origin: the current point has no angle; expected ^ (degrees) too");
      }
      const double r = in.has_radius ? in.radius : std::hypot(c.hole[0], c.hole[1]);
      const double a = in.has_angle ? in.angle_deg * deg : std::atan2(c.hole[1], c.hole[0]);
      c.hole[0] = r * std::cos(a);
      c.hole[1] = r * std::sin(a);
    }
  }
  if (c.r < c.bottom) {
    return failure('R', g + ": R level " + num(c.r) + " mm is below the bottom " + std::string(1, drill) + " " +
                            num(c.bottom) + " mm; expected R >= " + std::string(1, drill) +
                            (in.incremental ? " (G91: R from the initial level, the bottom from R)" : ""));
  }
  if (uses_p(in.code10)) {
    if (!in.has_p && (in.first_of_series || !modal.have_p)) {
      return failure(0, g + " without P (dwell at the bottom) on the first line of the cycle; expected P in seconds");
    }
    c.p = in.has_p ? in.p : modal.p;
    if (c.p < 0.0) return failure('P', g + ": negative dwell P" + num(c.p) + "; expected P >= 0 (seconds)");
  }
  if (uses_q(in.code10)) {
    if (!in.has_q && (in.first_of_series || !modal.have_q)) {
      return failure(0, g + " without Q (peck depth) on the first line of the cycle; expected Q > 0");
    }
    c.q = in.has_q ? in.q : modal.q;
    if (!(c.q > 0.0)) return failure('Q', g + ": peck depth Q" + num(c.q) + " is not positive; expected Q > 0");
    // Too many pecks, or a Q so small next to the levels that subtracting it would not move.
    const double largest = std::max({1.0, std::fabs(c.r), std::fabs(c.bottom)});
    const double q_min = std::max((c.r - c.bottom) / static_cast<double>(kMaxCycleSteps), largest * 1e-9);
    if (!(c.q >= q_min)) {
      return failure('Q', g + ": peck depth Q" + num(c.q) + " mm over a " + num(c.r - c.bottom) +
                              " mm deep hole makes too many pecks; expected Q >= " + num(q_min) + " mm");
    }
  }
  if (step_bound(c) > static_cast<double>(kMaxCycleSteps)) {
    const char letter = c.repeats > 1 ? 'L' : (uses_q(c.code10) ? 'Q' : 0);
    return failure(letter, g + " line would expand to about " + num(step_bound(c)) + " steps; expected at most " +
                               std::to_string(kMaxCycleSteps) + " (fewer repeats L or a larger peck Q)");
  }
  return CycleResult{};
}

}  // namespace

bool is_drilling_cycle(int code10) {
  return code10 == 730 || code10 == 810 || code10 == 820 || code10 == 830 || code10 == 850 || code10 == 890;
}

CycleResult expand_canned_cycle(const CycleInput& in, CannedCycleModal& modal, std::vector<CycleStep>& out) {
  if (!is_drilling_cycle(in.code10)) {
    return failure(0, "G" + num(in.code10 / 10.0) + " is not a drilling canned cycle; expected G73, G81, G82, G83, G85 or G89");
  }
  if (in.normal_axis < 0 || in.normal_axis > 2) {
    return failure(0, "canned cycle with no plane selected; expected G17, G18 or G19");
  }
  const auto n = static_cast<std::size_t>(in.normal_axis);
  const double initial = modal.have_initial_level ? modal.initial_level : in.position[n];
  Cycle c;
  CycleResult res = resolve(in, modal, initial, c);
  if (!res.ok) return res;

  StepWriter w(out, in.position);
  double old_level = initial;
  double current = in.position[n];
  if (old_level < c.r) {  // preliminary move: below R, straight up to R first
    Vec3 up = in.position;
    up[n] = c.r;
    w.rapid(up);
    old_level = c.r;
    current = c.r;
  }
  const double clear = in.retract_r ? c.r : old_level;
  Vec3 hole = c.hole;
  for (long rep = 0; rep < c.repeats; ++rep) {
    hole = hole + c.increment;
    if (c.polar_steps) {  // about the origin: the radius and the angle grow by their steps
      const double r = std::hypot(hole[0], hole[1]) + c.d_radius;
      const double a = std::atan2(hole[1], hole[0]) + c.d_angle;
      hole[0] = r * std::cos(a);
      hole[1] = r * std::sin(a);
    }
    Vec3 p = hole;
    if (rep == 0 && current > c.r) {  // across at the current level, then down to R
      p[n] = current;
      w.rapid(p);
      p[n] = c.r;
      w.rapid(p);
    } else {  // across at the clear level, then down to R
      p[n] = clear;
      w.rapid(p);
      if (clear > c.r) {
        p[n] = c.r;
        w.rapid(p);
      }
    }
    cycle_body(c, hole, clear, w);
  }

  modal.have_r = true;
  modal.r = in.has_r ? in.r : modal.r;
  modal.have_z = true;
  modal.z = in.has[n] ? in.axis[n] : modal.z;
  if (uses_p(in.code10)) {
    modal.have_p = true;
    modal.p = c.p;
  }
  if (uses_q(in.code10)) {
    modal.have_q = true;
    modal.q = c.q;
  }
  modal.have_initial_level = true;
  modal.initial_level = initial;
  res.end = hole;
  res.end[n] = clear;
  return res;
}

}  // namespace pcnc
