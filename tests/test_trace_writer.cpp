// test_trace_writer.cpp — the trace CSV: header, one row per pushed sample in order, values
// parse back, drops counted when the queue overflows, push never blocks.
#include <gtest/gtest.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <thread>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "machine_runner.hpp"
#include "make_blocks.hpp"
#include "loop/trace_writer.hpp"

namespace pcnc {
namespace {

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

TEST(TraceWriter, WritesHeaderAndEveryCycleOfAProgram) {
  const std::string path = ::testing::TempDir() + "pcnc_trace_test.csv";
  MachineConfig c = test::default_machine_config();
  test::MachineRunner run(c);
  test::ProgramBuilder p(c, test::home(c));
  p.line({14.0, 13.0, 24.0}, 20.0).end();
  run.start(p.blocks());
  std::size_t n = 0;
  {
    TraceWriter w(path);
    while (!run.status().program_done && n < 100000) {
      run.cycle();
      ASSERT_TRUE(w.push(run.machine().trace_sample()));
      ++n;
    }
    w.close();
    EXPECT_EQ(w.written(), n);
    EXPECT_EQ(w.dropped(), 0u);
  }
  const auto lines = lines_of(path);
  ASSERT_EQ(lines.size(), n + 1);
  EXPECT_EQ(lines[0], "t,line,state,cmd_x,cmd_y,cmd_z,act_x,act_y,act_z,ferr_x,ferr_y,ferr_z,speed");
  // the last row is the last sample: parse it back
  double t = 0, cx = 0, cy = 0, cz = 0;
  unsigned line = 0;
  char state[32] = {};
  ASSERT_EQ(std::sscanf(lines.back().c_str(), "%lf,%u,%31[^,],%lf,%lf,%lf", &t, &line, state, &cx, &cy, &cz), 6);
  EXPECT_NEAR(t, static_cast<double>(n) * c.cycle_period_s(), 1e-4);
  EXPECT_STREQ(state, "IDLE");
  EXPECT_NEAR(cx, 14.0, 1e-7);
  EXPECT_NEAR(cy, 13.0, 1e-7);
  EXPECT_NEAR(cz, 24.0, 1e-7);
  // rows are in time order
  double prev = -1.0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const double ti = std::stod(lines[i].substr(0, lines[i].find(',')));
    ASSERT_GT(ti, prev);
    prev = ti;
  }
  std::remove(path.c_str());
}

TEST(TraceWriter, CountsDropsWhenTheQueueOverflows) {
  const std::string path = ::testing::TempDir() + "pcnc_trace_drop.csv";
  TraceWriter w(path);
  TraceSample s;
  std::uint64_t ok = 0;
  const std::size_t pushes = 20 * TraceWriter::kQueueSlots;  // far faster than the writer drains
  for (std::size_t i = 0; i < pushes; ++i) {
    s.t = static_cast<double>(i);
    ok += w.push(s) ? 1 : 0;
  }
  w.close();
  EXPECT_EQ(ok + w.dropped(), pushes);
  EXPECT_EQ(w.written(), ok);
  EXPECT_EQ(lines_of(path).size(), ok + 1);
  std::remove(path.c_str());
}

// Issue 19: disk full is not silent. /dev/full fails every write with ENOSPC: the writer's
// thread notices at its first flush, reports once with the path and errno, sets failed(), and
// keeps taking samples off the queue so the rt never waits on it.
TEST(TraceWriter, AFullDiskIsReportedOnceAndTheQueueKeepsMoving) {
  std::vector<std::string> reports;
  std::mutex m;
  TraceWriter w("/dev/full", [&](const std::string& what) {
    std::lock_guard<std::mutex> lock(m);
    reports.push_back(what);
  });
  TraceSample s;
  const std::size_t pushes = 4 * TraceWriter::kQueueSlots;
  for (std::size_t i = 0; i < pushes; ++i) {
    s.t = static_cast<double>(i) * 0.0005;
    w.push_wait(s);  // would wait for ever if the failed writer stopped draining
  }
  for (int i = 0; i < 500 && !w.failed(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  EXPECT_TRUE(w.failed());
  EXPECT_EQ(w.error(), ENOSPC);
  w.close();
  EXPECT_GT(w.lost(), 0u);
  ASSERT_EQ(reports.size(), 1u) << "reported once";
  EXPECT_NE(reports[0].find("/dev/full"), std::string::npos) << reports[0];
  EXPECT_NE(reports[0].find("No space left on device"), std::string::npos) << reports[0];
  EXPECT_NE(reports[0].find("errno 28"), std::string::npos) << reports[0];
  EXPECT_EQ(w.failure(), reports[0]);
}

TEST(TraceWriter, AWritableFileHasNoFailure) {
  const std::string path = ::testing::TempDir() + "pcnc_trace_ok.csv";
  TraceWriter w(path);
  TraceSample s;
  for (int i = 0; i < 100; ++i) w.push_wait(s);
  w.close();
  EXPECT_FALSE(w.failed());
  EXPECT_EQ(w.failure(), "");
  EXPECT_EQ(w.lost(), 0u);
  EXPECT_EQ(lines_of(path).size(), 101u);
  std::remove(path.c_str());
}

TEST(TraceWriter, RefusesAnUnwritablePath) {
  EXPECT_THROW(TraceWriter("/nonexistent-dir/x/trace.csv"), std::runtime_error);
}

}  // namespace
}  // namespace pcnc
