// fuzz_gcode.cpp — libFuzzer entry: any bytes as a G-code program through check_program_text
// and, when the check passes, the whole BlockStream (half the inputs with a corner tolerance,
// which turns on merging of collinear segments). Crashes, sanitizer reports, a block with a
// non-finite number or a speed above an axis limit, and motion blocks that do not chain
// (each starting where the previous one ended) are failures.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "config/config.hpp"
#include "gcode/program.hpp"

namespace {

bool finite(const pcnc::Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

void check_block(const pcnc::Block& b, const pcnc::MachineConfig& c) {
  bool ok = finite(b.start) && finite(b.end) && finite(b.dir_start) && finite(b.dir_end) && std::isfinite(b.length) &&
            std::isfinite(b.speed) && std::isfinite(b.accel) && std::isfinite(b.decel_start) &&
            std::isfinite(b.dwell_s) && finite(b.arc.center) && std::isfinite(b.arc.angular_speed) &&
            std::isfinite(b.arc.sweep);
  if (b.kind == pcnc::BlockKind::kLine || b.kind == pcnc::BlockKind::kRapid) {
    for (int i = 0; i < pcnc::kAxes; ++i) {
      const auto k = static_cast<std::size_t>(i);
      ok = ok && b.speed * std::fabs(b.dir_start[k]) <= c.axes[k].max_velocity_mm_s * (1 + 1e-9);
      ok = ok && b.end[k] >= c.axes[k].travel_min_mm - 1e-3 && b.end[k] <= c.axes[k].travel_max_mm + 1e-3;
    }
  }
  if (!ok) __builtin_trap();
}

pcnc::MachineConfig make_config() {
  pcnc::MachineConfig c;  // the built-in defaults: 25 mm travel per axis
  c.gcode.work_offsets[0] = {12.5, 12.5, 25.0};
  c.gcode.work_offsets[1] = {0.0, 0.0, 25.0};
  c.gcode.max_executed_lines = 20000;  // loops end quickly under the fuzzer (the bound is an error)
  return c;
}

pcnc::MachineConfig make_merging_config() {
  pcnc::MachineConfig c = make_config();
  c.motion.path_tolerance_mm = 0.01;
  return c;
}

bool is_motion(pcnc::BlockKind k) {
  return k == pcnc::BlockKind::kLine || k == pcnc::BlockKind::kRapid || k == pcnc::BlockKind::kArc ||
         k == pcnc::BlockKind::kNurbs;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const pcnc::MachineConfig plain = make_config();
  static const pcnc::MachineConfig merging = make_merging_config();
  const pcnc::MachineConfig& config = size > 2 && (data[2] & 1) ? merging : plain;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  pcnc::JobOptions options;
  options.fit = size > 0 && (data[0] & 1);  // half the inputs with --fit
  options.contouring = size > 1 && (data[1] & 1);
  const pcnc::CheckResult r = pcnc::check_program_text(text, "fuzz.ngc", config, options);
  if (!r.ok) return 0;
  pcnc::BlockStream stream(pcnc::BlockStream::FromText{}, text, "fuzz.ngc", config, options, r.transform);
  pcnc::Block b;
  bool ended = false, moved = false;
  pcnc::Vec3 last{};
  while (stream.next(b)) {
    check_block(b, config);
    if (is_motion(b.kind)) {
      if (moved && std::hypot(b.start[0] - last[0], b.start[1] - last[1], b.start[2] - last[2]) > 1e-9) __builtin_trap();
      last = b.end;
      moved = true;
    }
    ended = b.kind == pcnc::BlockKind::kEnd;
  }
  if (!ended) __builtin_trap();  // every stream ends with an End block
  return 0;
}
