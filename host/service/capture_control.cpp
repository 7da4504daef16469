// capture_control.cpp — capture threads draining the rt's scope ring (see capture_control.hpp).
#include "service/capture_control.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include "service/scope_recorder.hpp"

namespace pcnc {

using rpc::json;

namespace {
constexpr auto kDrainEvery = std::chrono::milliseconds(5);  // 10 cycles; the ring holds kScopeSlots (2048)

double round_to(double v, double step) { return std::round(v / step) * step; }
}  // namespace

json capture_result(const ScopeRecorder& rec, const CaptureParams& p, double cycle_hz) {
  const auto& rows = rec.rows();
  json names = json::array();
  json columns = json::object();
  json t = json::array();
  for (const TraceSample& s : rows) t.push_back(round_to(s.t, 1e-4));
  columns["t"] = std::move(t);
  for (int i : p.signals) {
    const std::string& name = scope_signal_names()[static_cast<std::size_t>(i)];
    names.push_back(name);
    json col = json::array();
    const bool exact = name == "line" || name == "state";
    for (const TraceSample& s : rows) {
      const double v = scope_signal_value(s, i);
      col.push_back(exact ? v : round_to(v, name == "speed" ? 1e-5 : 1e-7));
    }
    columns[name] = std::move(col);
  }
  const std::size_t trig_row = rows.empty() ? 0 : rec.pre_rows();
  json r = {{"signals", names},
            {"rows", rows.size()},
            {"period_s", 1.0 / cycle_hz},
            {"trigger", p.trigger ? json(p.trigger->text) : json(nullptr)},
            {"pre_rows", rec.pre_rows()},
            {"trigger_row", trig_row},
            {"t_trigger_s", rows.empty() ? 0.0 : round_to(rows[trig_row].t, 1e-4)},
            {"first_sample", rec.first_sample()},
            {"lost", 0},
            {"columns", std::move(columns)}};
  if (p.trigger) r["t_armed_s"] = round_to(rec.armed_t(), 1e-4);
  return r;
}

std::uint64_t drain_scope(const ScopeRing<kScopeSlots>& ring, std::uint64_t next, ScopeRecorder& rec) {
  const std::uint64_t w = ring.written();
  if (w > next + kScopeSlots) {  // lapped: those samples are overwritten already
    rec.lost(next, w - kScopeSlots - next, "the host read more than " + std::to_string(kScopeSlots) + " cycles behind the rt");
    return w;
  }
  for (; next < w && !rec.finished(); ++next) {
    TraceSample s;
    const ScopeRead r = ring.read(next, s);
    if (r == ScopeRead::kNotYet) break;
    if (r == ScopeRead::kLost) {
      rec.lost(next, 1, "overwritten while the host read it");
      break;
    }
    rec.feed(next, s);
  }
  return next;
}

struct CaptureControl::Capture {
  ClientId client = 0;
  json id;
  std::shared_ptr<RtLink> link;
  CaptureParams params;
  std::uint64_t first = 0;  // the rt's first sample after the request
  std::atomic<bool> cancel{false}, done{false};
  std::thread thread;
};

CaptureControl::CaptureControl(double cycle_hz, Reply reply) : cycle_hz_(cycle_hz), reply_(std::move(reply)) {}

CaptureControl::~CaptureControl() { cancel_all(); }

void CaptureControl::cancel_all() {
  std::lock_guard lock(mutex_);
  for (auto& c : captures_) c->cancel = true;
  for (auto& c : captures_) {
    if (c->thread.joinable()) c->thread.join();
  }
  captures_.clear();
}

std::size_t CaptureControl::active() const {
  std::lock_guard lock(mutex_);
  return static_cast<std::size_t>(std::count_if(captures_.begin(), captures_.end(), [](const auto& c) { return !c->done; }));
}

void CaptureControl::reap() {
  for (auto it = captures_.begin(); it != captures_.end();) {
    if ((*it)->done) {
      if ((*it)->thread.joinable()) (*it)->thread.join();
      it = captures_.erase(it);
    } else {
      ++it;
    }
  }
}

void CaptureControl::client_gone(ClientId client) {
  std::lock_guard lock(mutex_);
  for (auto& c : captures_) {
    if (c->client == client) c->cancel = true;
  }
}

Outcome CaptureControl::start(ClientId client, const json& id, std::shared_ptr<RtLink> link, const Status& status,
                              const CaptureParams& params) {
  if (status.clock_virtual) {
    return Outcome::fail(refused("capture needs pcnc-rt on the real clock: under --clock virtual the rt runs faster than "
                                 "real time and no host can read every cycle"));
  }
  std::lock_guard lock(mutex_);
  reap();
  if (captures_.size() >= kMaxCaptures) {
    return Outcome::fail(refused(std::to_string(kMaxCaptures) + " captures are recording; try again when one has ended"));
  }
  auto cap = std::make_unique<Capture>();
  cap->client = client;
  cap->id = id;
  cap->link = std::move(link);
  cap->params = params;
  cap->first = cap->link->shm().scope.written();
  Capture* c = cap.get();
  const double hz = cycle_hz_;
  const Reply reply = reply_;
  c->thread = std::thread([c, hz, reply] {
    auto finish = [&](Outcome o) {
      c->link.reset();  // a finished capture holds no link (nor the old rt's segment) until reaped
      if (!c->cancel) reply(c->client, c->id, std::move(o));
      c->done = true;
    };
    ScopeRecorder rec(c->params, hz);
    const auto& ring = c->link->shm().scope;
    std::uint64_t next = c->first;
    const auto t0 = std::chrono::steady_clock::now();
    while (!c->cancel) {
      std::this_thread::sleep_for(kDrainEvery);
      if (!c->link->rt_alive()) {
        return finish(Outcome::fail(rpc::Error{rpc::kRtUnavailable, "pcnc-rt was lost during the capture: " +
                                                                        c->link->rt_loss_reason(), nullptr}));
      }
      next = drain_scope(ring, next, rec);
      if (rec.phase() == ScopeRecorder::Phase::kDone) {
        return finish(Outcome::ok(capture_result(rec, c->params, hz)));
      }
      if (rec.phase() == ScopeRecorder::Phase::kFailed) {
        spdlog::warn("capture: {}", rec.failure());
        return finish(Outcome::fail(rpc::Error{rpc::kInternalError, rec.failure(), json{{"lost", true}}}));
      }
      const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const bool waiting = rec.phase() == ScopeRecorder::Phase::kFilling || rec.phase() == ScopeRecorder::Phase::kArmed;
      if (waiting && waited > c->params.trigger_timeout_s) {
        char buf[160];
        if (rec.armed_min() <= rec.armed_max()) {
          std::snprintf(buf, sizeof buf, " (while armed it ranged over [%g, %g])", rec.armed_min(), rec.armed_max());
        } else {
          buf[0] = '\0';
        }
        char within[48];
        std::snprintf(within, sizeof within, "%g s", c->params.trigger_timeout_s);
        return finish(Outcome::fail(refused("the trigger '" + c->params.trigger->text + "' did not hold within " + within + buf)));
      }
    }
    c->link.reset();
    c->done = true;  // cancelled: the client left, or the service ends
  });
  captures_.push_back(std::move(cap));
  return Outcome::later();
}

}  // namespace pcnc
