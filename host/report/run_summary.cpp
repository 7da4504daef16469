// run_summary.cpp — RunSummary from a finished run, and its JSON form (see run_summary.hpp).
#include "report/run_summary.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <type_traits>

namespace pcnc {

namespace {

using nlohmann::json;

json timing_json(const TimingStats& t) {
  return json{{"wake_min_us", t.wake_min_us},       {"wake_mean_us", t.wake_mean_us},
              {"wake_p99_us", t.wake_p99_us},       {"wake_max_us", t.wake_max_us},
              {"compute_min_us", t.compute_min_us}, {"compute_mean_us", t.compute_mean_us},
              {"compute_p99_us", t.compute_p99_us}, {"compute_max_us", t.compute_max_us},
              {"overruns", t.overruns}};
}

TimingStats timing_from(const json& j) {
  TimingStats t;
  t.wake_min_us = j.at("wake_min_us").get<double>();
  t.wake_mean_us = j.at("wake_mean_us").get<double>();
  t.wake_p99_us = j.at("wake_p99_us").get<double>();
  t.wake_max_us = j.at("wake_max_us").get<double>();
  t.compute_min_us = j.at("compute_min_us").get<double>();
  t.compute_mean_us = j.at("compute_mean_us").get<double>();
  t.compute_p99_us = j.at("compute_p99_us").get<double>();
  t.compute_max_us = j.at("compute_max_us").get<double>();
  t.overruns = j.at("overruns").get<std::uint64_t>();
  return t;
}

template <typename Enum>
Enum enum_from(const std::string& name, int last) {
  for (int i = 0; i <= last; ++i) {
    if (name == to_string(static_cast<Enum>(i))) return static_cast<Enum>(i);
  }
  throw std::runtime_error("run summary: unknown name '" + name + "'");
}

json status_json(const Status& s) {
  return json{{"state", to_string(s.state)},
              {"fault", to_string(s.fault)},
              {"fault_axis", s.fault_axis},
              {"fault_line", s.fault_line},
              {"fault_value", s.fault_value},
              {"contouring", s.contouring},
              {"program_done", s.program_done},
              {"clock_virtual", s.clock_virtual},
              {"line", s.line},
              {"time_s", s.time_s},
              {"program_time_s", s.program_time_s},
              {"blocks_done", s.blocks_done},
              {"underruns", s.underruns},
              {"junction_stops", s.junction_stops},
              {"junction_flows", s.junction_flows},
              {"commanded", s.commanded},
              {"actual", s.actual},
              {"following_error", s.following_error},
              {"max_following_error", s.max_following_error},
              {"following_error_sq_sum", s.following_error_sq_sum},
              {"program_cycles", s.program_cycles},
              {"contour_error", s.contour_error},
              {"max_contour_error", s.max_contour_error},
              {"contour_error_sq_sum", s.contour_error_sq_sum},
              {"feed_override", s.feed_override},
              {"timing", timing_json(s.timing)}};
}

Status status_from(const json& j) {
  Status s;
  s.state = enum_from<MachineState>(j.at("state").get<std::string>(), static_cast<int>(MachineState::kHostLost));
  s.fault = enum_from<FaultCode>(j.at("fault").get<std::string>(), static_cast<int>(FaultCode::kSequence));
  s.fault_axis = j.at("fault_axis").get<std::uint8_t>();
  s.fault_line = j.at("fault_line").get<std::uint32_t>();
  s.fault_value = j.at("fault_value").get<double>();
  s.contouring = j.at("contouring").get<std::uint8_t>();
  s.program_done = j.at("program_done").get<std::uint8_t>();
  s.clock_virtual = j.at("clock_virtual").get<std::uint8_t>();
  s.line = j.at("line").get<std::uint32_t>();
  s.time_s = j.at("time_s").get<double>();
  s.program_time_s = j.at("program_time_s").get<double>();
  s.blocks_done = j.at("blocks_done").get<std::uint64_t>();
  s.underruns = j.at("underruns").get<std::uint64_t>();
  s.junction_stops = j.at("junction_stops").get<std::uint64_t>();
  s.junction_flows = j.at("junction_flows").get<std::uint64_t>();
  s.commanded = j.at("commanded").get<Vec3>();
  s.actual = j.at("actual").get<Vec3>();
  s.following_error = j.at("following_error").get<Vec3>();
  s.max_following_error = j.at("max_following_error").get<Vec3>();
  s.following_error_sq_sum = j.at("following_error_sq_sum").get<Vec3>();
  s.program_cycles = j.at("program_cycles").get<std::uint64_t>();
  s.contour_error = j.at("contour_error").get<double>();
  s.max_contour_error = j.at("max_contour_error").get<double>();
  s.contour_error_sq_sum = j.at("contour_error_sq_sum").get<double>();
  s.feed_override = j.at("feed_override").get<double>();
  s.timing = timing_from(j.at("timing"));
  return s;
}

// [[first, last], ...]
json rapid_lines_json(const std::vector<LineRange>& runs) {
  json a = json::array();
  for (const LineRange& r : runs) a.push_back(json::array({r.first, r.last}));
  return a;
}

std::vector<LineRange> rapid_lines_from(const json& a) {
  std::vector<LineRange> runs;
  for (const json& r : a) runs.push_back({r.at(0).get<std::uint32_t>(), r.at(1).get<std::uint32_t>()});
  return runs;
}

// One plan entry as one compact string, "first,last,cruise,accel,speed,before,after,angle_before,angle_after"
// (causes by key, junctions by number, speed mm/s, angles degrees): a CAM program has one per block.
// A number in plan_entry's text: std::to_chars with a precision prints what printf's %.Ng
// prints, without the format parsing and the multi-precision digits of printf.
template <typename T>
void append_number(std::string& out, T value, int precision = 0) {
  char buf[32];
  std::to_chars_result r{};
  if constexpr (std::is_floating_point_v<T>) {
    r = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::general, precision);
  } else {
    r = std::to_chars(buf, buf + sizeof buf, value);
  }
  out.append(buf, r.ptr);
}

void append_plan_entry(std::string& out, const LinePlan& p) {
  append_number(out, p.first);
  out += ',';
  append_number(out, p.last);
  out += ',';
  out += time_cause_key(p.cruise);
  out += ',';
  out += time_cause_key(p.accel);
  out += ',';
  append_number(out, p.speed, 9);
  out += ',';
  append_number(out, static_cast<int>(p.before));
  out += ',';
  append_number(out, static_cast<int>(p.after));
  out += ',';
  append_number(out, p.angle_before_deg, 4);
  out += ',';
  append_number(out, p.angle_after_deg, 4);
}

// The summary's plan: its entries in one string, separated by ';' (one JSON string rather
// than an array of 10,000s; with the splice around nlohmann below, a third of the time to
// write and to read back).
constexpr char kPlanSeparator = ';';
std::string plan_text(const std::vector<LinePlan>& plan) {
  std::string out;
  out.reserve(plan.size() * 64);
  for (const LinePlan& p : plan) {
    if (!out.empty()) out += kPlanSeparator;
    append_plan_entry(out, p);
  }
  return out;
}

// One comma-separated field of a plan entry, as a number (std::from_chars: the same values
// as sscanf's %u, %d and %lf give, without its format parsing: a summary holds one entry per
// block, and reading them was a seventh of the report's loading).
template <typename T>
bool plan_field(std::string_view& rest, T& out) {
  const std::size_t comma = rest.find(',');
  const std::string_view field = rest.substr(0, comma);
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), out);
  rest.remove_prefix(comma == std::string_view::npos ? rest.size() : comma + 1);
  return ec == std::errc() && end == field.data() + field.size();
}

bool plan_field(std::string_view& rest, TimeCause& out) {
  const std::size_t comma = rest.find(',');
  const std::string field(rest.substr(0, comma));
  rest.remove_prefix(comma == std::string_view::npos ? rest.size() : comma + 1);
  return parse_time_cause(field, out);
}

LinePlan plan_entry_from(std::string_view text) {
  LinePlan p;
  int before = 0, after = 0;
  std::string_view rest = text;
  if (!plan_field(rest, p.first) || !plan_field(rest, p.last) || !plan_field(rest, p.cruise) || !plan_field(rest, p.accel) ||
      !plan_field(rest, p.speed) || !plan_field(rest, before) || !plan_field(rest, after) ||
      !plan_field(rest, p.angle_before_deg) || !plan_field(rest, p.angle_after_deg) || !rest.empty() || before < 0 ||
      before > 5 || after < 0 || after > 5) {
    throw std::runtime_error("malformed plan entry '" + std::string(text) + "'");
  }
  p.before = static_cast<JunctionKind>(before);
  p.after = static_cast<JunctionKind>(after);
  return p;
}

}  // namespace

RunSummary make_run_summary(const RunReport& r, const MachineConfig& config, const std::string& config_path,
                            bool contouring_at_start) {
  RunSummary s;
  s.program = r.program;
  s.machine = config.name;
  s.config_path = config_path;
  s.clock = r.job.final_status.clock_virtual ? "virtual" : "real";
  s.contouring_at_start = contouring_at_start;
  s.contouring_angle_deg = config.motion.contouring_angle_deg;
  s.path_tolerance_mm = config.motion.path_tolerance_mm;
  s.cycle_hz = config.motion.cycle_hz;
  s.travel_min = config.travel_min();
  s.travel_max = config.travel_max();
  s.lines = r.check.lines;
  s.moves = r.check.moves;
  for (const Diagnostic& d : r.check.diagnostics) {
    if (d.severity != Diagnostic::Severity::kError) ++s.warnings;
  }
  s.transform = r.check.transform;
  s.min_point = r.check.min_point;
  s.max_point = r.check.max_point;
  s.last_point = r.check.last_point;
  s.feed_length_time_s = r.check.feed_length_time_s;
  s.smoothed_moves = r.check.smoothed_moves;
  s.smoothed_curves = r.check.smoothed_curves;
  s.smoothed_blocks = r.check.smoothed_blocks;
  s.max_path_deviation_mm = r.check.max_path_deviation_mm;
  s.smoothing_min_tolerance_mm = r.check.smoothing_min_tolerance_mm;
  s.smoothing_max_tolerance_mm = r.check.smoothing_max_tolerance_mm;
  s.packed_arcs = r.check.packed_arcs;
  s.packed_curves = r.check.packed_curves;
  s.packed_blocks = r.check.packed_blocks;
  s.packed_max_deviation_mm = r.check.packed_max_deviation_mm;
  s.rapid_lines = r.check.rapid_lines;
  s.plan = r.check.plan;
  s.tcp_tool_length_mm = r.check.tcp_tool_length_mm;
  s.comp_entries = r.check.comp.sessions;
  s.comp_moves_in = r.check.comp.moves_in;
  s.comp_moves_out = r.check.comp.moves_out;
  s.comp_biarcs = r.check.comp.biarcs;
  s.comp_moves_replaced = r.check.comp.moves_replaced;
  s.comp_tool_diameter_mm = 2.0 * r.check.comp.max_radius_mm;
  s.comp_contour = r.check.comp.contour;
  s.end = to_string(r.job.end);
  s.message = r.job.message;
  s.blocks_sent = r.job.blocks_sent;
  s.pauses = r.job.pauses;
  s.pauses_mode = r.job.pauses_mode;
  s.pause_lines = r.job.pause_lines;
  s.lines_read = r.job.lines_read;
  s.wall_time_s = r.job.wall_time_s;
  s.refill_count = r.job.refill_latency.count();
  s.refill_p50_us = r.job.refill_latency.quantile(0.5);
  s.refill_p99_us = r.job.refill_latency.quantile(0.99);
  s.refill_max_us = r.job.refill_latency.max();
  s.final_status = r.job.final_status;
  return s;
}

nlohmann::json to_json(const RunSummary& s) { return to_json(s, true); }

nlohmann::json to_json(const RunSummary& s, bool with_plan) {
  json j = json{{"format", s.format},
              {"program", s.program},
              {"machine", s.machine},
              {"config_path", s.config_path},
              {"clock", s.clock},
              {"contouring_at_start", s.contouring_at_start},
              {"contouring_angle_deg", s.contouring_angle_deg},
              {"path_tolerance_mm", s.path_tolerance_mm},
              {"cycle_hz", s.cycle_hz},
              {"travel_min", s.travel_min},
              {"travel_max", s.travel_max},
              {"check",
               {{"lines", s.lines},
                {"moves", s.moves},
                {"warnings", s.warnings},
                {"scale", s.transform.scale},
                {"offset", s.transform.offset},
                {"min_point", s.min_point},
                {"max_point", s.max_point},
                {"last_point", s.last_point},
                {"feed_length_time_s", s.feed_length_time_s},
                {"smoothed_moves", s.smoothed_moves},
                {"smoothed_curves", s.smoothed_curves},
                {"smoothed_blocks", s.smoothed_blocks},
                {"max_path_deviation_mm", s.max_path_deviation_mm},
                {"smoothing_tolerance_mm", {s.smoothing_min_tolerance_mm, s.smoothing_max_tolerance_mm}},
                {"packed_arcs", s.packed_arcs},
                {"packed_curves", s.packed_curves},
                {"packed_blocks", s.packed_blocks},
                {"packed_max_deviation_mm", s.packed_max_deviation_mm},
                {"rapid_lines", rapid_lines_json(s.rapid_lines)},
                {"tcp_tool_length_mm", s.tcp_tool_length_mm},
                {"plan", with_plan ? plan_text(s.plan) : std::string()}}},
              {"job",
               {{"end", s.end},
                {"message", s.message},
                {"blocks_sent", s.blocks_sent},
                {"lines_read", s.lines_read},
                {"wall_time_s", s.wall_time_s},
                {"refill_count", s.refill_count},
                {"refill_p50_us", s.refill_p50_us},
                {"refill_p99_us", s.refill_p99_us},
                {"refill_max_us", s.refill_max_us}}},
              {"status", status_json(s.final_status)}};
  if (!s.time_by_cause.empty()) j["time_by_cause"] = s.time_by_cause;
  if (s.pauses > 0) j["job"]["pauses"] = {{"count", s.pauses}, {"mode", s.pauses_mode}, {"lines", s.pause_lines}};
  if (s.comp_entries > 0) {
    j["check"]["cutter_comp"] = {{"entries", s.comp_entries},
                                 {"programmed_moves", s.comp_moves_in},
                                 {"tool_moves", s.comp_moves_out},
                                 {"biarcs", s.comp_biarcs},
                                 {"moves_replaced_by_biarcs", s.comp_moves_replaced},
                                 {"tool_diameter_mm", s.comp_tool_diameter_mm},
                                 {"contour", s.comp_contour}};
  }
  return j;
}

RunSummary run_summary_from_json(const nlohmann::json& j) {
  RunSummary s;
  s.format = j.at("format").get<int>();
  if (s.format != 1) throw std::runtime_error("run summary format " + std::to_string(s.format) + " is not known");
  s.program = j.at("program").get<std::string>();
  s.machine = j.at("machine").get<std::string>();
  s.config_path = j.at("config_path").get<std::string>();
  s.clock = j.at("clock").get<std::string>();
  s.contouring_at_start = j.at("contouring_at_start").get<bool>();
  s.contouring_angle_deg = j.at("contouring_angle_deg").get<double>();
  s.path_tolerance_mm = j.value("path_tolerance_mm", 0.0);  // absent in summaries before it existed
  s.cycle_hz = j.at("cycle_hz").get<double>();
  s.travel_min = j.at("travel_min").get<Vec3>();
  s.travel_max = j.at("travel_max").get<Vec3>();
  const json& c = j.at("check");
  s.lines = c.at("lines").get<std::uint64_t>();
  s.moves = c.at("moves").get<std::uint64_t>();
  s.warnings = c.at("warnings").get<std::uint64_t>();
  s.transform.scale = c.at("scale").get<double>();
  s.transform.offset = c.at("offset").get<Vec3>();
  s.min_point = c.at("min_point").get<Vec3>();
  s.max_point = c.at("max_point").get<Vec3>();
  s.last_point = c.at("last_point").get<Vec3>();
  s.feed_length_time_s = c.at("feed_length_time_s").get<double>();
  // absent in summaries written before smoothing existed
  s.smoothed_moves = c.value("smoothed_moves", std::uint64_t{0});
  s.smoothed_curves = c.value("smoothed_curves", std::uint64_t{0});
  s.smoothed_blocks = c.value("smoothed_blocks", std::uint64_t{0});
  s.max_path_deviation_mm = c.value("max_path_deviation_mm", 0.0);
  if (c.contains("smoothing_tolerance_mm")) {  // absent in older summaries
    s.smoothing_min_tolerance_mm = c.at("smoothing_tolerance_mm").at(0).get<double>();
    s.smoothing_max_tolerance_mm = c.at("smoothing_tolerance_mm").at(1).get<double>();
  }
  // absent in summaries written before arc packing existed
  s.packed_arcs = c.value("packed_arcs", std::uint64_t{0});
  s.packed_curves = c.value("packed_curves", std::uint64_t{0});
  s.packed_blocks = c.value("packed_blocks", std::uint64_t{0});
  s.packed_max_deviation_mm = c.value("packed_max_deviation_mm", 0.0);
  if (c.contains("rapid_lines")) s.rapid_lines = rapid_lines_from(c.at("rapid_lines"));  // absent in older summaries
  s.tcp_tool_length_mm = c.value("tcp_tool_length_mm", 0.0);  // absent before the report used it
  if (c.contains("cutter_comp")) {  // absent without G41/G42
    const json& k = c.at("cutter_comp");
    s.comp_entries = k.at("entries").get<std::uint64_t>();
    s.comp_moves_in = k.at("programmed_moves").get<std::uint64_t>();
    s.comp_moves_out = k.at("tool_moves").get<std::uint64_t>();
    s.comp_biarcs = k.value("biarcs", std::uint64_t{0});
    s.comp_moves_replaced = k.value("moves_replaced_by_biarcs", std::uint64_t{0});
    s.comp_tool_diameter_mm = k.at("tool_diameter_mm").get<double>();
    if (k.contains("contour")) s.comp_contour = k.at("contour").get<std::vector<std::vector<Vec3>>>();
  }
  if (c.contains("plan")) {
    const json& plan = c.at("plan");
    if (plan.is_string()) {
      const std::string& text = plan.get_ref<const std::string&>();
      for (std::size_t at = 0; at < text.size();) {
        const std::size_t end = std::min(text.find(kPlanSeparator, at), text.size());
        s.plan.push_back(plan_entry_from(std::string_view(text).substr(at, end - at)));
        at = end + 1;
      }
    } else {  // a summary written before the plan became one string: an array of entries
      for (const json& e : plan) s.plan.push_back(plan_entry_from(e.get<std::string>()));
    }
  }
  const json& b = j.at("job");
  s.end = b.at("end").get<std::string>();
  s.message = b.at("message").get<std::string>();
  s.blocks_sent = b.at("blocks_sent").get<std::uint64_t>();
  s.lines_read = b.at("lines_read").get<std::uint64_t>();
  s.wall_time_s = b.at("wall_time_s").get<double>();
  s.refill_count = b.at("refill_count").get<std::uint64_t>();
  s.refill_p50_us = b.at("refill_p50_us").get<double>();
  s.refill_p99_us = b.at("refill_p99_us").get<double>();
  s.refill_max_us = b.at("refill_max_us").get<double>();
  if (b.contains("pauses")) {  // absent without pauses gone on from
    const json& p = b.at("pauses");
    s.pauses = p.at("count").get<std::uint64_t>();
    s.pauses_mode = p.at("mode").get<std::string>();
    s.pause_lines = p.at("lines").get<std::vector<std::uint32_t>>();
  }
  s.final_status = status_from(j.at("status"));
  if (j.contains("time_by_cause")) s.time_by_cause = j.at("time_by_cause").get<std::map<std::string, double>>();
  return s;
}

namespace {
// The plan is nearly all of a summary's bytes (a CAM program's 10,000s of entries), and
// nlohmann's writer and reader look at a string's characters one by one (escapes, UTF-8): the
// plan's text goes around them. Its characters never need escaping (digits, letters, '_', '.',
// ',', ';', '+', '-'), so the file holds exactly the text nlohmann would have written.
constexpr std::string_view kPlanKey = "\"plan\": \"";

bool plain_json_text(std::string_view text) {
  return std::none_of(text.begin(), text.end(), [](char c) { return c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20; });
}
}  // namespace

void write_run_summary(const RunSummary& s, const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write the run summary to '" + path + "'");
  std::string plan = plan_text(s.plan);
  json j = to_json(s, false);
  std::string text;
  if (plain_json_text(plan)) {
    j["check"]["plan"] = "";
    text = j.dump(2);
    const std::size_t at = text.find(kPlanKey);  // the one key "plan" (other strings' quotes are escaped)
    text.insert(at + kPlanKey.size(), plan);
  } else {
    j["check"]["plan"] = std::move(plan);
    text = j.dump(2);
  }
  f << text << "\n";
  if (!f.flush()) throw std::runtime_error("cannot write the run summary to '" + path + "'");
}

RunSummary read_run_summary(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot read the run summary '" + path + "'");
  // the whole file first: nlohmann's parser reads a string several times faster than a stream
  f.seekg(0, std::ios::end);
  std::string text(static_cast<std::size_t>(std::max<std::streamoff>(0, f.tellg())), '\0');
  f.seekg(0);
  if (!f.read(text.data(), static_cast<std::streamsize>(text.size()))) {
    throw std::runtime_error("cannot read the run summary '" + path + "'");
  }
  // the plan's text taken out before the parse, and put back as the string it is (see above)
  std::optional<std::string> plan;
  if (const std::size_t key = text.find(kPlanKey); key != std::string::npos) {
    const std::size_t from = key + kPlanKey.size();
    const std::size_t to = text.find('"', from);
    if (to != std::string::npos && plain_json_text(std::string_view(text).substr(from, to - from))) {
      plan = text.substr(from, to - from);
      text.erase(from, to - from);
    }
  }
  try {
    nlohmann::json j = nlohmann::json::parse(text);
    if (plan && j.contains("check") && j["check"].is_object() && j["check"].contains("plan")) j["check"]["plan"] = std::move(*plan);
    return run_summary_from_json(j);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error("run summary '" + path + "': " + e.what());
  }
}

Vec3 rms_following_error(const Status& s) {
  if (s.program_cycles == 0) return {};
  const double n = static_cast<double>(s.program_cycles);
  return {std::sqrt(s.following_error_sq_sum[0] / n), std::sqrt(s.following_error_sq_sum[1] / n),
          std::sqrt(s.following_error_sq_sum[2] / n)};
}

double rms_contour_error(const Status& s) {
  if (s.program_cycles == 0) return 0.0;
  return std::sqrt(s.contour_error_sq_sum / static_cast<double>(s.program_cycles));
}

}  // namespace pcnc
