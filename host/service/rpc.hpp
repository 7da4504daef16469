// rpc.hpp — the control-socket protocol (docs/protocol.md): one JSON object per line,
// JSON-RPC style. A request {"id":..,"method":..,"params":{..}} gets exactly one reply,
// {"id":..,"result":..} or {"id":..,"error":{"code":..,"message":..}}; the server may also
// push notifications {"method":..,"params":..} (no id) to clients that subscribed.
//
// This file is pure: parsing a request line, checking each method's parameters into a typed
// value (types, ranges, unknown keys), and formatting replies and the status object. The
// socket (control_server) and the machine-facing logic (service) sit on top of it.
//
// May include: nlohmann/json, shared/ (config, ipc/status). Nothing else of the service.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "config/config.hpp"
#include "ipc/status.hpp"

namespace pcnc::rpc {

using json = nlohmann::json;

/// Error codes. The negative ones are JSON-RPC 2.0's; the positive ones are pcnc's.
enum ErrorCode : int {
  kParseError = -32700,      // the line is not valid JSON
  kInvalidRequest = -32600,  // valid JSON but not a request object (no method, bad id...)
  kMethodNotFound = -32601,  // no such method
  kInvalidParams = -32602,   // a parameter is missing, of the wrong type, out of range or unknown
  kInternalError = -32603,
  kRefused = 1,           // not allowed in the machine's current state (the message says why)
  kRtUnavailable = 2,     // pcnc-rt is not attached: not started, lost, or its segment refused
  kPreflightFailed = 3,   // the program has errors; data.diagnostics lists them
  kMailboxFull = 4,       // the rt's command mailbox is full (try again)
  kPermissionDenied = 5,  // the peer's uid may not use this socket
  kLineTooLong = 6,       // a request line exceeded the server's limit; the connection is closed
  kServerFull = 7,        // the connection table is full: only stop, estop and status are served; closed
  kIdleTimeout = 8,       // the connection was idle longer than process.client_idle_timeout_s; closed
};

struct Error {
  int code = kInternalError;
  std::string message;
  json data;  // optional details (null when none)
};

struct Request {
  json id;  // number, string or null (echoed as is)
  std::string method;
  json params = json::object();
};

/// Parses one request line (without its newline). On failure `error` is set and `id` holds
/// whatever id could be recovered (null otherwise), so the reply can still carry it.
struct ParsedRequest {
  Request request;
  std::optional<Error> error;
};
ParsedRequest parse_request(std::string_view line);

/// The methods, in documentation order.
const std::vector<std::string>& method_names();
bool is_method(const std::string& name);

// ---- typed parameters, one struct per method that takes any ----

struct RunParams {
  std::string file;
  int work_offset = 0;                // 0..5 = G54..G59: the default coordinate system
  std::optional<bool> contouring;     // default: the config's
  bool fit = false;
  std::optional<Vec3> offset;         // program zero in machine coordinates, mm: replaces G54 for this run
};

struct OverrideParams {
  double percent = 100.0;  // 0..200
};

struct JogParams {
  int axis = 0;               // 0 X, 1 Y, 2 Z
  bool continuous = false;
  double distance_mm = 0.0;   // incremental: signed distance
  int direction = 1;          // continuous: +1 / -1
  double feed_mm_min = 0.0;   // > 0, at most the axis's max velocity
};

struct SetOffsetParams {
  int index = 0;                      // 0..8 = G54..G59, G59.1..G59.3
  std::optional<double> xyz[kAxes];   // program zero in machine coordinates, mm; missing: unchanged
};

struct MdiParams {
  std::string text;  // one or more lines of G-code (a small program), at most kMaxMdiBytes
};

/// probe: one probing move for a person at the machine (docs/probe.md), run as an MDI.
struct ProbeParams {
  int axis = 2;                  // 0 X, 1 Y, 2 Z
  int direction = -1;            // -1 or +1
  double feed_mm_min = 50.0;
  std::optional<double> distance_mm;  // how far at most; default: to the end of the travel
  int code = 382;                // G38.2 .. G38.5 (x10)
};

struct TouchOffParams {
  int axis = 0;        // 0 X, 1 Y, 2 Z
  double value = 0.0;  // what the current position shall read in the active work system, mm
};

struct StreamOpenParams {
  bool check = false;  // $C: every check, no motion
};

struct StreamLinesParams {
  std::string text;  // whole lines of G-code, at most kMaxMdiBytes
};

struct SubscribeParams {
  double rate_hz = 10.0;  // 0 = unsubscribe, else (0, 50]
};

constexpr double kMaxSubscribeHz = 50.0;
constexpr double kMaxJogDistanceMm = 1000.0;
constexpr double kDefaultJogFeedMmMin = 600.0;
constexpr std::size_t kMaxMdiBytes = 16384;

/// Either a value or the error to send back.
template <typename T>
struct Checked {
  std::optional<T> value;
  Error error;
  bool ok() const { return value.has_value(); }
};

Checked<RunParams> check_run_params(const json& params);
Checked<OverrideParams> check_override_params(const json& params);
Checked<JogParams> check_jog_params(const json& params, const MachineConfig& config);
Checked<SetOffsetParams> check_set_offset_params(const json& params);
Checked<MdiParams> check_mdi_params(const json& params);
Checked<TouchOffParams> check_touch_off_params(const json& params);
Checked<ProbeParams> check_probe_params(const json& params);
Checked<SubscribeParams> check_subscribe_params(const json& params);
Checked<StreamOpenParams> check_stream_open_params(const json& params);
Checked<StreamLinesParams> check_stream_lines_params(const json& params);
/// For methods without parameters: params must be absent, null or an empty object.
std::optional<Error> check_no_params(const std::string& method, const json& params);

/// "G54".."G59", "G59.1".."G59.3" (case-insensitive) -> 0..8, else -1 (config/work_state.hpp).
int parse_work_offset_name(std::string_view name);
std::string work_offset_name(int index);
/// "X"/"Y"/"Z" (case-insensitive) -> 0..2, else -1.
int parse_axis_name(std::string_view name);

// ---- replies ----

/// One line each, '\n'-terminated. Invalid UTF-8 in strings is replaced, never thrown on.
std::string format_result(const json& id, const json& result);
std::string format_error(const json& id, const Error& error);
std::string format_notification(const std::string& method, const json& params);

/// The rt's status snapshot as JSON (positions {x,y,z} in mm, speeds mm/s, override %).
json status_to_json(const Status& s);
json vec3_to_json(const Vec3& v);

}  // namespace pcnc::rpc
