// test_grbl_parts.cpp — the grbl port's pure parts (host/grbl/), no processes: real-time
// bytes out of lines and the receive-buffer account, override steps, the status report from a
// status object, settings from the config and their writes, error numbers from pcnc's
// messages, alarms from states; and the LineFeed a streamed program reads.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <thread>

#include "config/config.hpp"
#include "gcode/line_feed.hpp"
#include "gcode/line_reader.hpp"
#include "grbl/error_codes.hpp"
#include "grbl/line_assembler.hpp"
#include "grbl/realtime.hpp"
#include "grbl/settings.hpp"
#include "grbl/status_report.hpp"

namespace pcnc::grbl {
namespace {

using nlohmann::json;

TEST(GrblLineAssembler, RealtimeBytesLeaveTheLineAndAreNotCounted) {
  LineAssembler a;
  std::vector<RxItem> out;
  a.feed("G1 X?1\x91\n", out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_TRUE(out[0].realtime);
  EXPECT_EQ(out[0].byte, '?');
  EXPECT_TRUE(out[1].realtime);
  EXPECT_EQ(out[1].byte, 0x91);
  ASSERT_FALSE(out[2].realtime);
  EXPECT_EQ(out[2].line.text, "G1 X1");
  EXPECT_EQ(out[2].line.bytes, 6u);
  EXPECT_EQ(a.buffered(), 6u);
  a.answered(6);
  EXPECT_EQ(a.buffered(), 0u);
  EXPECT_EQ(a.available(), kRxBufferSize);
}

TEST(GrblLineAssembler, CrLfIsOneLineEndAndPartialLinesWait) {
  LineAssembler a;
  std::vector<RxItem> out;
  a.feed("G0 X", out);
  EXPECT_TRUE(out.empty());
  a.feed("1\r\n\r\nG0 Y2\r", out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].line.text, "G0 X1");
  EXPECT_EQ(out[1].line.text, "");  // the empty line between two "\r\n" is a line (grbl answers ok)
  EXPECT_EQ(out[2].line.text, "G0 Y2");
}

TEST(GrblLineAssembler, OverfillingTheBufferIsCountedAndLongLinesFlagged) {
  LineAssembler a;
  std::vector<RxItem> out;
  a.feed(std::string(300, 'X') + "\n", out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].line.overflow);
  EXPECT_GT(a.overflows(), 0u);
  EXPECT_EQ(a.available(), 0u);
  a.clear();
  EXPECT_EQ(a.buffered(), 0u);
}

TEST(GrblRealtime, OverrideStepsStayWithinGrblsRange) {
  EXPECT_EQ(next_feed_override(kFeedOvPlus10, 100), 110);
  EXPECT_EQ(next_feed_override(kFeedOvMinus1, 100), 99);
  EXPECT_EQ(next_feed_override(kFeedOvPlus10, 195), 200);
  EXPECT_EQ(next_feed_override(kFeedOvMinus10, 15), 10);
  EXPECT_EQ(next_feed_override(kFeedOv100, 37), 100);
  EXPECT_EQ(next_spindle_override(kSpindleOvMinus10, 100), 90);
  EXPECT_TRUE(is_realtime(0x18));
  EXPECT_TRUE(is_realtime(0x85));
  EXPECT_FALSE(is_realtime('G'));
}

json idle_status() {
  return json{{"state", "IDLE"},
              {"actual", {{"x", 12.5}, {"y", 1.25}, {"z", -0.0}}},
              {"path_speed", 0.0},
              {"feed_override_percent", 120.0},
              {"line", 0},
              {"work_state", {{"active", "G55"}, {"G92_applied", false}, {"G92", {{"x", 1}, {"y", 1}, {"z", 1}}}}},
              {"work_offsets", {{"G54", {{"x", 12.5}, {"y", 12.5}, {"z", 25}}}, {"G55", {{"x", 1}, {"y", 2}, {"z", 3}}}}}};
}

TEST(GrblStatusReport, FieldsSendersParse) {
  PortState port;
  port.rx_available = 100;
  EXPECT_EQ(format_status(idle_status(), port),
            "<Idle|MPos:12.500,1.250,0.000|Bf:15,100|FS:0,0|Ov:120,100,100|WCO:1.000,2.000,3.000>");
}

TEST(GrblStatusReport, StatesFromTheServiceAndThePort) {
  PortState port;
  json st = idle_status();
  st["state"] = "PAUSED";
  st["path_speed"] = 2.0;
  EXPECT_EQ(grbl_state(st, port), "Hold:1");
  st["path_speed"] = 0.0;
  EXPECT_EQ(grbl_state(st, port), "Hold:0");
  st["state"] = "ESTOP";
  EXPECT_EQ(grbl_state(st, port), "Alarm");
  st["state"] = "RUNNING";
  EXPECT_EQ(grbl_state(st, port), "Run");
  // a stream that ran all it received: Idle; one line still pending: Run
  st["job"] = {{"active", true}, {"file", "stream"}, {"waiting_for_lines", true}, {"blocks_streamed", 4}};
  st["program_active"] = true;
  st["ring_fill"] = 0;
  st["blocks_done"] = 4;
  EXPECT_EQ(grbl_state(st, port), "Idle");
  st["blocks_done"] = 3;
  EXPECT_EQ(grbl_state(st, port), "Run") << "the last block still runs";
  st["blocks_done"] = 4;
  port.lines_pending = true;
  EXPECT_EQ(grbl_state(st, port), "Run");
  port.lines_pending = false;
  st["program_active"] = false;
  EXPECT_EQ(grbl_state(st, port), "Run") << "a status from before the rt took the program";
  port.check_mode = true;
  EXPECT_EQ(grbl_state(idle_status(), port), "Check");
}

TEST(GrblSettings, FromTheConfigAndReadOnly) {
  MachineConfig c;
  c.axes[0].max_velocity_mm_s = 100.0;
  c.axes[0].travel_min_mm = 0.0;
  c.axes[0].travel_max_mm = 25.0;
  const auto s = settings_for(c);
  auto find = [&](int n) {
    for (const auto& x : s)
      if (x.number == n) return format_setting(x);
    return std::string();
  };
  EXPECT_EQ(find(110), "$110=6000.000");
  EXPECT_EQ(find(130), "$130=25.000");
  EXPECT_EQ(find(20), "$20=1");
  EXPECT_EQ(write_setting(s, "110=6000"), 0);
  EXPECT_EQ(write_setting(s, "110=5000"), kSettingDisabled);
  EXPECT_EQ(write_setting(s, "110=-1"), kNegativeValue);
  EXPECT_EQ(write_setting(s, "110=abc"), kBadNumberFormat);
  EXPECT_EQ(write_setting(s, "999=1"), kInvalidStatement);
  EXPECT_EQ(write_setting(s, "=1"), kInvalidStatement);
}

TEST(GrblErrors, PcncMessagesMapToGrblNumbers) {
  EXPECT_EQ(error_for_message("X 32.5 mm (machine) is above the travel maximum 25 mm; expected ..."), kInvalidTarget);
  EXPECT_EQ(error_for_message("feed move with no feed rate in effect (F0 or no F yet); expected an F word > 0"), kUndefinedFeedRate);
  EXPECT_EQ(error_for_message("Q word with no G code that uses it; expected no Q word on this line"), kUnusedWords);
  EXPECT_EQ(error_for_message("unknown G code G7.5; expected an RS274 G code"), kUnsupportedCommand);
  EXPECT_EQ(error_for_message("G53 needs G0 or G1 in effect; expected G53 G0 or G53 G1"), kG53InvalidMotionMode);
  EXPECT_EQ(alarm_for("FAULT", "soft limit"), kSoftLimit);
  EXPECT_EQ(alarm_for("FAULT", "following error"), kHardLimit);
  EXPECT_EQ(alarm_for("ESTOP", "none"), kAbortCycle);
  EXPECT_EQ(alarm_for("IDLE", "none"), 0);
  EXPECT_EQ(msg_line("a ]b\nc"), "[MSG:a )b c]");
}

TEST(LineFeed, ReaderWaitsForLinesAndSeesTheEndAtClose) {
  auto feed = std::make_shared<LineFeed>();
  std::vector<std::uint64_t> done;
  feed->set_on_done([&](std::uint64_t d) {
    done.push_back(d);
    return true;
  });
  LineReader reader(LineReader::FromFeed{}, feed);
  feed->append("G1 X1\nG1 X2");
  std::string_view line;
  bool too_long = false;
  ASSERT_TRUE(reader.next(line, too_long));
  EXPECT_EQ(line, "G1 X1");
  ASSERT_TRUE(reader.next(line, too_long));
  EXPECT_EQ(line, "G1 X2");
  const auto at = reader.tell();
  std::thread later([&] { feed->append("G1 X3\n"); });
  ASSERT_TRUE(reader.next(line, too_long));  // waits for it
  later.join();
  EXPECT_EQ(line, "G1 X3");
  ASSERT_TRUE(reader.seek(at));  // back into text already received (a loop, a subroutine)
  ASSERT_TRUE(reader.next(line, too_long));
  EXPECT_EQ(line, "G1 X3");
  feed->close();
  EXPECT_FALSE(reader.next(line, too_long));
  EXPECT_EQ(done, (std::vector<std::uint64_t>{1, 2, 3}));
  EXPECT_EQ(feed->lines_appended(), 3u);
}

TEST(LineFeed, OnDoneFalseEndsTheInput) {
  auto feed = std::make_shared<LineFeed>();
  feed->set_on_done([](std::uint64_t) { return false; });
  LineReader reader(LineReader::FromFeed{}, feed);
  feed->append("G1 X1\nG1 X2\n");
  std::string_view line;
  bool too_long = false;
  ASSERT_TRUE(reader.next(line, too_long));
  EXPECT_FALSE(reader.next(line, too_long)) << "an error found in line 1: the stream ends there";
}

}  // namespace
}  // namespace pcnc::grbl
