// test_canned_cycle.cpp — the canned-cycle expander against LinuxCNC's rs274ngc: the worked
// examples of its G81 documentation, each cycle body (G73 G81 G82 G83 G85 G89), G98/G99 on the
// first and later holes, the preliminary move from below R, G91 with L repeats, the three
// planes, sticky R/Z/P/Q and the initial level across lines, and every error.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "gcode/canned_cycle.hpp"

namespace pcnc {
namespace {

using K = CycleStepKind;

// One cycle line: its G code, the current point and its words ("X4 Y5 Z1.5 R2.8 L3"), in G90
// G98 G17 unless changed afterwards.
CycleInput cycle(int code10, Vec3 position, const std::string& words) {
  CycleInput in;
  in.code10 = code10;
  in.position = position;
  const char* s = words.c_str();
  while (*s != '\0') {
    if (*s == ' ') {
      ++s;
      continue;
    }
    const char c = *s++;
    char* end = nullptr;
    const double v = std::strtod(s, &end);
    EXPECT_NE(end, s) << "bad test words: " << words;
    s = end;
    switch (c) {
      case 'X': case 'Y': case 'Z': {
        const auto i = static_cast<std::size_t>(c - 'X');
        in.has[i] = true;
        in.axis[i] = v;
        break;
      }
      case 'R': in.has_r = true; in.r = v; break;
      case 'P': in.has_p = true; in.p = v; break;
      case 'Q': in.has_q = true; in.q = v; break;
      case 'L': in.has_l = true; in.l = static_cast<long>(v); break;
      default: ADD_FAILURE() << "unknown test word " << c;
    }
  }
  return in;
}

CycleStep rapid(double x, double y, double z) { return {K::kRapid, Vec3{x, y, z}, 0.0}; }
CycleStep feed(double x, double y, double z) { return {K::kFeed, Vec3{x, y, z}, 0.0}; }
CycleStep dwell(double s, double x, double y, double z) { return {K::kDwell, Vec3{x, y, z}, s}; }

const char* kind_name(K k) { return k == K::kRapid ? "rapid" : k == K::kFeed ? "feed" : "dwell"; }

void expect_steps(const std::vector<CycleStep>& got, const std::vector<CycleStep>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    SCOPED_TRACE("step " + std::to_string(i));
    EXPECT_STREQ(kind_name(got[i].kind), kind_name(want[i].kind));
    for (std::size_t a = 0; a < 3; ++a) EXPECT_NEAR(got[i].target[a], want[i].target[a], 1e-9) << "axis " << a;
    EXPECT_DOUBLE_EQ(got[i].dwell_s, want[i].dwell_s);
  }
}

void expect_point(const Vec3& p, double x, double y, double z) {
  EXPECT_NEAR(p[0], x, 1e-9);
  EXPECT_NEAR(p[1], y, 1e-9);
  EXPECT_NEAR(p[2], z, 1e-9);
}

// Runs a line that must succeed.
std::vector<CycleStep> expand_ok(const CycleInput& in, CannedCycleModal& modal, Vec3* end = nullptr) {
  std::vector<CycleStep> out;
  const CycleResult r = expand_canned_cycle(in, modal, out);
  EXPECT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.error.empty());
  if (end != nullptr) *end = r.end;
  if (r.ok && !out.empty()) {
    for (std::size_t a = 0; a < 3; ++a) EXPECT_DOUBLE_EQ(r.end[a], out.back().target[a]);
  }
  return out;
}

// Runs a line that must fail: no steps, the modal state untouched; returns the result.
CycleResult expand_error(const CycleInput& in, CannedCycleModal& modal) {
  std::vector<CycleStep> out{rapid(9, 9, 9)};
  const CannedCycleModal before = modal;
  const CycleResult r = expand_canned_cycle(in, modal, out);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.error.empty());
  EXPECT_NE(r.error.find("; expected"), std::string::npos) << r.error;
  EXPECT_EQ(out.size(), 1u);
  EXPECT_EQ(modal.have_r, before.have_r);
  EXPECT_EQ(modal.have_z, before.have_z);
  EXPECT_EQ(modal.have_initial_level, before.have_initial_level);
  EXPECT_EQ(modal.r, before.r);
  EXPECT_EQ(modal.z, before.z);
  return r;
}

// ---- the worked examples of LinuxCNC's G81 documentation ----

TEST(CannedCycle, G81AbsoluteFromAboveRDocsExample1) {
  CannedCycleModal modal;
  Vec3 end{};
  const auto s = expand_ok(cycle(810, {1, 2, 3}, "X4 Y5 Z1.5 R2.8"), modal, &end);
  expect_steps(s, {rapid(4, 5, 3), rapid(4, 5, 2.8), feed(4, 5, 1.5), rapid(4, 5, 3)});
  expect_point(end, 4, 5, 3);
  EXPECT_TRUE(modal.have_initial_level);
  EXPECT_DOUBLE_EQ(modal.initial_level, 3.0);
}

TEST(CannedCycle, G81IncrementalWithThreeRepeatsDocsExample2) {
  CannedCycleModal modal;
  CycleInput in = cycle(810, {1, 2, 3}, "X4 Y5 Z-0.6 R1.8 L3");
  in.incremental = true;
  Vec3 end{};
  const auto s = expand_ok(in, modal, &end);
  // R = 3 + 1.8 = 4.8 (above the old level: up first), bottom 4.8 - 0.6 = 4.2
  expect_steps(s, {rapid(1, 2, 4.8),                                           //
                   rapid(5, 7, 4.8), feed(5, 7, 4.2), rapid(5, 7, 4.8),        //
                   rapid(9, 12, 4.8), feed(9, 12, 4.2), rapid(9, 12, 4.8),     //
                   rapid(13, 17, 4.8), feed(13, 17, 4.2), rapid(13, 17, 4.8)});
  expect_point(end, 13, 17, 4.8);
  EXPECT_DOUBLE_EQ(modal.initial_level, 3.0);  // the level before the preliminary move
  EXPECT_DOUBLE_EQ(modal.r, 1.8);              // the word as written
  EXPECT_DOUBLE_EQ(modal.z, -0.6);
}

TEST(CannedCycle, G81FromBelowRRisesFirstDocsExample5) {
  CannedCycleModal modal;
  const auto s = expand_ok(cycle(810, {0, 0, 0}, "X4 Y5 Z-0.6 R1.8"), modal);
  // G98 but the old level 0 is below R: the clear level is R
  expect_steps(s, {rapid(0, 0, 1.8), rapid(4, 5, 1.8), feed(4, 5, -0.6), rapid(4, 5, 1.8)});
}

// ---- G98 / G99 ----

TEST(CannedCycle, G99RetractsToROnEveryHole) {
  CannedCycleModal modal;
  CycleInput in = cycle(810, {0, 0, 10}, "X10 Y0 Z-5 R2");
  in.retract_r = true;
  expect_steps(expand_ok(in, modal), {rapid(10, 0, 10), rapid(10, 0, 2), feed(10, 0, -5), rapid(10, 0, 2)});
  CycleInput next = cycle(810, {10, 0, 2}, "X20");
  next.retract_r = true;
  next.first_of_series = false;
  expect_steps(expand_ok(next, modal), {rapid(20, 0, 2), feed(20, 0, -5), rapid(20, 0, 2)});
}

TEST(CannedCycle, G98RetractsToTheInitialLevelOnEveryHole) {
  CannedCycleModal modal;
  expect_steps(expand_ok(cycle(810, {0, 0, 10}, "X10 Y0 Z-5 R2"), modal),
               {rapid(10, 0, 10), rapid(10, 0, 2), feed(10, 0, -5), rapid(10, 0, 10)});
  CycleInput next = cycle(810, {10, 0, 10}, "X20");
  next.first_of_series = false;
  expect_steps(expand_ok(next, modal), {rapid(20, 0, 10), rapid(20, 0, 2), feed(20, 0, -5), rapid(20, 0, 10)});
}

TEST(CannedCycle, G98AfterG99InASeriesReturnsToTheInitialLevel) {
  // LinuxCNC keeps the initial level for the whole series, so a G98 line after G99 holes
  // rises to it; the move across starts at R and goes straight to (hole, initial level).
  CannedCycleModal modal;
  CycleInput first = cycle(810, {0, 0, 10}, "X10 Y0 Z-5 R2");
  first.retract_r = true;
  expand_ok(first, modal);
  CycleInput next = cycle(810, {10, 0, 2}, "X30");
  next.first_of_series = false;
  Vec3 end{};
  expect_steps(expand_ok(next, modal, &end), {rapid(30, 0, 10), rapid(30, 0, 2), feed(30, 0, -5), rapid(30, 0, 10)});
  expect_point(end, 30, 0, 10);
}

TEST(CannedCycle, G98BelowRKeepsTheLowInitialLevelForLaterLines) {
  CannedCycleModal modal;
  expand_ok(cycle(810, {0, 0, 0}, "X4 Y5 Z-0.6 R1.8"), modal);
  EXPECT_DOUBLE_EQ(modal.initial_level, 0.0);
  CycleInput next = cycle(810, {4, 5, 1.8}, "X8");
  next.first_of_series = false;
  // still below R: the preliminary move is to where the tool already is (kept, as LinuxCNC
  // emits it)
  expect_steps(expand_ok(next, modal), {rapid(4, 5, 1.8), rapid(8, 5, 1.8), feed(8, 5, -0.6), rapid(8, 5, 1.8)});
  EXPECT_DOUBLE_EQ(modal.initial_level, 0.0);
}

TEST(CannedCycle, EndSeriesForgetsTheInitialLevel) {
  CannedCycleModal modal;
  expand_ok(cycle(810, {0, 0, 10}, "X1 Z-1 R2"), modal);
  modal.end_series();  // e.g. G0 or G80 between the lines
  EXPECT_FALSE(modal.have_initial_level);
  EXPECT_FALSE(modal.have_r);
  // the new series starts at 5: G98 returns there, not to 10
  expect_steps(expand_ok(cycle(810, {1, 0, 5}, "X2 Z-1 R2"), modal),
               {rapid(2, 0, 5), rapid(2, 0, 2), feed(2, 0, -1), rapid(2, 0, 5)});
}

// ---- repeats and G91 ----

TEST(CannedCycle, AbsoluteRepeatsDrillTheSameHoleAgain) {
  CannedCycleModal modal;
  const auto s = expand_ok(cycle(810, {0, 0, 5}, "X1 Y1 Z0 R2 L3"), modal);
  // each later hole starts with the traverse to the clear level (where the tool is)
  expect_steps(s, {rapid(1, 1, 5), rapid(1, 1, 2), feed(1, 1, 0), rapid(1, 1, 5),                  //
                   rapid(1, 1, 5), rapid(1, 1, 2), feed(1, 1, 0), rapid(1, 1, 5),                  //
                   rapid(1, 1, 5), rapid(1, 1, 2), feed(1, 1, 0), rapid(1, 1, 5)});
}

TEST(CannedCycle, IncrementalRepeatsDocsTwelveHolesFirstLine) {
  CannedCycleModal modal;
  CycleInput in = cycle(810, {0, 0, 0}, "X1 Y0 Z-0.5 R1 L4");
  in.incremental = true;
  expect_steps(expand_ok(in, modal), {rapid(0, 0, 1),                                  //
                                      rapid(1, 0, 1), feed(1, 0, 0.5), rapid(1, 0, 1),  //
                                      rapid(2, 0, 1), feed(2, 0, 0.5), rapid(2, 0, 1),  //
                                      rapid(3, 0, 1), feed(3, 0, 0.5), rapid(3, 0, 1),  //
                                      rapid(4, 0, 1), feed(4, 0, 0.5), rapid(4, 0, 1)});
}

TEST(CannedCycle, IncrementalRIsFromTheInitialLevelOnLaterLines) {
  // LinuxCNC (since 2010, interp_cycles.cc: r = R + cycle_il) measures a G91 R from the level
  // the series started at, not from the current point: R0 on the second line of the docs'
  // twelve-holes program is level 0, and the sticky Z-0.5 puts the bottom at -0.5.
  CannedCycleModal modal;
  CycleInput first = cycle(810, {0, 0, 0}, "X1 Y0 Z-0.5 R1 L4");
  first.incremental = true;
  expand_ok(first, modal);
  CycleInput next = cycle(810, {4, 0, 1}, "X0 Y1 R0 L3");
  next.incremental = true;
  next.first_of_series = false;
  Vec3 end{};
  expect_steps(expand_ok(next, modal, &end), {rapid(4, 1, 1), rapid(4, 1, 0), feed(4, 1, -0.5), rapid(4, 1, 0),  //
                                              rapid(4, 2, 0), feed(4, 2, -0.5), rapid(4, 2, 0),                  //
                                              rapid(4, 3, 0), feed(4, 3, -0.5), rapid(4, 3, 0)});
  expect_point(end, 4, 3, 0);
}

TEST(CannedCycle, IncrementalWithoutPlaneWordsStaysOnTheCurrentHole) {
  CannedCycleModal modal;
  CycleInput in = cycle(810, {3, 4, 2}, "Z-3 R0 L2");
  in.incremental = true;
  in.retract_r = true;
  // R = 2 + 0 = 2, bottom -1; the tool is at R already: each hole starts with LinuxCNC's
  // traverse to the clear level, here to where the tool is
  expect_steps(expand_ok(in, modal), {rapid(3, 4, 2), feed(3, 4, -1), rapid(3, 4, 2),  //
                                      rapid(3, 4, 2), feed(3, 4, -1), rapid(3, 4, 2)});
}

// ---- the cycle bodies ----

TEST(CannedCycle, G82DwellsAtTheBottom) {
  CannedCycleModal modal;
  CycleInput in = cycle(820, {0, 0, 5}, "X1 Y1 Z-2 R1 P0.5");
  in.retract_r = true;
  expect_steps(expand_ok(in, modal),
               {rapid(1, 1, 5), rapid(1, 1, 1), feed(1, 1, -2), dwell(0.5, 1, 1, -2), rapid(1, 1, 1)});
  EXPECT_TRUE(modal.have_p);
  EXPECT_DOUBLE_EQ(modal.p, 0.5);
}

TEST(CannedCycle, G83PecksRetractToRAndComeBackAboveTheLastDepth) {
  CannedCycleModal modal;
  const auto s = expand_ok(cycle(830, {0, 0, 10}, "X3 Y4 Z-5 R1 Q2"), modal);
  // pecks to -1 and -3 (-5 is not above the bottom: the final feed goes there)
  expect_steps(s, {rapid(3, 4, 10), rapid(3, 4, 1),                      //
                   feed(3, 4, -1), rapid(3, 4, 1), rapid(3, 4, -0.746),  //
                   feed(3, 4, -3), rapid(3, 4, 1), rapid(3, 4, -2.746),  //
                   feed(3, 4, -5), rapid(3, 4, 10)});
  EXPECT_TRUE(modal.have_q);
  EXPECT_DOUBLE_EQ(modal.q, 2.0);
}

TEST(CannedCycle, G83LastPeckShorterThanQ) {
  CannedCycleModal modal;
  CycleInput in = cycle(830, {0, 0, 0}, "Z-5 R0 Q2");
  in.retract_r = true;
  expect_steps(expand_ok(in, modal), {rapid(0, 0, 0),                                       //
                                      feed(0, 0, -2), rapid(0, 0, 0), rapid(0, 0, -1.746),  //
                                      feed(0, 0, -4), rapid(0, 0, 0), rapid(0, 0, -3.746),  //
                                      feed(0, 0, -5), rapid(0, 0, 0)});
}

TEST(CannedCycle, G83PeckDepthsAccumulateLikeLinuxCnc) {
  // LinuxCNC steps the depth by repeated subtraction: ten steps of 0.1 end at -0.9999999999999999,
  // still above -1, so there are ten pecks before the final feed to -1.
  CannedCycleModal modal;
  const auto s = expand_ok(cycle(830, {0, 0, 0}, "Z-1 R0 Q0.1"), modal);
  int feeds = 0;
  for (const CycleStep& st : s) feeds += st.kind == K::kFeed ? 1 : 0;
  EXPECT_EQ(feeds, 11);
  ASSERT_EQ(s.size(), 1u + 10u * 3u + 2u);  // the traverse to where the tool is, then the pecks
  EXPECT_EQ(s[28].kind, K::kFeed);
  EXPECT_NEAR(s[28].target[2], -1.0, 1e-12);
  EXPECT_GT(s[28].target[2], -1.0);
  EXPECT_EQ(s[31].kind, K::kFeed);
  EXPECT_DOUBLE_EQ(s[31].target[2], -1.0);
  EXPECT_EQ(s[32].kind, K::kRapid);
  EXPECT_DOUBLE_EQ(s[32].target[2], 0.0);
}

TEST(CannedCycle, G73BreaksChipsWithASmallRetract) {
  CannedCycleModal modal;
  CycleInput in = cycle(730, {0, 0, 1}, "X3 Y4 Z-5 R1 Q2");
  in.retract_r = true;
  expect_steps(expand_ok(in, modal), {rapid(3, 4, 1),                          //
                                      feed(3, 4, -1), rapid(3, 4, -0.746),     //
                                      feed(3, 4, -3), rapid(3, 4, -2.746),     //
                                      feed(3, 4, -5), rapid(3, 4, 1)});
}

TEST(CannedCycle, PeckClearanceIsAnInput) {
  CannedCycleModal modal;
  CycleInput in = cycle(730, {0, 0, 1}, "Z-3 R1 Q2");
  in.peck_clearance = 1.0;  // LinuxCNC master's metric G73_PECK_CLEARANCE default
  expect_steps(expand_ok(in, modal), {rapid(0, 0, 1), feed(0, 0, -1), rapid(0, 0, 0), feed(0, 0, -3), rapid(0, 0, 1)});
}

TEST(CannedCycle, G85FeedsOutToRThenRapidsToTheClearLevel) {
  CannedCycleModal modal;
  expect_steps(expand_ok(cycle(850, {0, 0, 10}, "X1 Y2 Z-3 R2"), modal),
               {rapid(1, 2, 10), rapid(1, 2, 2), feed(1, 2, -3), feed(1, 2, 2), rapid(1, 2, 10)});
  CannedCycleModal m99;
  CycleInput in = cycle(850, {0, 0, 10}, "X1 Y2 Z-3 R2");
  in.retract_r = true;
  // LinuxCNC's G85 always ends with a traverse to the clear level, here R where the tool is
  expect_steps(expand_ok(in, m99), {rapid(1, 2, 10), rapid(1, 2, 2), feed(1, 2, -3), feed(1, 2, 2), rapid(1, 2, 2)});
}

TEST(CannedCycle, G89DwellsAndFeedsOutStraightToTheClearLevel) {
  CannedCycleModal modal;
  expect_steps(expand_ok(cycle(890, {0, 0, 10}, "X1 Y2 Z-3 R2 P1.5"), modal),
               {rapid(1, 2, 10), rapid(1, 2, 2), feed(1, 2, -3), dwell(1.5, 1, 2, -3), feed(1, 2, 10)});
}

TEST(CannedCycle, RAtTheBottomIsAllowed) {
  CannedCycleModal modal;
  CycleInput in = cycle(810, {0, 0, 5}, "X1 Z0 R0");
  in.retract_r = true;
  Vec3 end{};
  expect_steps(expand_ok(in, modal, &end), {rapid(1, 0, 5), rapid(1, 0, 0), feed(1, 0, 0), rapid(1, 0, 0)});
  expect_point(end, 1, 0, 0);
}

TEST(CannedCycle, StepsAreAppended) {
  CannedCycleModal modal;
  std::vector<CycleStep> out{rapid(7, 7, 7)};
  ASSERT_TRUE(expand_canned_cycle(cycle(810, {0, 0, 5}, "X1 Z0 R2"), modal, out).ok);
  ASSERT_EQ(out.size(), 5u);
  EXPECT_DOUBLE_EQ(out[0].target[0], 7.0);
  expect_point(out[1].target, 1, 0, 5);
}

// ---- the planes ----

TEST(CannedCycle, G18DrillsAlongYWithZAndXInThePlane) {
  CannedCycleModal modal;
  CycleInput in = cycle(810, {0, 10, 0}, "X5 Z7 Y-3 R2");
  in.normal_axis = 1;
  expect_steps(expand_ok(in, modal), {rapid(5, 10, 7), rapid(5, 2, 7), feed(5, -3, 7), rapid(5, 10, 7)});
}

TEST(CannedCycle, G19DrillsAlongXWithYAndZInThePlane) {
  CannedCycleModal modal;
  CycleInput in = cycle(810, {10, 0, 0}, "Y5 Z7 X-3 R2");
  in.normal_axis = 0;
  in.retract_r = true;
  expect_steps(expand_ok(in, modal), {rapid(10, 5, 7), rapid(2, 5, 7), feed(-3, 5, 7), rapid(2, 5, 7)});
}

TEST(CannedCycle, G18IncrementalRepeatsStepZAndX) {
  CannedCycleModal modal;
  CycleInput in = cycle(810, {0, 10, 0}, "X1 Z2 Y-4 R-5 L2");
  in.normal_axis = 1;
  in.incremental = true;
  in.retract_r = true;
  // R = 10 - 5 = 5, bottom 5 - 4 = 1
  expect_steps(expand_ok(in, modal), {rapid(1, 10, 2), rapid(1, 5, 2), feed(1, 1, 2), rapid(1, 5, 2),  //
                                      rapid(2, 5, 4), feed(2, 1, 4), rapid(2, 5, 4)});
}

TEST(CannedCycle, G19PeckDrillsAlongX) {
  CannedCycleModal modal;
  CycleInput in = cycle(830, {5, 0, 0}, "Y1 Z1 X-3 R1 Q2");
  in.normal_axis = 0;
  expect_steps(expand_ok(in, modal), {rapid(5, 1, 1), rapid(1, 1, 1),                     //
                                      feed(-1, 1, 1), rapid(1, 1, 1), rapid(-0.746, 1, 1),  //
                                      feed(-3, 1, 1), rapid(5, 1, 1)});
}

// ---- sticky words ----

TEST(CannedCycle, StickyRZAndQOnTheNextLine) {
  CannedCycleModal modal;
  CycleInput first = cycle(830, {0, 0, 1}, "X0 Z-3 R1 Q2");
  first.retract_r = true;
  expand_ok(first, modal);
  CycleInput next = cycle(830, {0, 0, 1}, "X6");
  next.retract_r = true;
  next.first_of_series = false;
  expect_steps(expand_ok(next, modal), {rapid(6, 0, 1), feed(6, 0, -1), rapid(6, 0, 1), rapid(6, 0, -0.746),
                                        feed(6, 0, -3), rapid(6, 0, 1)});
}

TEST(CannedCycle, StickyPAndANewRWithTheOldZ) {
  CannedCycleModal modal;
  CycleInput first = cycle(820, {0, 0, 10}, "X1 Z-1 R2 P0.25");
  expand_ok(first, modal);
  CycleInput next = cycle(820, {1, 0, 10}, "X2 R3");
  next.first_of_series = false;
  expect_steps(expand_ok(next, modal),
               {rapid(2, 0, 10), rapid(2, 0, 3), feed(2, 0, -1), dwell(0.25, 2, 0, -1), rapid(2, 0, 10)});
  EXPECT_DOUBLE_EQ(modal.r, 3.0);
  EXPECT_DOUBLE_EQ(modal.z, -1.0);
}

TEST(CannedCycle, ANewCycleNeedsItsWordsButKeepsTheInitialLevel) {
  CannedCycleModal modal;
  CycleInput first = cycle(810, {0, 0, 10}, "X1 Z-1 R2");
  first.retract_r = true;
  expand_ok(first, modal);
  // G81 -> G83: R, Z and Q are required again (first of its series) ...
  CycleInput g83 = cycle(830, {1, 0, 2}, "X2 Q5");
  EXPECT_FALSE(expand_error(g83, modal).ok);
  // ... but the initial level 10 (G98 return) survives the change of cycle
  g83 = cycle(830, {1, 0, 2}, "X2 Z-1 R2 Q5");
  expect_steps(expand_ok(g83, modal), {rapid(2, 0, 10), rapid(2, 0, 2), feed(2, 0, -1), rapid(2, 0, 10)});
}

// ---- errors ----

TEST(CannedCycleErrors, NoAxisWord) {
  CannedCycleModal modal;
  const CycleResult r = expand_error(cycle(810, {0, 0, 5}, "R2"), modal);
  EXPECT_EQ(r.error_letter, 0);
  EXPECT_NE(r.error.find("no X, Y or Z"), std::string::npos) << r.error;
}

TEST(CannedCycleErrors, MissingROnTheFirstLine) {
  CannedCycleModal modal;
  const CycleResult r = expand_error(cycle(810, {0, 0, 5}, "X1 Z0"), modal);
  EXPECT_EQ(r.error_letter, 0);
  EXPECT_NE(r.error.find("G81 without R"), std::string::npos) << r.error;
}

TEST(CannedCycleErrors, MissingRWithNothingSticky) {
  CannedCycleModal modal;
  CycleInput in = cycle(810, {0, 0, 5}, "X1 Z0");
  in.first_of_series = false;  // the caller says "same cycle" but no R was ever kept
  EXPECT_NE(expand_error(in, modal).error.find("without R"), std::string::npos);
}

TEST(CannedCycleErrors, ZeroAndNegativeRepeats) {
  CannedCycleModal modal;
  CycleResult r = expand_error(cycle(810, {0, 0, 5}, "X1 Z0 R2 L0"), modal);
  EXPECT_EQ(r.error_letter, 'L');
  EXPECT_NE(r.error.find("zero repeats"), std::string::npos) << r.error;
  r = expand_error(cycle(810, {0, 0, 5}, "X1 Z0 R2 L-2"), modal);
  EXPECT_EQ(r.error_letter, 'L');
  EXPECT_NE(r.error.find("negative repeats"), std::string::npos) << r.error;
}

TEST(CannedCycleErrors, MissingDrillAxisWordOnTheFirstLine) {
  CannedCycleModal modal;
  CycleResult r = expand_error(cycle(810, {0, 0, 5}, "X1 R2"), modal);
  EXPECT_EQ(r.error_letter, 0);
  EXPECT_NE(r.error.find("without Z"), std::string::npos) << r.error;
  CycleInput g18 = cycle(810, {0, 0, 5}, "X1 Z2 R2");
  g18.normal_axis = 1;
  r = expand_error(g18, modal);
  EXPECT_NE(r.error.find("without Y"), std::string::npos) << r.error;
  CycleInput g19 = cycle(810, {0, 0, 5}, "Y1 Z2 R2");
  g19.normal_axis = 0;
  r = expand_error(g19, modal);
  EXPECT_NE(r.error.find("without X"), std::string::npos) << r.error;
}

TEST(CannedCycleErrors, RBelowTheBottom) {
  CannedCycleModal modal;
  CycleResult r = expand_error(cycle(810, {0, 0, 5}, "X1 Z0 R-1"), modal);
  EXPECT_EQ(r.error_letter, 'R');
  EXPECT_NE(r.error.find("below the bottom"), std::string::npos) << r.error;
  CycleInput inc = cycle(810, {0, 0, 5}, "X1 Z1 R-1");  // G91: a positive Z puts the bottom above R
  inc.incremental = true;
  EXPECT_EQ(expand_error(inc, modal).error_letter, 'R');
}

TEST(CannedCycleErrors, MissingDwellForG82AndG89) {
  CannedCycleModal modal;
  CycleResult r = expand_error(cycle(820, {0, 0, 5}, "X1 Z0 R2"), modal);
  EXPECT_NE(r.error.find("G82 without P"), std::string::npos) << r.error;
  r = expand_error(cycle(890, {0, 0, 5}, "X1 Z0 R2"), modal);
  EXPECT_NE(r.error.find("G89 without P"), std::string::npos) << r.error;
}

TEST(CannedCycleErrors, NegativeDwell) {
  CannedCycleModal modal;
  const CycleResult r = expand_error(cycle(820, {0, 0, 5}, "X1 Z0 R2 P-1"), modal);
  EXPECT_EQ(r.error_letter, 'P');
}

TEST(CannedCycleErrors, MissingPeckForG73AndG83) {
  CannedCycleModal modal;
  CycleResult r = expand_error(cycle(830, {0, 0, 5}, "X1 Z0 R2"), modal);
  EXPECT_NE(r.error.find("G83 without Q"), std::string::npos) << r.error;
  r = expand_error(cycle(730, {0, 0, 5}, "X1 Z0 R2"), modal);
  EXPECT_NE(r.error.find("G73 without Q"), std::string::npos) << r.error;
}

TEST(CannedCycleErrors, PeckNotPositive) {
  CannedCycleModal modal;
  CycleResult r = expand_error(cycle(830, {0, 0, 5}, "X1 Z0 R2 Q0"), modal);
  EXPECT_EQ(r.error_letter, 'Q');
  EXPECT_NE(r.error.find("not positive"), std::string::npos) << r.error;
  r = expand_error(cycle(730, {0, 0, 5}, "X1 Z0 R2 Q-1"), modal);
  EXPECT_EQ(r.error_letter, 'Q');
}

TEST(CannedCycleErrors, TooManyPecks) {
  CannedCycleModal modal;
  const CycleResult r = expand_error(cycle(830, {0, 0, 5}, "X1 Z-50 R0 Q0.0001"), modal);
  EXPECT_EQ(r.error_letter, 'Q');
  EXPECT_NE(r.error.find("too many pecks"), std::string::npos) << r.error;
}

TEST(CannedCycleErrors, PecksOverTheStepLimit) {
  // 40000 pecks are allowed per hole, but at three steps each they exceed 100000 steps
  CannedCycleModal modal;
  const CycleResult r = expand_error(cycle(830, {0, 0, 5}, "X1 Z-40 R0 Q0.001"), modal);
  EXPECT_EQ(r.error_letter, 'Q');
  EXPECT_NE(r.error.find("100000"), std::string::npos) << r.error;
}

TEST(CannedCycleErrors, TooManyRepeats) {
  CannedCycleModal modal;
  CycleInput in = cycle(810, {0, 0, 5}, "X1 Z0 R2 L30000");
  in.incremental = true;
  const CycleResult r = expand_error(in, modal);
  EXPECT_EQ(r.error_letter, 'L');
  EXPECT_NE(r.error.find("100000"), std::string::npos) << r.error;
  in.l = 1000000000000L;  // no overflow in the count
  EXPECT_EQ(expand_error(in, modal).error_letter, 'L');
}

TEST(CannedCycleErrors, RepeatsJustUnderTheLimitExpand) {
  CannedCycleModal modal;
  CycleInput in = cycle(810, {0, 0, 5}, "X1 Z-7 R0 L24999");  // bound 1 + 24999 * 4 = 99997 steps
  in.incremental = true;
  in.retract_r = true;
  std::vector<CycleStep> out;
  ASSERT_TRUE(expand_canned_cycle(in, modal, out).ok);
  EXPECT_LE(out.size(), kMaxCycleSteps);
  EXPECT_EQ(out.size(), 24999u * 3u);  // the tool starts on R: across, feed, rapid out per hole
  expect_point(out.back().target, 24999, 0, 5);
}

TEST(CannedCycleErrors, NotADrillingCycle) {
  CannedCycleModal modal;
  const CycleResult r = expand_error(cycle(840, {0, 0, 5}, "X1 Z0 R2"), modal);
  EXPECT_NE(r.error.find("G84"), std::string::npos) << r.error;
  EXPECT_TRUE(is_drilling_cycle(730));
  EXPECT_FALSE(is_drilling_cycle(800));
  EXPECT_FALSE(is_drilling_cycle(860));
}

}  // namespace
}  // namespace pcnc
