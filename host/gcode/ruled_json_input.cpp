// ruled_json_input.cpp — a JSON ruled-surface program as its G-code form. See ruled_json_input.hpp.
#include "gcode/ruled_json_input.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "config/joint_map.hpp"
#include "gcode/tcp_fit_travel.hpp"
#include "geometry/kinematics.hpp"

namespace pcnc {
namespace {

std::string degrees(double rad) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", rad * 180.0 / M_PI);
  return buf;
}

}  // namespace

bool is_ruled_json_program(const std::string& path) {
  if (path.size() < 5) return false;
  std::string ext = path.substr(path.size() - 5);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".json";
}

RuledTurnWords ruled_turn_words(const MachineConfig& config, const Vec3& tip, const Vec3& axis) {
  if (config.kinematics.kind == KinematicsKind::kTrivial) return {};
  const Joints q = inverse(kinematics_with_tool(config, 0.0), ToolPose{tip, axis}, home_joints(config), config.rotary_travel());
  const std::string tilt = tilt_index(config) == 1 ? "B" : "A";
  return {tilt + degrees(q[kTilt]) + " C" + degrees(q[kRotary]), tilt + "0 C0"};
}

RuledJsonInput ruled_json_input(const std::string& json_text, const std::string& origin, const MachineConfig& config,
                                const Vec3& offset, double scale) {
  RuledJsonInput out;
  const RuledJsonProgram prog = read_ruled_program_json(json_text, origin);
  if (!prog.error.empty()) {
    out.refusal = prog.refusal;
    out.refusal_text = prog.error;
    return out;
  }
  if (config.kinematics.kind == KinematicsKind::kTrivial || config.rotary_mask() == 0) {
    // refused once, at the first piece (the G-code form refuses M428 and every G5.4)
    const JsonPlace& p = prog.places.front().piece;
    out.refusal = Diagnostic{Diagnostic::Severity::kError, origin, p.line, p.column,
                             p.path + ": a ruled-surface program needs a 5-axis machine (rotary joints and a "
                                      "[kinematics] section); this machine has none"};
    out.refusal_text = format_diagnostic(out.refusal);
    return out;
  }
  const RuledPiece& first_piece = prog.pieces.front();
  const RuledPiece& last_piece = prog.pieces.back();
  const Vec3 first = first_piece.points.front(), last = last_piece.points.back();
  RuledProgramOptions o;
  o.feed_mm_min = prog.feed_mm_min;
  o.clearance_z = std::max(first[2], last[2]);
  o.rapid_to_first_z = true;
  const RuledTurnWords words = ruled_turn_words(config, scale * first + offset, first_piece.axes.front());
  o.turn_joints = words.turn;
  o.turn_back = words.back;
  const std::vector<std::string> lines = ruled_program_lines(prog.pieces, o);

  // Each line's place: the preamble at the first set point (the turn at its tool vector), each
  // group's G5.4 and G5.5 at its piece, each set point at its own, the rest at the last point.
  auto places = std::make_shared<SourcePlaces>();
  places->reserve(lines.size());
  const JsonPlace& p0 = prog.places.front().points.front();
  const JsonPlace& plast = prog.places.back().points.back();
  auto at = [](const JsonPlace& p) { return SourcePlace{p.line, p.column, p.path}; };
  std::size_t piece = 0, point = 0;
  bool in_group = false, after = false;
  for (const std::string& l : lines) {
    out.text += l;
    out.text += '\n';
    if (l.rfind("G5.4", 0) == 0) {
      in_group = true;
      point = 0;
      places->push_back(at(prog.places[piece].piece));
    } else if (l.rfind("G5.5", 0) == 0) {
      in_group = false;
      places->push_back(at(prog.places[piece].piece));
      after = ++piece == prog.pieces.size();
    } else if (in_group) {
      places->push_back(at(prog.places[piece].points[point++]));
    } else if (after) {
      places->push_back(at(plast));
    } else if (!words.turn.empty() && l.rfind("G0 " + words.turn, 0) == 0) {
      places->push_back(at(prog.places.front().first_axis));
    } else {
      places->push_back(at(p0));
    }
  }
  out.places = std::move(places);
  return out;
}

std::unique_ptr<LineReader> open_ruled_json_program(const std::string& path, const MachineConfig& config,
                                                    const Vec3& offset, double scale) {
  std::string why;
  const int fd = open_program_file(path, &why);
  if (fd < 0) throw std::runtime_error(why);
  std::string text;
  char buf[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string e = std::strerror(errno);
      ::close(fd);
      throw std::runtime_error(path + ": cannot read: " + e);
    }
    if (n == 0) break;
    text.append(buf, static_cast<std::size_t>(n));
    if (text.size() > kMaxRuledJsonBytes) {
      ::close(fd);
      throw ProgramRefused(Diagnostic{Diagnostic::Severity::kError, path, 0, 0,
                                      "a JSON program larger than " + std::to_string(kMaxRuledJsonBytes >> 20) +
                                          " MiB is not read (the G-code form streams programs of any size)"});
    }
  }
  ::close(fd);
  RuledJsonInput in = ruled_json_input(text, path, config, offset, scale);
  if (!in.refusal_text.empty()) throw ProgramRefused(in.refusal);
  return std::make_unique<LineReader>(LineReader::Generated{}, std::move(in.text), std::move(in.places));
}

}  // namespace pcnc
