// command.hpp — what pcnc-host asks of pcnc-rt outside the motion ring (the mailbox).
// Plain trivially copyable values; the rt reads them at the start of each cycle.
#pragma once

#include <cstdint>
#include <type_traits>

namespace pcnc {

enum class CommandKind : std::uint8_t {
  kNone = 0,
  kProgramStart = 1,  // a program begins: reset per-program figures; value = contouring default (0/1)
  kPause = 2,         // feed hold: decelerate along the path to rest
  kResume = 3,        // continue after feed hold or M00/M01
  kStop = 4,          // decelerate to rest, flush the ring, back to idle
  kEstop = 5,         // amplifiers off at once, ESTOP state
  kReset = 6,         // leave FAULT/ESTOP/HOST_LOST when the cause is gone
  kFeedOverride = 7,  // value = override fraction 0.0 .. 2.0
  kJogIncrement = 8,  // axis, value = signed distance mm, feed mm/s (axis 3, 4, 5: A, B, C in rad, rad/s)
  kJogContinuous = 9, // axis, value = direction +1/-1, feed mm/s; needs keep-alives
  kJogStop = 10,      // decelerate any jog to rest
  kJogKeepAlive = 11, // continuous jog deadman keep-alive
};

struct Command {
  std::uint64_t id = 0;  // host-chosen, echoed in Status::last_command_id when taken
  CommandKind kind = CommandKind::kNone;
  std::uint8_t axis = 0;
  std::uint8_t pad_[6]{};
  double value = 0.0;
  double feed = 0.0;  // mm/s
};

static_assert(std::is_trivially_copyable_v<Command>, "Command lives in shared memory");

const char* to_string(CommandKind kind);

}  // namespace pcnc
