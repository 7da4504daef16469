// hand_over_memo.hpp — the bounded store behind the front end's memos (nurbs_plan_memo,
// spline_fit_memo): what the check pass computed, handed over once to the stream pass of the
// same process. An entry is found by a hash (a sieve) and the caller's full comparison, and is
// removed when taken; past the byte cap the store is emptied rather than grown. Thread-safe.
//
// May include: the standard library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <utility>

namespace pcnc {

/// What a memo holds now (entries, bytes) and has done (hits, misses): for tests.
struct MemoStats {
  std::size_t entries = 0, bytes = 0, hits = 0, misses = 0;
};

/// FNV-1a: `h` starts at kFnv1aSeed; each call mixes `n` bytes at `p` into it.
inline constexpr std::uint64_t kFnv1aSeed = 1469598103934665603ull;
inline void fnv1a_mix(std::uint64_t& h, const void* p, std::size_t n) {
  const auto* b = static_cast<const unsigned char*>(p);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
}

template <class Entry>
class HandOverMemo {
 public:
  explicit HandOverMemo(std::size_t cap_bytes) : cap_(cap_bytes) {}

  /// The entry under `hash` for which `same(entry)` holds, removed from the memo; else none.
  template <class Same>
  std::optional<Entry> take(std::uint64_t hash, const Same& same) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto [lo, hi] = slots_.equal_range(hash);
    for (auto it = lo; it != hi; ++it) {
      if (same(it->second.entry)) {
        std::optional<Entry> out(std::move(it->second.entry));
        bytes_ -= it->second.bytes;
        slots_.erase(it);
        ++hits_;
        return out;
      }
    }
    ++misses_;
    return std::nullopt;
  }

  /// Keeps `entry` (of `bytes`) under `hash`; one larger than the cap is not kept.
  void put(std::uint64_t hash, Entry entry, std::size_t bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (bytes > cap_) return;
    if (bytes_ + bytes > cap_) {
      slots_.clear();
      bytes_ = 0;
    }
    bytes_ += bytes;
    slots_.emplace(hash, Slot{std::move(entry), bytes});
  }

  MemoStats stats() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return {slots_.size(), bytes_, hits_, misses_};
  }

  void clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    slots_.clear();
    bytes_ = hits_ = misses_ = 0;
  }

 private:
  struct Slot {
    Entry entry;
    std::size_t bytes;
  };
  std::size_t cap_;
  mutable std::mutex mutex_;
  std::unordered_multimap<std::uint64_t, Slot> slots_;
  std::size_t bytes_ = 0, hits_ = 0, misses_ = 0;
};

}  // namespace pcnc
