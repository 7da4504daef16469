// names.cpp — printable names of the shared enums, for logs, status and the block listing.
#include "ipc/block.hpp"
#include "ipc/command.hpp"
#include "ipc/status.hpp"

namespace pcnc {

const char* to_string(BlockKind kind) {
  switch (kind) {
    case BlockKind::kRapid: return "rapid";
    case BlockKind::kLine: return "line";
    case BlockKind::kArc: return "arc";
    case BlockKind::kNurbs: return "nurbs";
    case BlockKind::kDwell: return "dwell";
    case BlockKind::kPause: return "pause";
    case BlockKind::kEnd: return "end";
    case BlockKind::kRuled: return "ruled";
  }
  return "?";
}

const char* to_string(MotionClass motion_class) {
  switch (motion_class) {
    case MotionClass::kNone: return "none";
    case MotionClass::kSingleAxis: return "axis";
    case MotionClass::kPlane: return "plane";
    case MotionClass::kSpace: return "space";
  }
  return "?";
}

const char* to_string(CommandKind kind) {
  switch (kind) {
    case CommandKind::kNone: return "none";
    case CommandKind::kProgramStart: return "program_start";
    case CommandKind::kPause: return "pause";
    case CommandKind::kResume: return "resume";
    case CommandKind::kStop: return "stop";
    case CommandKind::kEstop: return "estop";
    case CommandKind::kReset: return "reset";
    case CommandKind::kFeedOverride: return "feed_override";
    case CommandKind::kJogIncrement: return "jog_increment";
    case CommandKind::kJogContinuous: return "jog_continuous";
    case CommandKind::kJogStop: return "jog_stop";
    case CommandKind::kJogKeepAlive: return "jog_keepalive";
  }
  return "?";
}

const char* to_string(MachineState state) {
  switch (state) {
    case MachineState::kStarting: return "STARTING";
    case MachineState::kIdle: return "IDLE";
    case MachineState::kRunning: return "RUNNING";
    case MachineState::kPaused: return "PAUSED";
    case MachineState::kJogging: return "JOGGING";
    case MachineState::kStopping: return "STOPPING";
    case MachineState::kFault: return "FAULT";
    case MachineState::kEstop: return "ESTOP";
    case MachineState::kHostLost: return "HOST_LOST";
  }
  return "?";
}

const char* to_string(FaultCode code) {
  switch (code) {
    case FaultCode::kNone: return "none";
    case FaultCode::kFollowingError: return "following error";
    case FaultCode::kSoftLimit: return "soft limit";
    case FaultCode::kBadBlock: return "bad block";
    case FaultCode::kSequence: return "block sequence";
  }
  return "?";
}

const char* to_string(ProbeOutcome outcome) {
  switch (outcome) {
    case ProbeOutcome::kNone: return "none";
    case ProbeOutcome::kContact: return "contact";
    case ProbeOutcome::kNoContact: return "no contact";
    case ProbeOutcome::kAlreadyTriggered: return "already in the state sought";
  }
  return "?";
}

}  // namespace pcnc
