// tcp_fit_travel.hpp — `--fit` of a tool-centre-point program on the configured machine: the
// pure fit (geometry/tcp_fit.hpp) with the config's kinematics, joint travel and home joints,
// beside the 3-axis fit_to_travel (preflight.hpp). The interpreter does not hand tool poses to
// the --fit path yet (M428 and A/C words are issue 16's other branch); this is what it calls
// when it does (docs/kinematics.md, "--fit of a tool-centre-point program").
#pragma once

#include <vector>

#include "config/config.hpp"
#include "geometry/tcp_fit.hpp"

namespace pcnc {

/// The joints' travel of `config`: X, Y, Z and the tilt and (unless continuous) rotary joints.
JointTravel joint_travel(const MachineConfig& config);

/// The joints where pcnc-rt starts (home), for the inverse kinematics' choice of solution.
Joints home_joints(const MachineConfig& config);

/// fit_tcp_program on `config`, with the tool length of the program's tool (from the tool table).
TcpFitResult fit_tcp_to_travel(const std::vector<FitPose>& poses, const MachineConfig& config,
                               double tool_length_mm = 0.0);

}  // namespace pcnc
