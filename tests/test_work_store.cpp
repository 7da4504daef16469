// test_work_store.cpp — the service's work-coordinate state without processes: touch-off is G10
// L20's arithmetic on the active system (with G92 applied or not), a failed save changes
// nothing, replace() keeps what a program left, and work_position() is its inverse.
#include <gtest/gtest.h>

#include "config/config.hpp"
#include "service/work_store.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

TEST(WorkStore, TouchOffSetsTheActiveSystemSoThePositionReadsTheValue) {
  const MachineConfig c = load_config(test::default_config());
  WorkStore w("", default_work_state(c));
  const Vec3 at{14.0, 9.0, 23.5};
  ASSERT_FALSE(w.touch_off(2, 0.0, at));
  EXPECT_DOUBLE_EQ(w.state().g5x[0][2], 23.5);
  EXPECT_DOUBLE_EQ(w.state().g5x[0][0], c.gcode.work_offsets[0][0]) << "one axis only";
  EXPECT_DOUBLE_EQ(work_position(w.state(), at)[2], 0.0);

  // In G56 with G92 applied: offset = machine - G92 - value.
  WorkState s = w.state();
  s.active = 2;
  s.g92 = {1.0, -2.0, 0.5};
  s.g92_applied = true;
  ASSERT_FALSE(w.replace(s));
  ASSERT_FALSE(w.touch_off(0, 3.0, at));
  EXPECT_DOUBLE_EQ(w.state().g5x[2][0], 14.0 - 1.0 - 3.0);
  EXPECT_DOUBLE_EQ(work_position(w.state(), at)[0], 3.0);
  ASSERT_FALSE(w.touch_off(1, -1.0, at));
  EXPECT_DOUBLE_EQ(work_position(w.state(), at)[1], -1.0);
  EXPECT_EQ(w.state().g5x[0][0], c.gcode.work_offsets[0][0]) << "G54 untouched";
  // The tool length offset in effect (G43, left by the last program) is taken off: the tool
  // tip reads the value.
  s = w.state();
  s.tool = 3;
  s.tool_offset_applied = true;
  s.tool_offset = {0.0, 0.0, 4.0};
  ASSERT_FALSE(w.replace(s));
  ASSERT_FALSE(w.touch_off(2, 0.0, at));
  EXPECT_DOUBLE_EQ(w.state().g5x[2][2], 23.5 - 0.5 - 4.0);
  EXPECT_DOUBLE_EQ(work_position(w.state(), at)[2], 0.0);
  s = w.state();
  s.tool_offset_applied = false;  // G49: the same position reads the tool length higher
  ASSERT_FALSE(w.replace(s));
  EXPECT_DOUBLE_EQ(work_position(w.state(), at)[2], 4.0);
  EXPECT_TRUE(w.touch_off(3, 0.0, at)) << "no axis 3";
}

TEST(WorkStore, AFailedSaveChangesNothing) {
  const MachineConfig c = load_config(test::default_config());
  WorkStore w("/proc/pcnc-no-such-dir/work_state.json", default_work_state(c));
  const WorkState before = w.state();
  const auto error = w.touch_off(2, 0.0, {1, 2, 3});
  ASSERT_TRUE(error);
  EXPECT_NE(error->find("/proc/pcnc-no-such-dir/work_state.json"), std::string::npos) << *error;
  EXPECT_EQ(w.state(), before);
  WorkState next = before;
  next.g92_applied = true;
  EXPECT_TRUE(w.replace(next));
  EXPECT_EQ(w.state(), before);
}

TEST(WorkStore, WhatAJobChangedIsMergedIntoWhatTheOperatorChangedMeanwhile) {
  const MachineConfig c = load_config(test::default_config());
  const WorkState before = default_work_state(c);
  WorkState after = before;  // the program: G10 L2 P2, G92, G55 selected
  after.g5x[1] = {1, 2, 3};
  after.g92 = {5, 0, 0};
  after.g92_applied = true;
  after.active = 1;
  WorkState current = before;  // the operator, while it ran: set_offset G56, touch-off G54 Z
  current.g5x[2] = {7, 8, 9};
  current.g5x[0][2] = 21.5;
  const WorkState m = merge_work_change(current, before, after);
  EXPECT_EQ(m.g5x[1], (Vec3{1, 2, 3})) << "the program's G10";
  EXPECT_EQ(m.g5x[2], (Vec3{7, 8, 9})) << "set_offset meanwhile stays";
  EXPECT_DOUBLE_EQ(m.g5x[0][2], 21.5) << "the touch-off meanwhile stays";
  EXPECT_EQ(m.active, 1);
  EXPECT_TRUE(m.g92_applied);
  EXPECT_EQ(m.g92, (Vec3{5, 0, 0}));
  EXPECT_EQ(m.g28, before.g28);
  EXPECT_EQ(merge_work_change(current, before, before), current) << "a job that changed nothing changes nothing";
}

}  // namespace
}  // namespace pcnc
