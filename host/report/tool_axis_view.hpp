// tool_axis_view.hpp — the run report's view of a 5-axis run from the workpiece: the commanded
// tool tip's path in workpiece coordinates and, every N mm along it, the tool axis as a short
// line from the tip towards the spindle (joint_digest.hpp, from the forward kinematics of the
// commanded joints), as a static isometric SVG (the same projection as the tool path's).
#pragma once

#include <string>

#include "report/joint_digest.hpp"

namespace pcnc {

/// The <svg> element (class "tool-axis-view"): one <polyline class="tip-path">, one
/// <line class="tool-axis"> per mark, the workpiece axes' directions and a legend. A note in
/// the picture when the digest has no tool axis.
std::string render_tool_axis_svg(const JointDigest& d);

}  // namespace pcnc
