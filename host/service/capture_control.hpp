// capture_control.hpp — the scope's captures (`capture`, docs/protocol.md): each one a thread
// that drains the rt's flight recorder (ipc/scope_ring.hpp) into a ScopeRecorder every few
// milliseconds, and replies, later, with the record or with why there is none (the samples
// were lost because the host read too slowly, the trigger did not come in time, the rt was
// lost, the client left). The rt never knows a capture runs: it writes its ring every cycle
// either way, so a capture cannot disturb its timing or the program.
//
// At most kMaxCaptures run at once (memory is bounded: each record at most
// kMaxCaptureValues values). Loop thread: start, client_gone; the reply comes through the
// callback from the capture's thread (the service posts it to the loop).
//
// May include: rt_link.hpp, outcome.hpp, scope_recorder.hpp, control_server.hpp (ClientId).
#pragma once

#include <functional>
#include <list>
#include <memory>
#include <mutex>

#include "service/control_server.hpp"
#include "service/outcome.hpp"
#include "service/rt_link.hpp"
#include "service/scope_signals.hpp"

namespace pcnc {

class CaptureControl {
 public:
  static constexpr std::size_t kMaxCaptures = 4;
  using Reply = std::function<void(ClientId, rpc::json id, Outcome)>;

  CaptureControl(double cycle_hz, Reply reply);
  ~CaptureControl();  // cancels and joins every capture (no reply)
  CaptureControl(const CaptureControl&) = delete;
  CaptureControl& operator=(const CaptureControl&) = delete;

  /// Starts a capture for `client`; Outcome::later() (the reply comes when it ends), or a
  /// refusal (virtual clock, too many captures).
  Outcome start(ClientId client, const rpc::json& id, std::shared_ptr<RtLink> link, const Status& status,
                const CaptureParams& params);
  /// The client disconnected: its captures end without a reply.
  void client_gone(ClientId client);
  /// Ends every capture without a reply and joins their threads (service shutdown).
  void cancel_all();
  /// Captures recording now.
  std::size_t active() const;

 private:
  struct Capture;
  void reap();
  const double cycle_hz_;
  Reply reply_;
  mutable std::mutex mutex_;
  std::list<std::unique_ptr<Capture>> captures_;
};

/// One turn of a capture's thread: feeds `rec` the samples from `next` up to what the rt has
/// written, or tells it which were lost (lapped: more than kScopeSlots behind, or overwritten
/// during the copy). Returns the next sample to read. Pure of threads, for tests.
std::uint64_t drain_scope(const ScopeRing<kScopeSlots>& ring, std::uint64_t next, class ScopeRecorder& rec);

/// The record as the `capture` result: signals, rows, period, trigger and its row, and the
/// columns (t and each signal) rounded as the trace writes them. Pure, for tests.
rpc::json capture_result(const class ScopeRecorder& rec, const CaptureParams& params, double cycle_hz);

}  // namespace pcnc
