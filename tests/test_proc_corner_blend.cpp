// test_proc_corner_blend.cpp — the rt's corner blending (docs/rt-executor.md, "Corner blending")
// with the real processes on a corpus program: LHchips4.ngc (linuxcnc-tp; default desktop mill,
// `pcnc run --fit --contouring on --clock virtual --tolerance 0.005 --trace`). Its worst measured
// points were the real corners passed at the junction-deviation speed (10.67 µm before the blend,
// all at corners; the goal is tolerance + 5 µm = 10 µm): the traced measured position now
// stays within 8 µm of the programmed polyline and the commanded one within the tolerance, both
// measured by bench/bench_path_deviation against the programmed moves (not the host's blocks).
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "subprocess.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

TEST(PcncRunCornerBlend, LHchips4MeasuredPathStaysWithin8umOfTheProgrammedPolyline) {
  if (!std::filesystem::exists(bin_dir() + "/bench/bench_path_deviation")) GTEST_SKIP() << "bench/ not built (PCNC_BENCH off)";
  const std::string dir = make_temp_dir("blend");
  const std::string config = write_test_config(dir, "blend", {{"host_timeout_s = 0.1", "host_timeout_s = 2.0"},
                                                              {"rt_timeout_s = 0.1", "rt_timeout_s = 2.0"}});
  const std::string prog = shared_dir() + "/gcode/cam/linuxcnc-tp/LHchips4.ngc";
  const std::string trace = dir + "/t.csv";
  const ProcessResult r = run_process({bin_dir() + "/tools/pcnc", "run", prog, "--config", config, "--fit", "--clock", "virtual",
                                       "--contouring", "on", "--tolerance", "0.005", "--trace", trace, "-q"},
                                      600);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const ProcessResult d = run_process({bin_dir() + "/bench/bench_path_deviation", prog, trace, "--config", config, "--fit",
                                       "--contouring", "on"},
                                      600);
  ASSERT_EQ(d.exit_code, 0) << d.out << d.err;
  std::istringstream in(d.out);
  double cmd_um = -1.0, act_um = -1.0;
  long rows = 0;
  in >> cmd_um >> act_um >> rows;
  ASSERT_GT(rows, 100000) << d.out;
  EXPECT_LE(cmd_um, 5.0) << "the commanded path left the tolerance of the programmed moves";
  EXPECT_LE(act_um, 8.0) << "the measured path strays from the programmed moves";
  EXPECT_GT(cmd_um, 1.0);  // the bench measured something
  std::cout << "[ figures  ] LHchips4 (--fit, tolerance 0.005): commanded " << cmd_um << " um, measured " << act_um
            << " um from the programmed polyline\n";
}

}  // namespace
}  // namespace pcnc::test
