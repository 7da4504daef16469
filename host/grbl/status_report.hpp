// status_report.hpp — grbl 1.1's real-time status report, pure: the service's status object
// (docs/protocol.md) as `<State|MPos:x,y,z|Bf:b,r|FS:f,s|Ov:f,r,s|WCO:x,y,z>` with the fields
// senders parse, and the grbl state a sender sees (docs/grbl-protocol.md, "states").
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace pcnc::grbl {

/// What the grbl port adds to the service's status to name the state.
struct PortState {
  bool alarm = false;        // an alarm is latched (until $X or a reset)
  bool check_mode = false;   // $C
  bool homing = false;       // $H under way
  bool jogging = false;      // a $J= motion under way
  bool lines_pending = false;  // streamed lines not yet answered
  int rapid_override = 100;
  int spindle_override = 100;
  double spindle_speed = 0.0;  // the last S word (the simulated mill has no spindle)
  std::size_t rx_available = 128;
  int planner_available = 15;
};

/// grbl's state name: Idle, Run, Hold:0, Hold:1, Jog, Home, Alarm, Check.
std::string grbl_state(const nlohmann::json& status, const PortState& port);

/// The whole report line, without the line end.
std::string format_status(const nlohmann::json& status, const PortState& port);

/// "x,y,z" with three decimals from {"x":..,"y":..,"z":..}.
std::string format_xyz(const nlohmann::json& v);

}  // namespace pcnc::grbl
