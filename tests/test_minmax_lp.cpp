// test_minmax_lp.cpp — min over x of max_j (a_j·x − b_j) (geometry/minmax_lp.hpp): a box's
// rows give its centre and half its smallest width; on random bounded sets of rows the
// simplex's value equals the brute-force optimum over every vertex (4 active rows), and the
// returned point attains it; degenerate rows (all normals in one plane) still solve.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "geometry/minmax_lp.hpp"

namespace pcnc {
namespace {

// Solves A·s = b (4 x 4) by Gaussian elimination with partial pivoting; false when singular.
bool solve4(double A[4][4], double b[4], double s[4]) {
  for (int c = 0; c < 4; ++c) {
    int p = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(A[r][c]) > std::abs(A[p][c])) p = r;
    if (std::abs(A[p][c]) < 1e-9) return false;
    std::swap(A[p], A[c]);
    std::swap(b[p], b[c]);
    for (int r = c + 1; r < 4; ++r) {
      const double f = A[r][c] / A[c][c];
      for (int k = c; k < 4; ++k) A[r][k] -= f * A[c][k];
      b[r] -= f * b[c];
    }
  }
  for (int r = 3; r >= 0; --r) {
    double v = b[r];
    for (int k = r + 1; k < 4; ++k) v -= A[r][k] * s[k];
    s[r] = v / A[r][r];
  }
  return true;
}

double value_at(const std::vector<MinMaxRow>& rows, const Vec3& x) {
  double v = -1e300;
  for (const MinMaxRow& r : rows) v = std::max(v, dot(r.a, x) - r.b);
  return v;
}

TEST(MinMaxLp, ABoxGivesItsCentre) {
  // 1 <= x <= 5, -2 <= y <= 0, 10 <= z <= 30
  const std::vector<MinMaxRow> rows = {{{1, 0, 0}, 5},  {{-1, 0, 0}, -1}, {{0, 1, 0}, 0},
                                       {{0, -1, 0}, 2}, {{0, 0, 1}, 30},  {{0, 0, -1}, -10}};
  const MinMaxResult r = minimize_max_affine(rows);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.value, -1.0, 1e-12);  // y's width 2: the margin is 1
  EXPECT_NEAR(r.x[1], -1.0, 1e-12);
  EXPECT_GE(r.x[0], 2.0 - 1e-12);  // x and z anywhere with a margin of at least 1
  EXPECT_LE(r.x[0], 4.0 + 1e-12);
}

TEST(MinMaxLp, RandomRowsMatchTheBestVertex) {
  std::mt19937 rng(16);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<MinMaxRow> rows;
    const int pairs = 3 + trial % 4;
    for (int k = 0; k < pairs; ++k) {  // a slab each: bounded
      const Vec3 a = normalized(Vec3{g(rng), g(rng), g(rng)});
      const double lo = u(rng), hi = u(rng);
      rows.push_back({a, std::max(lo, hi)});
      rows.push_back({-1.0 * a, -std::min(lo, hi)});
    }
    // brute force: every 4 rows equal at a vertex
    double best = 1e300;
    const int m = static_cast<int>(rows.size());
    for (int i = 0; i < m; ++i)
      for (int j = i + 1; j < m; ++j)
        for (int k = j + 1; k < m; ++k)
          for (int l = k + 1; l < m; ++l) {
            double A[4][4], b[4], s[4];
            const int idx[4] = {i, j, k, l};
            for (int r = 0; r < 4; ++r) {
              const MinMaxRow& row = rows[static_cast<std::size_t>(idx[r])];
              A[r][0] = row.a[0];
              A[r][1] = row.a[1];
              A[r][2] = row.a[2];
              A[r][3] = -1.0;
              b[r] = row.b;
            }
            if (!solve4(A, b, s)) continue;
            best = std::min(best, value_at(rows, {s[0], s[1], s[2]}));
          }
    const MinMaxResult r = minimize_max_affine(rows);
    ASSERT_TRUE(r.ok) << trial;
    EXPECT_NEAR(r.value, best, 1e-9) << trial;
    EXPECT_NEAR(value_at(rows, r.x), r.value, 1e-12) << trial;
  }
}

TEST(MinMaxLp, NormalsInOnePlaneLeaveAFreeDirection) {
  // only x and y are bounded; z is free: any z, the margin from x, y alone
  const std::vector<MinMaxRow> rows = {{{1, 0, 0}, 4}, {{-1, 0, 0}, 0}, {{0.6, 0.8, 0}, 3}, {{-0.6, -0.8, 0}, 3}};
  const MinMaxResult r = minimize_max_affine(rows);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.value, -2.0, 1e-12);
  EXPECT_NEAR(r.x[0], 2.0, 1e-12);
}

TEST(MinMaxLp, AnOpenSideIsUnbounded) {
  const std::vector<MinMaxRow> rows = {{{1, 0, 0}, 4}, {{0, 1, 0}, 0}, {{0, 0, 1}, 3}};
  EXPECT_FALSE(minimize_max_affine(rows).ok);
}

}  // namespace
}  // namespace pcnc
