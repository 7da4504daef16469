// segment.hpp — the shared-memory segment where pcnc-host and pcnc-rt meet (the seed's
// dual-port RAM): header, 4-slot motion ring, command mailbox, status snapshot, and the
// scope's flight recorder of per-cycle samples (scope_ring.hpp).
//
// pcnc-rt creates it (RtSegment) and removes it on a clean exit; pcnc-host opens it
// (HostSegment) and refuses anything whose magic, layout version or size differ from its own.
// A segment left by a crashed rt (its pid no longer alive) is recognised and recreated; when
// it is of this very layout, the last status the dead rt published is kept for the new one
// (RtSegment::previous_status): the simulated axes start where they were last measured.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "ipc/block.hpp"
#include "ipc/command.hpp"
#include "ipc/scope_ring.hpp"
#include "ipc/seqlock.hpp"
#include "ipc/spsc_ring.hpp"
#include "ipc/status.hpp"
#include "ipc/wakeup.hpp"

namespace pcnc {

constexpr std::uint64_t kSegmentMagic = 0x314D48534E434350ull;  // "PCCNSHM1" little-endian
constexpr std::uint32_t kLayoutVersion = 11;  // bump on any change of the types below (11: the stage holds 16 blocks; 10: the replay stage, SharedSegment::stage; 9: the ruled block: BlockKind::kRuled, Block::ruled; 8: rotary joints: Block::rotary, Status::rot_*; 4: the scope ring; 5: Block::path_tolerance_mm; 6: NurbsGeometry::schedule_accel and schedule_s; 7: the probe: Block::probe_rule, Status::probe_*)
constexpr std::size_t kRingSlots = 4;        // the seed's 4-line circular buffer
constexpr std::size_t kMailboxSlots = 64;
// The replay stage (virtual clock only): 16 blocks the host has prepared ahead of the ring.
constexpr std::size_t kStageSlots = 16;
// A host that finds the stage full naps on its own timer (a few tens of µs at a time; the rt
// never has to wake it) until the rt has drained the stage to this many blocks, then refills
// it (host/service/ring_feeder.cpp): it no longer follows the rt block by block on a core of its
// own, which leaves that core to the rt's trace writer and the report.
constexpr std::size_t kStageLowWater = kStageSlots * 3 / 4;
// 1.02 s of cycles at 2 kHz: how far a capture may lag (it reads every 5 ms). 2048 x 104 bytes
// is 213 KB of the segment's 426 KB (it is a file: RLIMIT_FSIZE applies to its creation).
constexpr std::size_t kScopeSlots = 2048;

/// The motion ring: host -> rt, preprocessed blocks (the executor consumes it).
using MotionRing = SpscRing<Block, kRingSlots>;
/// The replay stage: under the virtual clock the host writes its blocks here and the rt moves
/// them into the motion ring itself, before each cycle, as slots free (rt/loop/rt_loop.cpp).
/// The ring the executor sees is the same as with a host that refills it at once, but the two
/// processes no longer meet once per block: the host runs up to kStageSlots blocks ahead.
/// Unused under the real clock, where the host writes into the ring as the seed's host did.
using StageRing = SpscRing<Block, kStageSlots>;

struct SegmentHeader {
  std::uint64_t magic = 0;
  std::uint32_t layout_version = 0;
  std::uint32_t pad_ = 0;
  std::uint64_t total_size = 0;
  std::atomic<std::int32_t> rt_pid{0};
  std::atomic<std::int32_t> host_pid{0};
  std::atomic<std::uint64_t> rt_heartbeat_ns{0};    // CLOCK_MONOTONIC of the rt's last cycle
  std::atomic<std::uint64_t> host_heartbeat_ns{0};  // CLOCK_MONOTONIC of the host's last beat
  std::atomic<std::uint64_t> slot_freed_ns{0};      // CLOCK_MONOTONIC when the rt last freed a ring slot
  std::atomic<std::uint32_t> ready{0};              // 1 once the rt initialised everything
};

struct SharedSegment {
  SegmentHeader header;
  MotionRing motion;                         // host -> rt, preprocessed blocks
  StageRing stage;                           // host -> rt under the virtual clock: blocks ahead of the ring
  Wakeup slot_freed;                         // rt -> host: a ring slot was freed (real clock)
  Wakeup block_published;                    // host -> rt: a block was published (virtual clock)
  SpscRing<Command, kMailboxSlots> commands; // host -> rt
  Seqlock<Status> status;                    // rt -> host
  ScopeRing<kScopeSlots> scope;              // rt -> host: every cycle's sample, overwritten after kScopeSlots
};

static_assert(std::atomic<std::int32_t>::is_always_lock_free);
static_assert(std::atomic<std::uint64_t>::is_always_lock_free);
static_assert(std::atomic<std::uint32_t>::is_always_lock_free);

struct SegmentError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// CLOCK_MONOTONIC in nanoseconds (system-wide, comparable between processes).
std::uint64_t monotonic_ns();
/// True when a process with this pid runs (kill(pid, 0), and not a zombie in /proc).
bool process_alive(int pid);

/// The rt's side under the virtual clock: moves the blocks the host staged (stage) into the
/// motion ring while it has a free slot, oldest first. It wakes nobody: a host that waits for
/// room in the stage naps on its own timer (kStageLowWater). Returns how many moved.
std::size_t take_staged(SharedSegment& shm);

/// The rt serves one host at a time: header.host_pid is a claim. claim_host takes it for
/// `pid` when it is free or its holder no longer runs, and returns 0; when another running
/// process holds it, it returns that process's pid and changes nothing. release_host gives
/// it back (only if `pid` still holds it).
int claim_host(SegmentHeader& header, int pid);
void release_host(SegmentHeader& header, int pid);

/// The rt's side: creates the segment, owns it, removes it when destroyed.
class RtSegment {
 public:
  /// Creates `name`. An existing segment whose rt is still alive is an error; one whose rt
  /// is gone (stale, after a crash) or that is not ours at all is removed and recreated.
  /// `note` receives a human-readable line about any stale segment recovered.
  explicit RtSegment(const std::string& name, std::string* note = nullptr);
  ~RtSegment();
  RtSegment(const RtSegment&) = delete;
  RtSegment& operator=(const RtSegment&) = delete;

  SharedSegment& shm() { return *seg_; }
  const std::string& name() const { return name_; }

  /// The last status published by the dead rt whose stale segment this one replaced, when
  /// that segment had this build's magic, layout version and size and held a consistent
  /// snapshot of a running machine (the rt had cycled at least once). Empty otherwise: no
  /// segment, a foreign or older one, or a snapshot torn by the crash.
  const std::optional<Status>& previous_status() const { return previous_; }

 private:
  std::string name_;
  std::optional<Status> previous_;
  SharedSegment* seg_ = nullptr;
  struct Mapping;
  std::unique_ptr<Mapping> mapping_;
};

/// The host's side: opens an existing segment after checking magic, version and size.
class HostSegment {
 public:
  /// Throws SegmentError naming what is missing or what differs.
  explicit HostSegment(const std::string& name);
  ~HostSegment();
  HostSegment(const HostSegment&) = delete;
  HostSegment& operator=(const HostSegment&) = delete;

  SharedSegment& shm() { return *seg_; }
  const SharedSegment& shm() const { return *seg_; }

 private:
  SharedSegment* seg_ = nullptr;
  struct Mapping;
  std::unique_ptr<Mapping> mapping_;
};

/// Removes a segment by name (no error if absent). For tests and tools.
void remove_segment(const std::string& name);

}  // namespace pcnc
