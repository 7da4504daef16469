// session.cpp — the grbl protocol over the service's socket (see session.hpp).
#include "grbl/session.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <thread>

#include "grbl/error_codes.hpp"
#include "grbl/realtime.hpp"

namespace pcnc::grbl {

using nlohmann::json;

namespace {

bool is_error(const json& reply) { return reply.contains("error"); }
std::string error_message(const json& reply) { return reply["error"].value("message", std::string("error")); }
int error_code(const json& reply) { return reply["error"].value("code", 0); }

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

std::string trim(std::string_view s) {
  const auto a = s.find_first_not_of(" \t");
  if (a == std::string_view::npos) return {};
  const auto b = s.find_last_not_of(" \t");
  return std::string(s.substr(a, b - a + 1));
}

// The first error of a refused MDI or stream check (error.data.errors), else the message.
std::string first_error(const json& reply) {
  const json& e = reply["error"];
  if (e.contains("data") && e["data"].is_object() && e["data"].contains("errors") && !e["data"]["errors"].empty())
    return e["data"]["errors"][0].get<std::string>();
  return e.value("message", std::string("error"));
}

// A $J= line's words as an MDI program: only G20/G21, G90/G91, G53, X, Y, Z and F (grbl's
// rule); empty when another word appears. F is required.
std::string jog_program(const std::string& words) {
  std::string g, axes, f;
  std::size_t i = 0;
  const std::string w = upper(words);
  while (i < w.size()) {
    if (w[i] == ' ') {
      ++i;
      continue;
    }
    const char letter = w[i++];
    std::size_t j = i;
    while (j < w.size() && (std::isdigit(static_cast<unsigned char>(w[j])) || w[j] == '.' || w[j] == '-' || w[j] == '+')) ++j;
    const std::string value = w.substr(i, j - i);
    i = j;
    if (value.empty()) return {};
    if (letter == 'G') {
      if (value != "20" && value != "21" && value != "90" && value != "91" && value != "53") return {};
      g += "G" + value + " ";
    } else if (letter == 'X' || letter == 'Y' || letter == 'Z') {
      axes += std::string(1, letter) + value + " ";
    } else if (letter == 'F') {
      f = "F" + value;
    } else {
      return {};
    }
  }
  if (axes.empty() || f.empty()) return {};
  return g + "G1 " + axes + f;
}

}  // namespace

Session::Session(ServicePort& service, const MachineConfig& config, std::function<void(const std::string&)> write)
    : service_(service), config_(config), settings_(settings_for(config)), write_(std::move(write)) {}

void Session::connected() {
  rx_.clear();
  write_("\r\n");
  emit(kBanner);
}

void Session::on_bytes(std::string_view data) {
  std::vector<RxItem> items;
  rx_.feed(data, items);
  for (auto& item : items) {
    if (item.realtime) {
      realtime(item.byte);
    } else {
      line(std::move(item.line));
    }
  }
  pump();
}

// ---------------------------------------------------------------- real-time commands

json Session::status() {
  const json reply = service_.call("status", json::object());
  if (reply.contains("result")) note_status(reply["result"]);
  return last_status_;
}

void Session::note_status(const json& st) {
  last_status_ = st;
  const int alarm = alarm_for(st.value("state", std::string()), st.value("fault", std::string()));
  // Latched when the machine enters an alarm state (a status pushed before $X that still
  // says ESTOP does not latch it again).
  const bool entered = alarm != 0 && !in_alarm_state_;
  in_alarm_state_ = alarm != 0;
  if (entered && alarm_ == 0) {
    alarm_ = alarm;
    port_.alarm = true;
    alarm_message_ = st.value("fault", std::string("none")) != "none"
                         ? "pcnc fault: " + st.value("fault", std::string()) + "; '$X' to reset"
                         : "pcnc: the machine is " + st.value("state", std::string()) + "; '$X' to reset";
  }
}

// The machine stopped on its own (a fault, an e-stop): what was queued is dropped, as grbl's
// alarm reset drops it, and the stream's input ends. Done here, between lines, never inside a
// command that asked for the status.
void Session::flush_alarm() {
  if (alarm_message_.empty()) return;
  if (stream_ != 0) service_.call("stream_close", json::object());
  stream_ = 0;
  sent_ = acked_ = 0;
  queue_.clear();
  rx_.clear();
  port_.jogging = port_.homing = false;
  emit("ALARM:" + std::to_string(alarm_));
  emit(msg_line(alarm_message_));
  alarm_message_.clear();
}

void Session::realtime(std::uint8_t b) {
  switch (b) {
    case kStatusQuery: {
      const json st = status();
      port_.lines_pending = !queue_.empty();
      port_.rx_available = rx_.available();
      emit(format_status(st, port_));
      return;
    }
    case kFeedHold: {
      const std::string s = status().value("state", std::string());
      if (port_.jogging || s == "JOGGING") {
        service_.call("stop", json::object());  // a hold during a jog cancels it (grbl)
      } else if (s == "RUNNING") {
        service_.call("pause", json::object());
      }
      return;
    }
    case kCycleStart:
      if (status().value("state", std::string()) == "PAUSED") service_.call("resume", json::object());
      return;
    case kSoftReset: soft_reset(); return;
    case kJogCancel:
      if (port_.jogging || status().value("state", std::string()) == "JOGGING") {
        service_.call("stop", json::object());
        // jog lines still waiting are cancelled with the jog
        for (auto it = queue_.begin(); it != queue_.end();) {
          if (!it->sent && it->text.rfind("$J=", 0) == 0) {
            rx_.answered(it->bytes);
            it = queue_.erase(it);
            emit("ok");
          } else {
            ++it;
          }
        }
      }
      return;
    default: break;
  }
  if (b >= kFeedOv100 && b <= kFeedOvMinus1) {
    const int p = next_feed_override(b, feed_override_);
    if (p != feed_override_ && !is_error(service_.call("override", json{{"percent", p}}))) feed_override_ = p;
  } else if (b == kRapidOv100 || b == kRapidOv50 || b == kRapidOv25) {
    port_.rapid_override = b == kRapidOv100 ? 100 : (b == kRapidOv50 ? 50 : 25);
  } else if (b >= kSpindleOv100 && b <= kSpindleOvMinus1) {
    port_.spindle_override = next_spindle_override(b, port_.spindle_override);
  }
  // 0x84 safety door, 0x9E spindle stop, 0xA0/0xA1 coolant and unknown bytes: no such
  // hardware on the simulated mill; ignored, as grbl ignores a byte it does not know.
}

// Ctrl-X: what moves stops under control (the rt decelerates along the path), the stream
// ends, everything received is dropped unanswered, the overrides return to 100 %, and the
// banner says the controller is ready again.
void Session::soft_reset() {
  const json st = status();
  const std::string s = st.value("state", std::string());
  if (s == "RUNNING" || s == "PAUSED" || s == "JOGGING" || s == "STOPPING") service_.call("stop", json::object());
  if (stream_ != 0) service_.call("stream_close", json::object());
  stream_ = 0;
  sent_ = acked_ = 0;
  queue_.clear();
  rx_.clear();
  // wait for the machine to come to rest and the job to end (bounded; the rt stops within
  // its deceleration distance)
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < deadline) {
    const json now = status();
    const std::string state = now.value("state", std::string());
    const bool job = now.value("job", json::object()).value("active", false);
    if (!job && state != "RUNNING" && state != "STOPPING" && state != "JOGGING" && state != "PAUSED") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (feed_override_ != 100 && !is_error(service_.call("override", json{{"percent", 100}}))) feed_override_ = 100;
  port_.rapid_override = port_.spindle_override = 100;
  port_.jogging = port_.homing = false;
  port_.check_mode = false;
  write_("\r\n");
  emit(kBanner);
  if (alarm_ != 0) emit("[MSG:'$X' to unlock]");
}

// ---------------------------------------------------------------- lines

void Session::line(ReceivedLine l) {
  Item it;
  it.text = trim(l.text);
  it.bytes = l.bytes;
  if (l.overflow) {
    queue_.push_back(it);
    queue_.back().text = "\x01overflow";
    return;
  }
  // '%' (a tape's start or end) is answered and dropped: a '%' after M30 would open a new
  // stream that waits for its closing '%'
  it.gcode = !it.text.empty() && it.text[0] != '$' && it.text != "%";
  if (it.gcode && alarm_ != 0 && !port_.check_mode) {
    it.gcode = false;
    it.text = "\x01lock";  // G-code is locked out during an alarm (error:9)
  }
  queue_.push_back(std::move(it));
}

void Session::answer_front(int error, const std::string& message) {
  if (queue_.empty()) return;
  const Item it = queue_.front();
  queue_.pop_front();
  rx_.answered(it.bytes);
  if (error == 0) {
    emit("ok");
  } else {
    emit("error:" + std::to_string(error));
    if (!message.empty()) emit(msg_line(message));
  }
}

void Session::pump() {
  flush_alarm();
  while (!queue_.empty()) {
    if (queue_.front().gcode) {  // G-code lines at the front: to the stream (or wait for it)
      send_stream_lines();
      return;
    }
    if (queue_.front().sent) return;  // a command under way ($H): answered when it ends
    const Step step = command(queue_.front());
    if (step == Step::kWait) return;
    if (step == Step::kStarted) {
      if (!queue_.empty()) queue_.front().sent = true;
      return;
    }
    flush_alarm();
  }
}

// Hands the G-code lines at the front of the queue (up to the first command) to the stream,
// opening one when none is open. False when that has to wait (a job still ending).
bool Session::send_stream_lines() {
  std::string text;
  std::uint64_t n = 0;
  for (Item& it : queue_) {
    if (!it.gcode) break;
    if (it.sent) continue;
    text += it.text;
    text += '\n';
    ++n;
  }
  if (n == 0) return true;
  if (stream_ != 0 && stream_check_ != port_.check_mode) close_stream_and_wait();
  if (stream_ == 0) {
    const json r = service_.call("stream_open", json{{"check", port_.check_mode}});
    if (is_error(r)) return false;  // not IDLE yet (the last job is ending); tick() tries again
    stream_ = r["result"].value("stream", std::uint64_t{0});
    stream_check_ = port_.check_mode;
    sent_ = acked_ = 0;
  }
  const json r = service_.call("stream_lines", json{{"text", text}});
  // Refused: the stream has just ended (an error in a line sent before); its `end` event is
  // on its way and hands the lines it did not take to a new stream.
  if (is_error(r)) return false;
  for (Item& it : queue_) {
    if (!it.gcode) break;
    if (!it.sent) {
      it.sent = true;
      ++sent_;
    }
  }
  return true;
}

void Session::on_notification(const json& n) {
  const std::string method = n.value("method", std::string());
  if (!n.contains("params")) return;
  const json& p = n["params"];
  if (method == "status") {
    note_status(p);
  } else if (method == "event") {
    const std::string ev = p.value("event", std::string());
    if (ev == "stream") {
      stream_event(p);
    } else if (ev == "program_end" && p.value("file", std::string()) == "MDI") {
      if (!queue_.empty() && queue_.front().sent && !queue_.front().gcode) {
        const bool ok = p.value("end", std::string()) == "completed";
        answer_front(ok ? 0 : kIdleError, ok ? std::string() : "pcnc: " + p.value("message", std::string()));
      }
      port_.jogging = port_.homing = false;
    } else if (ev == "message") {
      emit(msg_line(p.value("text", std::string())));
    }
  }
  pump();
}

// `done`: the stream's pipeline is done with its first `done` lines: each gets its ok. `end`
// with `error`: the line it names gets error:N, the lines sent after it go to a new stream.
void Session::stream_event(const json& ev) {
  if (ev.value("stream", std::uint64_t{0}) != stream_ || stream_ == 0) return;
  std::uint64_t done = ev.value("done", std::uint64_t{0});
  const bool failed = ev.contains("error");
  std::uint64_t error_line = 0;
  if (failed) {
    error_line = ev["error"].value("line", std::uint64_t{0});
    if (error_line > 0) done = std::min(done, error_line - 1);
  }
  while (acked_ < std::min(done, sent_) && !queue_.empty() && queue_.front().gcode && queue_.front().sent) {
    ++acked_;
    answer_front(0);
  }
  if (!ev.value("end", false)) return;
  if (failed) {
    const std::string msg = ev["error"].value("message", std::string());
    if (error_line == acked_ + 1 && !queue_.empty() && queue_.front().gcode && queue_.front().sent) {
      ++acked_;
      answer_front(error_for_message(msg), msg);
    } else {
      emit(msg_line(ev["error"].value("text", msg)));
    }
  }
  // lines the ended stream did not take go to the next one
  for (Item& it : queue_) {
    if (it.gcode) it.sent = false;
  }
  stream_ = 0;
  sent_ = acked_ = 0;
}

void Session::tick() {
  pump();
}

// ---------------------------------------------------------------- $ commands

// Commands that move or change the mode need the machine at rest with no program: the open
// stream is closed first when its sender has sent everything (the machine then shows Idle).
bool Session::idle_for_command(int* error) {
  const json st = status();
  if (alarm_ != 0) {
    *error = kSystemGcLock;
    return false;
  }
  if (port_.check_mode) {  // grbl: no motion commands in check mode
    *error = kIdleError;
    return false;
  }
  PortState p = port_;  // the command is at the front: no line before it is pending
  p.lines_pending = p.check_mode = p.homing = false;
  const bool dry = grbl_state(st, p) == "Idle";
  if (!dry) {
    *error = kIdleError;
    return false;
  }
  if (!close_stream_and_wait()) {
    *error = kIdleError;
    return false;
  }
  return true;
}

bool Session::close_stream_and_wait() {
  if (stream_ != 0) service_.call("stream_close", json::object());
  stream_ = 0;
  sent_ = acked_ = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < deadline) {
    const json now = status();
    if (!now.value("job", json::object()).value("active", false) && now.value("state", std::string()) == "IDLE") return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return false;
}

Session::Step Session::command(Item& it) {
  const std::string& t = it.text;
  if (t == "\x01overflow") return answer_front(kOverflow, "line longer than " + std::to_string(kMaxLineLength) + " characters"), Step::kDone;
  if (t == "\x01lock") return answer_front(kSystemGcLock, "alarm: '$X' to unlock"), Step::kDone;
  if (t.empty() || t == "%") return answer_front(0), Step::kDone;
  const std::string u = upper(t);
  if (u == "$") {
    emit("[HLP:$$ $# $G $I $N $x=val $Nx=line $J=line $SLP $C $X $H ~ ! ? ctrl-x]");
    return answer_front(0), Step::kDone;
  }
  if (u == "$$") {
    for (const Setting& s : settings_) emit(format_setting(s));
    return answer_front(0), Step::kDone;
  }
  if (u == "$#") return report_parameters(), answer_front(0), Step::kDone;
  if (u == "$G") return report_parser_state(), answer_front(0), Step::kDone;
  if (u == "$I") {
    emit("[VER:1.1h.pcnc:" + config_.name + "]");
    emit("[OPT:V,15,128]");
    emit("[MSG:pcnc: a PC-based NC controller; streamed lines run through its G-code pipeline]");
    return answer_front(0), Step::kDone;
  }
  if (u == "$N") {
    emit("$N0=");
    emit("$N1=");
    return answer_front(0), Step::kDone;
  }
  if (u == "$SLP") return answer_front(0), Step::kDone;  // the simulated mill has nothing to put to sleep
  if (u == "$X") {
    const std::string s = status().value("state", std::string());
    if (s == "FAULT" || s == "ESTOP" || s == "HOST_LOST") {
      const json r = service_.call("reset", json::object());
      if (is_error(r)) return answer_front(kSystemGcLock, error_message(r)), Step::kDone;
    }
    if (alarm_ != 0) emit("[MSG:Caution: Unlocked]");
    alarm_ = 0;
    port_.alarm = false;
    return answer_front(0), Step::kDone;
  }
  if (u == "$H") return home();
  if (u == "$C") return toggle_check();
  if (u.rfind("$J=", 0) == 0) return jog(t.substr(3));
  if (u.size() > 1 && std::isdigit(static_cast<unsigned char>(u[1]))) {
    const int error = write_setting(settings_, u.substr(1));
    return answer_front(error, error == kSettingDisabled ? "pcnc: settings come from the machine config (read-only here)" : ""),
           Step::kDone;
  }
  if (u.rfind("$N", 0) == 0 || u.rfind("$RST=", 0) == 0) {
    return answer_front(kInvalidStatement, "pcnc: startup lines and restores are not kept"), Step::kDone;
  }
  return answer_front(kInvalidStatement), Step::kDone;
}

Session::Step Session::jog(const std::string& words) {
  const std::string program = jog_program(words);
  if (program.empty()) return answer_front(kInvalidJogCommand), Step::kDone;
  if (port_.jogging) return Step::kWait;  // the next jog starts when this one has ended
  int error = 0;
  if (!idle_for_command(&error)) return answer_front(error), Step::kDone;
  const json r = service_.call("mdi", json{{"text", program}});
  if (is_error(r)) {
    if (error_code(r) == 1) return Step::kWait;  // the last jog is still ending
    const std::string why = first_error(r);
    const bool travel = why.find("travel") != std::string::npos;
    return answer_front(travel ? kTravelExceeded : kInvalidJogCommand, why), Step::kDone;
  }
  port_.jogging = true;
  answer_front(0);  // grbl answers a jog once it is queued
  return Step::kDone;
}

Session::Step Session::home() {
  int error = 0;
  if (!idle_for_command(&error)) return answer_front(error), Step::kDone;
  const auto& a = config_.axes;
  char text[160];
  std::snprintf(text, sizeof text, "G53 G0 Z%.4f\nG53 G0 X%.4f Y%.4f", a[2].home_mm, a[0].home_mm, a[1].home_mm);
  const json r = service_.call("mdi", json{{"text", std::string(text)}});
  if (is_error(r)) return answer_front(kIdleError, first_error(r)), Step::kDone;
  port_.homing = true;
  return Step::kStarted;  // ok once it has arrived (program_end)
}

Session::Step Session::toggle_check() {
  int error = 0;
  if (!port_.check_mode && !idle_for_command(&error)) return answer_front(error), Step::kDone;
  if (port_.check_mode && stream_ != 0) close_stream_and_wait();
  port_.check_mode = !port_.check_mode;
  emit(port_.check_mode ? "[MSG:Enabled]" : "[MSG:Disabled]");
  answer_front(0);
  if (!port_.check_mode) {  // grbl resets when check mode ends
    write_("\r\n");
    emit(kBanner);
  }
  return Step::kDone;
}

void Session::report_parameters() {
  const json st = status();
  const json offsets = st.value("work_offsets", json::object());
  for (const char* g : {"G54", "G55", "G56", "G57", "G58", "G59"}) {
    emit(std::string("[") + g + ":" + format_xyz(offsets.value(g, json::object())) + "]");
  }
  const json ws = st.value("work_state", json::object());
  emit("[G28:" + format_xyz(ws.value("G28", json::object())) + "]");
  emit("[G30:" + format_xyz(ws.value("G30", json::object())) + "]");
  emit("[G92:" + format_xyz(ws.value("G92_applied", false) ? ws.value("G92", json::object()) : json::object()) + "]");
  emit("[TLO:0.000]");
  emit("[PRB:0.000,0.000,0.000:0]");
}

void Session::report_parser_state() {
  const json st = status();
  const std::string wcs = st.value("work_state", json::object()).value("active", std::string("G54"));
  emit("[GC:G0 " + wcs + " G17 G21 G90 G94 M5 M9 T0 F0 S0]");
}

}  // namespace pcnc::grbl
