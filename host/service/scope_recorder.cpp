// scope_recorder.cpp — pre-trigger, trigger and record of one capture (see scope_recorder.hpp).
#include "service/scope_recorder.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {

ScopeRecorder::ScopeRecorder(const CaptureParams& params, double cycle_hz) : params_(params) {
  total_ = static_cast<std::size_t>(std::max(1.0, std::floor(params.seconds * cycle_hz + 0.5)));
  pre_ = params.trigger ? static_cast<std::size_t>(std::floor(params.pre_trigger * static_cast<double>(total_))) : 0;
  if (pre_ >= total_) pre_ = total_ - 1;
  ring_.resize(pre_);
  rows_.reserve(total_);
  phase_ = params.trigger ? (pre_ == 0 ? Phase::kArmed : Phase::kFilling) : Phase::kRecording;
}

void ScopeRecorder::lost(std::uint64_t n, std::uint64_t count, const std::string& why) {
  if (finished()) return;
  phase_ = Phase::kFailed;
  failure_ = "the capture lost " + std::to_string(count) + " sample(s) from the rt's sample " + std::to_string(n) + " on (" +
             why + "); nothing was recorded, try again";
}

ScopeRecorder::Phase ScopeRecorder::feed(std::uint64_t n, const TraceSample& s) {
  if (finished()) return phase_;
  if (fed_ == 0) {
    first_n_ = n;
  } else if (n != next_n_) {
    lost(next_n_, n > next_n_ ? n - next_n_ : 0, "a sample number was skipped");
    return phase_;
  }
  next_n_ = n + 1;
  const std::uint64_t k = fed_++;  // 0-based since the start
  switch (phase_) {
    case Phase::kFilling:
    case Phase::kArmed:
      if (k >= pre_) {
        if (k == pre_) armed_t_ = s.t;
        phase_ = Phase::kArmed;
        double v = scope_signal_value(s, params_.trigger->signal);
        if (params_.trigger->absolute) v = std::fabs(v);
        armed_min_ = std::min(armed_min_, v);
        armed_max_ = std::max(armed_max_, v);
        if (params_.trigger->holds(s)) {
          // the pre-trigger's samples, oldest first, then the trigger sample
          for (std::size_t i = 0; i < pre_; ++i) rows_.push_back(ring_[(ring_next_ + i) % pre_]);
          trigger_n_ = n;
          rows_.push_back(s);
          phase_ = rows_.size() >= total_ ? Phase::kDone : Phase::kRecording;
          return phase_;
        }
      }
      if (pre_ > 0) {
        ring_[ring_next_] = s;
        ring_next_ = (ring_next_ + 1) % pre_;
      }
      return phase_;
    case Phase::kRecording:
      if (rows_.empty()) trigger_n_ = n;  // no trigger: the first sample is t = 0
      rows_.push_back(s);
      if (rows_.size() >= total_) phase_ = Phase::kDone;
      return phase_;
    default:
      return phase_;
  }
}

}  // namespace pcnc
