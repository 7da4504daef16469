// tcp_fit_travel.cpp — the tool-centre-point --fit on the configured machine. See tcp_fit_travel.hpp.
#include "gcode/tcp_fit_travel.hpp"

namespace pcnc {

JointTravel joint_travel(const MachineConfig& config) {
  JointTravel t;
  t.min = config.travel_min();
  t.max = config.travel_max();
  t.rotary = config.rotary_travel();
  return t;
}

Joints home_joints(const MachineConfig& config) {
  Joints q{config.axes[0].home_mm, config.axes[1].home_mm, config.axes[2].home_mm, 0.0, 0.0};
  if (const RotaryAxisConfig* t = config.tilt_joint()) q[kTilt] = t->home_rad;
  if (const RotaryAxisConfig* r = config.rotary_joint()) q[kRotary] = r->home_rad;
  return q;
}

TcpFitResult fit_tcp_to_travel(const std::vector<FitPose>& poses, const MachineConfig& config, double tool_length_mm) {
  Kinematics kin = config.kinematics;
  kin.tool_length = tool_length_mm;
  return fit_tcp_program(poses, kin, joint_travel(config), home_joints(config));
}

}  // namespace pcnc
