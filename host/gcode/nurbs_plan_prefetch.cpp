// nurbs_plan_prefetch.cpp — curve plans made ahead on a worker thread (see nurbs_plan_prefetch.hpp).
#include "gcode/nurbs_plan_prefetch.hpp"

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>

#include "gcode/nurbs_plan_key.hpp"

namespace pcnc {
namespace {

enum class State { kQueued, kPlanning, kDone };

struct Job {
  std::uint64_t hash = 0;
  NurbsPlanKey key;
  State state = State::kQueued;
  NurbsBlocks plan;
};

// The registry and its worker. Jobs are kept in arrival order; the worker plans the oldest
// queued one. A process-lifetime object: the worker is detached at exit rather than joined
// (static destruction order), and holds no resource but memory.
class Prefetcher {
 public:
  void submit(const NurbsCurve& curve, const NurbsLimits& limits) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (jobs_.size() >= kPrefetchEntries) {
      // drop the oldest entry nobody asked for and nobody is planning
      auto it = jobs_.begin();
      while (it != jobs_.end() && (*it)->state == State::kPlanning) ++it;
      if (it == jobs_.end()) return;
      jobs_.erase(it);
    }
    auto job = std::make_shared<Job>();
    job->hash = plan_input_hash(curve, limits);
    job->key = NurbsPlanKey{curve, limits};
    jobs_.push_back(std::move(job));
    if (!started_) {
      started_ = true;
      std::thread([this] { work(); }).detach();
    }
    lock.unlock();
    wake_.notify_one();
  }

  std::optional<NurbsBlocks> take(const NurbsCurve& curve, const NurbsLimits& limits) {
    const std::uint64_t h = plan_input_hash(curve, limits);
    std::unique_lock<std::mutex> lock(mutex_);
    for (auto it = jobs_.begin(); it != jobs_.end(); ++it) {
      const std::shared_ptr<Job> job = *it;
      if (job->hash != h || !same_plan_input(job->key, curve, limits)) continue;
      if (job->state == State::kQueued) {  // not started: the caller plans it
        jobs_.erase(it);
        ++stats_.reclaimed;
        return std::nullopt;
      }
      done_.wait(lock, [&] { return job->state == State::kDone; });
      for (auto jt = jobs_.begin(); jt != jobs_.end(); ++jt) {
        if (*jt == job) {
          jobs_.erase(jt);
          break;
        }
      }
      ++stats_.taken;
      return std::move(job->plan);
    }
    return std::nullopt;
  }

  PrefetchStats stats() {
    std::lock_guard<std::mutex> lock(mutex_);
    return stats_;
  }

 private:
  void work() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      std::shared_ptr<Job> job;
      wake_.wait(lock, [&] {
        for (const auto& j : jobs_) {
          if (j->state == State::kQueued) {
            job = j;
            return true;
          }
        }
        return false;
      });
      job->state = State::kPlanning;
      lock.unlock();
      NurbsBlocks plan = plan_nurbs_blocks(job->key.curve, job->key.limits);
      plan.schedule = FeedSchedule{};  // the pipeline keeps the blocks only
      lock.lock();
      job->plan = std::move(plan);
      job->state = State::kDone;
      ++stats_.planned;
      done_.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::deque<std::shared_ptr<Job>> jobs_;
  bool started_ = false;
  PrefetchStats stats_;
};

Prefetcher& prefetcher() {
  static Prefetcher* p = new Prefetcher();  // never destroyed: its detached worker may outlive main
  return *p;
}

}  // namespace

void prefetch_plan(const NurbsCurve& curve, const NurbsLimits& limits) { prefetcher().submit(curve, limits); }

std::optional<NurbsBlocks> take_prefetched(const NurbsCurve& curve, const NurbsLimits& limits) {
  return prefetcher().take(curve, limits);
}

PrefetchStats prefetch_stats() { return prefetcher().stats(); }

}  // namespace pcnc
