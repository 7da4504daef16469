// machine.cpp — the machine's construction and its public face (machine.hpp): commands go to
// the state machine, cycles to cycle.cpp, queries read the parts (machine_impl.hpp).
#include "loop/machine.hpp"

#include <algorithm>
#include <cmath>

#include "loop/machine_impl.hpp"

namespace pcnc {

Machine::Impl::Impl(const MachineConfig& c)
    : cfg(c), dt(c.cycle_period_s()), exec(c), jog(c), drive(c), probe(c), sm(cfg, st, sp, exec, jog, ovr, drive) {
  sp.pos = exec.position();
  sp.rot = exec.rotary();
  st.actual = drive.encoder();
  st.commanded = sp.pos;
  st.rotary_mask = c.rotary_mask();
  st.rot_commanded = sp.rot;
  st.rot_actual = drive.rotary_encoder();
  tj.mask = st.rotary_mask;
  tj.commanded = sp.rot;
  tj.actual = st.rot_actual;
}

Machine::Machine(const MachineConfig& config) : impl_(std::make_unique<Impl>(config)) {}
Machine::~Machine() = default;

void Machine::command(const Command& cmd) { impl_->sm.command(cmd); }
void Machine::set_host_alive(bool alive) { impl_->sm.set_host_alive(alive); }
void Machine::cycle(MotionRing& ring) { impl_->cycle(ring); }

bool Machine::wants_more_blocks(const MotionRing& ring) const {
  const Status& s = impl_->st;
  if (!s.program_active || impl_->sm.discarding()) return false;
  if (s.state != MachineState::kRunning && s.state != MachineState::kPaused) return false;
  const std::size_t n = ring.size();
  if (n >= kRingSlots) return false;
  for (std::size_t i = 0; i < n; ++i) {
    if (ring.peek(i).kind == BlockKind::kEnd) return false;
  }
  // nothing follows a probing move until its result is read (docs/probe.md)
  if (n > 0 && ring.peek(n - 1).probe_rule != kProbeNone) return false;
  return true;
}

bool Machine::paused_at_rest() const {
  const Impl& m = *impl_;
  return m.st.state == MachineState::kPaused && !m.jog.active() && m.exec.speed() == 0.0 && m.sp.vel[0] == 0.0 &&
         m.sp.vel[1] == 0.0 && m.sp.vel[2] == 0.0;
}

bool Machine::take_up_position(const Vec3& at) {
  Impl& m = *impl_;
  Vec3 p = at;
  for (int i = 0; i < kAxes; ++i) {
    if (!std::isfinite(p[i])) return false;
    p[i] = std::clamp(p[i], m.cfg.axes[i].travel_min_mm, m.cfg.axes[i].travel_max_mm);
  }
  m.drive.place(p);
  m.exec.set_position(p);
  m.sp = Setpoint{};
  m.sp.pos = p;
  m.st.commanded = p;
  m.st.actual = m.drive.encoder();
  m.ts.commanded = p;
  m.ts.actual = m.st.actual;
  return true;
}

bool Machine::take_up_rotary(const Rot3& at) {
  Impl& m = *impl_;
  Rot3 r = at;
  for (int i = 0; i < kRotaryJoints; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const auto& j = m.cfg.rotary[k];
    if (!std::isfinite(r[k])) return false;
    if (!j) r[k] = 0.0;
    else if (!j->continuous) r[k] = std::clamp(r[k], j->travel_min_rad, j->travel_max_rad);
  }
  m.drive.place_rotary(r);
  m.drive.reset_servo();
  m.exec.set_rotary(r);
  m.exec.set_position(m.exec.position());
  m.sp.rot = r;
  m.st.rot_commanded = r;
  m.st.rot_actual = m.drive.rotary_encoder();
  m.tj.commanded = r;
  m.tj.actual = m.st.rot_actual;
  return true;
}

void Machine::trace_failed(bool stop) {
  impl_->st.trace_failed = 1;
  if (stop) impl_->sm.refuse_programs();
}

void Machine::begin_shutdown() { impl_->sm.shut_down(); }
bool Machine::motion_at_rest() const { return impl_->sm.motion_at_rest(); }

const Status& Machine::status() const { return impl_->st; }
const TraceSample& Machine::trace_sample() const { return impl_->ts; }
const TraceJoints& Machine::trace_joints() const { return impl_->tj; }
const char* Machine::fault_reason() const { return impl_->sm.fault_reason(); }
void Machine::set_axis_blocked(int axis, bool blocked) { impl_->drive.set_blocked(axis, blocked); }
Vec3 Machine::true_position() const { return impl_->drive.true_position(); }

bool Machine::blending() const { return impl_->exec.blending(); }

}  // namespace pcnc
