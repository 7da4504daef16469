// test_segment.cpp — the segment's header contract: the host refuses a segment whose magic,
// layout version or size differ (naming what differs), a stale segment left by a dead rt is
// recovered, a live one is not stolen, and a clean exit removes the segment.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <vector>

#include "ipc/segment.hpp"

namespace pcnc {
namespace {

std::string unique_name(const char* what) { return "/pcnc-test-" + std::string(what) + "-" + std::to_string(getpid()); }

bool segment_exists(const std::string& name) {
  const int fd = shm_open(name.c_str(), O_RDONLY, 0);
  if (fd < 0) return false;
  close(fd);
  return true;
}

// Writes raw bytes as a segment, as a foreign program or an old build might have left it.
void write_raw_segment(const std::string& name, const void* data, std::size_t size) {
  const int fd = shm_open(name.c_str(), O_CREAT | O_RDWR | O_TRUNC, 0600);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(ftruncate(fd, static_cast<off_t>(size)), 0);
  void* p = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  ASSERT_NE(p, MAP_FAILED);
  std::memcpy(p, data, size);
  munmap(p, size);
  close(fd);
}

std::string host_open_error(const std::string& name) {
  try {
    HostSegment h(name);
  } catch (const SegmentError& e) {
    return e.what();
  }
  return "";
}

TEST(Segment, HostOpensWhatTheRtCreatedAndSeesTheRtPid) {
  const std::string name = unique_name("open");
  RtSegment rt(name);
  HostSegment host(name);
  EXPECT_EQ(host.shm().header.rt_pid.load(), getpid());
  EXPECT_EQ(host.shm().header.magic, kSegmentMagic);
  // the two mappings are the same memory
  rt.shm().header.host_heartbeat_ns.store(12345);
  EXPECT_EQ(host.shm().header.host_heartbeat_ns.load(), 12345u);
}

// Issue 19, squatting: a segment that is writable by others, or owned by another uid, is
// refused even when its contents look right.
TEST(Segment, HostRefusesASegmentOthersCanWriteOrAnotherUidOwns) {
  const std::string name = unique_name("squat");
  RtSegment rt(name);
  const int fd = shm_open(name.c_str(), O_RDWR, 0);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(fchmod(fd, 0666), 0);
  std::string err = host_open_error(name);
  EXPECT_NE(err.find("mode 0666"), std::string::npos) << err;
  ASSERT_EQ(fchmod(fd, 0600), 0);
  EXPECT_EQ(host_open_error(name), "");
  if (geteuid() == 0) {
    ASSERT_EQ(fchown(fd, 65534, 65534), 0);
    err = host_open_error(name);
    EXPECT_NE(err.find("owned by uid 65534"), std::string::npos) << err;
    ASSERT_EQ(fchown(fd, 0, 0), 0);
  }
  close(fd);
}

TEST(Segment, MissingSegmentIsNamed) {
  const std::string err = host_open_error("/pcnc-test-does-not-exist");
  EXPECT_NE(err.find("does not exist"), std::string::npos) << err;
}

TEST(Segment, WrongMagicVersionOrSizeIsRefusedWithTheReason) {
  const std::string name = unique_name("bad");
  // Writes a full-size segment whose header is well formed except for what `mutate` changes.
  auto write_with = [&](auto mutate, std::size_t size = sizeof(SharedSegment)) {
    std::vector<unsigned char> bytes(sizeof(SharedSegment), 0);
    auto* h = new (bytes.data()) SegmentHeader();
    h->magic = kSegmentMagic;
    h->layout_version = kLayoutVersion;
    h->total_size = sizeof(SharedSegment);
    h->ready.store(1);
    mutate(*h);
    write_raw_segment(name, bytes.data(), size);
  };

  write_with([](SegmentHeader& h) { h.magic = 0xdeadbeef; });
  std::string err = host_open_error(name);
  EXPECT_NE(err.find("magic is 0xdeadbeef"), std::string::npos) << err;

  write_with([](SegmentHeader& h) { h.layout_version = kLayoutVersion + 7; });
  err = host_open_error(name);
  EXPECT_NE(err.find("layout version is " + std::to_string(kLayoutVersion + 7)), std::string::npos) << err;

  write_with([](SegmentHeader& h) { h.total_size = 64; });
  err = host_open_error(name);
  EXPECT_NE(err.find("size is 64"), std::string::npos) << err;

  // a segment shorter than ours, even with a perfect header
  write_with([](SegmentHeader&) {}, sizeof(SegmentHeader));
  err = host_open_error(name);
  EXPECT_NE(err.find("size"), std::string::npos) << err;

  // garbage
  std::vector<unsigned char> junk(4096);
  for (std::size_t i = 0; i < junk.size(); ++i) junk[i] = static_cast<unsigned char>(i * 131 + 7);
  write_raw_segment(name, junk.data(), junk.size());
  err = host_open_error(name);
  EXPECT_NE(err.find("refusing"), std::string::npos) << err;

  write_with([](SegmentHeader&) {});
  EXPECT_EQ(host_open_error(name), "") << "the well-formed segment opens";
  remove_segment(name);
}

TEST(Segment, StaleSegmentOfACrashedRtIsRecovered) {
  const std::string name = unique_name("stale");
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    auto* rt = new RtSegment(name);  // never destroyed: the child "crashes"
    (void)rt;
    _exit(0);
  }
  int st = 0;
  waitpid(child, &st, 0);
  ASSERT_TRUE(segment_exists(name)) << "the crashed rt left its segment behind";
  std::string note;
  {
    RtSegment rt(name, &note);
    EXPECT_NE(note.find("stale"), std::string::npos) << note;
    EXPECT_NE(note.find(std::to_string(child)), std::string::npos) << note;
    EXPECT_EQ(rt.shm().header.rt_pid.load(), getpid());
    HostSegment host(name);
    EXPECT_EQ(host.shm().header.rt_pid.load(), getpid());
  }
  EXPECT_FALSE(segment_exists(name)) << "a clean exit removes the segment";
}

// Issue 19: the simulated plant's state lives in the segment. A new rt that replaces the
// segment of a dead one (same magic and layout) gets the last status it published; a torn
// snapshot (the crash came in the middle of a store), one never published, or a segment of
// another layout give none.
TEST(Segment, StaleSegmentKeepsTheLastPublishedStatus) {
  const std::string name = unique_name("prev");
  auto crash_after = [&](auto publish) {
    const pid_t child = fork();
    if (child == 0) {
      auto* rt = new RtSegment(name);  // never destroyed: the child "crashes"
      publish(rt->shm());
      _exit(0);
    }
    int st = 0;
    waitpid(child, &st, 0);
  };
  crash_after([](SharedSegment& shm) {
    Status s{};
    s.state = MachineState::kRunning;
    s.actual = {3.25, 17.5, 21.0};
    s.commanded = {3.3, 17.5, 21.0};
    shm.status.store(s);
  });
  {
    RtSegment rt(name);
    ASSERT_TRUE(rt.previous_status().has_value());
    EXPECT_EQ(rt.previous_status()->actual, (Vec3{3.25, 17.5, 21.0}));
    EXPECT_EQ(rt.previous_status()->state, MachineState::kRunning);
  }
  // never published (the rt died before its first cycle)
  crash_after([](SharedSegment&) {});
  {
    RtSegment rt(name);
    EXPECT_FALSE(rt.previous_status().has_value());
  }
  // torn: the sequence left odd by a store that never finished
  crash_after([](SharedSegment& shm) {
    Status s{};
    s.state = MachineState::kIdle;
    shm.status.store(s);
    auto* seq = reinterpret_cast<std::atomic<std::uint64_t>*>(&shm.status);
    seq->fetch_add(1);
  });
  {
    RtSegment rt(name);
    EXPECT_FALSE(rt.previous_status().has_value()) << "a torn snapshot is not trusted";
  }
  // another layout version: not ours, nothing taken from it
  std::vector<unsigned char> bytes(sizeof(SharedSegment), 0);
  auto* seg = new (bytes.data()) SharedSegment();
  seg->header.magic = kSegmentMagic;
  seg->header.layout_version = kLayoutVersion + 1;
  seg->header.total_size = sizeof(SharedSegment);
  Status s{};
  s.state = MachineState::kIdle;
  s.actual = {1, 2, 3};
  seg->status.store(s);
  write_raw_segment(name, bytes.data(), bytes.size());
  {
    std::string note;
    RtSegment rt(name, &note);
    EXPECT_FALSE(rt.previous_status().has_value());
    EXPECT_NE(note.find("layout version"), std::string::npos) << note;
  }
}

TEST(Segment, ZombieRtCountsAsGone) {
  // An rt that died but was not reaped yet (its parent, e.g. a launcher, is busy) must not
  // block the next rt from recovering the segment.
  const std::string name = unique_name("zombie");
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    new RtSegment(name);  // never destroyed: the child "crashes"
    char c = 1;
    (void)!write(ready[1], &c, 1);
    _exit(0);
  }
  char c;
  ASSERT_EQ(read(ready[0], &c, 1), 1);
  // wait until the child has exited (zombie), without reaping it
  siginfo_t info{};
  ASSERT_EQ(waitid(P_PID, static_cast<id_t>(child), &info, WEXITED | WNOWAIT), 0);
  EXPECT_FALSE(process_alive(child)) << "a zombie is not a running rt";
  std::string note;
  {
    RtSegment rt(name, &note);
    EXPECT_NE(note.find(std::to_string(child)), std::string::npos) << note;
  }
  waitpid(child, nullptr, 0);
  EXPECT_TRUE(process_alive(getpid()));
}

TEST(Segment, LiveRtSegmentIsNotStolen) {
  const std::string name = unique_name("live");
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    RtSegment rt(name);
    char c = 1;
    (void)!write(ready[1], &c, 1);
    pause();  // stays alive until killed
    _exit(0);
  }
  char c;
  ASSERT_EQ(read(ready[0], &c, 1), 1);
  try {
    RtSegment second(name);
    ADD_FAILURE() << "a second rt must not take over a live segment";
  } catch (const SegmentError& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(child)), std::string::npos) << e.what();
  }
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  std::string note;
  RtSegment recovered(name, &note);
  EXPECT_FALSE(note.empty());
}

}  // namespace
}  // namespace pcnc
