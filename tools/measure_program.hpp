// measure_program.hpp — the probing programs `pcnc measure` runs (docs/measurement.md): the
// touches of a phase (reference sphere, artefact balls, workpiece grid) as start/end ball
// centres in machine coordinates, written as G-code that logs every result with LinuxCNC's
// (PROBEOPEN)/(PROBECLOSE), and the reader of that log. Between touches the probe retracts
// along the approach to its start, rises to a safe Z, crosses, and descends onto the next
// start, so it never crosses an object it is not probing (the starts lie outside them).
#pragma once

#include <string>
#include <vector>

#include "geometry/vec3.hpp"

namespace pcnc {

struct PlannedTouch {
  Vec3 start{};     // ball centre where the G38.2 move starts (clear of every object)
  Vec3 end{};       // its commanded end (past the expected contact by the probing distance)
  Vec3 approach{};  // unit direction start → end
};

/// Touches on a sphere (centre, radius) along each unit approach direction d: the expected
/// contact c − R_s·d, the start `clearance` outside the ball's touching position, the end
/// `distance` past it.
std::vector<PlannedTouch> sphere_touches(const Vec3& centre, double sphere_radius, double ball_radius,
                                         const std::vector<Vec3>& approaches, double clearance, double distance);

/// The program: G21 G90, no tool length offset, no G92; for each touch G0 to the safe Z,
/// over the start, down to it, G38.2 to the end at `feed` (mm/min), G0 back to the start; the
/// log `log_path` (absolute) open around the touches. Runs with program zero = machine zero.
std::string probing_program(const std::vector<PlannedTouch>& touches, double safe_z, double feed,
                            const std::string& log_path, const std::string& title);

/// The X Y Z of each line of a probe log; throws std::runtime_error naming the file and line.
std::vector<Vec3> read_probe_log(const std::string& path);

}  // namespace pcnc
