// trace_format.cpp — the trace row as text, written and read (see trace_format.hpp).
#include "ipc/trace_format.hpp"

#include <charconv>
#include <cstdio>

namespace pcnc {

namespace {

// Next comma-separated field of `s` from `pos`; advances pos past the comma.
std::string_view field(std::string_view s, std::size_t& pos) {
  if (pos > s.size()) return {};  // past the last field
  const std::size_t start = pos;
  const std::size_t comma = s.find(',', pos);
  if (comma == std::string_view::npos) {
    pos = s.size() + 1;
    return s.substr(start);
  }
  pos = comma + 1;
  return s.substr(start, comma - start);
}

bool to_double(std::string_view f, double& v) {
  if (f.empty()) return false;
  const char* b = f.data();
  if (*b == '+') ++b;
  const auto r = std::from_chars(b, f.data() + f.size(), v);
  return r.ec == std::errc() && r.ptr == f.data() + f.size();
}

}  // namespace

int format_trace_row(char* buf, std::size_t n, const TraceSample& s) {
  // positions to 0.1 µm resolution and beyond (encoder steps are 0.1 µm): %.7f mm
  return std::snprintf(buf, n, "%.4f,%u,%s,%.7f,%.7f,%.7f,%.7f,%.7f,%.7f,%.7f,%.7f,%.7f,%.5f", s.t, s.line,
                       to_string(s.state), s.commanded[0], s.commanded[1], s.commanded[2], s.actual[0], s.actual[1],
                       s.actual[2], s.following_error[0], s.following_error[1], s.following_error[2], s.speed);
}

std::string trace_csv_header(RotaryMask mask) {
  std::string h = kTraceCsvHeader;
  for (int i = 0; i < kRotaryJoints; ++i) {
    if (!has_joint(mask, i)) continue;
    const char c = joint_lower(i);
    for (const char* f : {",cmd_", ",act_", ",ferr_"}) {
      h += f;
      h += c;
    }
  }
  return h;
}

int format_trace_row(char* buf, std::size_t n, const TraceSample& s, const TraceJoints& j) {
  int len = format_trace_row(buf, n, s);
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  for (int i = 0; i < kRotaryJoints && len >= 0; ++i) {
    if (!has_joint(j.mask, i)) continue;
    const auto k = static_cast<std::size_t>(i);
    const std::size_t at = static_cast<std::size_t>(len) < n ? static_cast<std::size_t>(len) : n;
    // angles to 1e-7 degrees (about 2e-9 rad)
    const int m = std::snprintf(buf + at, n - at, ",%.7f,%.7f,%.7f", j.commanded[k] * kDeg, j.actual[k] * kDeg,
                                (j.commanded[k] - j.actual[k]) * kDeg);
    if (m < 0) return m;
    len += m;
  }
  return len;
}

std::string trace_csv_row(const TraceSample& s) {
  char buf[512];
  format_trace_row(buf, sizeof buf, s);
  return buf;
}

bool parse_state_name(std::string_view name, MachineState& state) {
  for (int i = 0; i <= static_cast<int>(MachineState::kHostLost); ++i) {
    const auto s = static_cast<MachineState>(i);
    if (name == to_string(s)) {
      state = s;
      return true;
    }
  }
  return false;
}

bool parse_trace_row(std::string_view text, TraceSample& row, TraceJoints* joints) {
  if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
  std::size_t pos = 0;
  if (!to_double(field(text, pos), row.t)) return false;
  const std::string_view line = field(text, pos);
  const auto r = std::from_chars(line.data(), line.data() + line.size(), row.line);
  if (r.ec != std::errc() || r.ptr != line.data() + line.size()) return false;
  if (!parse_state_name(field(text, pos), row.state)) return false;
  Vec3* vecs[3] = {&row.commanded, &row.actual, &row.following_error};
  for (Vec3* v : vecs) {
    for (std::size_t i = 0; i < 3; ++i) {
      if (!to_double(field(text, pos), (*v)[i])) return false;
    }
  }
  if (!to_double(field(text, pos), row.speed)) return false;
  // the rotary joints' columns, three per joint
  constexpr double kRad = 3.14159265358979323846 / 180.0;
  int joint = -1;
  while (pos <= text.size()) {
    double v[3];
    for (double& x : v) {
      if (!to_double(field(text, pos), x)) return false;
    }
    if (joints) {
      do ++joint;
      while (joint < kRotaryJoints && !has_joint(joints->mask, joint));
      if (joint < kRotaryJoints) {
        joints->commanded[static_cast<std::size_t>(joint)] = v[0] * kRad;
        joints->actual[static_cast<std::size_t>(joint)] = v[1] * kRad;
      }
    }
  }
  return pos == text.size() + 1;  // nothing after the last field
}

}  // namespace pcnc
