// scope_recorder.hpp — one capture's record, pure: fed the rt's samples in order (sample
// number and value), it keeps the pre-trigger in a circular buffer, arms the trigger once
// that is full, and records until the record is complete, like halscope: with a trigger the
// record is `pre` samples before the trigger sample, the trigger sample, and the rest after
// it; without one it starts with the first sample fed. A sample number that skips one (the
// host read too slowly and the rt's ring lapped it) ends the capture as failed: a record
// never has a gap.
//
// May include: scope_signals.hpp, shared/ipc.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ipc/trace_format.hpp"
#include "service/scope_signals.hpp"

namespace pcnc {

class ScopeRecorder {
 public:
  enum class Phase { kFilling, kArmed, kRecording, kDone, kFailed };

  ScopeRecorder(const CaptureParams& params, double cycle_hz);

  /// Sample number `n` (the rt's count) with its value. Returns the phase after it.
  Phase feed(std::uint64_t n, const TraceSample& s);
  /// Samples from `n` on could not be read (overwritten before the host read them).
  void lost(std::uint64_t n, std::uint64_t count, const std::string& why);

  Phase phase() const { return phase_; }
  bool finished() const { return phase_ == Phase::kDone || phase_ == Phase::kFailed; }
  const std::string& failure() const { return failure_; }

  std::size_t total_rows() const { return total_; }
  std::size_t pre_rows() const { return pre_; }
  /// The record (complete when phase() is kDone): rows_[pre_rows()] is the trigger sample.
  const std::vector<TraceSample>& rows() const { return rows_; }
  std::uint64_t first_sample() const { return first_n_; }   // the first sample fed
  std::uint64_t trigger_sample() const { return trigger_n_; }
  double armed_t() const { return armed_t_; }               // machine time the trigger was armed at
  std::uint64_t samples_fed() const { return fed_; }
  /// The trigger's value (abs() applied) while armed and not holding: its range, for the
  /// message when it never holds (+inf/-inf before any).
  double armed_min() const { return armed_min_; }
  double armed_max() const { return armed_max_; }

 private:
  CaptureParams params_;
  std::size_t total_ = 0, pre_ = 0;
  Phase phase_ = Phase::kFilling;
  std::vector<TraceSample> ring_;  // the pre-trigger, circular
  std::size_t ring_next_ = 0;
  std::vector<TraceSample> rows_;
  std::uint64_t first_n_ = 0, next_n_ = 0, trigger_n_ = 0, fed_ = 0;
  double armed_t_ = 0.0;
  double armed_min_ = 1e300, armed_max_ = -1e300;
  std::string failure_;
};

}  // namespace pcnc
