// program.cpp — check_program and BlockStream: the two uses of the one front-end pipeline
// (gcode/pipeline.hpp). Check runs it to the blocks and keeps only figures and diagnostics;
// the stream hands the very same blocks on to the ring.
#include "gcode/program.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "gcode/line_reader.hpp"
#include "gcode/pipeline.hpp"
#include "gcode/planned_time.hpp"
#include "config/surface_file.hpp"
#include "gcode/preprocessor.hpp"
#include "gcode/ruled_json_input.hpp"
#include "gcode/tcp_fit_travel.hpp"
#include "config/joint_map.hpp"

namespace pcnc {

std::string program_file_problem(const std::string& path) {
  // Opened as the pipeline opens it (never blocking); a file that cannot be opened at all is
  // left to the check, which reports it as a diagnostic.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) return {};
  ::close(fd);
  std::string why;
  const int checked = open_program_file(path, &why);
  if (checked >= 0) ::close(checked);
  return why;
}
namespace {

Vec3 clamp_to_travel(const Vec3& p, const MachineConfig& c) {
  Vec3 r = p;
  for (int i = 0; i < kAxes; ++i) {
    const auto k = static_cast<std::size_t>(i);
    r[k] = std::clamp(p[k], c.axes[k].travel_min_mm, c.axes[k].travel_max_mm);
  }
  return r;
}

// The work state a job starts from: the state file's (or the config's), --offset as its G54.
WorkState start_work(const MachineConfig& config, const JobOptions& options) {
  WorkState w = options.work ? *options.work : default_work_state(config);
  if (options.offset) w.g5x[0] = *options.offset;
  return w;
}

// What a job leaves for the state file: --offset was this job's G54 only, so unless the
// program set G54 itself (G10 L2 P1 ...) the file's G54 stays.
WorkState work_left(const MachineConfig& config, const JobOptions& options, WorkState after) {
  if (options.offset && after.g5x[0] == *options.offset) {
    after.g5x[0] = (options.work ? *options.work : default_work_state(config)).g5x[0];
  }
  return after;
}

JobFrame make_frame(const MachineConfig& config, const JobOptions& options, const Transform& t) {
  JobFrame f;
  f.work = start_work(config, options);
  f.tools = options.tools;
  f.surface = options.surface;
  f.probe = options.probe;
  f.offset = t.offset;
  f.scale = t.scale;
  f.work_offset_index = std::clamp(options.work_offset_index, 0, 8);
  f.start = options.start_position ? *options.start_position : clamp_to_travel(t.offset, config);
  f.rot_start = options.start_rotary;
  f.contouring = options.contouring ? *options.contouring : config.motion.contouring_default;
  return f;
}

// The program's reader: a G-code file or text as it is; a JSON ruled-surface program (by its
// name, ".json") as the G-code form made from it for this machine and frame (ruled_json_input.hpp;
// throws ProgramRefused when the file is refused).
std::unique_ptr<LineReader> open_reader(const std::string* path, std::string_view text, const std::string& name,
                                        const MachineConfig& config, const JobFrame& frame) {
  if (is_ruled_json_program(path ? *path : name)) {
    if (path) return open_ruled_json_program(*path, config, frame.offset, frame.scale);
    RuledJsonInput in = ruled_json_input(std::string(text), name, config, frame.offset, frame.scale);
    if (!in.refusal_text.empty()) throw ProgramRefused(in.refusal);
    return std::make_unique<LineReader>(LineReader::Generated{}, std::move(in.text), std::move(in.places));
  }
  if (path) return std::make_unique<LineReader>(*path);
  return std::make_unique<LineReader>(LineReader::FromText{}, text);
}

struct Input {
  const std::string* path = nullptr;
  std::string_view text;
  std::unique_ptr<LineReader> open(const std::string& name, const MachineConfig& config, const JobFrame& frame) const {
    return open_reader(path, text, name, config, frame);
  }
};

// Source lines that hold a rapid block, as runs: block lines never decrease, so a rapid on the
// line after a run's last line extends the run.
void note_rapid(std::vector<LineRange>& runs, std::uint32_t line) {
  if (!runs.empty() && line >= runs.back().first && line <= runs.back().last + 1) {
    runs.back().last = std::max(runs.back().last, line);
    return;
  }
  runs.push_back({line, line});
}

// Sorted, overlapping or adjacent runs joined (a no-op unless block lines went back).
void tidy(std::vector<LineRange>& runs) {
  if (std::is_sorted(runs.begin(), runs.end(), [](const LineRange& a, const LineRange& b) { return a.first < b.first; }))
    return;
  std::sort(runs.begin(), runs.end(), [](const LineRange& a, const LineRange& b) { return a.first < b.first; });
  std::vector<LineRange> joined;
  for (const LineRange& r : runs) {
    if (!joined.empty() && r.first <= joined.back().last + 1) {
      joined.back().last = std::max(joined.back().last, r.last);
    } else {
      joined.push_back(r);
    }
  }
  runs = std::move(joined);
}

// Hands the pipeline's progress to options.on_check_progress (none: nothing is reported), at
// most every check_progress_interval_s of wall time and not before the check has run that
// long, so a short check reports nothing. `blocks`: the check pass's count of blocks (null in the fit pass);
// `reached`: the reader's line at the last report, where a CheckInterrupted from the handler is
// put (the sink names a made program's place for it, as for any diagnostic).
void report_progress(Pipeline& pipeline, const JobOptions& options, const DiagnosticSink& sink, CheckPass pass,
                     const std::uint64_t* blocks, int& reached) {
  if (!options.on_check_progress) return;
  using Clock = std::chrono::steady_clock;
  const auto interval = std::chrono::duration<double>(std::max(0.0, options.check_progress_interval_s));
  pipeline.set_progress_hook([&pipeline, &sink, &handler = options.on_check_progress, pass, blocks, &reached,
                              interval, last = Clock::now()]() mutable {
    const Clock::time_point now = Clock::now();
    if (now - last < interval) return;
    last = now;
    const LineReader& r = pipeline.reader();
    CheckProgress p;
    p.pass = pass;
    reached = static_cast<int>(std::min<std::uint64_t>(r.line_number(), 0x7fffffff));
    p.line = static_cast<std::uint64_t>(std::max(0, sink.file_line(reached)));  // a made program: its file's line
    p.bytes_read = r.bytes_read();
    p.total_bytes = r.total_bytes();
    p.blocks = blocks ? *blocks : 0;
    handler(p);
  });
}

// --fit: the transform that brings the program's own points into the travel, measured by a
// pass of the pipeline up to the preflight (no soft limits, no blocks, diagnostics dropped).
// It measures the programmed moves (no smoothing: tolerance 0 whatever G64 P says), so that the
// transform does not depend on the path tolerance and runs at any tolerance compare.
//
// On a machine with rotary joints, a program that runs under tool-centre-point control or turns a
// joint is fitted by fit_tcp_to_travel instead (docs/kinematics.md, "--fit of a tool-centre-point
// program"): the largest scale s <= 1 and offset of X Y Z that keep every joint inside its travel
// after the inverse kinematics, the angles never scaled; a TCP-off move that turns a joint is
// refused at its line (`sink`), and the transform is left as it was.
Transform fit_transform(const Input& in, const std::string& name, const MachineConfig& config,
                        const JobOptions& options, Transform t, DiagnosticSink& sink, int& reached) {
  DiagnosticSink scratch(name);
  MachineConfig programmed = config;
  set_operator_tolerance(programmed.motion, 0.0);
  const JobFrame frame = make_frame(programmed, options, t);
  Pipeline measure(in.open(name, programmed, frame), programmed, frame, scratch, false);
  report_progress(measure, options, scratch, CheckPass::kFit, nullptr, reached);
  std::vector<FitPose> poses;
  double tool_length = 0.0;
  if (config.rotary_mask() != 0) measure.collect_fit_poses(&poses, &tool_length);
  measure.drain();
  const bool five_axis = std::any_of(poses.begin(), poses.end(),
                                     [](const FitPose& f) { return f.tcp || f.tilt != 0.0 || f.rotary != 0.0; });
  if (five_axis) {
    const Kinematics kin = kinematics_with_tool(config, tool_length);
    for (FitPose& f : poses) {
      if (f.turn_only) {  // the tool pose its joints give, for the TCP move after it
        f.pose.tip = forward(kin, Joints{f.joint_xyz[0], f.joint_xyz[1], f.joint_xyz[2], f.tilt, f.rotary}).tip;
        f.joint_xyz = f.joint_xyz - t.offset;
      }
      f.pose.tip = f.pose.tip - t.offset;  // program coordinates (scale 1)
    }
    const TcpFitResult r = fit_tcp_to_travel(poses, config, tool_length);
    if (!r.ok) {
      sink.error(r.error_line, 0, "--fit: " + r.error);
      return t;
    }
    t.offset = r.offset;
    t.scale = r.scale;
    return t;
  }
  const FitResult f =
      fit_to_travel(measure.preflight().fit_extents(), t.offset, config, measure.comp_figures().max_radius_mm);
  t.offset = f.offset;
  t.scale = f.scale;
  return t;
}

CheckResult check_input(const Input& in, const std::string& name, const MachineConfig& config,
                        const JobOptions& options, const std::function<void(const Block&)>* on_block) {
  CheckResult result;
  DiagnosticSink sink(name);
  int reached = 0;  // the line of the last progress report
  try {
    Transform t;
    t.offset = start_work(config, options).g5x[0];
    if (options.fit) {
      t = fit_transform(in, name, config, options, t, sink, reached);
      if (options.offset)
        sink.warning(0, 0, "fit-offset", "--fit recentres the program: the --offset value is not used");
    }
    const JobFrame frame = make_frame(config, options, t);
    Pipeline pipeline(in.open(name, config, frame), config, frame, sink);
    if (options.on_message) pipeline.set_message_handler(options.on_message);
    report_progress(pipeline, options, sink, CheckPass::kCheck, &result.blocks, reached);
    Block b;
    PlanRecorder plan(config);
    while (pipeline.next(b)) {
      ++result.blocks;
      result.planned_time_s += planned_time_s(b);
      if (b.kind == BlockKind::kRapid) note_rapid(result.rapid_lines, b.line);
      if (b.rotary.tcp) result.tcp_tool_length_mm = b.rotary.tool_length;
      plan.add(b);
      if (on_block) (*on_block)(b);
    }
    result.plan = plan.finish();
    if (pipeline.failed()) pipeline.drain();  // the rest of the program's diagnostics
    const Preflight& pre = pipeline.preflight();
    result.comp = pipeline.comp_figures();
    result.transform = t;
    result.lines = pipeline.lines();
    if (const auto& places = pipeline.reader().source_places(); places && !places->empty())
      result.lines = static_cast<std::uint64_t>(std::max_element(places->begin(), places->end(), [](const SourcePlace& a, const SourcePlace& b) {
                       return a.line < b.line;
                     })->line);  // a made program: the last line of its file that it reached
    // the programmed moves: a smoothed curve counts for the G1 moves it replaced, a packed one
    // for its arcs
    result.moves = pre.moves() + pipeline.smoothing().moves - pipeline.smoothing().curves +
                   pipeline.arc_packing().arcs - pipeline.arc_packing().curves;
    result.last_point = pre.moves() > 0 ? pre.last_point() : frame.start;
    if (pre.moves() > 0) {
      result.min_point = pre.extents().min;
      result.max_point = pre.extents().max;
    } else {
      result.min_point = result.max_point = result.last_point;
    }
    result.feed_length_time_s = pre.feed_time_s();
    result.smoothed_moves = pipeline.smoothing().moves;
    result.smoothed_curves = pipeline.smoothing().curves;
    result.smoothed_blocks = pipeline.smoothed_blocks();
    result.max_path_deviation_mm = pipeline.smoothing().max_deviation_mm;
    result.smoothing_min_tolerance_mm = pipeline.smoothing().min_tolerance_mm;
    result.smoothing_max_tolerance_mm = pipeline.smoothing().max_tolerance_mm;
    result.packed_arcs = pipeline.arc_packing().arcs;
    result.packed_curves = pipeline.arc_packing().curves;
    result.packed_blocks = pipeline.packed_blocks();
    result.packed_max_deviation_mm = pipeline.arc_packing().max_deviation_mm;
    result.assumed_probe_lines = pipeline.interpreter().assumed_probe_lines();
  } catch (const ProgramRefused& e) {
    sink.error(e.diagnostic.line, e.diagnostic.column, e.diagnostic.message);
  } catch (const CheckInterrupted& e) {
    result.interrupted = true;
    sink.error(reached, 0, e.what());
  } catch (const std::exception& e) {
    sink.error(0, 0, e.what());
  }
  result.ok = !sink.has_errors();
  result.error_count = sink.error_count();
  result.diagnostics = sink.take();
  if (!result.ok) result.rapid_lines.clear(), result.plan.clear();
  tidy(result.rapid_lines);
  return result;
}

}  // namespace

bool is_null_move(const Move& m) {
  return (m.kind == MoveKind::kRapid || m.kind == MoveKind::kLine) && norm(m.end - m.start) <= 1e-12 &&
         m.rot_start == m.rot_end;
}

CheckResult check_program(const std::string& path, const MachineConfig& config, const JobOptions& options) {
  Input in;
  in.path = &path;
  return check_input(in, path, config, options, nullptr);
}

CheckResult check_program(const std::string& path, const MachineConfig& config, const JobOptions& options,
                          const std::function<void(const Block&)>& on_block) {
  Input in;
  in.path = &path;
  return check_input(in, path, config, options, &on_block);
}

CheckResult check_program_text(std::string_view text, const std::string& name, const MachineConfig& config,
                               const JobOptions& options) {
  Input in;
  in.text = text;
  return check_input(in, name, config, options, nullptr);
}

CheckResult check_program_text(std::string_view text, const std::string& name, const MachineConfig& config,
                               const JobOptions& options, const std::function<void(const Block&)>& on_block) {
  Input in;
  in.text = text;
  return check_input(in, name, config, options, &on_block);
}

namespace {

MoveListing list_input(const Input& in, const std::string& name, const MachineConfig& config, const JobOptions& options,
                       const std::function<void(const Move&)>& on_move, const MessageHandler& on_message,
                       const Transform* framed = nullptr) {
  MoveListing result;
  DiagnosticSink sink(name);
  try {
    Transform t;
    t.offset = start_work(config, options).g5x[0];
    if (framed) t = *framed;
    const JobFrame frame = make_frame(config, options, t);
    Pipeline pipeline(in.open(name, config, frame), config, frame, sink, false);
    pipeline.set_message_handler(on_message);
    Move m;
    // Up to the first error, as LinuxCNC's interpreter stops there (pcnc check without
    // --print-moves goes on for every diagnostic); the exact gouges cutter compensation finds
    // beyond LinuxCNC's own tests are errors that LinuxCNC would run through, so the listing
    // goes on past them.
    auto stop = [&] { return sink.error_count() > pipeline.comp_figures().gouges; };
    while (!stop() && pipeline.front_end_move(m)) {
      if (stop()) break;
      ++result.moves;
      if (on_move) on_move(m);
    }
    result.lines = pipeline.lines();
    result.work = work_left(config, options, pipeline.work_state());
  } catch (const ProgramRefused& e) {
    sink.error(e.diagnostic.line, e.diagnostic.column, e.diagnostic.message);
  } catch (const std::exception& e) {
    sink.error(0, 0, e.what());
  }
  result.ok = !sink.has_errors();
  result.diagnostics = sink.take();
  return result;
}

}  // namespace

MoveListing list_moves(const std::string& path, const MachineConfig& config, const JobOptions& options,
                       const std::function<void(const Move&)>& on_move, const MessageHandler& on_message) {
  Input in;
  in.path = &path;
  return list_input(in, path, config, options, on_move, on_message);
}

MoveListing list_moves(const std::string& path, const MachineConfig& config, const JobOptions& options,
                       const Transform& transform, const std::function<void(const Move&)>& on_move) {
  Input in;
  in.path = &path;
  return list_input(in, path, config, options, on_move, {}, &transform);
}

MoveListing list_moves_text(std::string_view text, const std::string& name, const MachineConfig& config,
                            const JobOptions& options, const std::function<void(const Move&)>& on_move,
                            const MessageHandler& on_message) {
  Input in;
  in.text = text;
  return list_input(in, name, config, options, on_move, on_message);
}

std::string load_job_state(const MachineConfig& config, const std::string& tool_table_path, JobOptions& options) {
  try {
    const std::string path = work_state_path(config);
    options.work = load_work_state(config, path);
    const std::string table = tool_table_path.empty() ? config.gcode.tool_table : tool_table_path;
    if (!table.empty()) options.tools = std::make_shared<const ToolTable>(load_tool_table(table));
    if (!options.surface && !config.gcode.surface.empty())
      options.surface = std::make_shared<const BSplineSurface>(load_surface_file(config.gcode.surface));
  } catch (const std::exception& e) {
    return e.what();
  }
  return {};
}

std::string format_move(const Move& m) {
  const char* kind = nullptr;
  switch (m.kind) {
    case MoveKind::kRapid: kind = "rapid"; break;
    case MoveKind::kLine: kind = "line"; break;
    case MoveKind::kArc: kind = "arc"; break;
    case MoveKind::kNurbs: kind = "nurbs"; break;
    case MoveKind::kRuled: kind = "ruled"; break;
    case MoveKind::kDwell: kind = "dwell"; break;
    case MoveKind::kPause:
    case MoveKind::kEnd: return {};
  }
  auto c = [](double v) { return std::fabs(v) < 5e-7 ? 0.0 : v; };
  char buf[256];
  const int n = std::snprintf(buf, sizeof buf, "L%d %s (%.6f,%.6f,%.6f)->(%.6f,%.6f,%.6f)", m.line, kind, c(m.start[0]),
                              c(m.start[1]), c(m.start[2]), c(m.end[0]), c(m.end[1]), c(m.end[2]));
  return std::string(buf, n > 0 ? std::min<std::size_t>(static_cast<std::size_t>(n), sizeof buf - 1) : 0);
}

struct BlockStream::Impl {
  Impl(std::unique_ptr<LineReader> reader, const std::string& name, const MachineConfig& config, const JobFrame& frame)
      : sink(name), pipeline(std::move(reader), config, frame, sink) {}
  MachineConfig config;  // for work_left
  JobOptions options;
  DiagnosticSink sink;
  Pipeline pipeline;  // keeps its own copy of the config: the stream may outlive the caller's
  bool streamed = false;             // FromFeed: an error ends the stream, it is not thrown
  std::optional<Diagnostic> error;   // ... and is kept here
  Vec3 last_end{};                   // where the last block ended (the end block after an error)
  std::uint64_t last_seq = 0;
  bool have_last = false;
  bool ended = false;                // FromFeed: the End block was handed out
};

BlockStream::BlockStream(const std::string& path, const MachineConfig& config, const JobOptions& options,
                         const Transform& transform)
    : impl_(std::make_unique<Impl>(open_reader(&path, {}, path, config, make_frame(config, options, transform)), path,
                                   config, make_frame(config, options, transform))) {
  if (options.on_message) impl_->pipeline.set_message_handler(options.on_message);
  impl_->config = config;
  impl_->options = options;
}

BlockStream::BlockStream(FromText, std::string_view text, const std::string& name, const MachineConfig& config,
                         const JobOptions& options, const Transform& transform)
    : impl_(std::make_unique<Impl>(open_reader(nullptr, text, name, config, make_frame(config, options, transform)), name,
                                   config, make_frame(config, options, transform))) {
  if (options.on_message) impl_->pipeline.set_message_handler(options.on_message);
  impl_->config = config;
  impl_->options = options;
}

namespace {
Transform stream_transform(const MachineConfig& config, const JobOptions& options) {
  Transform t;
  t.offset = start_work(config, options).g5x[0];
  return t;
}
}  // namespace

BlockStream::BlockStream(FromFeed, std::shared_ptr<LineFeed> feed, const std::string& name, const MachineConfig& config,
                         const JobOptions& options)
    : impl_(std::make_unique<Impl>(std::make_unique<LineReader>(LineReader::FromFeed{}, std::move(feed)), name, config,
                                   make_frame(config, options, stream_transform(config, options)))) {
  if (options.on_message) impl_->pipeline.set_message_handler(options.on_message);
  impl_->config = config;
  impl_->options = options;
  impl_->streamed = true;
}

const std::optional<Diagnostic>& BlockStream::error() const { return impl_->error; }
bool BlockStream::probe_sync() const { return impl_->pipeline.interpreter().probe_sync(); }
std::string BlockStream::probe_log() const { return impl_->pipeline.interpreter().probe_log(); }
Vec3 BlockStream::to_program(const Vec3& machine) const { return impl_->pipeline.interpreter().to_program(machine); }
bool BlockStream::failed() const { return impl_->pipeline.failed(); }

WorkState BlockStream::work_state() const {
  return work_left(impl_->config, impl_->options, impl_->pipeline.work_state());
}

BlockStream::~BlockStream() = default;
BlockStream::BlockStream(BlockStream&&) noexcept = default;
BlockStream& BlockStream::operator=(BlockStream&&) noexcept = default;

bool BlockStream::next(Block& out) {
  // A stream ends with its End block (M2/M30): the pipeline would read on for lines after it.
  if (impl_->streamed && impl_->ended) return false;
  if (impl_->pipeline.next(out)) {
    if (impl_->streamed && out.kind == BlockKind::kEnd) impl_->ended = true;
    impl_->last_end = out.end;
    impl_->last_seq = out.seq;
    impl_->have_last = true;
    return true;
  }
  if (!impl_->pipeline.failed()) return false;
  if (impl_->streamed) {
    // The blocks before the error run to their end: an End block where the last one ended.
    for (Diagnostic& d : impl_->sink.take()) {
      if (d.severity == Diagnostic::Severity::kError && !impl_->error) impl_->error = std::move(d);
    }
    if (impl_->ended) return false;
    impl_->ended = true;
    Move end;
    end.kind = MoveKind::kEnd;
    end.start = end.end = impl_->have_last ? impl_->last_end : impl_->options.start_position.value_or(Vec3{});
    end.line = impl_->error ? impl_->error->line : 0;
    make_block_into(end, impl_->config, out);
    out.seq = impl_->last_seq + 1;
    return true;
  }
  for (const Diagnostic& d : impl_->sink.take()) {
    if (d.severity == Diagnostic::Severity::kError) {
      throw std::runtime_error(format_diagnostic(d) + " (the program changed since it was checked?)");
    }
  }
  throw std::runtime_error("the program has an error (the program changed since it was checked?)");
}

std::uint64_t BlockStream::lines_read() const { return impl_->pipeline.reader().line_number(); }
std::uint64_t BlockStream::total_bytes() const { return impl_->pipeline.reader().total_bytes(); }
std::uint64_t BlockStream::bytes_read() const { return impl_->pipeline.reader().bytes_read(); }

std::string format_block(const Block& b) {
  // One snprintf per part into a fixed buffer: --print-blocks prints millions of these.
  char buf[1024];
  int n = std::snprintf(buf, sizeof buf, "L%u %s", b.line, to_string(b.kind));
  auto add = [&](const char* fmt, auto... args) {
    if (n >= 0 && n < static_cast<int>(sizeof buf))
      n += std::snprintf(buf + n, sizeof buf - static_cast<std::size_t>(n), fmt, args...);
  };
  auto c = [](double v, double scale) {  // what prints as zero prints as "0.0000", never "-0.0000"
    return std::fabs(v) * scale < 0.5 ? 0.0 : v;
  };
  auto pt = [&](const Vec3& p) { add("(%.4f,%.4f,%.4f)", c(p[0], 1e4), c(p[1], 1e4), c(p[2], 1e4)); };
  switch (b.kind) {
    case BlockKind::kRapid:
    case BlockKind::kLine:
    case BlockKind::kArc:
    case BlockKind::kNurbs:
    case BlockKind::kRuled:
      add("%s", " ");
      pt(b.start);
      add("%s", "->");
      pt(b.end);
      add(" len=%.4f class=%s v=%.3f a=%.1f drive=%c%c vd=%.3f ad=%.1f dec=%.4f t0=", c(b.length, 1e4),
          to_string(b.motion_class), c(b.speed, 1e3), c(b.accel, 1e1), axis_name(b.driving_axis),
          b.driving_dir < 0 ? '-' : '+', c(b.driving_speed, 1e3), c(b.driving_accel, 1e1), c(b.decel_start, 1e4));
      pt(b.dir_start);
      add("%s", " t1=");
      pt(b.dir_end);
      add(" m21=%d", static_cast<int>(b.contouring));
      if (b.probe_rule != 0) add(" probe=G38.%d", static_cast<int>(b.probe_rule) + 1);
      if (b.kind == BlockKind::kNurbs) {
        add(" degree=%d points=%d knots=[", static_cast<int>(b.nurbs.degree), static_cast<int>(b.nurbs.point_count));
        for (int k = 0; k < b.nurbs.knot_count && k < kMaxNurbsKnots; ++k) add(k ? " %.6g" : "%.6g", b.nurbs.knots[k]);
        add("] schedule=%d", static_cast<int>(b.nurbs.schedule_count));
      }
      if (b.kind == BlockKind::kRuled) {
        add(" segments=%d schedule=%d v0=%.3f v1=%.3f axis0=", static_cast<int>(b.ruled.segment_count),
            static_cast<int>(b.ruled.schedule_count), c(b.ruled.start_speed, 1e3), c(b.ruled.end_speed, 1e3));
        pt(b.rotary.axis_start);
        add("%s", " axis1=");
        pt(b.rotary.axis_end);
      }
      if (b.kind == BlockKind::kArc) {
        add("%s", " center=");
        pt(b.arc.center);
        add(" r=%.4f normal=%c a0=%.6f sweep=%.6f helix=%.4f w=%.4f aw=%.2f dec_a=%.6f", c(b.arc.radius, 1e4),
            axis_name(b.arc.normal_axis), c(b.arc.start_angle, 1e6), c(b.arc.sweep, 1e6), c(b.arc.helix, 1e4),
            c(b.arc.angular_speed, 1e4), c(b.arc.angular_accel, 1e2), c(b.arc.decel_start_angle, 1e6));
      }
      break;
    case BlockKind::kDwell:
      add(" %.3f s at ", c(b.dwell_s, 1e3));
      pt(b.end);
      break;
    case BlockKind::kPause:
      add("%s", b.optional_stop ? " optional (M1) at " : " (M0) at ");
      pt(b.end);
      break;
    case BlockKind::kEnd:
      add("%s", " at ");
      pt(b.end);
      break;
  }
  return std::string(buf, n > 0 ? std::min<std::size_t>(static_cast<std::size_t>(n), sizeof buf - 1) : 0);
}

}  // namespace pcnc
