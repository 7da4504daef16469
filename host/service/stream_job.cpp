// stream_job.cpp — the streamed program of the grbl port (JobControl::stream_open and
// friends, see job_control.hpp): a LineFeed the front end appends lines to, read by the one
// pipeline (BlockStream::FromFeed) while the ring feeder sends its blocks, so the look-ahead
// works over the lines already received and the motion is continuous while the sender keeps
// its buffer full. Each line is acknowledged (a `stream` event with `done`, the number of lines
// the pipeline is done with) when the pipeline asks for the next one; the first error ends the
// stream at once (a `stream` event with `error`), the blocks before it still run. Check mode
// runs the lines through every stage and the rt's block check, with no motion.
#include <spdlog/spdlog.h>

#include <algorithm>

#include "service/job_control.hpp"
#include "service/work_store.hpp"

namespace pcnc {

using rpc::json;

Outcome JobControl::stream_open(ClientId client, const json& id, bool check, std::shared_ptr<RtLink> link, const Status& st,
                                const MachineConfig& config, const WorkState& work) {
  if (Outcome no = refuse_start(st); no.error) return no;
  MachineConfig job_config = config;
  job_config.gcode.work_offsets = first_six(work.g5x);
  auto feed = std::make_shared<LineFeed>();
  std::uint64_t n = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    feed_ = feed;
    n = ++streams_;
  }
  start_worker(client, id, [this, client, id, check, feed, n, link, job_config, ws = work, start = st.commanded] {
    replied_ = true;  // the reply is stream_open's own, at once: the stream's lines follow it
    stream_job(client, id, check, feed, n, link, job_config, ws, start);
  });
  return Outcome::ok(json{{"started", true}, {"stream", n}, {"check", check}});
}

Outcome JobControl::stream_lines(const std::string& text) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!feed_ || feed_->closed()) return Outcome::fail(refused("no stream is open: stream_open first"));
  const std::size_t lines = feed_->append(text);
  return Outcome::ok(json{{"stream", streams_}, {"lines", feed_->lines_appended()}, {"appended", lines}});
}

Outcome JobControl::stream_close() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!feed_ || feed_->closed()) return Outcome::ok(json{{"closed", false}, {"note", "no stream is open"}});
  feed_->close();
  return Outcome::ok(json{{"stream", streams_}, {"closed", true}, {"lines", feed_->lines_appended()}});
}

void JobControl::stream_job(ClientId client, const json& id, bool check, std::shared_ptr<LineFeed> feed, std::uint64_t n,
                            std::shared_ptr<RtLink> l, const MachineConfig& cfg, const WorkState& ws, const Vec3& start) {
  const std::string name = check ? "stream-check" : "stream";
  JobOptions opts;
  if (!cfg.gcode.tool_table.empty()) {
    if (const std::string why = load_job_state(cfg, cfg.gcode.tool_table, opts); !why.empty()) {
      feed->close();
      notices_.event(json{{"event", "stream"}, {"stream", n}, {"done", 0}, {"end", true},
                          {"error", {{"line", 0}, {"column", 0}, {"message", why}, {"text", why}}}});
      end_job(nullptr);
      return;
    }
  }
  opts.work = ws;
  opts.work_offset_index = ws.active;
  opts.start_position = start;
  if (l) opts.start_rotary = l->status().rot_commanded;
  if (!check) {  // a probing move cannot be a sync point in a stream (docs/probe.md)
    auto probe = std::make_shared<ProbeResults>();
    probe->refuse_unknown = true;
    opts.probe = probe;
  }
  opts.on_message = [this, n](const ProgramMessage& m) {
    notices_.event(json{{"event", "message"}, {"file", "stream"}, {"stream", n}, {"line", m.line}, {"text", m.text}});
  };
  {
    std::lock_guard<std::mutex> lock(mutex_);
    info_ = json{{"file", name}, {"phase", "running"}, {"stream", n}, {"check", check}};
  }
  auto stream = std::make_shared<BlockStream>(BlockStream::FromFeed{}, feed, name, cfg, opts);
  // A line is done once the pipeline asks for the next one without having found an error;
  // after an error the pipeline would read on for more diagnostics: the input ends there.
  // Called on this thread, from inside stream->next().
  feed->set_on_done([this, n, s = stream.get()](std::uint64_t done) {
    if (s->failed()) return false;  // the stream ends at its error
    notices_.event(json{{"event", "stream"}, {"stream", n}, {"done", done}});
    return true;
  });
  // The end of the stream's input (or its error), said once, as soon as the pipeline knows.
  auto ended = [this, n, stream, feed] {
    feed->close();
    // Ended by the program itself (M2/M30): its last line read is done too; lines after it
    // were not read (a sender's next lines start a new stream).
    const std::uint64_t done = stream->error() ? feed->done() : std::max<std::uint64_t>(feed->done(), stream->lines_read());
    json ev = {{"event", "stream"}, {"stream", n}, {"done", done}, {"end", true}};
    if (const auto& e = stream->error()) {
      ev["error"] = json{{"line", e->line}, {"column", e->column}, {"message", e->message}, {"text", format_diagnostic(*e)}};
      spdlog::warn("stream {}: {}", n, format_diagnostic(*e));
    }
    notices_.event(ev);
  };
  if (check) {
    Block b;
    std::uint64_t blocks = 0;
    while (!interrupt_.load() && stream->next(b)) ++blocks;
    ended();
    const json last = {{"file", name}, {"end", stream->error() ? "error" : "checked"}, {"blocks_checked", blocks}};
    end_job(&last);
    return;
  }
  stream_blocks_ = 0;
  BlockSource source;
  source.next = [this, stream, ended](Block& b) {
    if (stream->next(b)) {
      ++stream_blocks_;
      return true;
    }
    ended();
    return false;
  };
  source.progress = [stream] { return JobProgress{stream->lines_read(), stream->bytes_read(), 0, Status{}}; };
  json started = {{"started", true}, {"stream", n}, {"check", false}};
  follow_job(
      client, id, l, cfg, started, name,
      [&](JobRunner& runner) {
        runner.set_staging(false);  // the pipeline may wait for lines: nothing it made may wait with it
        return runner.run_source(source, cfg.motion.contouring_default, interrupt_, progress_fn());
      },
      &ws, [stream](const JobRunner&) { return std::optional<WorkState>(stream->work_state()); });
  feed->close();
  std::lock_guard<std::mutex> lock(mutex_);
  if (feed_ == feed) feed_.reset();
}

}  // namespace pcnc
