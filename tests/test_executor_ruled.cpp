// test_executor_ruled.cpp — ruled blocks (issue 17) in the rt's executor and block check, in
// process: blocks made by the host's plan_ruled_move from a piece of 60 segments (two blocks),
// run by the Executor on the 5-axis config: the split flows with the carried remainder, the feed
// override scales the speed (capped at 1), a feed hold brings the tip to rest on the piece and
// resumes from there, the piece ends on the host's end joints, and the setpoints' feed-forward
// is the analytic joint velocity. The block check refuses corrupted ruled blocks by name.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "config/joint_map.hpp"
#include "gcode/ruled_move.hpp"
#include "geometry/ruled_model.hpp"
#include "ipc/block_check.hpp"
#include "ipc/block_ruled.hpp"
#include "motion/executor.hpp"
#include "service/resume.hpp"
#include "test_paths.hpp"
#include "machine_runner.hpp"

namespace pcnc {
namespace {


struct ExecutorPiece {
  MachineConfig cfg = test::five_axis_config();
  Vec3 xyz{10.5, 11.5, 20.0};
  Rot3 rot{0.2, 0.0, 0.6};
  std::vector<Block> blocks;
  double feed = 8.0;  // mm/s
};

// The blocks of a piece through `pts` and `axes` planned from the pose of `s`, numbered 1, 2, ...
// and followed by an End block.
RuledMoveBlocks plan_piece(ExecutorPiece& s, const std::vector<Vec3>& pts, const std::vector<Vec3>& axes) {
  RuledModelResult m = ruled_model_through(pts, axes, RulingForm::kVector);
  EXPECT_TRUE(m.error.empty()) << m.error;
  Move mv;
  mv.kind = MoveKind::kRuled;
  mv.line = 7;
  mv.start = pts.front();
  mv.end = pts.back();
  mv.rot_start = mv.rot_end = s.rot;
  mv.tcp = true;
  mv.feed_mm_s = s.feed;
  mv.ruled = std::make_shared<const RuledModel>(m.model);
  RuledMoveBlocks rb = plan_ruled_move(mv, s.cfg);
  EXPECT_TRUE(rb.error.empty()) << rb.error;
  const RuledMoveBlocks planned = rb;
  for (std::size_t i = 0; i < rb.blocks.size(); ++i) rb.blocks[i].seq = i + 1;
  Block end{};
  end.kind = BlockKind::kEnd;
  end.seq = rb.blocks.size() + 1;
  if (!rb.blocks.empty()) {
    end.start = end.end = rb.blocks.back().rotary.joint_end;
    end.rotary.start = end.rotary.end = rb.blocks.back().rotary.end;
  }
  s.blocks = rb.blocks;
  s.blocks.push_back(end);
  return planned;
}

// A 60-segment piece from the pose the joints give: 9 mm along X with a Y wave, the axis swinging.
ExecutorPiece make_setup() {
  ExecutorPiece s;
  const Kinematics kin = kinematics_with_tool(s.cfg, 0.0);
  const ToolPose p0 = forward(kin, to_joints(s.cfg, s.xyz, s.rot));
  std::vector<Vec3> pts, axes;
  for (int k = 0; k <= 60; ++k) {
    const double t = k / 60.0;
    pts.push_back(p0.tip + Vec3{9.0 * t, 0.5 * std::sin(6.283185307179586 * t), 0.0});
    axes.push_back(normalized(p0.axis + (0.1 * std::sin(3.141592653589793 * t)) * Vec3{1.0, 0.0, 0.0}));
  }
  const RuledMoveBlocks rb = plan_piece(s, pts, axes);
  EXPECT_EQ(rb.blocks.size(), 2u);
  EXPECT_EQ(rb.feed, s.feed) << "the joints allow the feed";
  return s;
}

// n + 1 set points along `length` mm of X from the tip the joints of `s` give, with the tool
// vector axis(t, that pose, kinematics) at each (t from 0 to 1).
template <class Axis>
void straight_piece(const ExecutorPiece& s, int n, double length, std::vector<Vec3>& pts, std::vector<Vec3>& axes, Axis axis) {
  const Kinematics kin = kinematics_with_tool(s.cfg, 0.0);
  const ToolPose p0 = forward(kin, to_joints(s.cfg, s.xyz, s.rot));
  for (int k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    pts.push_back(p0.tip + Vec3{length * t, 0.0, 0.0});
    axes.push_back(axis(t, p0, kin));
  }
}

struct Runner {
  Executor ex;
  MotionRing ring;
  std::size_t next = 0;
  explicit Runner(const ExecutorPiece& s) : ex(s.cfg) {
    ex.set_rotary(s.rot);
    ex.set_position(s.xyz);
  }
  ExecResult step(const ExecutorPiece& s, const ExecInput& in) {
    while (next < s.blocks.size() && ring.try_push(s.blocks[next])) ++next;
    ExecResult r;
    ex.step(ring, in, r);
    EXPECT_EQ(r.fault, FaultCode::kNone) << r.reason;
    return r;
  }
};

TEST(ExecutorRuled, SplitPieceFlowsAndEndsOnTheHostsEndJoints) {
  const ExecutorPiece s = make_setup();
  Runner run(s);
  const double dt = s.cfg.cycle_period_s();
  int flows = 0, cycles = 0;
  double min_mid = 1e9;
  bool ended = false;
  Vec3 last{};
  const Kinematics kin = kinematics_with_tool(s.cfg, 0.0);
  double worst_ff = 0.0, last_speed = 0.0;
  Vec3 last_vel{};
  int constant = 0;
  for (; cycles < 100000 && !ended; ++cycles) {
    const ExecResult r = run.step(s, ExecInput{});
    flows += r.junction_flows;
    ended = r.program_end;
    if (run.ex.seq() <= 2 && run.ex.speed() == s.feed && last_speed == s.feed) {
      // the velocity feed-forward is the joints' rate: at constant feed the difference of the
      // setpoints over the cycle agrees with the mean of the feed-forward at its ends
      const Vec3 d = (1.0 / dt) * (run.ex.position() - last);
      const Vec3 mean = 0.5 * (run.ex.velocity() + last_vel);
      for (int i = 0; i < 3; ++i) worst_ff = std::max(worst_ff, std::abs(d[i] - mean[i]));
      ++constant;
    }
    if (run.ex.seq() == 1 && run.ex.progress() > 5.0) min_mid = std::min(min_mid, run.ex.speed());
    if (run.ex.seq() == 2 && run.ex.progress() > 0.0 && run.ex.progress() < 2.0) min_mid = std::min(min_mid, run.ex.speed());
    last = run.ex.position();
    last_vel = run.ex.velocity();
    last_speed = run.ex.speed();
  }
  ASSERT_TRUE(ended);
  EXPECT_EQ(flows, 1) << "the two parts of the piece flow";
  EXPECT_NEAR(min_mid, s.feed, 1e-9) << "no slow-down around the split";
  EXPECT_GT(constant, 1500);
  EXPECT_LT(worst_ff, 1e-4 * s.feed) << "velocity feed-forward against the setpoints' differences, mm/s";
  // the end: the host's end joints, exactly, and the tip at the piece's end
  EXPECT_EQ(run.ex.position(), s.blocks[1].rotary.joint_end);
  EXPECT_EQ(run.ex.rotary(), s.blocks[1].rotary.end);
  EXPECT_LT(norm(forward(kin, to_joints(s.cfg, run.ex.position(), run.ex.rotary())).tip - s.blocks[1].end), 1e-6);
  // time: the length at the feed plus about one ramp up and down (accel 0.95 of the slowest axis)
  const double len = s.blocks[0].length + s.blocks[1].length;
  EXPECT_NEAR(cycles * dt, len / s.feed + s.feed / s.blocks[0].accel, 0.01);
}

TEST(ExecutorRuled, FeedOverrideAndHoldOnThePiece) {
  const ExecutorPiece s = make_setup();
  Runner run(s);
  const double dt = s.cfg.cycle_period_s();
  const double a = s.blocks[0].accel;
  ExecInput in;
  in.feed_override = 0.5;
  for (int i = 0; i < 400; ++i) run.step(s, in);
  EXPECT_NEAR(run.ex.speed(), 0.5 * s.feed, 1e-9) << "override 50 %";
  in.feed_override = 2.0;
  for (int i = 0; i < 400; ++i) run.step(s, in);
  EXPECT_NEAR(run.ex.speed(), s.feed, 1e-9) << "override above 100 % is capped at the piece's schedule";
  in.hold = true;
  double prev = run.ex.speed();
  int n = 0;
  while (run.ex.speed() > 0.0 && n < 10000) {
    run.step(s, in);
    EXPECT_LE(prev - run.ex.speed(), a * dt * (1.0 + 1e-9));
    prev = run.ex.speed();
    ++n;
  }
  EXPECT_EQ(n, static_cast<int>(std::ceil(s.feed / (a * dt) - 1e-9))) << "ramps down at the piece's acceleration";
  const Vec3 held = run.ex.position();
  const Rot3 held_rot = run.ex.rotary();
  const double progress = run.ex.progress();
  for (int i = 0; i < 50; ++i) run.step(s, in);
  EXPECT_EQ(run.ex.position(), held);
  EXPECT_EQ(run.ex.rotary(), held_rot);
  EXPECT_EQ(run.ex.velocity(), (Vec3{0.0, 0.0, 0.0}));
  EXPECT_GT(progress, 0.0);
  in.hold = false;
  in.feed_override = 1.0;
  bool ended = false;
  for (int i = 0; i < 100000 && !ended; ++i) ended = run.step(s, in).program_end;
  EXPECT_TRUE(ended);
  EXPECT_EQ(run.ex.position(), s.blocks[1].rotary.joint_end);
}

// A piece whose tool axis swings fast in its middle at F3000: the host's schedule slows the tip
// there so that every joint keeps its velocity limit on every cycle, and runs at F elsewhere.
TEST(ExecutorRuled, ScheduleFromTheJointLimitsKeepsEveryJointWithinItsVelocity) {
  ExecutorPiece s;
  s.feed = 50.0;
  std::vector<Vec3> pts, axes;
  straight_piece(s, 30, 6.0, pts, axes, [](double t, const ToolPose& p0, const Kinematics&) {
    const double bump = std::exp(-std::pow((t - 0.5) / 0.06, 2.0));  // 0.3 rad within about a millimetre
    return normalized(p0.axis + (0.3 * bump) * Vec3{1.0, 0.0, 0.0});
  });
  const RuledMoveBlocks rb = plan_piece(s, pts, axes);
  ASSERT_EQ(rb.blocks.size(), 1u);
  const RuledGeometry& g = rb.blocks[0].ruled;
  double lo = 1e9, hi = 0.0;
  for (int i = 0; i < g.schedule_count; ++i) lo = std::min(lo, g.schedule_speed[i]), hi = std::max(hi, g.schedule_speed[i]);
  EXPECT_EQ(hi, s.feed) << "away from the swing the feed stands";
  EXPECT_LT(lo, 0.5 * s.feed) << "the swing is slowed";
  EXPECT_NE(rb.speed_joint, -1);
  Runner run(s);
  const double dt = s.cfg.cycle_period_s();
  bool ended = false;
  Vec3 last = s.xyz;
  Rot3 last_rot = s.rot;
  double worst = 0.0;  // the largest share of a joint's velocity limit, by the setpoints' differences
  for (int i = 0; i < 100000 && !ended; ++i) {
    ended = run.step(s, ExecInput{}).program_end;
    for (int a = 0; a < 3; ++a) {
      worst = std::max(worst, std::abs(run.ex.position()[a] - last[a]) / dt / s.cfg.axes[static_cast<std::size_t>(a)].max_velocity_mm_s);
    }
    for (int a : {0, 2}) {
      const auto k = static_cast<std::size_t>(a);
      worst = std::max(worst, std::abs(run.ex.rotary()[k] - last_rot[k]) / dt / s.cfg.rotary[k]->max_velocity_rad_s);
    }
    last = run.ex.position();
    last_rot = run.ex.rotary();
  }
  EXPECT_TRUE(ended);
  EXPECT_LE(worst, 1.0) << "a joint above its velocity limit";
  EXPECT_GT(worst, 0.5) << "the schedule uses the joints' speed where it caps";
  std::printf("[ figures ] schedule %.2f .. %.2f mm/s, joint %d caps it; the joints reach %.1f %% of a velocity limit\n", lo,
              hi, rb.speed_joint, worst * 100.0);
}

// A piece whose tool axis tilts steadily along a straight line (A turns 0.1 rad per mm, and the
// table's tilt moves the linear joints more than the tip moves): a joint's acceleration is
// q' s̈ + q'' ṡ², and here the tangential term q' s̈ alone, at the linear axes' acceleration,
// would be 95 rad/s² on A (limit 62.8) and beyond Y's and Z's limits. The host's tangential
// acceleration leaves every joint its budget, so run by the executor from rest, held in the
// middle, resumed and stopped at the end, no joint exceeds its acceleration limit on any cycle:
// neither the analytic acceleration feed-forward nor the setpoints' second differences.
TEST(ExecutorRuled, TangentialAccelerationKeepsEveryJointWithinItsAcceleration) {
  ExecutorPiece s;
  s.feed = 20.0;
  std::vector<Vec3> pts, axes;
  straight_piece(s, 20, 4.0, pts, axes, [&s](double t, const ToolPose&, const Kinematics& kin) {
    return forward(kin, to_joints(s.cfg, s.xyz, Rot3{s.rot[0] + 0.4 * t, 0.0, s.rot[2]})).axis;
  });
  const RuledMoveBlocks rb = plan_piece(s, pts, axes);
  ASSERT_EQ(rb.blocks.size(), 1u);
  const double a_tan = rb.blocks[0].ruled.accel;
  double a_lin = 1e9;
  for (const AxisConfig& ax : s.cfg.axes) a_lin = std::min(a_lin, ax.max_accel_mm_s2);
  EXPECT_GT(0.1 * 0.95 * a_lin, s.cfg.rotary[0]->max_accel_rad_s2) << "the tangential term alone would exceed A's limit";
  EXPECT_LT(a_tan, 0.95 * a_lin) << "the tangential acceleration is lowered for the joints";

  Runner run(s);
  const double dt = s.cfg.cycle_period_s();
  Joints amax{};
  for (int a = 0; a < 3; ++a) amax[static_cast<std::size_t>(a)] = s.cfg.axes[static_cast<std::size_t>(a)].max_accel_mm_s2;
  amax[kTilt] = s.cfg.rotary[0]->max_accel_rad_s2;
  amax[kRotary] = s.cfg.rotary[2]->max_accel_rad_s2;
  auto joints = [&] { return to_joints(s.cfg, run.ex.position(), run.ex.rotary()); };
  std::vector<Joints> q{joints(), joints()};  // at rest before the first cycle
  double worst_ff = 0.0, worst_diff = 0.0;  // the largest share of a joint's acceleration limit
  int worst_joint = -1, held = 0;
  bool ended = false;
  ExecInput in;
  for (int i = 0; i < 200000 && !ended; ++i) {
    // a feed hold once the tip is at full speed in the middle, released once at rest
    if (!in.hold && held == 0 && run.ex.progress() > 1.5) in.hold = true, held = 1;
    if (in.hold && held == 1 && run.ex.speed() == 0.0 && ++held) in.hold = false;
    ended = run.step(s, in).program_end;
    q.push_back(joints());
    const Joints ff = to_joints(s.cfg, run.ex.acceleration(), run.ex.rotary_acceleration());
    const std::size_t n = q.size();
    for (std::size_t j = 0; j < 5; ++j) {
      const double diff = std::abs(q[n - 1][j] - 2.0 * q[n - 2][j] + q[n - 3][j]) / (dt * dt);
      worst_ff = std::max(worst_ff, std::abs(ff[j]) / amax[j]);
      if (diff / amax[j] > worst_diff) worst_diff = diff / amax[j], worst_joint = static_cast<int>(j);
    }
  }
  EXPECT_TRUE(ended);
  EXPECT_EQ(held, 2) << "held and resumed";
  EXPECT_LE(worst_ff, 1.0) << "an analytic joint acceleration above its limit";
  EXPECT_LE(worst_diff, 1.0) << "a joint's setpoints accelerate above its limit (joint " << worst_joint << ")";
  EXPECT_GT(worst_diff, 0.3) << "the joints' acceleration is used";
  std::printf("[ figures ] tangential acceleration %.1f mm/s^2 (linear axes' %.0f), schedule top %.2f mm/s; the joints "
              "reach %.1f %% (feed-forward) and %.1f %% (setpoints, joint %d) of an acceleration limit\n",
              a_tan, 0.95 * a_lin, rb.feed, worst_ff * 100.0, worst_diff * 100.0, worst_joint);
}

// Resuming inside a ruled block (host/service/resume.hpp, as after HOST_LOST): the machine is
// held in the middle of the first part of a split piece; continue_block cuts that part at the
// parameter its joints' tip lies at. A fresh executor standing there accepts the continuation
// (the rt's block check: start joints, lengths, schedule, end joints), runs it and the second
// part unchanged to the end without a jump, every tip on the original piece, and lands on the
// host's end joints. Refused without the rotary joints and off the piece.
TEST(ExecutorRuled, ResumedInsideTheBlockFromWhereTheMachineStands) {
  const ExecutorPiece s = make_setup();
  Runner run(s);
  ExecInput in;
  while (run.ex.progress() < 3.0 || run.ex.seq() != 1) run.step(s, in);
  in.hold = true;
  for (int i = 0; i < 200 || run.ex.speed() > 0.0; ++i) run.step(s, in);
  ASSERT_EQ(run.ex.seq(), 1u);
  const Vec3 at = run.ex.position();
  const Rot3 rot = run.ex.rotary();
  const Block& b = s.blocks[0];
  std::string why;
  const auto cont = continue_block(b, at, s.cfg, 0.005, &why, rot);
  ASSERT_TRUE(cont) << why;
  ASSERT_FALSE(cont->skip);
  const Block& r = cont->block;
  EXPECT_EQ(r.kind, BlockKind::kRuled);
  EXPECT_EQ(r.line, b.line);
  EXPECT_LT(r.ruled.segment_count, b.ruled.segment_count);
  EXPECT_NEAR(r.length, b.length - run.ex.progress(), 1e-6) << "the rest of the part";
  EXPECT_EQ(r.ruled.start_speed, 0.0);
  EXPECT_EQ(r.ruled.end_speed, b.ruled.end_speed) << "flows into the next part as before";
  EXPECT_EQ(r.rotary.start, rot);
  EXPECT_EQ(r.rotary.joint_end, b.rotary.joint_end);

  ExecutorPiece rest = s;
  rest.xyz = at;
  rest.rot = rot;
  rest.blocks.assign(s.blocks.begin() + 1, s.blocks.end());
  rest.blocks.insert(rest.blocks.begin(), r);
  for (std::size_t i = 0; i < rest.blocks.size(); ++i) rest.blocks[i].seq = i + 1;
  Runner again(rest);
  const Kinematics kin = kinematics_with_tool(s.cfg, 0.0);
  const double dt = s.cfg.cycle_period_s();
  RuledCurves parts[2] = {curves_of(s.blocks[0].ruled), curves_of(s.blocks[1].ruled)};
  double worst_step = 0.0, worst_off = 0.0;
  Vec3 last = at;
  bool ended = false;
  for (int i = 0; i < 100000 && !ended; ++i) {
    ended = again.step(rest, ExecInput{}).program_end;
    for (int a = 0; a < 3; ++a)
      worst_step = std::max(worst_step, std::abs(again.ex.position()[a] - last[a]) / dt /
                                            s.cfg.axes[static_cast<std::size_t>(a)].max_velocity_mm_s);
    last = again.ex.position();
    if (i % 50 == 0 && again.ex.seq() <= 2) {  // the tip on the original piece (nearest point, dense then refined)
      const Vec3 tip = forward(kin, to_joints(s.cfg, again.ex.position(), again.ex.rotary())).tip;
      const RuledCurves& c = parts[again.ex.seq() == 1 ? 0 : 1];
      const int n = again.ex.seq() == 1 ? s.blocks[0].ruled.segment_count : s.blocks[1].ruled.segment_count;
      double best = 1e9, bu = 0.0;
      for (int k = 0; k <= 64 * n; ++k) {
        const double d = norm(ruled_jet(c, k / 64.0).c.p - tip);
        if (d < best) best = d, bu = k / 64.0;
      }
      for (double h = 1.0 / 128.0; h > 1e-12; h *= 0.5) {
        for (double cand : {bu - h, bu + h}) {
          const double d = cand >= 0.0 && cand <= n ? norm(ruled_jet(c, cand).c.p - tip) : 1e9;
          if (d < best) best = d, bu = cand;
        }
      }
      worst_off = std::max(worst_off, best);
    }
  }
  EXPECT_TRUE(ended);
  EXPECT_EQ(again.ex.position(), s.blocks[1].rotary.joint_end) << "the host's end joints";
  EXPECT_LE(worst_step, 1.0) << "a jump";
  EXPECT_LT(worst_off, 1e-6) << "the resumed tip left the piece, mm";
  std::printf("[ figures ] resumed at %.4f of %.4f mm: rest %.4f mm, %d segments; tip off the piece at most %.3g mm\n",
              run.ex.progress(), b.length, r.length, r.ruled.segment_count, worst_off);

  EXPECT_FALSE(continue_block(b, at, s.cfg, 0.005, &why)) << "the rotary joints are needed";
  EXPECT_NE(why.find("rotary joints"), std::string::npos) << why;
  EXPECT_FALSE(continue_block(b, at + Vec3{0.0, 0.0, 0.1}, s.cfg, 0.005, &why, rot));
  EXPECT_NE(why.find("not on the interrupted ruled piece"), std::string::npos) << why;
}

TEST(ExecutorRuled, BlockCheckRefusesCorruptRuledBlocks) {
  const ExecutorPiece s = make_setup();
  const Block good = s.blocks[0];
  const Vec3 start = good.start;  // under TCP: the tip the joints give
  auto verdict = [&](const Block& b, const MachineConfig& c) {
    BlockVerdict v = check_block(b, start, 1, c);
    if (v.fault == FaultCode::kNone) v = check_rotary(b, s.rot, c);
    return v;
  };
  EXPECT_EQ(verdict(good, s.cfg).fault, FaultCode::kNone) << verdict(good, s.cfg).reason;
  auto refused = [&](Block b, const char* what) {
    const BlockVerdict v = verdict(b, s.cfg);
    EXPECT_EQ(v.fault, FaultCode::kBadBlock) << what;
    return std::string(v.reason);
  };
  Block b = good;
  b.ruled.length *= 1.001;
  b.length = b.ruled.length;
  EXPECT_EQ(refused(b, "length"), "ruled: length is not the directrix's arc length");
  b = good;
  b.ruled.directrix[5].p0[1] += 0.01;
  EXPECT_EQ(refused(b, "gap"), "ruled: the directrix's segments do not join");
  b = good;
  b.ruled.schedule_u[3] = b.ruled.schedule_u[2];
  EXPECT_EQ(refused(b, "schedule"), "ruled: schedule parameters do not increase");
  b = good;
  b.ruled.segment_count = 33;
  EXPECT_EQ(refused(b, "count"), "ruled: segment count outside 1 .. 32");
  b = good;
  b.rotary.tcp = 0;
  EXPECT_EQ(refused(b, "tcp"), "ruled: a ruled block runs under TCP (tcp 1, angular 0)");
  b = good;
  b.speed *= 1.5;
  EXPECT_EQ(refused(b, "speed"), "ruled: block speed is not the schedule's largest speed");
  b = good;
  b.rotary.axis_end = normalized(b.rotary.axis_end + Vec3{0.0, 1e-3, 0.0});
  EXPECT_EQ(refused(b, "axis"), "ruled: the TCP tool axes are not the ruling's ends");
  b = good;
  b.rotary.end[2] += 0.01;
  EXPECT_EQ(refused(b, "end joints"), std::string("rotary: TCP end joints do not put the tool tip at the end"));
  // a 3-axis machine refuses the kind
  const MachineConfig three = load_config(test::source_dir() + "/configs/desktop-mill.toml");
  b = good;
  b.rotary = RotaryMotion{};
  b.rotary.tcp = 1;
  const BlockVerdict v3 = check_block(b, start, 1, three);
  EXPECT_EQ(v3.fault, FaultCode::kBadBlock);
  EXPECT_STREQ(v3.reason, "ruled: a ruled block on a machine without 5-axis kinematics");
}

}  // namespace
}  // namespace pcnc
