// rpc.cpp — request parsing, parameter checking and reply formatting (see rpc.hpp).
#include "service/rpc.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <initializer_list>

#include "config/work_state.hpp"

namespace pcnc::rpc {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

const char* type_name(const json& v) {
  switch (v.type()) {
    case json::value_t::null: return "null";
    case json::value_t::boolean: return "a boolean";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float: return "a number";
    case json::value_t::string: return "a string";
    case json::value_t::array: return "an array";
    case json::value_t::object: return "an object";
    default: return "something else";
  }
}

Error invalid(std::string message) { return Error{kInvalidParams, std::move(message), nullptr}; }

// Reads the parameters of one method: each getter checks type and range, and finish()
// refuses any key no getter asked for (a misspelt parameter must not pass silently).
class ParamReader {
 public:
  ParamReader(std::string method, const json& params) : method_(std::move(method)), params_(params) {
    if (!params_.is_null() && !params_.is_object()) {
      fail("params of '" + method_ + "' must be an object, got " + type_name(params_));
    }
  }

  bool ok() const { return !error_.has_value(); }
  const Error& error() const { return *error_; }

  const json* find(const std::string& key) {
    known_.push_back(key);
    if (!ok() || !params_.is_object()) return nullptr;
    auto it = params_.find(key);
    return it == params_.end() ? nullptr : &*it;
  }

  bool require(const std::string& key, const json* v) {
    if (v == nullptr && ok()) fail("missing parameter '" + key + "' for " + method_);
    return v != nullptr;
  }

  std::optional<double> number(const std::string& key, double lo, double hi, bool required, const std::string& unit = "") {
    const json* v = find(key);
    if (!v) {
      if (required) require(key, v);
      return std::nullopt;
    }
    if (!ok()) return std::nullopt;
    if (!v->is_number()) {
      fail("parameter '" + key + "' of " + method_ + " must be a number, got " + type_name(*v));
      return std::nullopt;
    }
    const double d = v->get<double>();
    if (!std::isfinite(d) || d < lo || d > hi) {
      fail("parameter '" + key + "' of " + method_ + " is out of range: " + v->dump() + " not in [" + fmt(lo) + ", " +
           fmt(hi) + "]" + (unit.empty() ? "" : " " + unit));
      return std::nullopt;
    }
    return d;
  }

  std::optional<std::string> string(const std::string& key, bool required) {
    const json* v = find(key);
    if (!v) {
      if (required) require(key, v);
      return std::nullopt;
    }
    if (!ok()) return std::nullopt;
    if (!v->is_string()) {
      fail("parameter '" + key + "' of " + method_ + " must be a string, got " + type_name(*v));
      return std::nullopt;
    }
    return v->get<std::string>();
  }

  std::optional<bool> boolean(const std::string& key) {
    const json* v = find(key);
    if (!v || !ok()) return std::nullopt;
    if (!v->is_boolean()) {
      fail("parameter '" + key + "' of " + method_ + " must be true or false, got " + type_name(*v));
      return std::nullopt;
    }
    return v->get<bool>();
  }

  void fail(std::string message) {
    if (ok()) error_ = invalid(std::move(message));
  }

  /// Refuses keys nobody asked for.
  void finish() {
    if (!ok() || !params_.is_object()) return;
    for (auto it = params_.begin(); it != params_.end(); ++it) {
      if (std::find(known_.begin(), known_.end(), it.key()) == known_.end()) {
        std::string list;
        for (const auto& k : known_) list += (list.empty() ? "" : ", ") + k;
        fail("unknown parameter '" + it.key() + "' for " + method_ + " (known: " + (list.empty() ? "none" : list) + ")");
        return;
      }
    }
  }

 private:
  static std::string fmt(double d) {
    json j = d;
    if (d == std::floor(d) && std::abs(d) < 1e15) j = static_cast<long long>(d);
    return j.dump();
  }
  std::string method_;
  const json& params_;
  std::vector<std::string> known_;
  std::optional<Error> error_;
};

template <typename T>
Checked<T> done(ParamReader& r, T value) {
  r.finish();
  Checked<T> out;
  if (r.ok()) {
    out.value = std::move(value);
  } else {
    out.error = r.error();
  }
  return out;
}

std::string dump_line(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace) + "\n"; }

}  // namespace

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names = {"status", "run",     "pause",  "resume",        "stop",
                                                 "estop",  "reset",   "override", "jog",         "jog_keepalive",
                                                 "jog_stop", "set_offset", "mdi",     "touch_off",   "subscribe", "capture",
                                                 "stream_open", "stream_lines", "stream_close", "probe"};
  return names;
}

bool is_method(const std::string& name) {
  const auto& n = method_names();
  return std::find(n.begin(), n.end(), name) != n.end();
}

ParsedRequest parse_request(std::string_view line) {
  ParsedRequest out;
  out.request.id = nullptr;
  // Parsed without exceptions; a key repeated inside one object is remembered (nlohmann
  // keeps the last one, so {"method":"status","method":"estop"} would silently become estop).
  std::vector<std::vector<std::string>> keys;  // the keys seen so far, per open object
  std::string repeated;
  bool id_repeated = false;  // the request's own "id" (top level), not one inside params
  const json::parser_callback_t watch_keys = [&](int, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::object_start) keys.emplace_back();
    if (event == json::parse_event_t::object_end && !keys.empty()) keys.pop_back();
    if (event == json::parse_event_t::key && !keys.empty() && parsed.is_string()) {
      const std::string& k = parsed.get_ref<const std::string&>();
      if (std::find(keys.back().begin(), keys.back().end(), k) != keys.back().end()) {
        if (repeated.empty()) repeated = k;
        if (keys.size() == 1 && k == "id") id_repeated = true;
      } else {
        keys.back().push_back(k);
      }
    }
    return true;
  };
  json j = json::parse(line.begin(), line.end(), watch_keys, false);
  if (j.is_discarded()) {
    // Say where: re-parse with exceptions for the message (cheap; the line is bounded). Any
    // json::exception counts: a number outside double range (1e309) is an out_of_range, not
    // a parse_error, and must never escape to the caller.
    std::string where;
    try {
      const json ignored = json::parse(line.begin(), line.end());
      (void)ignored;
    } catch (const json::exception& e) {
      where = e.what();
    }
    out.error = Error{kParseError, "invalid JSON: " + where, nullptr};
    return out;
  }
  if (!repeated.empty()) {
    out.error = Error{kInvalidRequest, "member '" + repeated + "' appears more than once in one object", nullptr};
    if (j.is_object()) {
      // The id cannot be trusted either when it is the repeated one.
      if (auto it = j.find("id"); it != j.end() && !id_repeated && (it->is_number() || it->is_string()))
        out.request.id = *it;
    }
    return out;
  }
  if (!j.is_object()) {
    out.error = Error{kInvalidRequest, std::string("a request must be a JSON object, got ") + type_name(j), nullptr};
    return out;
  }
  if (auto it = j.find("id"); it != j.end()) {
    if (it->is_number() || it->is_string() || it->is_null()) {
      out.request.id = *it;
    } else {
      out.error = Error{kInvalidRequest, std::string("'id' must be a number, a string or null, got ") + type_name(*it), nullptr};
      return out;
    }
  }
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it.key() != "id" && it.key() != "method" && it.key() != "params" && it.key() != "jsonrpc") {
      out.error = Error{kInvalidRequest, "unknown member '" + it.key() + "' in request (expected id, method, params)", nullptr};
      return out;
    }
  }
  auto m = j.find("method");
  if (m == j.end()) {
    out.error = Error{kInvalidRequest, "missing 'method'", nullptr};
    return out;
  }
  if (!m->is_string()) {
    out.error = Error{kInvalidRequest, std::string("'method' must be a string, got ") + type_name(*m), nullptr};
    return out;
  }
  out.request.method = m->get<std::string>();
  if (auto p = j.find("params"); p != j.end()) {
    if (!p->is_object() && !p->is_null()) {
      out.error = Error{kInvalidParams, std::string("'params' must be an object, got ") + type_name(*p), nullptr};
      return out;
    }
    if (p->is_object()) out.request.params = *p;
  }
  if (!is_method(out.request.method)) {
    std::string list;
    for (const auto& n : method_names()) list += (list.empty() ? "" : ", ") + n;
    out.error = Error{kMethodNotFound, "unknown method '" + out.request.method + "' (methods: " + list + ")", nullptr};
  }
  return out;
}

int parse_work_offset_name(std::string_view name) { return parse_work_system_name(name); }

std::string work_offset_name(int index) { return work_system_name(index); }

int parse_axis_name(std::string_view name) {
  const std::string l = lower(name);
  if (l == "x") return 0;
  if (l == "y") return 1;
  if (l == "z") return 2;
  return -1;
}

std::optional<Error> check_no_params(const std::string& method, const json& params) {
  ParamReader r(method, params);
  r.finish();
  if (!r.ok()) return r.error();
  return std::nullopt;
}

Checked<RunParams> check_run_params(const json& params) {
  ParamReader r("run", params);
  RunParams p;
  if (auto f = r.string("file", true)) {
    if (f->empty()) r.fail("parameter 'file' of run must not be empty");
    p.file = *f;
  }
  if (auto w = r.string("work_offset", false)) {
    p.work_offset = parse_work_offset_name(*w);
    // G59.1..G59.3 are kept and set, but a program starts in G54..G59 (the interpreter's).
    if (p.work_offset < 0 || p.work_offset > 5) r.fail("parameter 'work_offset' of run must be one of G54..G59, got '" + *w + "'");
  }
  p.contouring = r.boolean("contouring");
  p.fit = r.boolean("fit").value_or(false);
  // offset {"x","y","z"} (mm, each within ±1e4): what `pcnc run --offset` gives, G54 for this run
  if (const json* v = r.find("offset"); v && r.ok()) {
    if (!v->is_object()) {
      r.fail(std::string("parameter 'offset' of run must be an object {\"x\":..,\"y\":..,\"z\":..} in mm, got ") + type_name(*v));
    } else {
      ParamReader o("run's offset", *v);
      Vec3 off{};
      const char* names[3] = {"x", "y", "z"};
      for (std::size_t k = 0; k < 3; ++k) {
        if (auto d = o.number(names[k], -1e4, 1e4, true, "mm")) off[k] = *d;
      }
      o.finish();
      if (!o.ok()) r.fail(o.error().message);
      p.offset = off;
    }
  }
  return done(r, p);
}

Checked<OverrideParams> check_override_params(const json& params) {
  ParamReader r("override", params);
  OverrideParams p;
  if (auto v = r.number("percent", 0.0, 200.0, true, "%")) p.percent = *v;
  return done(r, p);
}

Checked<JogParams> check_jog_params(const json& params, const MachineConfig& config) {
  ParamReader r("jog", params);
  JogParams p;
  if (auto a = r.string("axis", true)) {
    p.axis = parse_axis_name(*a);
    // a rotary joint the machine declares: axis 3, 4, 5 (A, B, C), distance in degrees, feed in deg/min
    const std::string la = lower(*a);
    if (p.axis < 0 && la.size() == 1 && la[0] >= 'a' && la[0] <= 'c' && config.rotary[static_cast<std::size_t>(la[0] - 'a')]) {
      p.axis = kAxes + (la[0] - 'a');
    }
    if (p.axis < 0) r.fail("parameter 'axis' of jog must be X, Y or Z (or a rotary joint the machine has), got '" + *a + "'");
  }
  p.continuous = r.boolean("continuous").value_or(false);
  const bool rotary = p.axis >= kAxes;
  const double vmax = rotary ? config.rotary[static_cast<std::size_t>(p.axis - kAxes)]->max_velocity_rad_s * kDegPerRad * 60.0
                             : config.axes[static_cast<std::size_t>(std::max(p.axis, 0))].max_velocity_mm_s * 60.0;
  const double feed_default = std::min(kDefaultJogFeedMmMin, vmax);
  const json* dir = r.find("direction");
  const double max_dist = rotary ? 3600.0 : kMaxJogDistanceMm;
  auto dist = r.number("distance", -max_dist, max_dist, false, rotary ? "deg" : "mm");
  if (auto f = r.number("feed", 0.0, vmax, false, rotary ? "deg/min (the joint's max velocity)" : "mm/min (the axis's max velocity)")) {
    if (*f <= 0.0) r.fail("parameter 'feed' of jog must be > 0 mm/min");
    p.feed_mm_min = *f;
  } else {
    p.feed_mm_min = feed_default;
  }
  if (p.continuous) {
    if (dist) r.fail("a continuous jog takes 'direction', not 'distance'");
    if (!dir) {
      r.require("direction", dir);
    } else if (dir->is_string() && (*dir == "+" || *dir == "-")) {
      p.direction = *dir == "+" ? 1 : -1;
    } else if (dir->is_number_integer() && (dir->get<int>() == 1 || dir->get<int>() == -1)) {
      p.direction = dir->get<int>();
    } else {
      r.fail("parameter 'direction' of jog must be \"+\", \"-\", 1 or -1, got " + dir->dump());
    }
  } else {
    if (dir) r.fail("an incremental jog takes 'distance', not 'direction' (add \"continuous\": true)");
    if (!dist) {
      r.require("distance", nullptr);
    } else if (*dist == 0.0) {
      r.fail("parameter 'distance' of jog must not be 0");
    } else {
      p.distance_mm = *dist;
    }
  }
  return done(r, p);
}

Checked<SetOffsetParams> check_set_offset_params(const json& params) {
  ParamReader r("set_offset", params);
  SetOffsetParams p;
  if (auto w = r.string("offset", true)) {
    p.index = parse_work_offset_name(*w);
    if (p.index < 0) {
      r.fail("parameter 'offset' of set_offset must be one of G54..G59, G59.1, G59.2, G59.3, got '" + *w + "'");
    }
  }
  static const char* keys[kAxes] = {"x", "y", "z"};
  bool any = false;
  for (int i = 0; i < kAxes; ++i) {
    p.xyz[i] = r.number(keys[i], -1e4, 1e4, false, "mm");
    any = any || p.xyz[i].has_value();
  }
  if (!any) r.fail("set_offset needs at least one of x, y, z (mm)");
  return done(r, p);
}

Checked<MdiParams> check_mdi_params(const json& params) {
  ParamReader r("mdi", params);
  MdiParams p;
  if (auto t = r.string("text", true)) {
    if (t->find_first_not_of(" \t\r\n") == std::string::npos) {
      r.fail("parameter 'text' of mdi must hold at least one line of G-code");
    } else if (t->size() > kMaxMdiBytes) {
      r.fail("parameter 'text' of mdi is too long: " + std::to_string(t->size()) + " bytes, at most " +
             std::to_string(kMaxMdiBytes) + " (run a longer program as a file)");
    } else if (t->find('\0') != std::string::npos) {
      r.fail("parameter 'text' of mdi must not contain a NUL character");
    }
    p.text = *t;
  }
  return done(r, p);
}

Checked<TouchOffParams> check_touch_off_params(const json& params) {
  ParamReader r("touch_off", params);
  TouchOffParams p;
  if (auto a = r.string("axis", true)) {
    p.axis = parse_axis_name(*a);
    if (p.axis < 0) r.fail("parameter 'axis' of touch_off must be X, Y or Z, got '" + *a + "'");
  }
  if (auto v = r.number("value", -1e4, 1e4, true, "mm")) p.value = *v;
  return done(r, p);
}

Checked<ProbeParams> check_probe_params(const json& params) {
  ParamReader r("probe", params);
  ProbeParams p;
  if (auto a = r.string("axis", true)) {
    p.axis = parse_axis_name(*a);
    if (p.axis < 0) r.fail("parameter 'axis' of probe must be X, Y or Z, got '" + *a + "'");
  }
  if (auto d = r.number("direction", -1.0, 1.0, true, "")) {
    if (*d != -1.0 && *d != 1.0) r.fail("parameter 'direction' of probe must be -1 or 1");
    p.direction = *d < 0.0 ? -1 : 1;
  }
  if (auto f = r.number("feed", 1e-3, 1e6, false, "mm/min")) p.feed_mm_min = *f;
  if (auto d = r.number("distance", 1e-3, 1e4, false, "mm")) p.distance_mm = *d;
  if (auto c = r.string("code", false)) {
    static const char* codes[] = {"G38.2", "G38.3", "G38.4", "G38.5"};
    bool found = false;
    for (int i = 0; i < 4; ++i) {
      if (*c == codes[i]) p.code = 382 + i, found = true;
    }
    if (!found) r.fail("parameter 'code' of probe must be G38.2, G38.3, G38.4 or G38.5, got '" + *c + "'");
  }
  return done(r, p);
}

Checked<SubscribeParams> check_subscribe_params(const json& params) {
  ParamReader r("subscribe", params);
  SubscribeParams p;
  if (auto v = r.number("rate_hz", 0.0, kMaxSubscribeHz, false, "Hz")) p.rate_hz = *v;
  return done(r, p);
}

Checked<StreamOpenParams> check_stream_open_params(const json& params) {
  ParamReader r("stream_open", params);
  StreamOpenParams p;
  p.check = r.boolean("check").value_or(false);
  return done(r, p);
}

Checked<StreamLinesParams> check_stream_lines_params(const json& params) {
  ParamReader r("stream_lines", params);
  StreamLinesParams p;
  if (auto t = r.string("text", true)) {
    if (t->size() > kMaxMdiBytes) {
      r.fail("parameter 'text' of stream_lines is too long: " + std::to_string(t->size()) + " bytes, at most " +
             std::to_string(kMaxMdiBytes));
    } else if (t->find('\0') != std::string::npos) {
      r.fail("parameter 'text' of stream_lines must not contain a NUL character");
    }
    p.text = *t;
  }
  return done(r, p);
}

std::string format_result(const json& id, const json& result) { return dump_line(json{{"id", id}, {"result", result}}); }

std::string format_error(const json& id, const Error& error) {
  json e = {{"code", error.code}, {"message", error.message}};
  if (!error.data.is_null()) e["data"] = error.data;
  return dump_line(json{{"id", id}, {"error", e}});
}

std::string format_notification(const std::string& method, const json& params) {
  return dump_line(json{{"method", method}, {"params", params}});
}

json vec3_to_json(const Vec3& v) { return json{{"x", v[0]}, {"y", v[1]}, {"z", v[2]}}; }

json status_to_json(const Status& s) {
  json j;
  j["state"] = to_string(s.state);
  j["fault"] = to_string(s.fault);
  if (s.fault != FaultCode::kNone) {
    j["fault_axis"] = std::string(1, s.fault_axis < kAxes ? axis_name(s.fault_axis) : joint_letter(s.fault_axis - kAxes));
    j["fault_line"] = s.fault_line;
    j["fault_value"] = s.fault_value;
  }
  j["line"] = s.line;
  j["block_seq"] = s.block_seq;
  j["blocks_done"] = s.blocks_done;
  j["program_active"] = s.program_active != 0;
  j["program_done"] = s.program_done != 0;
  j["contouring"] = s.contouring != 0;
  j["commanded"] = vec3_to_json(s.commanded);
  j["actual"] = vec3_to_json(s.actual);
  j["velocity"] = vec3_to_json(s.velocity);
  j["following_error"] = vec3_to_json(s.following_error);
  j["max_following_error"] = vec3_to_json(s.max_following_error);
  if (s.program_cycles > 0) {
    const double n = static_cast<double>(s.program_cycles);
    j["rms_following_error"] = json{{"x", std::sqrt(s.following_error_sq_sum[0] / n)},
                                    {"y", std::sqrt(s.following_error_sq_sum[1] / n)},
                                    {"z", std::sqrt(s.following_error_sq_sum[2] / n)}};
    j["rms_contour_error"] = std::sqrt(s.contour_error_sq_sum / n);
  }
  // the rotary joints the machine declares, in degrees (DESIGN.md: degrees at every edge)
  if (s.rotary_mask != 0) {
    json rot = json::object();
    for (int i = 0; i < kRotaryJoints; ++i) {
      if (!has_joint(s.rotary_mask, i)) continue;
      const auto k = static_cast<std::size_t>(i);
      rot[std::string(1, joint_lower(i))] =
          json{{"commanded", s.rot_commanded[k] * kDegPerRad},     {"actual", s.rot_actual[k] * kDegPerRad},
               {"velocity", s.rot_velocity[k] * kDegPerRad},       {"following_error", s.rot_following_error[k] * kDegPerRad},
               {"max_following_error", s.rot_max_following_error[k] * kDegPerRad}};
    }
    j["rotary"] = rot;
    j["tcp"] = s.tcp != 0;
  }
  j["contour_error"] = s.contour_error;
  j["max_contour_error"] = s.max_contour_error;
  j["path_speed"] = s.path_speed;
  j["feed_override_percent"] = s.feed_override * 100.0;
  j["ring_fill"] = s.ring_fill;
  j["underruns"] = s.underruns;
  j["junction_stops"] = s.junction_stops;
  j["junction_flows"] = s.junction_flows;
  j["cycle"] = s.cycle;
  j["time_s"] = s.time_s;
  j["program_time_s"] = s.program_time_s;
  j["clock"] = s.clock_virtual ? "virtual" : "real";
  j["trace_failed"] = s.trace_failed != 0;
  // the touch probe (docs/probe.md): its input, and the last probing move's result
  j["probe"] = json{{"input", s.probe_input != 0},      {"outcome", to_string(s.probe_outcome)},
                    {"count", s.probe_count},           {"line", s.probe_line},
                    {"latched", vec3_to_json(s.probe_latched)}, {"stop", vec3_to_json(s.probe_stop)}};
  j["timing"] = json{{"wake_min_us", s.timing.wake_min_us},       {"wake_mean_us", s.timing.wake_mean_us},
                     {"wake_p99_us", s.timing.wake_p99_us},       {"wake_max_us", s.timing.wake_max_us},
                     {"compute_min_us", s.timing.compute_min_us}, {"compute_mean_us", s.timing.compute_mean_us},
                     {"compute_p99_us", s.timing.compute_p99_us}, {"compute_max_us", s.timing.compute_max_us},
                     {"overruns", s.timing.overruns}};
  return j;
}

}  // namespace pcnc::rpc
