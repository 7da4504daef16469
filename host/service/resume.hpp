// resume.hpp — continuing a program that stopped in the middle of a block (after the host
// that fed it was lost and pcnc-rt held the machine on the path, HOST_LOST).
//
// The rt stops along the path, so the machine stands on the interrupted block's curve. The
// continuation is that block's remaining part, re-planned from the standing point with the
// same kind, end, feed limit and contouring flag (a pure function of the block and the
// point). The blocks after it are re-streamed unchanged from the checked program.
//
// May include: shared/ (ipc/block, config); resume.cpp also gcode/move.hpp,
// gcode/preprocessor.hpp, gcode/nurbs_schedule.hpp and gcode/ruled_move.hpp, to re-plan the
// remaining part the way the front end plans a block.
#pragma once

#include <optional>
#include <string>

#include "ipc/block.hpp"
#include "config/config.hpp"

namespace pcnc {

struct Continuation {
  bool skip = false;  // nothing of the block is left (stopped at its end, or a pause block)
  Block block{};      // the remaining part (seq 0: the feeder numbers it), when !skip
};

/// The rest of `interrupted` from `at` (machine coordinates, at rest). Lines and rapids
/// continue straight to the end; arcs and helices from the angle (or height) reached; a
/// NURBS block from the parameter u* of the curve point nearest `at` (geometry/nurbs.hpp
/// nurbs_project), the curve cut there (nurbs_segment) with its first control point moved to
/// `at` (the rt's corner blend may stop the machine a few µm off the curve, docs/rt-executor.md),
/// and its feed schedule cut at u* (never raised). A dwell is repeated whole; an M00/M01 pause is skipped (resuming is its
/// continue). Nothing is left (skip) only within half the rt's block tolerance of the end, so
/// that the next block starts where the machine stands. Fails (nullopt, `why` set) when `at` is not on the block's path within
/// `tolerance_mm`, or inside a flat arc of more than one turn (the point does not say which
/// turn, and the rt's status holds no progress along a block).
/// A ruled block (G5.4) is cut likewise at the parameter u* of the directrix point nearest the
/// tip the joints give (`at` the linear joints, `rot` the rotary ones, both as commanded:
/// forward kinematics with the block's tool length): the Ferguson segment holding u* is cut
/// there (the same cubic on [u*, its end]), the later segments kept, the schedule cut at u*,
/// the joints starting at `rot`; refused without `rot`, or when the tip is off the directrix or
/// the tool axis off the ruling at u*.
std::optional<Continuation> continue_block(const Block& interrupted, const Vec3& at, const MachineConfig& config,
                                           double tolerance_mm, std::string* why,
                                           const std::optional<Rot3>& rot = std::nullopt);

}  // namespace pcnc
