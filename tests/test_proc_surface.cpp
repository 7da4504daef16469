// test_proc_surface.cpp — the measured surface through the real command line: `pcnc surface
// fit` on a generated grid CSV (figures, the file, the report page, refusals with FILE:LINE:COL
// and exit 2) and `pcnc check --surface` on the file it wrote (and on broken ones).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "config/surface_file.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

std::string pcnc_bin() { return bin_dir() + "/tools/pcnc"; }

void write(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
}

// A 7 x 7 probe grid over X/Y 2..22 of a gently warped part top at z = 0.
std::string grid_csv() {
  std::string s = "x,y,z\n";
  for (int j = 0; j < 7; ++j)
    for (int i = 0; i < 7; ++i) {
      const double x = 2 + i * 20.0 / 6, y = 2 + j * 20.0 / 6;
      s += std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(0.03 * std::sin(0.3 * x) * std::cos(0.25 * y)) + "\n";
    }
  return s;
}

TEST(ProcSurface, FitThenCheckWithTheSurface) {
  const std::string dir = make_temp_dir("surface");
  write(dir + "/grid.csv", grid_csv());
  const ProcessResult fit = run_process({pcnc_bin(), "surface", "fit", dir + "/grid.csv", "-o", dir + "/S.json", "--fair",
                                         "--design-plane", "0", "--report", dir + "/S.html"});
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  EXPECT_NE(fit.out.find("7 x 7 points"), std::string::npos) << fit.out;
  EXPECT_NE(fit.out.find("faired: e = "), std::string::npos) << fit.out;
  EXPECT_NE(fit.out.find("distance to the plane z = 0 mm"), std::string::npos) << fit.out;
  const BSplineSurface s = load_surface_file(dir + "/S.json");
  EXPECT_EQ(s.count_u, 7);
  const std::string page = read_file(dir + "/S.html");
  EXPECT_NE(page.find("<svg"), std::string::npos);
  EXPECT_EQ(page.find("http://"), page.find("http://www.w3.org/2000/svg"));  // nothing from the network

  write(dir + "/p.ngc", "G21 G90\nG0 X-8 Y-8 Z-2\nG1 X8 Y8 F300\nG2 X-8 Y8 I-8 J0\nM2\n");
  // its own config and state: the program is placed by the config's G54, not by what other
  // runs on this machine stored as G54
  const std::string config = write_test_config(dir, "surface_check");
  const ProcessResult plain = run_process({pcnc_bin(), "check", dir + "/p.ngc", "--config", config, "--print-moves"});
  const ProcessResult corrected = run_process(
      {pcnc_bin(), "check", dir + "/p.ngc", "--config", config, "--surface", dir + "/S.json", "--print-moves"});
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(corrected.exit_code, 0) << corrected.err;
  EXPECT_EQ(plain.out.find("arc") != std::string::npos, true);
  EXPECT_EQ(corrected.out.find("arc"), std::string::npos) << "arcs become lines";
  EXPECT_NE(plain.out, corrected.out);
  const ProcessResult checked =
      run_process({pcnc_bin(), "check", dir + "/p.ngc", "--config", config, "--surface", dir + "/S.json"});
  EXPECT_EQ(checked.exit_code, 0) << checked.err;
  EXPECT_NE(checked.out.find("OK"), std::string::npos);
}

// The corrected program on the two processes: the trace's commanded Z at the end of the G1
// move is the program's Z plus the surface's offset there (12.5 + 8 = X20.5, Y20.5).
TEST(ProcSurface, RunCorrectsTheCommandedZ) {
  const std::string dir = make_temp_dir("surface_run");
  write(dir + "/grid.csv", grid_csv());
  ASSERT_EQ(run_process({pcnc_bin(), "surface", "fit", dir + "/grid.csv", "-o", dir + "/S.json"}).exit_code, 0);
  const std::string config = write_test_config(dir, "surface_run");
  write(dir + "/p.ngc", "G21 G90\nG0 X0 Y0 Z-2\nG1 X8 Y8 F600\nG4 P0.2\nM2\n");
  const ProcessResult run =
      run_process({pcnc_bin(), "run", dir + "/p.ngc", "--clock", "virtual", "--config", config, "--surface",
                   dir + "/S.json", "--trace", dir + "/trace.csv", "-q"},
                  300);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const BSplineSurface s = load_surface_file(dir + "/S.json");
  const double offset = surface_height(s, 20.5, 20.5).z - surface_height(s, 12.5, 12.5).z;
  ASSERT_GT(std::fabs(offset), 0.002) << "the test needs a visible offset";
  // the last trace row (the dwell, then the end): commanded X, Y, Z
  const std::string trace = read_file(dir + "/trace.csv");
  const auto last = trace.rfind('\n', trace.size() - 2);
  double t, line, x, y, z;
  ASSERT_EQ(std::sscanf(trace.c_str() + last + 1, "%lf,%lf,%*[^,],%lf,%lf,%lf", &t, &line, &x, &y, &z), 5)
      << trace.substr(last);
  EXPECT_NEAR(x, 20.5, 1e-6);
  EXPECT_NEAR(z, 23.0 + offset, 1e-6);
}

TEST(ProcSurface, RefusalsExitTwoNamingTheCause) {
  const std::string dir = make_temp_dir("surface_bad");
  write(dir + "/bad.csv", "x,y,z\n0,0,0\n1,0,zz\n");
  const ProcessResult bad = run_process({pcnc_bin(), "surface", "fit", dir + "/bad.csv", "-o", dir + "/S.json"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("bad.csv:3:5: 'zz' is not a finite number"), std::string::npos) << bad.err;
  write(dir + "/small.csv", "x,y,z\n0,0,0\n1,0,0\n0,1,0\n1,1,0\n");
  const ProcessResult small = run_process({pcnc_bin(), "surface", "fit", dir + "/small.csv", "-o", dir + "/S.json"});
  EXPECT_EQ(small.exit_code, 2);
  EXPECT_NE(small.err.find("too small for degree 3"), std::string::npos) << small.err;
  const ProcessResult help = run_process({pcnc_bin(), "surface", "fit", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("--fair"), std::string::npos);
  const ProcessResult none = run_process({pcnc_bin(), "surface", "fit"});
  EXPECT_EQ(none.exit_code, 2);

  // pcnc-host refuses a bad surface before it serves or runs anything
  const ProcessResult host = run_process({bin_dir() + "/host/pcnc-host", "--serve", "--config",
                                          write_test_config(dir, "surface_bad"), "--surface", dir + "/small.csv"});
  EXPECT_EQ(host.exit_code, 2);
  EXPECT_NE(host.err.find("small.csv: not valid JSON"), std::string::npos) << host.err;

  write(dir + "/p.ngc", "G0 X1\nM2\n");
  write(dir + "/broken.json", "{\"format\": \"pcnc-bspline-surface\", \"version\": 1}");
  const std::string config = write_test_config(dir, "surface_refusals");  // its own state, as above
  const ProcessResult check =
      run_process({pcnc_bin(), "check", dir + "/p.ngc", "--config", config, "--surface", dir + "/broken.json"});
  EXPECT_EQ(check.exit_code, 2);
  EXPECT_NE(check.err.find("broken.json: missing key"), std::string::npos) << check.err;
  const ProcessResult missing =
      run_process({pcnc_bin(), "check", dir + "/p.ngc", "--config", config, "--surface", dir + "/none.json"});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("none.json"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace pcnc::test
