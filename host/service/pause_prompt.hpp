// pause_prompt.hpp — `pcnc-host --run --pauses ask`: at one of the program's pauses (M0/M1)
// the job runner asks the launcher over the progress channel (progress_update.hpp: "pause
// LINE M0" out, "resume" or "stop" back) and waits for the operator's answer. The machine
// stands at rest on the path meanwhile.
//
// May include: job_runner.hpp, progress_update.hpp.
#pragma once

#include <atomic>

#include "service/job_runner.hpp"

namespace pcnc {

/// Writes the request to `fd` (non-blocking, a stream socket) and waits for the answer: true
/// for "resume"; false for "stop", a channel that closed or failed, or `interrupt` raised.
bool ask_over_progress_channel(int fd, const PauseAt& at, const std::atomic<bool>& interrupt);

}  // namespace pcnc
