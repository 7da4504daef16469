// make_blocks.cpp — the test block builder (see make_blocks.hpp).
#include "make_blocks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace pcnc::test {
namespace {

void plane_axes(int normal, int& a1, int& a2) {
  if (normal == 0) { a1 = 1; a2 = 2; }
  else if (normal == 1) { a1 = 2; a2 = 0; }
  else { a1 = 0; a2 = 1; }
}

void driving_axis(Block& b) {
  const Vec3 d = b.end - b.start;
  int k = 0;
  for (int i = 1; i < kAxes; ++i)
    if (std::abs(d[i]) > std::abs(d[k])) k = i;
  b.driving_axis = static_cast<std::uint8_t>(k);
  b.driving_dir = d[k] >= 0.0 ? 1 : -1;
  const double share = b.length > 0.0 ? std::abs(d[k]) / b.length : 0.0;
  b.driving_speed = b.speed * share;
  b.driving_accel = b.accel * share;
  const double brake = b.driving_accel > 0.0 ? b.driving_speed * b.driving_speed / (2.0 * b.driving_accel) : 0.0;
  b.decel_start = b.end[k] - b.driving_dir * std::min(brake, std::abs(d[k]) / 2.0);
  int moving = 0;
  for (int i = 0; i < kAxes; ++i) moving += std::abs(d[i]) > 1e-9;
  b.motion_class = static_cast<MotionClass>(moving);
}

// An arc's driving axis is its normal (helical) axis; decel_start is that axis's coordinate
// at decel_start_angle (docs/gcode.md, "Preprocessing").
void arc_driving_axis(Block& b) {
  const int n = b.arc.normal_axis;
  const double helix = b.arc.helix, turn = std::abs(b.arc.sweep);
  const double share = std::abs(helix) / b.length;
  b.driving_axis = static_cast<std::uint8_t>(n);
  b.driving_dir = helix < 0.0 ? -1 : 1;
  b.driving_speed = b.speed * share;
  b.driving_accel = b.accel * share;
  b.decel_start = b.start[n] + helix * b.arc.decel_start_angle / turn;
  b.motion_class = std::abs(helix) > 1e-9 ? MotionClass::kSpace : MotionClass::kPlane;
}

}  // namespace

ProgramBuilder::ProgramBuilder(const MachineConfig& config, const Vec3& start) : cfg_(config), pos_(start) {}

Block ProgramBuilder::next(BlockKind kind) {
  Block b{};
  b.seq = ++seq_;
  b.line = ++line_;
  b.kind = kind;
  b.contouring = contouring_ ? 1 : 0;
  // the tolerance the host would make the block with: the config's, under M21
  b.path_tolerance_mm = contouring_ ? static_cast<float>(cfg_.motion.path_tolerance_mm) : 0.0f;
  b.start = pos_;
  b.end = pos_;
  return b;
}

ProgramBuilder& ProgramBuilder::contouring(bool on) {
  contouring_ = on;
  return *this;
}

ProgramBuilder& ProgramBuilder::line(const Vec3& end, double feed) {
  Block b = next(BlockKind::kLine);
  b.end = end;
  b.length = norm(end - pos_);
  const Vec3 u = normalized(end - pos_);
  double v = feed, a = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kAxes; ++i) {
    if (std::abs(u[i]) < 1e-12) continue;
    v = std::min(v, cfg_.axes[i].max_velocity_mm_s / std::abs(u[i]));
    a = std::min(a, cfg_.axes[i].max_accel_mm_s2 / std::abs(u[i]));
  }
  b.speed = v;
  b.accel = std::isfinite(a) ? a : cfg_.axes[0].max_accel_mm_s2;
  b.dir_start = u;
  b.dir_end = u;
  driving_axis(b);
  blocks_.push_back(b);
  pos_ = end;
  return *this;
}

ProgramBuilder& ProgramBuilder::rapid(const Vec3& end) {
  line(end, std::numeric_limits<double>::infinity());
  blocks_.back().kind = BlockKind::kRapid;
  return *this;
}

ProgramBuilder& ProgramBuilder::arc(const Vec3& end, const Vec3& center_in, int normal, bool cw, double feed, int turns) {
  Block b = next(BlockKind::kArc);
  int a1 = 0, a2 = 1;
  plane_axes(normal, a1, a2);
  Vec3 center = center_in;
  center[normal] = pos_[normal];
  const double r = std::hypot(pos_[a1] - center[a1], pos_[a2] - center[a2]);
  const double th0 = std::atan2(pos_[a2] - center[a2], pos_[a1] - center[a1]);
  const double th1 = std::atan2(end[a2] - center[a2], end[a1] - center[a1]);
  const double two_pi = 2.0 * std::numbers::pi;
  double sweep = th1 - th0;
  if (cw) {
    while (sweep >= 0.0) sweep -= two_pi;  // a full circle when end == start
    sweep -= two_pi * turns;
  } else {
    while (sweep <= 0.0) sweep += two_pi;
    sweep += two_pi * turns;
  }
  const double helix = end[normal] - pos_[normal];
  b.end = end;
  b.length = std::hypot(r * sweep, helix);
  const double q = r * std::abs(sweep) / b.length, h = std::abs(helix) / b.length;
  const auto& A = cfg_.axes;
  const double a_plane = std::min(A[a1].max_accel_mm_s2, A[a2].max_accel_mm_s2);
  const double v_plane = std::min(A[a1].max_velocity_mm_s, A[a2].max_velocity_mm_s);
  double v = feed, a = std::numeric_limits<double>::infinity();
  if (q > 1e-12) {
    v = std::min({v, v_plane / q, std::sqrt(0.5 * a_plane * r) / q});
    a = std::min(a, 0.5 * a_plane / q);
  }
  if (h > 1e-12) {
    v = std::min(v, A[normal].max_velocity_mm_s / h);
    a = std::min(a, A[normal].max_accel_mm_s2 / h);
  }
  b.speed = v;
  b.accel = a;
  b.arc.center = center;
  b.arc.radius = r;
  b.arc.start_angle = th0;
  b.arc.sweep = sweep;
  b.arc.helix = helix;
  b.arc.normal_axis = static_cast<std::uint8_t>(normal);
  b.arc.angular_speed = v * q / r;
  b.arc.angular_accel = a * q / r;
  const double brake = b.arc.angular_speed * b.arc.angular_speed / (2.0 * b.arc.angular_accel);
  b.arc.decel_start_angle = 2.0 * brake >= std::abs(sweep) ? 0.5 * std::abs(sweep) : std::abs(sweep) - brake;
  // tangents
  const double sgn = sweep > 0.0 ? 1.0 : -1.0;
  auto tangent = [&](double th) {
    Vec3 t{};
    t[a1] = -std::sin(th) * sgn * r * std::abs(sweep);
    t[a2] = std::cos(th) * sgn * r * std::abs(sweep);
    t[normal] = helix;
    return normalized(t);
  };
  b.dir_start = tangent(th0);
  b.dir_end = tangent(th0 + sweep);
  arc_driving_axis(b);
  blocks_.push_back(b);
  pos_ = end;
  return *this;
}

ProgramBuilder& ProgramBuilder::dwell(double seconds) {
  Block b = next(BlockKind::kDwell);
  b.dwell_s = seconds;
  blocks_.push_back(b);
  return *this;
}

ProgramBuilder& ProgramBuilder::pause(bool optional) {
  Block b = next(BlockKind::kPause);
  b.optional_stop = optional ? 1 : 0;
  blocks_.push_back(b);
  return *this;
}

ProgramBuilder& ProgramBuilder::end() {
  blocks_.push_back(next(BlockKind::kEnd));
  return *this;
}

Vec3 home(const MachineConfig& cfg) { return {cfg.axes[0].home_mm, cfg.axes[1].home_mm, cfg.axes[2].home_mm}; }

std::vector<Block> square_program(const MachineConfig& cfg, const Vec3& corner, double side, double feed,
                                  bool contouring) {
  ProgramBuilder p(cfg, home(cfg));
  p.contouring(contouring);
  p.rapid(corner);
  const Vec3 c = corner;
  p.line({c[0] + side, c[1], c[2]}, feed)
      .line({c[0] + side, c[1] + side, c[2]}, feed)
      .line({c[0], c[1] + side, c[2]}, feed)
      .line(c, feed)
      .end();
  return p.blocks();
}

std::vector<Block> polygon_circle_program(const MachineConfig& cfg, const Vec3& center, double radius,
                                          int segments, double feed, bool contouring) {
  ProgramBuilder p(cfg, home(cfg));
  p.contouring(contouring);
  const Vec3 first{center[0] + radius, center[1], center[2]};
  p.rapid(first);
  for (int k = 1; k <= segments; ++k) {
    const double th = 2.0 * std::numbers::pi * k / segments;
    Vec3 q{center[0] + radius * std::cos(th), center[1] + radius * std::sin(th), center[2]};
    if (k == segments) q = first;
    p.line(q, feed);
  }
  p.end();
  return p.blocks();
}

}  // namespace pcnc::test
