// test_proc_virtual_replay.cpp — `pcnc run --clock virtual` is a deterministic replay whatever
// the scheduling. The rt takes a cycle only with a full ring (or the program's end queued), so
// the host and the rt hand every block over in lock step, each waiting for the other with a
// short spin and then the semaphore (docs/architecture.md, "The virtual clock's lock step";
// docs/replay.md, "Replay speed with a report"). A program of
// 1,200 short moves (one block each: tolerance 0) is run twice on whatever cores the machine
// has, and once with both processes and the rt's trace writer pinned to one CPU, where a wait
// that kept its core would leave the other side nothing to run on (the lock step's worst
// schedule, and the most different from the first two): the three traces hold the
// same rows from the program's first moving cycle to its last, the summaries the same machine
// time, and every block the host sent was done, with no ring underrun.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "one_cpu.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"
#include "service_procs.hpp"

namespace pcnc::test {
namespace {

using nlohmann::json;


// A spiral of short G1 moves turning by a few degrees (they flow under M21), with a square
// corner every 100 moves (a stop), around program zero (the top of Z).
std::string write_spiral_program(const std::string& dir) {
  const std::string path = dir + "/spiral.ngc";
  std::ofstream f(path);
  f << "G21 G90 G17\nG0 X0 Y0 Z-1\nG1 Z-1.5 F300\nF1200\n";
  double a = 0.0;
  for (int i = 0; i < 1200; ++i) {
    a += (i % 100 == 99) ? M_PI / 2 : 0.06;
    const double r = 2.0 + 0.004 * i;
    f << "G1 X" << r * std::cos(a) << " Y" << r * std::sin(a) << "\n";
  }
  f << "G0 Z-1\nM2\n";
  return path;
}

// The trace's rows from the first not IDLE to the last not IDLE, without the time column (the
// idle cycles before the program start and after its end follow the wall clock: the rt idles
// in 10 ms steps while the host checks the program).
std::vector<std::string> program_rows(const std::string& csv) {
  std::ifstream f(csv);
  std::string line;
  std::getline(f, line);  // header
  std::vector<std::string> rows;
  std::size_t last_moving = 0;
  while (std::getline(f, line)) {
    const auto c1 = line.find(',');
    const auto c2 = line.find(',', c1 + 1);
    const auto c3 = line.find(',', c2 + 1);
    const bool idle = line.compare(c2 + 1, c3 - c2 - 1, "IDLE") == 0;
    if (rows.empty() && idle) continue;
    rows.push_back(line.substr(c1 + 1));
    if (!idle) last_moving = rows.size();
  }
  rows.resize(last_moving);
  return rows;
}

struct Replay {
  std::vector<std::string> rows;
  json summary;
};

Replay replay(const std::string& dir, const std::string& config, const std::string& program, const std::string& name) {
  const std::string trace = dir + "/" + name + ".csv", summary = dir + "/" + name + ".json";
  const ProcessResult r = run_process({pcnc_exe(), "run", program, "--clock", "virtual", "--config", config, "--contouring",
                                       "on", "--tolerance", "0", "--trace", trace, "--summary", summary, "-q"},
                                      300);
  EXPECT_EQ(r.exit_code, 0) << name << "\n" << r.out << r.err;
  Replay out;
  out.rows = program_rows(trace);
  std::ifstream s(summary);
  if (s) out.summary = json::parse(s, nullptr, false);
  return out;
}

TEST(VirtualReplay, SameTraceOnTwoCoresAndOnOneEveryBlockDone) {
  const std::string dir = make_temp_dir("vreplay");
  const std::string config = write_test_config(dir, "vreplay");
  const std::string program = write_spiral_program(dir);

  const Replay first = replay(dir, config, program, "first");
  const Replay second = replay(dir, config, program, "second");

  Replay pinned;
  {
    OneCpu one_cpu;  // pcnc and both processes inherit it
    ASSERT_TRUE(one_cpu.pinned());
    pinned = replay(dir, config, program, "pinned");
  }

  for (const Replay* r : {&first, &second, static_cast<const Replay*>(&pinned)}) {
    ASSERT_TRUE(r->summary.is_object());
    EXPECT_EQ(r->summary["job"]["end"], "completed");
    EXPECT_EQ(r->summary["job"]["blocks_sent"], r->summary["status"]["blocks_done"]) << "every block sent was done";
    EXPECT_GE(r->summary["job"]["blocks_sent"].get<int>(), 1200) << "one block per move at tolerance 0";
    EXPECT_EQ(r->summary["status"]["underruns"], 0);
    EXPECT_EQ(r->summary["status"]["program_time_s"], first.summary["status"]["program_time_s"]);
  }
  ASSERT_GT(first.rows.size(), 1000u);
  EXPECT_EQ(first.rows, second.rows) << "two runs on the machine's cores";
  EXPECT_EQ(first.rows, pinned.rows) << "a run with both processes on one CPU";
}

}  // namespace
}  // namespace pcnc::test
