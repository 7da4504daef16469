// test_proc_trace_full.cpp — a full disk for the trace is not silent (issue 19). /dev/full
// fails every write with ENOSPC; a file size limit (RLIMIT_FSIZE, set with prlimit) makes a
// real file fail in the middle of a run with EFBIG. The rt's trace writer thread reports it
// once with the path and errno, the status carries trace_failed, `pcnc run` exits 1 naming
// the file, and by process.on_trace_failure the program is stopped along the path ("stop",
// the default) or runs to its end ("continue").
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <sstream>
#include <thread>

#include "config/config.hpp"
#include "ipc/segment.hpp"
#include "service_procs.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

using namespace std::chrono_literals;



TEST(TraceFull, PcncRunWithStopExitsOneNamingTheTraceAndTheProgramIsStopped) {
  const std::string dir = make_temp_dir("tfull-stop");
  const std::string config = write_test_config(dir, "tfull-stop");
  const std::string prog = zigzag_program(dir, 40, 16.0, 60.0);  // ~700 s of machine time: never completes here
  const ProcessResult r =
      run_process({pcnc_exe(), "run", prog, "--clock", "virtual", "--config", config, "--trace", "/dev/full"}, 120);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("trace file '/dev/full' could not be written"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("stopped by pcnc-rt before its end: its trace file could not be written"), std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("result            completed"), std::string::npos) << r.out;
}

TEST(TraceFull, PcncRunWithContinueCompletesAndStillExitsOne) {
  const std::string dir = make_temp_dir("tfull-cont");
  const std::string config =
      write_test_config(dir, "tfull-cont", {{"on_trace_failure = \"stop\"", "on_trace_failure = \"continue\""}});
  const ProcessResult r = run_process(
      {pcnc_exe(), "run", source_dir() + "/examples/demo.ngc", "--clock", "virtual", "--config", config, "--trace", "/dev/full"},
      300);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("result            completed"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("trace file '/dev/full' could not be written"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("programs run on without it"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("pcnc-rt reported a failure"), std::string::npos) << r.err;
}

// A real file on a size-limited target: the trace fails in the middle of a move at 50 mm/s.
// The program stops along the path (no fault), the status says trace_failed, the service
// stays usable for jogs and refuses to run programs without a trace; the rt exits 1.
TEST(TraceFull, ASizeLimitedTraceStopsTheRunningProgramAlongThePath) {
  if (access("/usr/bin/prlimit", X_OK) != 0) GTEST_SKIP() << "no /usr/bin/prlimit to set RLIMIT_FSIZE";
  const std::string tag = "tfull-limit";
  ServicePair p(tag);
  const std::string trace = p.dir() + "/trace.csv";
  // 450 KB (the segment, also a file, is 342 KB): some 2 s of rows at 2 kHz, the program runs ~8 s
  const std::vector<std::string> rt = {"/usr/bin/prlimit", "--fsize=450000", rt_exe(), "--config", p.config(),
                                       "--clock", "real", "--trace", trace};
  BackgroundProcess rtp = start_process(rt, p.dir() + "/rt-limited");
  Reaped guard{rtp};
  ASSERT_TRUE(p.start_host()) << p.host_log();
  json s = p.wait_status([](const json& x) { return x["rt"]["state"] == "attached" && x["state"] == "IDLE"; }, 20);
  ASSERT_EQ(s["state"], "IDLE") << s.dump() << rtp.err();
  EXPECT_FALSE(s["trace_failed"].get<bool>());
  const std::string prog = zigzag_program(p.dir(), 16, 20.0, 3000.0);
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  s = p.wait_status([](const json& x) { return x["trace_failed"].get<bool>(); }, 30);
  ASSERT_TRUE(s["trace_failed"].get<bool>()) << s.dump() << rtp.err();
  s = p.wait_status([](const json& x) { return !x["job"]["active"].get<bool>() && x["state"] == "IDLE"; }, 30);
  EXPECT_EQ(s["state"], "IDLE") << s.dump();
  EXPECT_EQ(s["fault"], "none") << "stopped along the path, not faulted";
  ASSERT_TRUE(s["last_job"].is_object()) << s.dump();
  EXPECT_NE(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_FALSE(s["program_done"].get<bool>());
  // no program runs without its trace; a jog does
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  s = p.wait_status([](const json& x) { return !x["job"]["active"].get<bool>() && x["last_job"].is_object(); }, 30);
  EXPECT_NE(s["last_job"]["end"], "completed") << s.dump();
  const json j = p.call("jog", {{"axis", "Z"}, {"distance", -1.0}});
  EXPECT_TRUE(j.contains("result")) << j.dump();
  kill(rtp.pid, SIGTERM);
  EXPECT_EQ(wait_for(rtp, 10), 1) << rtp.err();
  EXPECT_NE(rtp.err().find("File too large"), std::string::npos) << rtp.err();
  EXPECT_NE(rtp.err().find(trace), std::string::npos) << rtp.err();
  std::cout << "[ figures  ] size-limited trace: " << rtp.err().substr(rtp.err().find("trace file")).substr(0, 200) << "\n";
}

}  // namespace
}  // namespace pcnc::test
