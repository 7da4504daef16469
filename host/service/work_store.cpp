// work_store.cpp — the service's work-coordinate state (see work_store.hpp).
#include "service/work_store.hpp"

namespace pcnc {

void WorkStore::load(const MachineConfig& config) {
  if (!path_.empty()) state_ = load_work_state(config, path_);
}

std::optional<std::string> WorkStore::set_g5x(int index, const std::optional<double> (&xyz)[kAxes]) {
  if (index < 0 || index >= kWorkSystems) return "no work coordinate system " + std::to_string(index);
  WorkState next = state_;
  Vec3& o = next.g5x[static_cast<std::size_t>(index)];
  for (int i = 0; i < kAxes; ++i) {
    if (xyz[i]) o[static_cast<std::size_t>(i)] = *xyz[i];
  }
  return replace(next);
}

std::optional<std::string> WorkStore::touch_off(int axis, double value, const Vec3& machine) {
  if (axis < 0 || axis >= kAxes) return "no axis " + std::to_string(axis);
  WorkState next = state_;
  const auto a = static_cast<std::size_t>(axis);
  const double g92 = next.g92_applied ? next.g92[a] : 0.0;
  const double tlo = next.tool_offset_applied ? next.tool_offset[a] : 0.0;
  next.g5x[static_cast<std::size_t>(next.active)][a] = machine[a] - g92 - tlo - value;
  return replace(next);
}

std::optional<std::string> WorkStore::replace(const WorkState& next) {
  if (!path_.empty()) {
    try {
      save_work_state(path_, next);
    } catch (const WorkStateError& e) {
      return e.what();
    }
  }
  state_ = next;
  return std::nullopt;
}

WorkState merge_work_change(const WorkState& current, const WorkState& before, const WorkState& after) {
  WorkState out = current;
  for (std::size_t i = 0; i < out.g5x.size(); ++i) {
    if (after.g5x[i] != before.g5x[i]) out.g5x[i] = after.g5x[i];
  }
  if (after.active != before.active) out.active = after.active;
  if (after.g92 != before.g92 || after.g92_applied != before.g92_applied) {
    out.g92 = after.g92;
    out.g92_applied = after.g92_applied;
  }
  if (after.g28 != before.g28) out.g28 = after.g28;
  if (after.g30 != before.g30) out.g30 = after.g30;
  if (after.tool != before.tool || after.tool_offset_applied != before.tool_offset_applied ||
      after.tool_offset != before.tool_offset) {
    out.tool = after.tool;
    out.tool_offset_applied = after.tool_offset_applied;
    out.tool_offset = after.tool_offset;
  }
  return out;
}

Vec3 work_position(const WorkState& w, const Vec3& machine) {
  Vec3 p = machine - w.g5x[static_cast<std::size_t>(w.active)];
  if (w.g92_applied) p = p - w.g92;
  if (w.tool_offset_applied) p = p - w.tool_offset;
  return p;
}

std::array<Vec3, 6> first_six(const WorkOffsets& g5x) {
  std::array<Vec3, 6> out{};
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = g5x[i];
  return out;
}

}  // namespace pcnc
