// test_measure_no_alloc.cpp — the measurement models' evaluation allocates nothing and their
// values are trivially copyable (so the rt's simulation and a shared segment can hold them):
// r_eff(d), the contact point, E_V forward and inverse, counted by replacing the global
// operator new for this executable.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <vector>

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

}  // namespace
}  // namespace pcnc
