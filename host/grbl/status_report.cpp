// status_report.cpp — the `?` report from the service's status (see status_report.hpp).
#include "grbl/status_report.hpp"

#include <cmath>
#include <cstdio>

#include "config/fixed_text.hpp"  // fixed(): printf digits, no "-0.000"

namespace pcnc::grbl {

using nlohmann::json;

namespace {
double num(const json& j, const char* key, double fallback = 0.0) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : fallback;
}
}  // namespace

std::string format_xyz(const json& v) {
  if (!v.is_object()) return "0.000,0.000,0.000";
  return fixed(num(v, "x"), 3) + "," + fixed(num(v, "y"), 3) + "," + fixed(num(v, "z"), 3);
}

std::string grbl_state(const json& st, const PortState& port) {
  const std::string s = st.value("state", std::string("NO_RT"));
  if (port.alarm || s == "FAULT" || s == "ESTOP" || s == "HOST_LOST" || s == "NO_RT") return "Alarm";
  if (port.check_mode) return "Check";
  if (port.homing) return "Home";
  const double speed = num(st, "path_speed");
  if (s == "PAUSED") return speed > 1e-9 ? "Hold:1" : "Hold:0";
  if (s == "JOGGING" || port.jogging) return "Jog";
  const json job = st.value("job", json::object());
  const bool stream = job.value("active", false) && job.value("file", std::string()) == "stream";
  if (stream && (s == "IDLE" || s == "RUNNING" || s == "STOPPING")) {
    // A streamed program that has run every line received and waits for more: the rt has
    // its program (a status older than the program start says Run), its pipeline waits for
    // a line, and the rt has done every block the stream made; grbl (an empty planner) says Idle.
    const bool rested = job.value("waiting_for_lines", false) && !port.lines_pending && st.value("program_active", false) &&
                        num(st, "blocks_done") >= num(job, "blocks_streamed") && num(st, "ring_fill") == 0.0 && speed <= 1e-9;
    return rested ? "Idle" : "Run";
  }
  if (s == "RUNNING" || s == "STOPPING") return "Run";
  return "Idle";
}

std::string format_status(const json& st, const PortState& port) {
  std::string out = "<" + grbl_state(st, port);
  out += "|MPos:" + format_xyz(st.value("actual", json::object()));
  out += "|Bf:" + std::to_string(port.planner_available) + "," + std::to_string(port.rx_available);
  const int line = static_cast<int>(num(st, "line"));
  if (line > 0) out += "|Ln:" + std::to_string(line);
  out += "|FS:" + fixed(num(st, "path_speed") * 60.0, 0) + "," + fixed(port.spindle_speed, 0);
  out += "|Ov:" + fixed(num(st, "feed_override_percent", 100.0), 0) + "," + std::to_string(port.rapid_override) + "," +
         std::to_string(port.spindle_override);
  // WCO: the active work offset (and G92 when applied), what senders subtract from MPos.
  const json ws = st.value("work_state", json::object());
  const json offsets = st.value("work_offsets", json::object());
  const std::string active = ws.value("active", std::string("G54"));
  if (offsets.contains(active)) {
    json wco = offsets[active];
    if (ws.value("G92_applied", false) && ws.contains("G92")) {
      for (const char* k : {"x", "y", "z"}) wco[k] = num(wco, k) + num(ws["G92"], k);
    }
    out += "|WCO:" + format_xyz(wco);
  }
  return out + ">";
}

}  // namespace pcnc::grbl
