// interpreter_ruled.cpp — a G5.4 ... G5.5 group (read by gcode/ruled_reader.hpp) as a Move of
// the interpreter (docs/ruled-surface.md, "The G-code form", rules 3 and 5): the set points
// placed like G1's (units, work offsets, --fit), the first against where the tool stands (then
// taken exactly as that pose, so the piece starts without a jump), the piece
// ruled_model_through the points and unit tool vectors, the joints walked along it through the
// inverse kinematics (where they stand after it), and the feed in mm/s.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "config/joint_map.hpp"
#include "gcode/interpreter.hpp"
#include "gcode/interpreter_text.hpp"
#include "gcode/rotary_move.hpp"
#include "gcode/ruled_move.hpp"
#include "geometry/ruled_model.hpp"

namespace pcnc {

using namespace interp;

bool Interpreter::ruled_machine() const {
  return config_.kinematics.kind != KinematicsKind::kTrivial && config_.rotary_mask() != 0;
}

RuledModal Interpreter::ruled_modal(bool in_nurbs_group) const {
  RuledModal r;
  r.tcp = tcp_;
  r.incremental = incremental_;
  r.inverse_time = inverse_time_;
  r.feed = feed_;
  r.spline_group = in_nurbs_group || nurbs_.open;
  return r;
}

bool Interpreter::ruled_group(const RuledGroup& g, MoveList& out) {
  auto fail_at = [&](int line, std::string message) {
    sink_.error(line, 1, std::move(message));
    return false;
  };
  const double unit = inches_ ? kInch : 1.0;
  const double tol = config_.motion.block_tolerance_mm;
  std::vector<Vec3> points(g.points.size());
  for (std::size_t i = 0; i < g.points.size(); ++i) points[i] = to_machine(unit * g.points[i] + origin_);
  std::vector<Vec3> axes = g.axes;
  // rule 3: the first set point is the current pose
  const Vec3 tip = to_machine(q_);
  const Vec3 axis = tool_axis_of(config_, rot_);
  if (norm(points[0] - tip) > tol) {
    return fail_at(g.point_lines[0], "the first set point of the G5.4 group is " + num(norm(points[0] - tip)) +
                                         " mm from where the tool tip stands; expected the current tip within " +
                                         num(tol) + " mm (motion.block_tolerance_mm)");
  }
  const double turn = std::acos(std::clamp(dot(normalized(axes[0]), axis), -1.0, 1.0));
  if (turn > kRuledAxisTolerance) {
    return fail_at(g.point_lines[0], "the first tool vector of the G5.4 group is " + num(turn) +
                                         " rad from the tool axis the joints give; expected the current axis within " +
                                         num(kRuledAxisTolerance) + " rad");
  }
  points[0] = tip;
  axes[0] = axis;
  RuledModelResult model = ruled_model_through(points, axes, RulingForm::kVector);
  if (!model.error.empty()) return fail_at(g.line, "G5.4 group: " + model.error);
  Move m;
  m.kind = MoveKind::kRuled;
  m.line = g.line;
  m.column = 1;
  m.start = tip;
  m.end = points.back();
  m.rot_start = m.rot_end = rot_;
  m.tcp = true;
  m.tool_length = tcp_length_;
  m.contouring = contouring_;
  m.path_tolerance_mm = path_tolerance_;
  m.known = known_;
  m.comp = comp_;
  m.feed_mm_s = std::min(g.feed * unit / 60.0, max_feed_mm_s_);
  m.ruled = std::make_shared<const RuledModel>(std::move(model.model));
  const RuledJointWalk w = walk_ruled_piece(*m.ruled, config_, m.tool_length, ruled_start_joints(m, config_));
  if (!w.error.empty()) return fail_at(g.line, "G5.4 group: " + w.error);
  Vec3 xyz{};
  from_joints(config_, w.q_end, xyz, m.rot_end);
  feed_ = g.feed;
  rot_ = m.rot_end;
  q_ = to_job(m.end);
  out.push(m);
  return true;
}

}  // namespace pcnc
