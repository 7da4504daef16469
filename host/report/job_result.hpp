// job_result.hpp — how one run of a program on the machine ended, as a plain value: the
// end (completed, fault, rt lost, interrupted, stopped), why, the rt's final status, what
// was sent, and the host's slot-refill latency. The job runner (service/job_runner.hpp)
// produces it; the run report and summary (this folder) read it. It lives here, below the
// service, so that report/ includes nothing from service/.
//
// May include: shared/ipc only.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ipc/latency_histogram.hpp"
#include "ipc/status.hpp"

namespace pcnc {

enum class JobEnd { kCompleted, kFault, kRtLost, kInterrupted, kStopped };

inline const char* to_string(JobEnd end) {
  switch (end) {
    case JobEnd::kCompleted: return "completed";
    case JobEnd::kFault: return "fault";
    case JobEnd::kRtLost: return "pcnc-rt lost";
    case JobEnd::kInterrupted: return "interrupted";
    case JobEnd::kStopped: return "stopped";
  }
  return "?";
}

struct JobResult {
  JobEnd end = JobEnd::kCompleted;
  std::string message;    // why, when not completed
  Status final_status{};  // the rt's status at the end
  std::uint64_t blocks_sent = 0;
  std::uint64_t lines_read = 0;
  LatencyHistogram refill_latency;  // host slot-refill latency, µs
  double wall_time_s = 0.0;
  // The program's pauses (M0/M1) the run went on from without a resume command from the
  // control socket (pcnc run --pauses): how many, how (ProgramPauses' name: "continue" or
  // "ask"), and the source lines of the first kMaxPauseLines.
  std::uint64_t pauses = 0;
  std::string pauses_mode;
  std::vector<std::uint32_t> pause_lines;
  static constexpr std::size_t kMaxPauseLines = 32;
};

}  // namespace pcnc
