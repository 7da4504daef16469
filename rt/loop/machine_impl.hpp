// machine_impl.hpp — inside Machine (private to rt/loop): the parts the machine owns and the
// order the cycle runs them in. Construction and the public face are in machine.cpp, one
// cycle in cycle.cpp, the states and their transitions in state_machine.{hpp,cpp}.
//
// Parts: motion (rt/motion: the block executor, the jog, the feed override), the drive
// (rt/drive: servo and plant per axis), the state machine that decides which motion part
// produces the setpoint, and the published status and trace sample.
#pragma once

#include "config/config.hpp"
#include "drive/drive.hpp"
#include "drive/sim_probe.hpp"
#include "ipc/status.hpp"
#include "loop/machine.hpp"
#include "loop/state_machine.hpp"
#include "motion/executor.hpp"
#include "motion/feed_override.hpp"
#include "motion/jog.hpp"
#include "motion/setpoint.hpp"

namespace pcnc {

struct Machine::Impl {
  explicit Impl(const MachineConfig& c);

  /// One 500 µs cycle, in order (cycle.cpp).
  void cycle(MotionRing& ring);

  MachineConfig cfg;
  double dt;
  Executor exec;
  Jog jog;
  FeedOverride ovr;
  Drive drive;
  SimProbe probe;  // the touch probe's input (docs/probe.md)
  Status st{};
  TraceSample ts{};
  TraceJoints tj{};
  Setpoint sp{};  // this cycle's setpoint; its position holds while nothing moves
  StateMachine sm;  // last: it works on the parts above
};

}  // namespace pcnc
