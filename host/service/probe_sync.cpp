// probe_sync.cpp — the run's sync points at probing moves (probe_sync.hpp).
#include "service/probe_sync.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

namespace pcnc {

ProbeSync::ProbeSync(RtLink& link, const MachineConfig& config, std::string path, const JobOptions& options,
                     const Transform& transform)
    : link_(link), config_(config), path_(std::move(path)), options_(options), transform_(transform) {
  results_ = std::make_shared<ProbeResults>();
  if (options.probe) *results_ = *options.probe;  // a resumed program's results, from the journal
  results_->stop_at_unknown = true;
  probe_count_at_start_ = link_.status().probe_count;
  open_stream();
}

ProbeSync::ProbeSync(RtLink& link, const MachineConfig& config, FromText, std::string text, std::string name,
                     const JobOptions& options, const Transform& transform)
    : link_(link), config_(config), path_(std::move(name)), from_text_(true), text_(std::move(text)), options_(options),
      transform_(transform) {
  results_ = std::make_shared<ProbeResults>();
  if (options.probe) *results_ = *options.probe;
  results_->stop_at_unknown = true;
  probe_count_at_start_ = link_.status().probe_count;
  open_stream();
}

void ProbeSync::open_stream() {
  JobOptions o = options_;
  o.probe = std::make_shared<const ProbeResults>(*results_);
  messages_seen_ = 0;
  if (options_.on_message) {
    // the messages of the lines before the sync point were shown by the stream before
    o.on_message = [this](const ProgramMessage& m) {
      if (++messages_seen_ > messages_shown_) {
        messages_shown_ = messages_seen_;
        options_.on_message(m);
      }
    };
  }
  stream_ = from_text_ ? std::make_unique<BlockStream>(BlockStream::FromText{}, text_, path_, config_, o, transform_)
                      : std::make_unique<BlockStream>(path_, config_, o, transform_);
}

bool ProbeSync::next(Block& out) {
  while (stream_->next(out)) {
    if (out.seq <= skip_through_) continue;  // sent before the last sync point
    last_seq_ = out.seq;
    return true;
  }
  return false;
}

std::string ProbeSync::resume(const std::atomic<bool>& interrupt, bool& more) {
  more = false;
  if (!stream_->probe_sync()) return "";
  // Everything up to the probing block is sent: wait for its result.
  const std::uint64_t expected = probe_count_at_start_ + 1;
  Status s;
  const auto t0 = std::chrono::steady_clock::now();
  bool seen_active = false;  // the rt may not have taken the program start yet
  for (;;) {
    s = link_.status();
    if (s.probe_count >= expected && s.probe_seq + seq_base_ == last_seq_) break;
    seen_active = seen_active || s.program_active;
    const bool idle = !s.program_active && s.state == MachineState::kIdle &&
                      (seen_active || std::chrono::steady_clock::now() - t0 > std::chrono::seconds(2));
    if (s.state == MachineState::kFault || s.state == MachineState::kEstop || s.state == MachineState::kHostLost || idle) {
      return "";  // the program ended otherwise (a fault, a stop): the runner reports it
    }
    if (interrupt.load() || !link_.rt_alive()) return "";
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // status follow-up, not the ring path
  }
  ProbeResult r;
  r.outcome = s.probe_outcome;
  r.latched = s.probe_latched;
  r.stop = s.probe_stop;
  if (const std::string why = write_log(r); !why.empty()) return why;
  results_->known.push_back(r);
  probe_count_at_start_ = s.probe_count;  // the next result is the one after this
  if (on_result_) on_result_(*results_);

  // The rest of the program with this result, checked before any of it moves.
  JobOptions check_options = options_;
  auto known = std::make_shared<ProbeResults>(*results_);
  known->stop_at_unknown = false;
  check_options.probe = known;
  check_options.on_message = nullptr;
  const CheckResult check = from_text_ ? check_program_text(text_, path_, config_, check_options)
                                       : check_program(path_, config_, check_options);
  if (!check.ok) {
    for (const Diagnostic& d : check.diagnostics) {
      if (d.severity == Diagnostic::Severity::kError) return format_diagnostic(d);
    }
    return "the program cannot go on after the probing move at line " + std::to_string(s.probe_line);
  }
  skip_through_ = last_seq_;
  open_stream();
  more = true;
  return "";
}

std::string ProbeSync::write_log(const ProbeResult& r) {
  const std::string name = stream_->probe_log();
  if (name.empty()) return "";
  std::filesystem::path file(name);
  if (file.is_relative() && !from_text_) file = std::filesystem::path(path_).parent_path() / file;
  const bool first = logs_written_.insert(file.string()).second && !resumed_;
  return write_probe_log(*stream_, from_text_ ? std::string() : path_, r, first);
}

// LinuxCNC's probe log: one line per probing move, "%f %f %f %f %f %f %f %f %f" (X Y Z A B C U V W
// of the probed point in the work coordinates and units), to the file (PROBEOPEN name) opened.
std::string write_probe_log(const BlockStream& stream, const std::string& program_path, const ProbeResult& r,
                            bool truncate) {
  const std::string name = stream.probe_log();
  if (name.empty()) return "";
  namespace fs = std::filesystem;
  fs::path file(name);
  if (file.is_relative() && !program_path.empty()) file = fs::path(program_path).parent_path() / file;
  std::FILE* f = std::fopen(file.c_str(), truncate ? "w" : "a");
  if (!f) return "cannot write the probe log " + file.string() + " (PROBEOPEN)";
  const Vec3 p = stream.to_program(r.latched);
  std::fprintf(f, "%f %f %f %f %f %f %f %f %f\n", p[0], p[1], p[2], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  const bool ok = std::fclose(f) == 0;
  return ok ? "" : "cannot write the probe log " + file.string() + " (PROBEOPEN)";
}

}  // namespace pcnc
