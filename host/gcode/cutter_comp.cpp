// cutter_comp.cpp — the compensation stage: sessions, the held-back queue, and LinuxCNC's
// entry (comp1) and continuation (comp2) rules for straight moves and arcs (see
// cutter_comp.hpp). Angles and tolerances are LinuxCNC's, so that the end points agree.
#include "gcode/cutter_comp.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "gcode/preflight.hpp"
#include "geometry/intersect.hpp"

namespace pcnc {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kHalfPi = kPi / 2.0;
constexpr double kSmall = 0.05;  // radians: LinuxCNC's TOLERANCE_CONCAVE_CORNER

bool is_motion(MoveKind k) { return k == MoveKind::kRapid || k == MoveKind::kLine || k == MoveKind::kArc; }

std::string mm(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4f", v);
  return b;
}
}  // namespace

Vec2 CutterComp::in_plane(const Vec3& p) const {
  const auto ax = plane_axes(normal_);
  return {p[static_cast<std::size_t>(ax[0])], p[static_cast<std::size_t>(ax[1])]};
}

Vec3 CutterComp::to_space(Vec2 p, double o) const {
  const auto ax = plane_axes(normal_);
  Vec3 v{};
  v[static_cast<std::size_t>(ax[0])] = p.x;
  v[static_cast<std::size_t>(ax[1])] = p.y;
  v[static_cast<std::size_t>(normal_)] = o;
  return v;
}

bool CutterComp::next(const std::function<bool(Move&)>& pull, Move& out) {
  for (;;) {
    if (!ready_.empty()) {
      out = ready_.front();
      ready_.pop_front();
      return true;
    }
    if (ended_) return false;
    Move m;
    if (!pull(m)) {
      if (!run_.empty()) flush_run();
      dequeue();
      if (active_) note_crossings();
      ended_ = true;
      continue;
    }
    process(m);
  }
}

bool CutterComp::fail(const Move& m, const std::string& message) {
  sink_.error(m.line, m.column, message);
  broken_serial_ = serial_;
  active_ = false;
  dequeue();
  return false;
}

void CutterComp::process(Move& m) {
  if (!have_pos_) {
    emitted_ = m.start;
    have_pos_ = true;
  }
  const MoveComp& c = m.comp;
  if (!run_.empty() && !run_candidate(m)) flush_run();
  if (active_ && (c.side == 0 || c.serial != serial_)) comp_off();
  if (!active_ && c.side != 0 && c.radius_mm > 0.0 && c.serial != serial_ && c.serial != broken_serial_) {
    if (!comp_on(m)) return;
  }
  if (!active_) {  // passes unchanged, but starts where the tool is after a G40
    if (m.kind == MoveKind::kArc && arc_not_allowed_) {
      sink_.error(m.line, m.column,
                  "the move just after turning cutter compensation off (G40) must be straight, not an arc; expected "
                  "G0 or G1 from the compensated end point");
      arc_not_allowed_ = false;
    }
    if (m.kind == MoveKind::kRapid || m.kind == MoveKind::kLine) arc_not_allowed_ = false;
    if (resume_from_tool_) {
      if (is_motion(m.kind) || m.kind == MoveKind::kNurbs) {
        m.start = emitted_;
        resume_from_tool_ = false;
      } else {
        m.start = m.end = emitted_;
      }
    }
    ready_.push_back(m);
    emitted_ = m.end;
    return;
  }
  if (run_candidate(m)) {
    run_.push_back(m);
    return;
  }
  dispatch(m);
}

void CutterComp::dispatch(Move& m) {
  switch (m.kind) {
    case MoveKind::kNurbs:
      fit_nurbs(m);
      break;
    case MoveKind::kRapid:
    case MoveKind::kLine:
      arc_not_allowed_ = false;
      first_move_ ? straight_entry(m) : straight_next(m);
      break;
    case MoveKind::kArc:
      first_move_ ? arc_entry(m) : arc_next(m);
      break;
    case MoveKind::kDwell: {
      Held h;
      h.m = m;
      h.motion = false;
      queue_.push_back(h);
      break;
    }
    default:  // a pause or the end: LinuxCNC's stop ends the held move where it is
      if (!first_move_ && !move_endpoint_and_flush(m, cur())) return;
      dequeue();
      if (m.kind == MoveKind::kEnd) note_crossings();
      m.start = m.end = emitted_;
      ready_.push_back(m);
      break;
  }
}

void CutterComp::note_crossings() {
  if (gouge_.crossings() == 0 || sink_.repeat("comp-crossing")) return;
  sink_.warning(session_line_, 0, "comp-crossing",
                "the compensated contour from this line crosses itself: " + std::to_string(gouge_.crossings()) +
                    " tool move(s) near the crossing were not tested for gouges (no side of it is the material's)");
}

bool CutterComp::comp_on(const Move& m) {
  const MoveComp& c = m.comp;
  active_ = true;
  first_move_ = true;
  serial_ = c.serial;
  side_ = c.side == 1 ? CompSide::kLeft : CompSide::kRight;
  radius_ = c.radius_mm;
  normal_ = c.normal_axis;
  arc_tolerance_ = c.inch ? 0.001 : 0.0254;
  cur_ = prog_ = m.start;
  session_line_ = m.line;
  endpoint_valid_ = false;
  index_ = 0;
  gouge_.start(radius_);
  ++figures_.sessions;
  if (radius_ > figures_.max_radius_mm) figures_.max_radius_mm = radius_;
  return true;
}

void CutterComp::comp_off() {
  if (!first_move_ && !queue_.empty()) {
    Move at = queue_.back().m;
    if (!move_endpoint_and_flush(at, cur())) return;
  }
  dequeue();
  note_crossings();
  if (!first_move_) {
    arc_not_allowed_ = true;
    resume_from_tool_ = true;
  }
  active_ = false;
}

void CutterComp::record_contour(const Move& m) {
  if (figures_.contour.empty() || index_ == 0) {
    if (figures_.contour.empty() || !figures_.contour.back().empty()) figures_.contour.emplace_back();
  }
  std::vector<Vec3>& line = figures_.contour.back();
  const auto add = [&](const Vec3& p) {
    if (contour_points_ >= CompFigures::kMaxContourPoints) {
      figures_.contour_truncated = true;
      return;
    }
    line.push_back(p);
    ++contour_points_;
  };
  if (line.empty()) add(prog_);
  if (m.kind == MoveKind::kArc) {
    const Vec2 c = in_plane(m.center), a = prog();
    const double sweep = turn_angle(a, c, m.sweep > 0.0 ? 1 : -1, in_plane(m.end));
    const int n = std::max(1, static_cast<int>(std::ceil(std::fabs(sweep) / (3.0 * kPi / 180.0))));
    const double a0 = angle_of(a - c), r = norm(a - c), z0 = oop(prog_), z1 = oop(m.end);
    for (int i = 1; i < n; ++i) {
      const double t = static_cast<double>(i) / n;
      add(to_space(c + polar(r, a0 + t * sweep), z0 + t * (z1 - z0)));
    }
  }
  add(m.end);
}

void CutterComp::programmed_piece(const Move& m) {
  record_contour(m);
  const Vec2 a = prog(), b = in_plane(m.end);
  Piece p;
  if (m.kind == MoveKind::kArc) {
    p = arc_piece(a, b, in_plane(m.center), m.sweep > 0.0 ? 1 : -1);
  } else {
    if (a.x == b.x && a.y == b.y) return;
    p = segment(a, b);
  }
  Gouge g;
  if (options_.gouge_check && !gouge_.programmed(p, index_, m.line, g)) report_gouge(g);
}

// An exact gouge found by the look-ahead (a test LinuxCNC does not make): an error, so nothing
// of the program moves, but the session goes on as LinuxCNC's would, so that the listing
// (pcnc check --print-moves) still shows LinuxCNC's moves and every further gouge is reported.
void CutterComp::report_gouge(const Gouge& g) {
  sink_.error(g.line, g.column, describe_gouge(g, radius_));
  ++figures_.gouges;
}

CutterComp::Held CutterComp::held(const Move& m, Vec2 end, double o) const {
  Held h;
  h.m = m;
  h.end = end;
  h.out_of_plane = o;
  h.entry = first_move_;
  h.index = index_;
  return h;
}

void CutterComp::enqueue_line(const Move& m, Vec2 dir, Vec2 end, double o) {
  Held h = held(m, end, o);
  h.dir = dir;
  queue_.push_back(h);
}

void CutterComp::enqueue_arc(const Move& m, double original_turn, Vec2 end, Vec2 center, int turn, double o) {
  Held h = held(m, end, o);
  h.m.kind = MoveKind::kArc;
  h.center = center;
  h.turn = turn;
  h.original_turn = original_turn;
  queue_.push_back(h);
}

void CutterComp::emit(const Held& h) {
  Move out = h.m;
  if (!h.motion) {
    out.start = out.end = emitted_;
    ready_.push_back(out);
    return;
  }
  const Vec2 s = in_plane(emitted_);
  out.start = emitted_;
  out.end = to_space(h.end, h.out_of_plane);
  out.machine_frame = false;
  Piece piece = segment(s, h.end);
  if (out.kind == MoveKind::kArc) {
    out.center = to_space(h.center, oop(emitted_));
    out.radius = norm(s - h.center);
    out.sweep = turn_angle(s, h.center, h.turn, h.end);
    out.normal_axis = normal_;
    piece = arc_piece(s, h.end, h.center, h.turn);
  }
  if (out.inverse_time_s > 0.0 && out.kind != MoveKind::kRapid) {
    if (h.corner) {
      out.inverse_time_s = 0.0;  // the programmed move's feed (mm/s), not its time
    } else {
      const double length = move_length(out);
      out.feed_mm_s = length > 0.0 ? std::min(length / out.inverse_time_s, options_.max_feed_mm_s) : out.feed_mm_s;
    }
  }
  ready_.push_back(out);
  emitted_ = out.end;
  ++figures_.moves_out;
  if (h.entry || !active_ || !options_.gouge_check) return;
  Gouge g;
  if (!gouge_.tool(piece, h.index, out.line, out.column, g)) report_gouge(g);
}

void CutterComp::dequeue() {
  endpoint_valid_ = false;
  // The held moves go out in order (a gouge emit() finds is reported, the session goes on).
  std::vector<Held> held;
  held.swap(queue_);
  for (const Held& h : held) emit(h);
}

// LinuxCNC's move_endpoint_and_flush: the held moves end at p instead; one that would run
// backwards (a line against its programmed direction, an arc sweeping further than made) cannot
// be reached without gouging.
bool CutterComp::move_endpoint_and_flush(const Move& m, Vec2 p) {
  if (queue_.empty()) return true;
  for (Held& h : queue_) {
    if (!h.motion) continue;
    if (h.m.kind == MoveKind::kArc) {
      const double r1 = norm(h.end - h.center);
      const double r2 = norm(p - h.center);
      const double l2 = turn_angle(endpoint_, h.center, h.turn, p);
      if (std::fabs(r1 - r2) > 0.01)
        return fail(m, "cutter compensation made an arc whose radii differ (r1 " + mm(r1) + ", r2 " + mm(r2) +
                           " mm); expected a contour without this corner");
      if (h.original_turn != 0.0 && endpoint_valid_ && std::fabs(l2) > std::fabs(h.original_turn) + arc_tolerance_) {
        return fail(m, "arc move in concave corner cannot be reached by the tool without gouging: the offset arc of "
                       "line " + std::to_string(h.m.line) + " would have to sweep " +
                           mm((std::fabs(l2) - std::fabs(h.original_turn)) * r2) +
                           " mm further than it goes (tool radius " + mm(radius_) + " mm)");
      }
    } else {
      const Vec2 d = p - endpoint_;
      const double along = dot(h.dir, d);
      if (endpoint_valid_ && along < 0.0) {
        const double n = norm(h.dir);
        return fail(m, std::string(h.m.kind == MoveKind::kRapid ? "straight traverse" : "straight feed") +
                           " in concave corner cannot be reached by the tool without gouging: the offset move of line " +
                           std::to_string(h.m.line) + " would run " + mm(n > 0.0 ? -along / n : 0.0) +
                           " mm backwards (tool radius " + mm(radius_) + " mm)");
      }
    }
    h.end = p;
  }
  dequeue();
  set_endpoint(p);
  return true;
}

void CutterComp::straight_entry(const Move& m) {
  const Vec2 c = cur(), p = in_plane(m.end);
  const double pz = oop(m.end);
  programmed_piece(m);
  if (!active_) return;
  const double distance = norm(p - c);
  if (distance <= radius_) {
    fail(m, "length of cutter compensation entry move (" + mm(distance) +
                " mm) is not greater than the tool radius (" + mm(radius_) + " mm); expected a longer entry move");
    return;
  }
  const double alpha = angle_of(p - c) + (side_ == CompSide::kLeft ? kHalfPi : -kHalfPi);
  const Vec2 end = p + polar(radius_, alpha);
  set_endpoint(c);
  enqueue_line(m, polar(1.0, alpha), end, pz);
  first_move_ = false;
  cur_ = to_space(end, pz);
  prog_ = to_space(p, pz);
  ++index_;
  ++figures_.moves_in;
}

void CutterComp::straight_next(const Move& m) {
  const Vec2 c = cur(), op = prog(), p = in_plane(m.end);
  const double pz = oop(m.end), cz = oop(cur_);
  programmed_piece(m);
  if (!active_) return;
  Vec2 end = c;
  if (p.x == op.x && p.y == op.y) {  // no motion in the plane
    enqueue_line(m, {0.0, 0.0}, c, pz);
  } else {
    const bool left = side_ == CompSide::kLeft;
    double theta = angle_of(c - op);
    double alpha = angle_of(p - op);
    double beta = 0.0;
    double gamma = 0.0;
    if (left) {
      if (theta < alpha) theta += 2.0 * kPi;
      beta = (theta - alpha) - kHalfPi;
      gamma = kHalfPi;
    } else {
      if (alpha < theta) alpha += 2.0 * kPi;
      beta = (alpha - theta) - kHalfPi;
      gamma = -kHalfPi;
    }
    end = p + polar(radius_, alpha + gamma);
    Vec2 mid = op + polar(radius_, alpha + gamma);
    const bool front_arc = !queue_.empty() && queue_.front().motion && queue_.front().m.kind == MoveKind::kArc;
    bool concave = false;
    if (beta < -kSmall || beta > kPi + kSmall) {
      concave = true;
    } else if (beta > kPi - kSmall && front_arc &&
               ((!left && queue_.front().turn > 0) || (left && queue_.front().turn < 0))) {
      concave = true;  // LinuxCNC's "h" shape: stay above and beside, not around
    }
    if (!concave && beta > kSmall) {  // convex: an arc about the programmed corner
      if (!move_endpoint_and_flush(m, c)) return;
      if (m.kind == MoveKind::kLine) {
        enqueue_arc(m, 0.0, mid, op, left ? -1 : 1, cz);
        queue_.back().corner = true;
      } else {
        Move r = m;  // a rapid has no arc: a straight traverse to the corner's far side
        enqueue_line(r, {0.0, 0.0}, mid, cz);
      }
      dequeue();
      set_endpoint(mid);
      ++figures_.corner_arcs;
    } else if (concave) {
      if (!front_arc) {  // line -> line: the held line ends where the offset lines meet
        const double halfcorner = (beta + kPi) / 2.0;
        if (halfcorner == 0.0) {
          fail(m, "zero degree inside corner is invalid for cutter compensation");
          return;
        }
        const double retreat = radius_ / std::tan(halfcorner);
        mid = c + polar(retreat, theta + gamma);
      } else {  // arc -> line: where the line's offset meets the held offset arc
        const Held& prev = queue_.front();
        const double oldrad = norm(prev.end - prev.center);
        const double base_dir = angle_of(p - op);
        const double th = prev.turn > 0 ? base_dir + kHalfPi : base_dir - kHalfPi;
        const double phi = angle_of(prev.center - op);
        const bool inside = tool_inside_arc(side_, prev.turn);
        const double oldrad_uncomp = inside ? oldrad + radius_ : oldrad - radius_;
        const double d = oldrad_uncomp * std::cos(th - phi);
        const double l = (inside ? d - radius_ : d + radius_) / oldrad;
        if (l > 1.0 || l < -1.0) {
          fail(m, "arc to straight motion makes a corner the compensated tool can't fit in without gouging (by " +
                      mm((std::fabs(l) - 1.0) * oldrad) + " mm, tool radius " + mm(radius_) + " mm)");
          return;
        }
        const double a = inside ? (prev.turn > 0 ? -std::acos(l) : std::acos(l))
                                : (prev.turn > 0 ? std::acos(l) : -std::acos(l));
        mid = prev.center + polar(oldrad, a + th + kPi);
      }
      if (!move_endpoint_and_flush(m, mid)) return;
      ++figures_.concave_corners;
    } else {  // tangent within 0.05 rad: nothing in between
      dequeue();
      set_endpoint(c);
    }
    enqueue_line(m, p - op, end, pz);
  }
  cur_ = to_space(end, pz);
  prog_ = to_space(p, pz);
  ++index_;
  ++figures_.moves_in;
}

void CutterComp::arc_entry(const Move& m) {
  const Vec2 c = cur(), end = in_plane(m.end), center0 = in_plane(m.center);
  const double end_z = oop(m.end);
  const int turn = m.sweep > 0.0 ? 1 : -1;
  programmed_piece(m);
  if (!active_) return;
  const double entry = norm(end - c);
  if (entry <= radius_) {
    fail(m, "radius of cutter compensation entry arc (" + mm(entry) + " mm) is not greater than the tool radius (" +
                mm(radius_) + " mm)");
    return;
  }
  const double arc_radius = norm(c - center0);
  const bool inside = tool_inside_arc(side_, turn);
  if (inside && arc_radius <= radius_) {
    fail(m, "tool radius (" + mm(radius_) + " mm) not less than arc radius (" + mm(arc_radius) +
                " mm) with cutter compensation: the tool would gouge by " + mm(radius_ - arc_radius) + " mm");
    return;
  }
  const double gamma = inside ? angle_of(center0 - end) : angle_of(end - center0);
  const Vec2 new_end = end + polar(radius_, gamma);
  // The compensated arc's center: on the line from the new end toward the programmed center,
  // equally far from the new end and the tool.
  const double b_len = norm(c - new_end) / 2.0;
  const double ab_ang = angle_of(center0 - new_end);
  const double a_ang = angle_of(c - new_end) - ab_ang;
  if (std::fabs(std::cos(a_ang)) < 1e-6) {
    fail(m, "tool radius not less than arc radius with cutter compensation (entry arc)");
    return;
  }
  const double c_len = b_len / std::cos(a_ang);
  const Vec2 center = new_end + polar(c_len, ab_ang);
  first_move_ = false;
  enqueue_arc(m, turn_angle(c, center, turn, new_end), new_end, center, turn, end_z);
  cur_ = to_space(new_end, end_z);
  prog_ = to_space(end, end_z);
  ++index_;
  ++figures_.moves_in;
}

void CutterComp::arc_next(const Move& m) {
  const Vec2 op = prog(), c = cur(), end = in_plane(m.end), center = in_plane(m.center);
  const double end_z = oop(m.end), cz = oop(cur_);
  const int turn = m.sweep > 0.0 ? 1 : -1;
  const bool left = side_ == CompSide::kLeft;
  programmed_piece(m);
  if (!active_) return;
  const double arc_radius = norm(center - end);
  double theta = angle_of(c - op);
  theta = left ? theta - kHalfPi : theta + kHalfPi;
  double delta = angle_of(center - op);
  const double alpha = turn > 0 ? delta - kHalfPi : delta + kHalfPi;
  double beta = left ? theta - alpha : alpha - theta;
  beta = beta > 1.5 * kPi ? beta - 2.0 * kPi : beta < -kHalfPi ? beta + 2.0 * kPi : beta;
  const bool inside = tool_inside_arc(side_, turn);
  double gamma = 0.0;
  if (inside) {
    gamma = angle_of(center - end);
    if (arc_radius <= radius_) {
      fail(m, "tool radius (" + mm(radius_) + " mm) not less than arc radius (" + mm(arc_radius) +
                  " mm) with cutter compensation: the tool would gouge by " + mm(radius_ - arc_radius) + " mm");
      return;
    }
  } else {
    gamma = angle_of(end - center);
    delta += kPi;
  }
  const Vec2 new_end = end + polar(radius_, gamma);
  const double original = turn_angle(op, center, turn, end);
  if (beta < -kSmall || beta > kPi + kSmall || (std::fabs(beta - kPi) < kSmall && !inside)) {  // concave
    const bool front_arc = !queue_.empty() && queue_.front().motion && queue_.front().m.kind == MoveKind::kArc;
    Vec2 mid;
    if (!front_arc) {  // line -> arc
      const double cy = arc_radius * std::sin(beta - kHalfPi);
      const double dist = inside ? arc_radius - radius_ : arc_radius + radius_;
      const double l = (inside ? cy + radius_ : cy - radius_) / dist;
      if (l > 1.0 || l < -1.0) {
        fail(m, "arc move in concave corner cannot be reached by the tool without gouging (by " +
                    mm((std::fabs(l) - 1.0) * dist) + " mm, tool radius " + mm(radius_) + " mm)");
        return;
      }
      const double a = inside ? (turn > 0 ? theta + std::asin(l) : theta - std::asin(l))
                              : (turn > 0 ? theta + kPi - std::asin(l) : theta + kPi + std::asin(l));
      mid = center + polar(dist, a);
    } else {  // arc -> arc: where the two offset circles meet
      const Held& prev = queue_.front();
      const double oldrad = norm(prev.center - prev.end);
      const double newrad = inside ? arc_radius - radius_ : arc_radius + radius_;
      const double arc_cc = norm(prev.center - center);
      if (oldrad == 0.0 || arc_cc == 0.0) {
        fail(m, "arc to arc motion is invalid because the arcs have the same center");
        return;
      }
      const double a = (oldrad * oldrad + arc_cc * arc_cc - newrad * newrad) / (2.0 * oldrad * arc_cc);
      if (a > 1.0 || a < -1.0) {
        fail(m, "arc to arc motion makes a corner the compensated tool can't fit in without gouging (the offset "
                "circles miss by " + mm(std::fabs(oldrad + (a > 0 ? 1 : -1) * newrad - arc_cc) / 1.0) +
                    " mm, tool radius " + mm(radius_) + " mm)");
        return;
      }
      const double pullback = std::acos(a);
      const double cc_dir = angle_of(center - prev.center);
      const bool prev_inside = tool_inside_arc(side_, prev.turn);
      const double dir = prev_inside ? (turn > 0 ? cc_dir + pullback : cc_dir - pullback)
                                     : (turn > 0 ? cc_dir - pullback : cc_dir + pullback);
      mid = prev.center + polar(oldrad, dir);
    }
    if (!move_endpoint_and_flush(m, mid)) return;
    ++figures_.concave_corners;
    enqueue_arc(m, original, new_end, center, turn, end_z);
  } else if (beta > kSmall) {  // convex: an arc about the programmed corner, then the arc
    const Vec2 mid = op + polar(radius_, delta);
    dequeue();
    enqueue_arc(m, 0.0, mid, op, left ? -1 : 1, cz);
    queue_.back().corner = true;
    dequeue();
    set_endpoint(mid);
    ++figures_.corner_arcs;
    enqueue_arc(m, original, new_end, center, turn, end_z);
  } else {
    dequeue();
    set_endpoint(c);
    enqueue_arc(m, original, new_end, center, turn, end_z);
  }
  cur_ = to_space(new_end, end_z);
  prog_ = to_space(end, end_z);
  ++index_;
  ++figures_.moves_in;
}

}  // namespace pcnc
