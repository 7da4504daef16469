// program.cpp — wires the front-end stages over a streamed file: check pass and block stream.
#include "gcode/program.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "gcode/interpreter.hpp"
#include "gcode/lexer.hpp"
#include "gcode/line_reader.hpp"
#include "gcode/nurbs_move.hpp"
#include "gcode/parser.hpp"
#include "gcode/preflight.hpp"
#include "gcode/preprocessor.hpp"
#include "gcode/segment_merge.hpp"

namespace pcnc {
namespace {

// Lines -> Moves: the shared loop of both passes. Handles '%' delimiters, '/' block delete,
// over-long lines, program end (M2/M30) and a missing end.
class MoveSource {
 public:
  MoveSource(LineReader& reader, const MachineConfig& config, const JobFrame& frame, DiagnosticSink& sink)
      : reader_(reader), sink_(sink), interp_(config, frame, sink) {}

  // Next move; false once the End move has been returned.
  bool next(Move& m) {
    while (pos_ >= pending_.count) {
      if (done_) return false;
      pending_.clear();
      pos_ = 0;
      read_line();
    }
    m = pending_.moves[pos_++];
    if (m.kind == MoveKind::kEnd) {
      done_ = true;
      pending_.clear();
      pos_ = 0;
    }
    return true;
  }

  // After the End move: warns once if the file holds anything but blanks and comments after it.
  void check_trailing() {
    if (!ended_by_m2_) return;
    std::string_view text;
    bool too_long = false;
    DiagnosticSink scratch;
    while (reader_.next(text, too_long)) {
      const int line_no = static_cast<int>(reader_.line_number());
      if (!lex_line(text, line_no, lexed_, scratch) || lexed_.count > 0 || lexed_.block_delete) {
        sink_.warning(line_no, 0, "after-end", "text after the program end (M2/M30) is not executed");
        return;
      }
    }
  }

  std::uint64_t lines() const { return reader_.line_number(); }

 private:
  void read_line() {
    std::string_view text;
    bool too_long = false;
    if (!percent_closed_ && reader_.next(text, too_long)) {
      const int line_no = static_cast<int>(std::min<std::uint64_t>(reader_.line_number(), 0x7fffffff));
      last_line_ = line_no;
      if (too_long) {
        sink_.error(line_no, static_cast<int>(LineReader::kMaxLine),
                    "line too long; expected at most 65536 characters per line");
        return;
      }
      if (!lex_line(text, line_no, lexed_, sink_)) return;
      if (lexed_.block_delete) {
        sink_.warning(line_no, 1, "block-delete",
                      "'/' block delete: the line is skipped (the block delete switch is always on)");
        return;
      }
      if (lexed_.percent) {
        if (seen_content_ || seen_percent_) {
          percent_closed_ = true;  // the closing '%': the program ends here
        }
        seen_percent_ = true;
        return;
      }
      if (lexed_.count == 0) return;
      seen_content_ = true;
      if (!parse_line(lexed_, line_no, parsed_, sink_)) return;
      interp_.execute(parsed_, pending_);
      if (interp_.ended()) ended_by_m2_ = true;
      return;
    }
    // End of input (or closing '%') without M2/M30.
    interp_.end_of_input(last_line_);
    sink_.warning(last_line_, 0, "no-end", "the program has no M2/M30; it ends at the end of the file");
    pending_.push(interp_.end_move(last_line_));
  }

  LineReader& reader_;
  DiagnosticSink& sink_;
  Interpreter interp_;
  LexedLine lexed_;
  ParsedLine parsed_;
  MoveList pending_;
  int pos_ = 0;
  int last_line_ = 0;
  bool done_ = false;
  bool ended_by_m2_ = false;
  bool seen_content_ = false;
  bool seen_percent_ = false;
  bool percent_closed_ = false;
};

Vec3 clamp_to_travel(const Vec3& p, const MachineConfig& c) {
  Vec3 r = p;
  for (int i = 0; i < kAxes; ++i) {
    const auto k = static_cast<std::size_t>(i);
    r[k] = std::clamp(p[k], c.axes[k].travel_min_mm, c.axes[k].travel_max_mm);
  }
  return r;
}

JobFrame make_frame(const MachineConfig& config, const JobOptions& options, const Transform& t) {
  JobFrame f;
  f.offset = t.offset;
  f.scale = t.scale;
  f.work_offset_index = std::clamp(options.work_offset_index, 0, 5);
  f.start = options.start_position ? *options.start_position : clamp_to_travel(t.offset, config);
  f.contouring = options.contouring ? *options.contouring : config.motion.contouring_default;
  return f;
}

struct Input {
  const std::string* path = nullptr;
  std::string_view text;
  std::unique_ptr<LineReader> open() const {
    if (path) return std::make_unique<LineReader>(*path);
    return std::make_unique<LineReader>(LineReader::FromText{}, text);
  }
};

struct PassResult {
  std::uint64_t lines = 0;
  std::uint64_t moves = 0;
  Box all;
  Box fit;
  Vec3 last{};
  double feed_time = 0.0;
};

PassResult run_pass(const Input& in, const MachineConfig& config, const JobFrame& frame, DiagnosticSink& sink,
                    bool limits) {
  std::unique_ptr<LineReader> reader = in.open();
  MoveSource source(*reader, config, frame, sink);
  Preflight pre(config, sink, limits);
  Move m;
  while (source.next(m)) pre.add(m);
  source.check_trailing();
  pre.finish();
  PassResult r;
  r.lines = source.lines();
  r.moves = pre.moves();
  r.all = pre.extents();
  r.fit = pre.fit_extents();
  r.last = pre.moves() > 0 ? pre.last_point() : frame.start;
  r.feed_time = pre.feed_time_s();
  return r;
}

CheckResult check_input(const Input& in, const std::string& name, const MachineConfig& config,
                        const JobOptions& options) {
  CheckResult result;
  DiagnosticSink sink(name);
  try {
    Transform t;
    t.offset = options.offset ? *options.offset : config.gcode.work_offsets[0];
    if (options.fit) {
      DiagnosticSink scratch(name);
      const PassResult a = run_pass(in, config, make_frame(config, options, t), scratch, false);
      const FitResult f = fit_to_travel(a.fit, t.offset, config);
      t.offset = f.offset;
      t.scale = f.scale;
      if (options.offset)
        sink.warning(0, 0, "fit-offset", "--fit recentres the program: the --offset value is not used");
    }
    const PassResult b = run_pass(in, config, make_frame(config, options, t), sink, true);
    result.transform = t;
    result.lines = b.lines;
    result.moves = b.moves;
    if (b.moves > 0) {
      result.min_point = b.all.min;
      result.max_point = b.all.max;
    } else {
      result.min_point = result.max_point = b.last;
    }
    result.last_point = b.last;
    result.feed_length_time_s = b.feed_time;
  } catch (const std::exception& e) {
    sink.error(0, 0, e.what());
  }
  result.ok = !sink.has_errors();
  result.diagnostics = sink.take();
  return result;
}

}  // namespace

bool is_null_move(const Move& m) {
  return (m.kind == MoveKind::kRapid || m.kind == MoveKind::kLine) && norm(m.end - m.start) <= 1e-12;
}

CheckResult check_program(const std::string& path, const MachineConfig& config, const JobOptions& options) {
  Input in;
  in.path = &path;
  return check_input(in, path, config, options);
}

CheckResult check_program_text(std::string_view text, const std::string& name, const MachineConfig& config,
                               const JobOptions& options) {
  Input in;
  in.text = text;
  return check_input(in, name, config, options);
}

struct BlockStream::Impl {
  Impl(std::unique_ptr<LineReader> r, const std::string& name, const MachineConfig& c, const JobFrame& frame)
      : reader(std::move(r)),
        config(c),
        sink(name),
        source(*reader, config, frame, sink),
        merger(c.motion.corner_tolerance_mm),
        pull([this](Move& m) {
          do {
            if (!source.next(m)) return false;
          } while (is_null_move(m));
          return true;
        }) {}
  std::unique_ptr<LineReader> reader;
  MachineConfig config;  // a copy: the stream may outlive the caller's config (or a temporary)
  DiagnosticSink sink;
  MoveSource source;
  SegmentMerger merger;  // runs of collinear G1 moves under M21 -> one line (tolerance 0: off)
  std::function<bool(Move&)> pull;  // the interpreter's moves without the null ones
  std::vector<Block> nurbs;  // the blocks of the NURBS move being streamed (one curve at a time)
  std::size_t nurbs_next = 0;
};

BlockStream::BlockStream(const std::string& path, const MachineConfig& config, const JobOptions& options,
                         const Transform& transform)
    : impl_(std::make_unique<Impl>(std::make_unique<LineReader>(path), path, config,
                                   make_frame(config, options, transform))) {}

BlockStream::BlockStream(FromText, std::string_view text, const std::string& name, const MachineConfig& config,
                         const JobOptions& options, const Transform& transform)
    : impl_(std::make_unique<Impl>(std::make_unique<LineReader>(LineReader::FromText{}, text), name, config,
                                   make_frame(config, options, transform))) {}

BlockStream::~BlockStream() = default;
BlockStream::BlockStream(BlockStream&&) noexcept = default;
BlockStream& BlockStream::operator=(BlockStream&&) noexcept = default;

bool BlockStream::next(Block& out) {
  if (impl_->nurbs_next < impl_->nurbs.size()) {
    out = impl_->nurbs[impl_->nurbs_next++];
    return true;
  }
  Move m;
  if (!impl_->merger.next(impl_->pull, m)) return false;
  if (impl_->sink.has_errors()) {
    const std::vector<Diagnostic> d = impl_->sink.take();
    throw std::runtime_error(format_diagnostic(d.front()) + " (the program changed since it was checked?)");
  }
  if (m.kind == MoveKind::kNurbs) {
    NurbsMoveBlocks nb = plan_nurbs_move(m, impl_->config);
    if (!nb.error.empty() || nb.blocks.empty()) {
      throw std::runtime_error("line " + std::to_string(m.line) + ": NURBS curve could not be planned: " +
                               (nb.error.empty() ? std::string("no blocks") : nb.error));
    }
    impl_->nurbs = std::move(nb.blocks);
    impl_->nurbs_next = 1;
    out = impl_->nurbs.front();
    return true;
  }
  make_block_into(m, impl_->config, out);
  return true;
}

std::uint64_t BlockStream::lines_read() const { return impl_->reader->line_number(); }
std::uint64_t BlockStream::total_bytes() const { return impl_->reader->total_bytes(); }
std::uint64_t BlockStream::bytes_read() const { return impl_->reader->bytes_read(); }

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
      add(" ");
      pt(b.start);
      add("->");
      pt(b.end);
      add(" len=%.4f class=%s v=%.3f a=%.1f drive=%c%c vd=%.3f ad=%.1f dec=%.4f t0=", c(b.length, 1e4),
          to_string(b.motion_class), c(b.speed, 1e3), c(b.accel, 1e1), axis_name(b.driving_axis),
          b.driving_dir < 0 ? '-' : '+', c(b.driving_speed, 1e3), c(b.driving_accel, 1e1), c(b.decel_start, 1e4));
      pt(b.dir_start);
      add(" t1=");
      pt(b.dir_end);
      add(" m21=%d", static_cast<int>(b.contouring));
      if (b.kind == BlockKind::kNurbs) {
        add(" degree=%d points=%d knots=[", static_cast<int>(b.nurbs.degree), static_cast<int>(b.nurbs.point_count));
        for (int k = 0; k < b.nurbs.knot_count && k < kMaxNurbsKnots; ++k) add(k ? " %.6g" : "%.6g", b.nurbs.knots[k]);
        add("] schedule=%d", static_cast<int>(b.nurbs.schedule_count));
      }
      if (b.kind == BlockKind::kArc) {
        add(" center=");
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
      add(b.optional_stop ? " optional (M1) at " : " (M0) at ");
      pt(b.end);
      break;
    case BlockKind::kEnd:
      add(" at ");
      pt(b.end);
      break;
  }
  return std::string(buf, n > 0 ? std::min<std::size_t>(static_cast<std::size_t>(n), sizeof buf - 1) : 0);
}

}  // namespace pcnc
