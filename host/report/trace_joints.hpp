// trace_joints.hpp — the rotary-joint columns of a 5-axis machine's trace: after the unchanged
// 3-axis columns (ipc/trace_format.hpp) one triple per declared rotary joint, in degrees,
//   ...,speed,cmd_a,act_a,ferr_a,cmd_c,act_c,ferr_c
// (DESIGN.md "trace format"). The header tells which joints are there; each row's tail carries
// their values. The report reads them (trace_reader.hpp); the rt writes them.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>
#include <vector>

namespace pcnc {

constexpr std::size_t kMaxTraceJoints = 3;  // A, B, C

/// One row's joint values, degrees, in the header's order.
struct TraceJointRow {
  std::size_t count = 0;
  std::array<double, kMaxTraceJoints> cmd{}, act{}, ferr{};
};

/// The joint letters ('A', 'B', 'C', upper case) of a trace header: empty for the 3-axis header.
/// False when `header` is neither the 3-axis header nor it followed by cmd_L,act_L,ferr_L triples
/// of distinct joints a, b, c.
bool parse_trace_joint_header(std::string_view header, std::vector<char>& letters);

/// Splits a data row of a trace with `joints` joint columns: `base` is the 3-axis part (for
/// parse_trace_row), `row` the joint values. False when the row has not exactly 13 + 3·joints
/// fields or a joint value is not a number.
bool split_trace_joint_row(std::string_view text, std::size_t joints, std::string_view& base, TraceJointRow& row);

}  // namespace pcnc
