// segment.cpp — creating, validating and opening the shared segment with Boost.Interprocess.
#include "ipc/segment.hpp"

#include <signal.h>
#include <sys/stat.h>
#include <time.h>

#include <boost/interprocess/mapped_region.hpp>
#include <boost/interprocess/shared_memory_object.hpp>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <new>
#include <sstream>

namespace bip = boost::interprocess;

namespace pcnc {

std::uint64_t monotonic_ns() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<std::uint64_t>(t.tv_sec) * 1000000000ull + static_cast<std::uint64_t>(t.tv_nsec);
}

bool process_alive(int pid) {
  if (pid <= 0) return false;
  if (kill(pid, 0) != 0 && errno != EPERM) return false;
  // An exited process that its parent has not reaped yet (a zombie) still answers kill(0):
  // read its state from /proc, so a crashed rt's segment can be recovered at once.
  char path[64];
  std::snprintf(path, sizeof path, "/proc/%d/stat", pid);
  std::FILE* f = std::fopen(path, "r");
  if (!f) return true;
  char buf[512];
  const std::size_t n = std::fread(buf, 1, sizeof buf - 1, f);
  std::fclose(f);
  buf[n] = 0;
  const char* paren = std::strrchr(buf, ')');  // the command name may contain spaces
  if (!paren || paren[1] == 0 || paren[2] == 0) return true;
  return paren[2] != 'Z' && paren[2] != 'X';
}

std::size_t take_staged(SharedSegment& shm) {
  std::size_t moved = 0;
  while (!shm.stage.empty()) {
    Block* slot = shm.motion.begin_push();
    if (slot == nullptr) break;
    *slot = shm.stage.peek(0);
    shm.motion.commit_push();
    shm.stage.pop();
    ++moved;
  }
  return moved;  // no wake-up: a host waiting for stage room naps on its own timer (ring_feeder.cpp)
}

int claim_host(SegmentHeader& h, int pid) {
  for (;;) {
    std::int32_t holder = h.host_pid.load();
    if (holder == pid) return 0;
    if (holder > 0 && process_alive(holder)) return holder;
    // free, or its holder is gone (killed): take it over, unless someone was faster
    if (h.host_pid.compare_exchange_strong(holder, pid)) return 0;
  }
}

void release_host(SegmentHeader& h, int pid) {
  std::int32_t self = pid;
  h.host_pid.compare_exchange_strong(self, 0);
}

namespace {

// What an existing segment's header says, read without trusting anything else in it.
struct Inspection {
  bool exists = false;
  bool ours = false;   // magic, version and size all match this build
  int rt_pid = 0;
  std::string mismatch;  // what differs, when not ours
  std::optional<Status> status;  // ours: the last consistent status its rt published
};

std::string hex(std::uint64_t v) {
  std::ostringstream os;
  os << "0x" << std::hex << v;
  return os.str();
}

std::string describe_mismatch(const SegmentHeader& h, std::size_t region_size) {
  std::ostringstream os;
  if (region_size < sizeof(SegmentHeader)) {
    os << "segment is " << region_size << " bytes, too small for a header (" << sizeof(SegmentHeader) << ")";
  } else if (h.magic != kSegmentMagic) {
    os << "magic is " << hex(h.magic) << ", expected " << hex(kSegmentMagic) << " (not a pcnc segment)";
  } else if (h.layout_version != kLayoutVersion) {
    os << "layout version is " << h.layout_version << ", this build speaks version " << kLayoutVersion
       << " (rebuild or restart both processes from one build)";
  } else if (h.total_size != sizeof(SharedSegment) || region_size < sizeof(SharedSegment)) {
    os << "size is " << h.total_size << " bytes (mapped " << region_size << "), this build expects "
       << sizeof(SharedSegment) << " bytes";
  }
  return os.str();
}

Inspection inspect(const std::string& name) {
  Inspection r;
  try {
    bip::shared_memory_object obj(bip::open_only, name.c_str(), bip::read_only);
    r.exists = true;
    bip::offset_t size = 0;
    obj.get_size(size);
    if (size <= 0) {
      r.mismatch = "segment is empty";
      return r;
    }
    bip::mapped_region region(obj, bip::read_only);
    const auto* h = static_cast<const SegmentHeader*>(region.get_address());
    r.mismatch = describe_mismatch(*h, region.get_size());
    r.ours = r.mismatch.empty();
    if (static_cast<std::size_t>(region.get_size()) >= sizeof(SegmentHeader) && h->magic == kSegmentMagic) {
      r.rt_pid = h->rt_pid.load();
    }
    if (r.ours) {
      // A crash in the middle of a store leaves the sequence odd for ever: a bounded number
      // of tries, then no snapshot. Before the first store there is none either.
      const auto* seg = static_cast<const SharedSegment*>(region.get_address());
      Status st{};
      if (seg->status.version() > 0 && seg->status.load(st, 1000) && st.state != MachineState::kStarting) r.status = st;
    }
  } catch (const bip::interprocess_exception&) {
    // absent (or unreadable): treat as absent; create will report a real error
  }
  return r;
}

}  // namespace

struct RtSegment::Mapping {
  bip::shared_memory_object object;
  bip::mapped_region region;
};

RtSegment::RtSegment(const std::string& name, std::string* note) : name_(name) {
  const Inspection old = inspect(name);
  if (old.exists) {
    if (old.rt_pid > 0 && old.rt_pid != getpid() && process_alive(old.rt_pid)) {
      throw SegmentError("shared-memory segment '" + name + "' is in use by a running pcnc-rt (pid " +
                         std::to_string(old.rt_pid) + "); stop it first or choose another process.shm_name");
    }
    std::ostringstream os;
    if (old.ours) {
      os << "removed stale segment '" << name << "' left by pcnc-rt pid " << old.rt_pid << " (no longer running)";
      previous_ = old.status;
    } else {
      os << "removed segment '" << name << "' that this build cannot use: " << old.mismatch;
    }
    if (note) *note = os.str();
    bip::shared_memory_object::remove(name.c_str());
  }
  try {
    mapping_ = std::make_unique<Mapping>();
    mapping_->object = bip::shared_memory_object(bip::create_only, name.c_str(), bip::read_write, bip::permissions(0600));
    mapping_->object.truncate(static_cast<bip::offset_t>(sizeof(SharedSegment)));
    mapping_->region = bip::mapped_region(mapping_->object, bip::read_write);
  } catch (const bip::interprocess_exception& e) {
    throw SegmentError("cannot create shared-memory segment '" + name + "': " + e.what());
  }
  seg_ = new (mapping_->region.get_address()) SharedSegment();
  seg_->slot_freed.init();
  seg_->block_published.init();
  SegmentHeader& h = seg_->header;
  h.magic = kSegmentMagic;
  h.layout_version = kLayoutVersion;
  h.total_size = sizeof(SharedSegment);
  h.rt_pid.store(getpid());
  h.rt_heartbeat_ns.store(monotonic_ns());
  h.ready.store(1, std::memory_order_release);
}

RtSegment::~RtSegment() {
  if (seg_) {
    seg_->header.ready.store(0);
    seg_->header.rt_pid.store(0);
    seg_->slot_freed.destroy();
    seg_->block_published.destroy();
  }
  mapping_.reset();
  bip::shared_memory_object::remove(name_.c_str());
}

struct HostSegment::Mapping {
  bip::shared_memory_object object;
  bip::mapped_region region;
};

HostSegment::HostSegment(const std::string& name) {
  mapping_ = std::make_unique<Mapping>();
  try {
    mapping_->object = bip::shared_memory_object(bip::open_only, name.c_str(), bip::read_write);
  } catch (const bip::interprocess_exception&) {
    throw SegmentError("shared-memory segment '" + name + "' does not exist: is pcnc-rt running with this config?");
  }
  // Only a segment that pcnc-rt of this user (or root) created, writable by nobody else: a
  // segment another uid created first (squatting the name) would feed us a fake machine.
  struct stat st {};
  if (fstat(mapping_->object.get_mapping_handle().handle, &st) != 0) {
    throw SegmentError("cannot inspect shared-memory segment '" + name + "': " + std::strerror(errno));
  }
  if ((st.st_uid != 0 && st.st_uid != geteuid()) || (st.st_mode & 0077) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    throw SegmentError("refusing shared-memory segment '" + name + "': owned by uid " + std::to_string(st.st_uid) +
                       " with mode " + mode + "; pcnc-rt creates it as root or as you (uid " +
                       std::to_string(geteuid()) + ") with mode 0600");
  }
  bip::offset_t size = 0;
  mapping_->object.get_size(size);
  if (size <= 0) throw SegmentError("shared-memory segment '" + name + "' is empty: not a pcnc segment");
  try {
    mapping_->region = bip::mapped_region(mapping_->object, bip::read_write);
  } catch (const bip::interprocess_exception& e) {
    throw SegmentError("cannot map shared-memory segment '" + name + "': " + e.what());
  }
  auto* h = static_cast<SegmentHeader*>(mapping_->region.get_address());
  const std::string why = describe_mismatch(*h, mapping_->region.get_size());
  if (!why.empty()) throw SegmentError("refusing shared-memory segment '" + name + "': " + why);
  if (h->ready.load(std::memory_order_acquire) != 1) {
    throw SegmentError("shared-memory segment '" + name + "' is not initialised yet (pcnc-rt starting or gone)");
  }
  seg_ = reinterpret_cast<SharedSegment*>(mapping_->region.get_address());
}

HostSegment::~HostSegment() = default;

void remove_segment(const std::string& name) { bip::shared_memory_object::remove(name.c_str()); }

}  // namespace pcnc
