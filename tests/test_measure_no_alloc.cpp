// test_measure_no_alloc.cpp — the measurement models' evaluation allocates nothing and their
// values are trivially copyable (so the rt's simulation and a shared segment can hold them):
// r_eff(d), the contact point, E_V forward and inverse, and the simulated probe's sensing
// against a B-spline top with the Wiener error on a machine with a volumetric error (what the
// rt does every cycle), counted by replacing the global operator new for this executable.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <vector>

#include "config/config.hpp"
#include "drive/sim_probe.hpp"
#include "geometry/probe_calibration.hpp"
#include "geometry/probe_compensation.hpp"
#include "geometry/volumetric_error.hpp"

namespace {
std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};
void* counted_alloc(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  void* p = std::malloc(n ? n : 1);
  if (!p) throw std::bad_alloc();
  return p;
}
}  // namespace
void* operator new(std::size_t n) { return counted_alloc(n); }
void* operator new[](std::size_t n) { return counted_alloc(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace pcnc {
namespace {

static_assert(std::is_trivially_copyable_v<ProbeCalibration>);
static_assert(std::is_trivially_copyable_v<VolumetricError>);
static_assert(std::is_trivially_copyable_v<PitchTable>);

TEST(MeasureNoAlloc, EvaluationAllocatesNothing) {
  // build the models (allocating is fine here)
  const CalibrationLayout layout;
  std::vector<ProbeTouch> touches;
  const Vec3 c{0, 0, 0};
  for (const Vec3& d : calibration_directions(layout, 12))
    touches.push_back({c - (5.0 + 1.0 - 0.01 * approach_angles(d).polar) * d, d});
  const ProbeCalibrationResult cal = calibrate_probe(touches, 5.0, layout, &c);
  ASSERT_TRUE(cal.ok()) << cal.error;
  VolumetricError m;
  m.pitch[0].count = 3;
  m.pitch[0].error_mm = {0.0, 0.002, -0.001};
  m.squareness_xy_urad = 20.0;

  g_allocations = 0;
  g_counting = true;
  double sink = 0.0;
  for (int i = 0; i < 100; ++i) {
    const Vec3 d = approach_direction(0.01 * i, 0.05 * i);
    sink += effective_radius(cal.cal, d);
    sink += contact_point({0.1 * i, 0, 2}, {0, 0.1, 1}, d, cal.cal)[2];
    sink += actual_position(m, {0.02 * i, 1, 2})[1];
    sink += nominal_position(m, {0.02 * i, 1, 2})[0];
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_TRUE(std::isfinite(sink));
  // the counter does count: a vector allocates
  g_counting = true;
  std::vector<int>* v = new std::vector<int>(3);
  g_counting = false;
  delete v;
  EXPECT_GE(g_allocations.load(), 1);
}

TEST(MeasureNoAlloc, TheSimulatedProbeSensesWithoutAllocating) {
  MachineConfig c;
  c.probe.present = true;
  c.probe.model.repeatability_mm = 0.0005;
  c.table.has_surface = true;
  c.table.bspline = std::make_shared<const BSplineSurface>(bicubic_patch([](int i, int j) {
    return Vec3{10.0 * i / 3.0, 10.0 * j / 3.0, 5.0 + 0.3 * (i == 1 || i == 2) * (j == 1 || j == 2)};
  }));
  c.table.error = std::make_shared<const WienerSurface>(3, 4, 0.01);
  c.table.error_x0_mm = 0.0, c.table.error_x1_mm = 10.0, c.table.error_y0_mm = 0.0, c.table.error_y1_mm = 10.0;
  c.table.artefact_balls = 3;
  c.table.artefact_ball_radius_mm = 2.0;
  c.table.artefact_centres[2] = {20.0, 20.0, 5.0};
  c.has_machine_error = true;
  c.machine_error.pitch[2].count = 2;
  c.machine_error.pitch[2].error_mm = {0.0, 0.003};
  c.machine_error.squareness_xy_urad = 40.0;
  SimProbe p(c);
  g_allocations = 0;
  g_counting = true;
  int touching = 0;
  for (int i = 0; i < 200; ++i) {
    if (i % 20 == 0) p.arm({0.0, 0.01 * i, -1.0});
    touching += p.sense({0.05 * i, 5.0, 5.0 + 0.01 * (200 - i)}) ? 1 : 0;
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_GT(touching, 0);    // it does reach the surface
  EXPECT_LT(touching, 200);  // and starts clear of it
}

}  // namespace
}  // namespace pcnc
