// session.hpp — the grbl 1.1 protocol on one serial line (docs/grbl-protocol.md): bytes from
// the sender in, text to the sender out, every action a request to the pcnc service (its JSON
// control socket: no second path to the ring). Real-time bytes act at once; lines are answered
// in order with `ok` or `error:N`: G-code lines go to the service's streamed program
// (stream_open / stream_lines, host/service/stream_job.cpp) and are answered as the pipeline
// takes them, which is what makes character-counting streaming keep the machine busy; `$`
// commands are answered here (settings, parameters, parser state, build info) or become a
// service request (jog and home as MDI, unlock as reset, check mode as a check stream).
//
// Single-threaded: the caller feeds bytes, the service's notifications and a periodic tick.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <string_view>

#include "config/config.hpp"
#include "grbl/line_assembler.hpp"
#include "grbl/settings.hpp"
#include "grbl/status_report.hpp"

namespace pcnc::grbl {

/// The service as the session sees it: one request, its whole reply ({"id","result"} or
/// {"id","error"}). Notifications that arrive meanwhile are kept by the caller and handed to
/// Session::on_notification afterwards, never from inside call().
class ServicePort {
 public:
  virtual ~ServicePort() = default;
  virtual nlohmann::json call(const std::string& method, const nlohmann::json& params) = 0;
};

constexpr const char* kBanner = "Grbl 1.1h ['$' for help] pcnc";

class Session {
 public:
  Session(ServicePort& service, const MachineConfig& config, std::function<void(const std::string&)> write);

  /// A sender opened the port (or the session starts): the start-up banner.
  void connected();
  void on_bytes(std::string_view data);
  /// The service's notifications (subscribe): `stream` and `program_end` events, status pushes.
  void on_notification(const nlohmann::json& n);
  /// Now and then (a few ms): queued lines that can go on now, alarms.
  void tick();

  const PortState& port() const { return port_; }

 private:
  struct Item {
    std::string text;
    std::size_t bytes = 0;
    bool gcode = false;   // a G-code line for the stream (else a `$` command or an empty line)
    bool sent = false;    // handed to the stream, or a command under way
  };
  enum class Step { kDone, kWait, kStarted };

  void realtime(std::uint8_t b);
  void line(ReceivedLine l);
  void pump();
  bool send_stream_lines();
  Step command(Item& it);
  Step jog(const std::string& words);
  Step home();
  Step toggle_check();
  bool idle_for_command(int* error);
  bool close_stream_and_wait();
  void soft_reset();
  void stream_event(const nlohmann::json& ev);
  void answer_front(int error, const std::string& message = {});
  void emit(const std::string& line) { write_(line + "\r\n"); }
  nlohmann::json status();
  void note_status(const nlohmann::json& st);
  void flush_alarm();
  void report_parameters();
  void report_parser_state();

  ServicePort& service_;
  MachineConfig config_;
  std::vector<Setting> settings_;
  std::function<void(const std::string&)> write_;
  LineAssembler rx_;
  std::deque<Item> queue_;      // received lines not answered yet, in order
  std::uint64_t stream_ = 0;    // the open stream's number (0: none)
  bool stream_check_ = false;   // the open stream is a check stream ($C)
  std::uint64_t sent_ = 0;      // lines handed to the open stream
  std::uint64_t acked_ = 0;     // ... and answered
  PortState port_;
  int feed_override_ = 100;
  int alarm_ = 0;
  bool in_alarm_state_ = false;  // the last status seen was an alarm state
  std::string alarm_message_;    // an alarm latched and not yet announced (flush_alarm)
  nlohmann::json last_status_ = nlohmann::json::object();
};

}  // namespace pcnc::grbl
