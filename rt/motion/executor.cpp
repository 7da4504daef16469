// executor.cpp — the block executor's cycle (scheme and speed law in executor.hpp).
#include "motion/executor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "motion/junction.hpp"
#include "motion/nurbs_follower.hpp"
#include "ipc/block_check.hpp"
#include "config/joint_map.hpp"
#include "geometry/kinematics_rates.hpp"

namespace pcnc {

Executor::Executor(const MachineConfig& config) : cfg_(config), dt_(config.cycle_period_s()) {
  f_ = std::clamp(config.motion.junction_velocity_step_fraction, 0.0, 1.0);
  junction_.cos_limit = std::cos(config.motion.contouring_angle_deg * std::numbers::pi / 180.0);
  junction_.step_fraction = f_;
  junction_.dt = dt_;
  for (int i = 0; i < kAxes; ++i) junction_.axis_accel[i] = config.axes[i].max_accel_mm_s2;
  for (int i = 0; i < kAxes; ++i) joint_accel_[static_cast<std::size_t>(i)] = config.axes[i].max_accel_mm_s2;
  for (int i = 0; i < kRotaryJoints; ++i) {
    const auto& r = config.rotary[static_cast<std::size_t>(i)];
    joint_accel_[static_cast<std::size_t>(kAxes + i)] = r ? r->max_accel_rad_s2 : 0.0;
  }
  Vec3 home{};
  for (int i = 0; i < kAxes; ++i) home[i] = config.axes[i].home_mm;
  travel_ = config.rotary_travel();
  Rot3 rhome{};
  for (int i = 0; i < kRotaryJoints; ++i) {
    if (config.rotary[static_cast<std::size_t>(i)]) rhome[static_cast<std::size_t>(i)] = config.rotary[static_cast<std::size_t>(i)]->home_rad;
  }
  rot_ = rhome;
  set_position(home);
}

void Executor::set_rotary(const Rot3& r) {
  rot_ = r;
  rot_tail_ = r;
  rot_vel_ = {0.0, 0.0, 0.0};
  rot_acc_ = {0.0, 0.0, 0.0};
}

void Executor::set_position(const Vec3& p) {
  pos_ = p;
  tail_ = p;
  rot_tail_ = rot_;
  gap_.clear();
  hold_still();
  s_ = 0.0;
  dwell_ = 0.0;
  crossed_ = 0;
  rest_cycle_ = false;
  ended_at_rest_ = false;
  after_motion_ = false;
  fresh_ = true;
  has_prev_ = false;
  exit_valid_ = false;
  blend_.fill(CornerBlend{});
  entered_ = CornerBlend{};
  path_base_ = 0.0;
  blended_ = false;
  here_valid_ = false;
}

void Executor::flush(MotionRing& ring) {
  ring.pop_all();
  prepared_ = 0;
  set_position(pos_);
}

void Executor::hold_still() {
  v_ = 0.0;
  vel_ = {0.0, 0.0, 0.0};
  acc_ = {0.0, 0.0, 0.0};
  rot_vel_ = {0.0, 0.0, 0.0};
  rot_acc_ = {0.0, 0.0, 0.0};
}

bool Executor::prepare_visible(const MotionRing& ring, ExecResult& out) {
  const std::size_t n = std::min(ring.size(), kRingSlots);
  while (prepared_ < n) {
    const Block& b = ring.peek(prepared_);
    BlockVerdict verdict = check_block(b, expected_block_start(b, tail_, rot_tail_, cfg_), expected_seq_, cfg_);
    if (verdict.fault == FaultCode::kNone) verdict = check_rotary(b, rot_tail_, cfg_);
    if (verdict.fault != FaultCode::kNone) {
      out.fault = verdict.fault;
      out.reason = verdict.reason;
      out.fault_axis = verdict.axis;
      out.fault_line = b.line;
      out.fault_value = verdict.value;
      return false;
    }
    prep_[prepared_] = prepare_block(b, cfg_);
    if (prep_[prepared_].tcp) tcp_end_rates(prep_[prepared_], b, cfg_, tail_);  // tail_: where it starts
    if (prep_[prepared_].motion) block_tail(b, tail_, rot_tail_);
    if (prepared_ > 0) {
      const PreparedBlock& p = prep_[prepared_ - 1];
      const PreparedBlock& q = prep_[prepared_];
      const bool probing = ring.peek(prepared_ - 1).probe_rule != kProbeNone || b.probe_rule != kProbeNone;
      // a probing move starts and ends at rest, and so does an angular block (its speed is an angle's)
      if (p.motion && q.motion && !probing && !p.angular && !q.angular) {
        JunctionRules rules = junction_;
        rules.path_tolerance_mm = p.path_tolerance;  // the tolerance the block before the junction was made with
        // the tool tip's (TCP) or the linear axes' corner rule
        double cap = corner_speed(p.contouring, p.dir_end, q.dir_start, rules);
        // next to a block that turns a joint or runs under TCP, also every joint's velocity step
        if ((p.rotary || q.rotary) && cap > 0.0) {
          cap = std::fmin(cap, joint_junction_speed(p.jrate_end, p.jcurv_end, q.jrate_start, q.jcurv_start, joint_accel_, dt_, f_));
        }
        corner_[prepared_ - 1] = cap;
        plan_blend(prepared_ - 1, cap);
        const CornerBlend& w = blend_[prepared_ - 1];
        turn_[prepared_ - 1] = p.rotary || q.rotary ? TurnShare{}
                                                    : turn_share(p.dir_end, q.dir_start, junction_.axis_accel, dt_, w.on ? w.h : 0.0);
      } else {
        corner_[prepared_ - 1] = 0.0;
        blend_[prepared_ - 1] = CornerBlend{};
      }
    }
    exit_valid_ = false;
    probe_sync_ = false;
    ++expected_seq_;
    ++prepared_;
  }
  return true;
}

void Executor::pop(MotionRing& ring, ExecResult& out) {
  has_prev_ = prep_[0].motion;
  if (has_prev_) prev_ = prep_[0];
  if (prep_[0].motion) path_base_ += prep_[0].length;
  ring.pop();
  for (std::size_t i = 1; i < prepared_; ++i) {
    prep_[i - 1] = prep_[i];
    corner_[i - 1] = corner_[i];
    turn_[i - 1] = turn_[i];
    blend_[i - 1] = blend_[i];
  }
  --prepared_;
  blend_[prepared_] = CornerBlend{};
  entered_ = CornerBlend{};
  exit_valid_ = false;
  here_valid_ = false;
  ++out.blocks_done;
  s_ = 0.0;
  dwell_ = 0.0;
  fresh_ = true;
}

double Executor::cap_of(const PreparedBlock& b, const ExecInput& in) const {
  if (in.hold) return 0.0;
  return std::min(b.speed * in.feed_override, b.v_machine);
}

bool Executor::flows_after(std::size_t i) const { return i + 1 < prepared_ && corner_[i] > 0.0; }

double Executor::junction_cap(std::size_t i, const ExecInput& in) const {
  if (!flows_after(i)) return 0.0;
  return std::min({corner_[i], cap_of(prep_[i], in), cap_of(prep_[i + 1], in), prep_[i].v_last, prep_[i + 1].v_first});
}

double Executor::exit_speed_of_current(const ExecInput& in) {
  if (!exit_valid_ || exit_hold_ != in.hold || exit_override_ != in.feed_override) {
    exit_speed_ = compute_exit_speed(in);
    exit_hold_ = in.hold;
    exit_override_ = in.feed_override;
    exit_valid_ = true;
  }
  return exit_speed_;
}

// Backward pass over the chain of flowing blocks known in the ring; the last one ends at rest.
double Executor::compute_exit_speed(const ExecInput& in) const {
  std::size_t e = 0;
  while (flows_after(e)) ++e;
  double v_out = 0.0;
  for (std::size_t j = e; j >= 1; --j) {
    // the same discrete rule (with its margin) the block will be run with; a NURBS block may
    // brake at its schedule's accelerations (their mean over the block)
    const double cap = std::min(cap_of(prep_[j], in), prep_[j].v_first);
    // its margin: one cycle, and the share its entry's and its exit's turns take at their caps
    const double k = 1.0 + turn_share_at(turn_[j - 1], junction_cap(j - 1, in), f_) +
                     (flows_after(j) ? turn_share_at(turn_[j], junction_cap(j, in), f_) : 0.0);
    double stop = stop_speed(prep_[j].length, v_out, prep_[j].brake_accel, dt_, k);
    if (prep_[j].kind == BlockKind::kArc && stop < cap) stop = std::max(stop, arc_stop_speed(prep_[j], cfg_, prep_[j].length, v_out, false, cap, dt_, k));
    const double v_in = std::min(cap, stop);
    v_out = std::min(v_in, junction_cap(j - 1, in));
  }
  return v_out;
}

void Executor::begin_block(const Block& blk, bool from_rest) {
  s_ = 0.0;
  here_valid_ = false;
  if (prep_[0].tcp) {
    kin_ = kinematics_with_tool(cfg_, blk.rotary.tool_length);
    slerp_ = make_axis_slerp(blk.rotary.axis_start, blk.rotary.axis_end);
  }
  if (from_rest) last_pos_ = pos_;  // across a flowing junction last cycle's stays (remember_cycle)
  if (blk.kind == BlockKind::kRuled) {
    kin_ = kinematics_with_tool(cfg_, blk.rotary.tool_length);
    ruled_.start(blk.ruled, kin_, travel_, to_joints(cfg_, pos_, rot_), ruled_carry_, ruled_speed_);
    ruled_carry_ = ruled_speed_ = 0.0;
  }
  if (blk.kind == BlockKind::kNurbs) {
    const NurbsView view = view_of(blk.nurbs);
    nurbs_u_ = view.u_min();
    nurbs_at_ = nurbs_eval(view, nurbs_u_);
    nurbs_hint_ = nurbs_span_ = 0;
    nurbs_brake_.start(blk.nurbs);
  }
}

bool Executor::advance(const Block& blk, double ds, double& leftover) {
  const PreparedBlock& b = prep_[0];
  leftover = 0.0;
  bool at_end = false;
  if (blk.kind == BlockKind::kNurbs) {
    if (ds > 0.0) {
      const NurbsStep st = nurbs_parameter_step(view_of(blk.nurbs), nurbs_u_, nurbs_at_, ds, nurbs_span_);
      nurbs_u_ = st.u;
      nurbs_at_ = st.eval;
      s_ = std::min(s_ + st.chord, b.length);
      if (st.at_end) {
        at_end = true;
        leftover = std::max(0.0, ds - st.chord);
        s_ = b.length;
      }
    }
    pos_ = at_end ? blk.end : nurbs_at_.p;
    const double d1 = norm(nurbs_at_.d1);
    if (d1 > 0.0) {
      tangent_ = (1.0 / d1) * nurbs_at_.d1;
      curvature_ = (1.0 / (d1 * d1)) * (nurbs_at_.d2 - dot(nurbs_at_.d2, tangent_) * tangent_);
    } else {  // C' vanishes (a repeated end point): use the block's stated tangent
      tangent_ = s_ > 0.5 * b.length ? b.dir_end : b.dir_start;
      curvature_ = {0.0, 0.0, 0.0};
    }
    apply_blend();
    return at_end;
  }
  s_ += ds;
  if (s_ >= b.length) {
    at_end = true;
    leftover = s_ - b.length;
    s_ = b.length;
  }
  const PathPoint pp = evaluate(b, s_);
  here_ = pp;
  here_s_ = s_;
  here_valid_ = true;
  pos_ = pp.p;
  tangent_ = pp.tangent;
  curvature_ = pp.curvature;
  if (b.rotary) {
    place_joints(blk);
  } else {
    apply_blend();
  }
  return at_end;
}

void Executor::place_joints(const Block& blk) {
  const PreparedBlock& b = prep_[0];
  const double u = b.length > 0.0 ? std::clamp(s_ / b.length, 0.0, 1.0) : 1.0;
  if (!b.tcp) {
    for (int i = 0; i < kRotaryJoints; ++i) {
      const auto k = static_cast<std::size_t>(i);
      rot_[k] = u >= 1.0 ? b.rot_end[k] : b.rot_start[k] + u * (b.rot_end[k] - b.rot_start[k]);
    }
    return;
  }
  if (u >= 1.0) {  // the host's end joints (the block check verified them with the forward kinematics)
    pos_ = b.land;
    rot_ = b.rot_end;
    return;
  }
  // pos_ holds the tool tip on the line; the inverse kinematics nearest last cycle's joints
  const ToolPose pose{pos_, slerp_axis(slerp_, u)};
  const Joints q = inverse(kin_, pose, to_joints(cfg_, last_pos_, rot_), travel_);
  from_joints(cfg_, q, pos_, rot_);
  (void)blk;
}

void Executor::joint_rates(double v_new, double v_old) {
  const PreparedBlock& b = prep_[0];
  if (!b.tcp) {
    for (int i = 0; i < kRotaryJoints; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const double share = b.length > 0.0 ? (b.rot_end[k] - b.rot_start[k]) / b.length : 0.0;
      rot_vel_[k] = v_new * share;
      rot_acc_[k] = (v_new - v_old) / dt_ * share;
    }
    if (b.angular) {
      vel_ = {0.0, 0.0, 0.0};
      acc_ = {0.0, 0.0, 0.0};
    }
  } else {
    // the joints are the inverse kinematics of the path: their rates from the analytic kinematics
    // rates where the cycle lands (tip on the line, axis on the great circle at u = s/L):
    // q̇ = q'·ṡ, q̈ = q'·s̈ + q''·ṡ²
    const double inv = b.length > 0.0 ? 1.0 / b.length : 0.0;
    const double u = std::clamp(s_ * inv, 0.0, 1.0);
    const PoseRate d1{inv * (b.end - b.start), inv * slerp_axis_d1(slerp_, u)};
    const PoseRate d2{{0.0, 0.0, 0.0}, (inv * inv) * slerp_axis_d2(slerp_, u)};
    const Joints q = to_joints(cfg_, pos_, rot_);
    const Joints dq = pcnc::joint_rates(kin_, q, d1);
    const Joints ddq = joint_accels(kin_, q, dq, d2);
    const double s_acc = (v_new - v_old) / dt_;
    Joints qv{}, qa{};
    for (int j = 0; j < kJoints; ++j) {
      const auto k = static_cast<std::size_t>(j);
      qv[k] = dq[k] * v_new;
      qa[k] = dq[k] * s_acc + ddq[k] * v_new * v_new;
    }
    Rot3 rv{}, ra{};  // a joint the kinematics do not use stands still
    from_joints(cfg_, qv, vel_, rv);
    from_joints(cfg_, qa, acc_, ra);
    rot_vel_ = rv;
    rot_acc_ = ra;
  }
}

void Executor::remember_cycle() { last_pos_ = pos_; }

// Copied in, not built on the stack: GCC zeroes a temporary this size with `rep stos` and
// then reads it back, a store-forwarding stall in every cycle.
constexpr ExecResult kNoResult{};

void Executor::step(MotionRing& ring, const ExecInput& in, ExecResult& out) {
  out = kNoResult;
  if (!prepare_visible(ring, out)) {
    hold_still();
    return;
  }
  if (prepared_ == 0) {
    hold_still();
    rest_cycle_ = false;
    out.starved = true;
    out.probe_wait = probe_sync_;
    return;
  }
  const Block& blk = ring.peek(0);
  const PreparedBlock& b = prep_[0];
  line_ = blk.line;
  seq_ = blk.seq;
  if (b.motion) {
    contouring_ = b.contouring;
    motion_step(ring, in, out);
    return;
  }
  // Non-motion blocks run at rest.
  hold_still();
  rest_cycle_ = false;
  switch (b.kind) {
    case BlockKind::kDwell:
      dwell_ += dt_;
      after_motion_ = false;
      if (dwell_ >= blk.dwell_s - 1e-12) pop(ring, out);
      break;
    case BlockKind::kPause:
      after_motion_ = false;
      out.at_pause = true;
      if (in.resume_pause) {
        pop(ring, out);
        out.at_pause = false;
      }
      break;
    case BlockKind::kEnd:
      after_motion_ = false;
      pop(ring, out);
      out.program_end = true;
      break;
    default:  // a zero-length move: nothing to travel
      pop(ring, out);
      break;
  }
}

void Executor::motion_step(MotionRing& ring, const ExecInput& in, ExecResult& out) {
  if (rest_cycle_) {  // one cycle at rest after landing on a stop
    rest_cycle_ = false;
    hold_still();
    return;
  }
  const Block& blk = ring.peek(0);
  const bool probing = blk.probe_rule != kProbeNone;
  const bool sought = probe_toward(blk.probe_rule);  // the input state that ends the move
  if (fresh_ && !probing && start_gap_cycle(blk, in)) return;
  const bool first_cycle = fresh_;
  if (fresh_) {
    if (after_motion_ && ended_at_rest_) ++out.junction_stops;
    ended_at_rest_ = false;
    fresh_ = false;
    begin_block(blk, true);
    if (probing) {
      probe_tripped_ = false;
      probe_latched_ = pos_;
      if (in.probe_input == sought) {  // G38.2/.3 already triggered, G38.4/.5 not triggered
        hold_still();
        finish_probe(ring, out, ProbeOutcome::kAlreadyTriggered);
        return;
      }
      probe_arm_ = true;
      probe_dir_ = prep_[0].dir_start;
    }
  }
  if (prep_[0].kind == BlockKind::kRuled) {
    ruled_step(ring, in, out);
    return;
  }
  const PreparedBlock& b = prep_[0];
  const double a = b.accel;  // the stop rules brake at this: safe all along the block
  double a_ramp = a;         // speeding up and slowing down in this cycle
  // (not in the block's first cycle: that input was sensed before the probe was armed for it)
  if (probing && !probe_tripped_ && !first_cycle && in.probe_input == sought) {
    probe_tripped_ = true;  // sensed at last cycle's setpoint, where the machine was then
    probe_latched_ = pos_;
  }
  double cap = probing && probe_tripped_ ? 0.0 : cap_of(b, in);
  if (b.kind == BlockKind::kNurbs) {
    // the feed schedule where the machine is and where this cycle will land (floored at
    // one cycle's acceleration, so that a 0 at a corner of the schedule cannot freeze it),
    // and the tangential acceleration it allows there
    const NurbsGeometry& g = blk.nurbs;
    const double d1 = norm(nurbs_at_.d1);
    const double u_next = d1 > 0.0 ? std::min(nurbs_u_ + v_ * dt_ / d1, g.knots[g.point_count]) : nurbs_u_;
    if (cap > 0.0) {
      const double sched = std::min(block_schedule_speed(g, nurbs_u_, nurbs_hint_), block_schedule_speed(g, u_next, nurbs_hint_));
      cap = std::min(cap, std::max(sched, a * dt_));
    }
    a_ramp = std::max(a, std::min(block_schedule_accel(g, nurbs_u_, nurbs_hint_), block_schedule_accel(g, u_next, nurbs_hint_)));
    {
      // By speed, as arcs (path.hpp curve_tangential_accel): below the schedule's speed the axes
      // leave more than its accelerations (each taken at the schedule's speed) where the machine
      // is and where this cycle lands, at the fastest speed the cycle may reach (where it lands
      // evaluated only when where it is leaves more: else the smaller cannot raise a_ramp).
      const double a_here = curve_tangential_accel(nurbs_at_, cfg_, v_);
      const double v_hi = v_ + std::max(a_ramp, a_here) * dt_;
      const double here_hi = curve_tangential_accel(nurbs_at_, cfg_, v_hi);
      if (here_hi > a_ramp) {
        a_ramp = std::max(a_ramp, std::min(here_hi, curve_tangential_accel(nurbs_eval(view_of(g), u_next, nurbs_span_), cfg_, v_hi)));
      }
    }
  }
  double a_brake = a_ramp;  // slowing down in this cycle
  if (b.kind == BlockKind::kArc) {
    // An arc shares its acceleration by speed (path.hpp arc_stretch_accel): braking may take the
    // tangential part at the speed the machine has (the cycle's highest), speeding up the part
    // left at the speed this cycle may reach; `a` (its value at the top speed) at least.
    const ArcStretch stretch{here_valid_ && here_s_ == s_ ? here_ : evaluate(b, s_), evaluate(b, s_ + v_ * dt_)};
    a_brake = std::max(a, arc_stretch_accel(b, stretch, cfg_, v_));
    a_ramp = std::max(a, arc_stretch_accel(b, stretch, cfg_, v_ + a_brake * dt_));
  }
  const bool stop_at_end = !flows_after(0);
  const double v_exit = stop_at_end ? 0.0 : exit_speed_of_current(in);
  const double remaining = b.length - s_;
  // The cycles around a flowing junction leave the share its turn takes at the speed there: this
  // cycle crosses at v_most at most (and every junction within its reach past the first), a
  // later cycle at the junction's cap at most.
  const double share_in = crossed_ > 0 ? crossed_share_ : 0.0;
  const bool crossing = !stop_at_end && remaining <= (v_ + a * dt_) * dt_;
  const double v_most = v_ + std::max(a, a_ramp) * dt_;
  double share_out = !stop_at_end ? turn_share_at(turn_[0], crossing ? v_most : junction_cap(0, in), f_) : 0.0;
  if (crossing) {
    double reach = v_most * dt_ - remaining;  // how far past the first junction this cycle may go
    for (std::size_t i = 1; reach > 0.0 && flows_after(i); ++i) {
      share_out = std::max(share_out, turn_share_at(turn_[i], v_most, f_));
      reach -= prep_[i].length;
    }
  }
  const double share = std::max(share_in, crossing ? share_out : 0.0);
  const double a_step = (1.0 - share) * a_ramp;
  const double a_step_down = (1.0 - share) * a_brake;
  const double v_up = v_ + a_step * dt_;  // the fastest this cycle may go

  // A stop at the end of this block, with no junction-restricted cycle left: the exact
  // discrete braking rule. Otherwise the rule with a margin k: one cycle for the discrete
  // braking, plus the share φ of each junction-restricted cycle still ahead (the one after this
  // if this is the first after a crossing, and the one that crosses a flowing end): braking at
  // (1 − φ)·a in such a cycle leaves the speed φ·a·T higher, which costs φ·v·T of distance
  // (docs/rt-executor.md, "Speed law"). The look-ahead's backward pass counts a block's entry
  // and exit shares at their junctions' caps (compute_exit_speed).
  const double k_here = 1.0 + (crossed_ > 1 ? share_in : 0.0) + share_out;
  double v_stop = stop_at_end && crossed_ == 0 ? stop_speed_exact(remaining, a, dt_)
                                               : stop_speed(remaining, v_exit, a, dt_, k_here);
  if (b.kind == BlockKind::kArc && v_stop < cap && v_stop < v_up) {
    // An arc may also brake at what it keeps at every speed up to the one it brakes from (not
    // asked when v_stop reaches v_up already, and asked only up to v_up: a larger speed could not
    // bind, and most cycles are settled by the rule at v_up alone).
    v_stop = std::max(v_stop, arc_stop_speed(b, cfg_, remaining, v_exit, stop_at_end && crossed_ == 0, std::min(cap, v_up), dt_, k_here));
  }
  if (b.kind == BlockKind::kNurbs) {
    // A NURBS block may also brake at its schedule's accelerations along the rest of the block:
    // what it can shed from the point k cycles ahead (at the fastest speed this cycle may take).
    const double ahead = k_here * (v_ + a_ramp * dt_) * dt_;
    v_stop = std::max(v_stop, std::sqrt(v_exit * v_exit + 2.0 * nurbs_brake_.at(blk.nurbs, s_ + ahead)));
  }
  // Corner windows: inside one dp/ds mixes the two tangents, so each axis's share of the path
  // speed is |(1 − w)·t_a,i + w·t_b,i| (+ κ·h as the tangents turn): the speed keeps every axis
  // within its velocity limit where the machine is and where this cycle will land.
  {
    const double here = path_base_ + s_;
    const double next = here + (v_ + a_ramp * dt_) * dt_;
    auto window_cap = [&](const CornerBlend& w) {
      for (const double x : {here, next}) {
        if (!w.on || std::abs(x - w.at) >= w.h) continue;
        const double wt = blend_weight((x - w.at + w.h) / (2.0 * w.h)).w;
        for (int i = 0; i < kAxes; ++i) {
          const double share = std::abs((1.0 - wt) * w.t_in[i] + wt * w.t_out[i]) + w.v_window;
          if (share > 0.0) cap = std::min(cap, cfg_.axes[i].max_velocity_mm_s / share);
        }
      }
    };
    window_cap(entered_);
    for (std::size_t i = 0; i + 1 < prepared_ && flows_after(i); ++i) window_cap(blend_[i]);
  }
  const double v_allow = std::min(cap, v_stop);
  double v_new = std::min(v_allow, v_up);
  v_new = std::max({v_new, v_ - a_step_down * dt_, 0.0});
  if (probing && probe_tripped_ && v_new <= 0.0) {  // came to rest after the contact
    hold_still();
    finish_probe(ring, out, ProbeOutcome::kContact);
    return;
  }
  if (stop_at_end && cap > 0.0) {
    // Final approach: reach the end exactly this cycle when that takes no more than one
    // cycle's acceleration either way (and the stop after it is within a·dt too).
    const double v_land = remaining / dt_;
    if (v_land <= a * dt_ && v_land <= cap && v_land >= v_ - a * dt_) v_new = v_land;
  }
  if (crossed_ > 0) --crossed_;

  const double v_old = v_;
  v_ = v_new;
  double leftover = 0.0;
  double crossed_in_cycle = 0.0;  // the largest share of the junctions this cycle crosses
  bool at_end = advance(blk, v_new * dt_, leftover) || (stop_at_end && v_new > 0.0 && v_new * dt_ >= remaining);
  while (at_end) {
    if (!flows_after(0)) {
      // stop at the end: land exactly there, rest one cycle, then the next block.
      pos_ = prep_[0].land;
      vel_ = v_new * prep_[0].dir_end;
      acc_ = ((v_new - v_old) / dt_) * prep_[0].dir_end;
      if (prep_[0].rotary) {
        rot_ = prep_[0].rot_end;
        joint_rates(v_new, v_old);
      }
      remember_cycle();
      if (probing) {  // the end reached: the probe never changed (or only just now)
        finish_probe(ring, out, probe_tripped_ ? ProbeOutcome::kContact : ProbeOutcome::kNoContact);
        return;
      }
      pop(ring, out);
      rest_cycle_ = true;
      ended_at_rest_ = true;
      after_motion_ = true;
      return;
    }
    // flowing junction: carry the distance left over into the next block
    // the cycle after it keeps the share of every junction this cycle crossed
    crossed_in_cycle = std::max(crossed_in_cycle, turn_share_at(turn_[0], v_new, f_));
    crossed_share_ = crossed_in_cycle;
    const Block& next = flow_into_next(ring, out);
    crossed_ = 2;
    const double carry = leftover;
    at_end = advance(next, carry, leftover);
  }
  vel_ = v_new * tangent_;
  acc_ = ((v_new - v_old) / dt_) * tangent_ + (v_new * v_new) * curvature_;
  if (prep_[0].rotary) {
    joint_rates(v_new, v_old);
  } else {
    rot_vel_ = {0.0, 0.0, 0.0};
    rot_acc_ = {0.0, 0.0, 0.0};
  }
  remember_cycle();
}

const Block& Executor::flow_into_next(MotionRing& ring, ExecResult& out) {
  const CornerBlend crossing = blend_[0];
  pop(ring, out);
  entered_ = crossing;
  fresh_ = false;
  ++out.junction_flows;
  after_motion_ = true;
  ended_at_rest_ = false;
  const Block& next = ring.peek(0);
  contouring_ = prep_[0].contouring;
  line_ = next.line;
  seq_ = next.seq;
  begin_block(next, false);
  return next;
}

void Executor::plan_blend(std::size_t i, double cap) {
  blend_[i] = CornerBlend{};
  const PreparedBlock& p = prep_[i];
  const PreparedBlock& q = prep_[i + 1];
  auto blendable = [](const PreparedBlock& b) {
    return b.motion && !b.rotary && !b.angular &&
           (b.kind == BlockKind::kLine || b.kind == BlockKind::kRapid || b.kind == BlockKind::kArc || b.kind == BlockKind::kNurbs);
  };
  if (!(cap > 0.0) || !(p.path_tolerance > 0.0) || !blendable(p) || !blendable(q)) return;
  // a real corner: passed at the junction-deviation speed, above what the velocity-step rule allows
  const double step = junction_speed_cap(p.dir_end, q.dir_start, junction_.axis_accel, dt_, f_);
  const double jd = junction_deviation_speed(p.dir_end, q.dir_start, junction_.axis_accel, p.path_tolerance);
  if (!(jd > step)) return;
  CornerBlend b = corner_of(p.end, p.dir_end, q.dir_start, p.curv_end, q.curv_start);
  b.at = path_base_;
  for (std::size_t m = 0; m <= i; ++m) b.at += prep_[m].length;
  const double here = path_base_ + s_;  // the path position of the last setpoint
  const double kappa = 1.5 * std::max(norm(p.curv_end), norm(q.curv_start));  // a margin for a NURBS's change of curvature
  const double budget = kBlendToleranceShare * p.path_tolerance;
  const double sin_phi = norm(cross(b.t_in, b.t_out));
  // The window: within the deviation budget, its second half inside the first half of q (what
  // follows q is not known yet; the corner at q's end has the other half), not begun (the
  // setpoints so far are the blocks' own path).
  double h = std::min({corner_blend_half_length(sin_phi, kappa, budget), 0.5 * q.length, b.at - here});
  // The junction before p: a window there and this one overlap only as a group of equal
  // half-lengths (the superposition then runs p forward, never back) within the budget for both
  // turns; otherwise this window stays within p, clear of that one.
  CornerBlend& prev = i > 0 ? blend_[i - 1] : entered_;
  const bool prev_on = prev.on && (i == 0 || flows_after(i - 1));
  b.reach = prev_on ? std::max(0.0, p.length - prev.h) : p.length;
  if (h > b.reach) {
    const double alone = b.reach;
    double hg = 0.0;
    if (prev_on && !prev.grouped && i > 0) {
      const double sin_prev = norm(cross(prev.t_in, prev.t_out));
      hg = std::min({corner_blend_half_length(sin_prev + sin_phi, kappa, budget), 0.5 * q.length, prev.reach,
                     prev.at - here, b.at - here});
    }
    if (hg > alone && hg > prev.h) {
      prev.h = hg;  // the previous window widens: the two corners become one group
      prev.grouped = b.grouped = true;
      h = hg;
    } else {
      h = alone;
    }
  }
  if (!(h > 1e-3 * p.path_tolerance)) return;
  b.on = true;
  b.h = h;
  b.v_window = kappa * h;  // how far the tangents turn within the window (the speed cap's margin)
  blend_[i] = b;
}

void Executor::apply_blend() {
  const double s = path_base_ + s_;
  PathJet d{};
  bool any = false;
  auto add = [&](const CornerBlend& b) {
    if (!b.on || std::abs(s - b.at) >= b.h) return;
    const PathJet o = corner_blend_offset(b, s);
    d.p = d.p + o.p;
    d.d1 = d.d1 + o.d1;
    d.d2 = d.d2 + o.d2;
    any = true;
  };
  add(entered_);
  for (std::size_t i = 0; i + 1 < prepared_ && flows_after(i); ++i) add(blend_[i]);
  blended_ = any;
  if (!any) return;
  pos_ = pos_ + d.p;
  tangent_ = tangent_ + d.d1;
  curvature_ = curvature_ + d.d2;
}

}  // namespace pcnc
