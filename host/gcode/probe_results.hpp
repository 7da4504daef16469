// probe_results.hpp — what the front end knows of a program's probing moves (G38.2-G38.5,
// docs/probe.md): the results of the first ones, as the rt reported them, and what to do at the
// first one beyond them. A probing move ends where the probe stopped, which nothing can know
// before it runs, so every probing move is a sync point: `pcnc check` checks the rest assuming
// contact at the commanded end (and says so); a run streams the program up to the probing move,
// waits for the rt's result, and interprets the program again with it (host/service/job_runner).
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/vec3.hpp"
#include "ipc/status.hpp"

namespace pcnc {

struct ProbeResult {
  ProbeOutcome outcome = ProbeOutcome::kContact;
  Vec3 latched{};  // machine mm: where the input changed (kContact), else where the move ended
  Vec3 stop{};     // machine mm: where the probing move came to rest
};

struct ProbeResults {
  std::vector<ProbeResult> known;  // of the program's 1st, 2nd, ... probing moves as executed
  // Run: the stream ends after the first probing move beyond `known` (BlockStream::probe_sync).
  // Check (false): that move and any later are assumed to touch at their commanded end.
  bool stop_at_unknown = false;
  // A streamed program (the grbl port's lines, which arrive one by one and are answered as they
  // pass): no sync point is possible, so a probing move beyond `known` is an error.
  bool refuse_unknown = false;
};

}  // namespace pcnc
