// test_scope.cpp — the scope's parts without processes: the rt's flight-recorder ring (a
// lapped reader is told its samples are lost, never handed later ones), the signals and the
// trigger condition with their refusals, capture's parameter bounds, the recorder's
// pre-trigger and trigger position and its refusal of a gap, and the CSV/HTML files.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "config/config.hpp"
#include "ctl_capture.hpp"
#include "ipc/segment.hpp"
#include "ipc/scope_ring.hpp"
#include "report/scope_page.hpp"
#include "service/capture_control.hpp"
#include "service/rt_link.hpp"
#include "service/scope_recorder.hpp"
#include "service/scope_signals.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

using json = nlohmann::json;

TraceSample sample(std::uint64_t n) {
  TraceSample s;
  s.t = static_cast<double>(n) * 0.0005;
  s.line = static_cast<std::uint32_t>(n);
  s.state = MachineState::kRunning;
  s.commanded = {static_cast<double>(n), 0.0, 0.0};
  s.following_error = {static_cast<double>(n) * 1e-6, -static_cast<double>(n) * 1e-6, 0.0};
  s.speed = static_cast<double>(n) * 0.01;
  return s;
}

TEST(ScopeRing, ReadsWhatWasWrittenAndReportsLappedSamplesAsLost) {
  auto ring = std::make_unique<ScopeRing<8>>();
  TraceSample out;
  EXPECT_EQ(ring->read(0, out), ScopeRead::kNotYet);
  for (std::uint64_t n = 0; n < 5; ++n) ring->publish(sample(n));
  EXPECT_EQ(ring->written(), 5u);
  ASSERT_EQ(ring->read(3, out), ScopeRead::kOk);
  EXPECT_EQ(out.line, 3u);
  EXPECT_EQ(ring->read(5, out), ScopeRead::kNotYet);
  for (std::uint64_t n = 5; n < 20; ++n) ring->publish(sample(n));
  EXPECT_EQ(ring->read(3, out), ScopeRead::kLost) << "slot 3 now holds sample 19: lost, not handed over";
  EXPECT_EQ(ring->read(11, out), ScopeRead::kLost);
  ASSERT_EQ(ring->read(12, out), ScopeRead::kOk);
  EXPECT_EQ(out.line, 12u);
  ASSERT_EQ(ring->read(19, out), ScopeRead::kOk);
  EXPECT_DOUBLE_EQ(out.commanded[0], 19.0);
  EXPECT_EQ(ring->read(20, out), ScopeRead::kNotYet);
}

TEST(ScopeSignals, NamedAsTheTraceColumns) {
  std::string header = "t";
  for (const auto& n : scope_signal_names()) header += "," + n;
  EXPECT_EQ(header, kTraceCsvHeader);
  const TraceSample s = sample(7);
  EXPECT_DOUBLE_EQ(scope_signal_value(s, scope_signal_index("cmd_x")), 7.0);
  EXPECT_DOUBLE_EQ(scope_signal_value(s, scope_signal_index("ferr_y")), -7e-6);
  EXPECT_DOUBLE_EQ(scope_signal_value(s, scope_signal_index("state")), 2.0);
  EXPECT_EQ(scope_signal_index("ferr_q"), -1);
}

TEST(ScopeSignals, TriggerConditions) {
  std::string why;
  auto t = parse_trigger("ferr_x>0.005", why);
  ASSERT_TRUE(t) << why;
  TraceSample s = sample(0);
  s.following_error[0] = 0.005;
  EXPECT_FALSE(t->holds(s));
  s.following_error[0] = 0.0051;
  EXPECT_TRUE(t->holds(s));
  t = parse_trigger(" abs( ferr_y ) >= 2e-3 ", why);
  ASSERT_TRUE(t) << why;
  s.following_error[1] = -0.002;
  EXPECT_TRUE(t->holds(s));
  s.following_error[1] = 0.0019;
  EXPECT_FALSE(t->holds(s));
  t = parse_trigger("state==PAUSED", why);
  ASSERT_TRUE(t) << why;
  s.state = MachineState::kPaused;
  EXPECT_TRUE(t->holds(s));
  t = parse_trigger("line != 12", why);
  ASSERT_TRUE(t) << why;
  s.line = 12;
  EXPECT_FALSE(t->holds(s));
  t = parse_trigger("speed<=+1.5", why);
  ASSERT_TRUE(t) << why;

  const std::pair<const char*, const char*> bad[] = {
      {"ferr_q>0.005", "unknown signal 'ferr_q'"}, {"ferr_x>>0.005", "'>0.005' is not a number"},
      {"ferr_x 0.005", "no comparison"},           {">0.005", "no signal"},
      {"ferr_x>", "no level"},                     {"ferr_x=0.005", "'=' is not a comparison"},
      {"ferr_x>fast", "'fast' is not a number"},   {"abs(state)>1", "abs() of state"},
      {"t>1", "unknown signal 't'"},
  };
  for (const auto& [text, message] : bad) {
    why.clear();
    EXPECT_FALSE(parse_trigger(text, why)) << text;
    EXPECT_NE(why.find(message), std::string::npos) << text << ": " << why;
    EXPECT_NE(why.find("bad trigger '" + std::string(text) + "'"), std::string::npos) << why;
  }
}

TEST(ScopeSignals, CaptureParametersAreBoundedAndChecked) {
  auto ok = check_capture_params(json{{"signals", {"cmd_x", "act_x", "ferr_x", "ferr_y"}}, {"seconds", 2}}, 2000.0);
  ASSERT_TRUE(ok.ok()) << ok.error.message;
  EXPECT_EQ(ok.value->signals.size(), 4u);
  EXPECT_FALSE(ok.value->trigger);

  auto refused = [](const json& params, const std::string& message) {
    const auto r = check_capture_params(params, 2000.0);
    ASSERT_FALSE(r.ok()) << params.dump();
    EXPECT_EQ(r.error.code, rpc::kInvalidParams);
    EXPECT_NE(r.error.message.find(message), std::string::npos) << params.dump() << ": " << r.error.message;
  };
  refused(json{{"signals", {"cmd_x", "ferr_q"}}, {"seconds", 1}}, "unknown signal 'ferr_q'");
  refused(json{{"signals", {"cmd_x", "cmd_x"}}, {"seconds", 1}}, "named twice");
  refused(json{{"signals", json::array()}, {"seconds", 1}}, "non-empty array");
  refused(json{{"seconds", 1}}, "missing parameter 'signals'");
  refused(json{{"signals", {"cmd_x"}}}, "missing parameter 'seconds'");
  refused(json{{"signals", {"cmd_x"}}, {"seconds", 10.5}}, "at most 10 s");
  refused(json{{"signals", {"cmd_x"}}, {"seconds", 0}}, "must be > 0");
  refused(json{{"signals", {"cmd_x", "act_x", "ferr_x"}}, {"seconds", 10}}, "at most 48000 values");
  refused(json{{"signals", {"cmd_x"}}, {"seconds", 1}, {"trigger", "ferr_x>>1"}}, "bad trigger 'ferr_x>>1'");
  refused(json{{"signals", {"cmd_x"}}, {"seconds", 1}, {"trigger", 5}}, "must be a string");
  refused(json{{"signals", {"cmd_x"}}, {"seconds", 1}, {"pre_trigger_percent", 10}}, "needs a 'trigger'");
  refused(json{{"signals", {"cmd_x"}}, {"seconds", 1}, {"trigger", "speed>1"}, {"pre_trigger_percent", 100}}, "[0, 100)");
  refused(json{{"signals", {"cmd_x"}}, {"seconds", 1}, {"colour", "red"}}, "unknown parameter 'colour'");
  // 8 s of 3 signals is exactly the bound
  EXPECT_TRUE(check_capture_params(json{{"signals", {"cmd_x", "act_x", "ferr_x"}}, {"seconds", 8}}, 2000.0).ok());
}

CaptureParams params_with(const char* trigger, double seconds, double pre) {
  auto p = check_capture_params(json{{"signals", {"speed", "line"}}, {"seconds", seconds}}, 2000.0);
  CaptureParams c = *p.value;
  std::string why;
  if (trigger) c.trigger = parse_trigger(trigger, why);
  c.pre_trigger = pre;
  return c;
}

TEST(ScopeRecorder, WithoutATriggerItRecordsFromTheFirstSample) {
  ScopeRecorder rec(params_with(nullptr, 0.01, 0.1), 2000.0);  // 20 rows
  EXPECT_EQ(rec.total_rows(), 20u);
  EXPECT_EQ(rec.pre_rows(), 0u);
  for (std::uint64_t n = 100; n < 119; ++n) EXPECT_EQ(rec.feed(n, sample(n)), ScopeRecorder::Phase::kRecording);
  EXPECT_EQ(rec.feed(119, sample(119)), ScopeRecorder::Phase::kDone);
  ASSERT_EQ(rec.rows().size(), 20u);
  EXPECT_EQ(rec.rows().front().line, 100u);
  EXPECT_EQ(rec.rows().back().line, 119u);
}

TEST(ScopeRecorder, TheTriggerIsTheFirstSampleThatHoldsAfterThePreTriggerIsFull) {
  // 100 rows, 10 % pre-trigger: armed after 10 samples. The condition (line >= 3) already
  // holds at sample 3, while the pre-trigger fills: that is no trigger. It still holds at the
  // arming sample (the 11th fed), which is then the trigger; the record is the 10 before it.
  ScopeRecorder rec(params_with("line>=3", 0.05, 0.1), 2000.0);
  ASSERT_EQ(rec.total_rows(), 100u);
  ASSERT_EQ(rec.pre_rows(), 10u);
  std::uint64_t n = 0;
  while (!rec.finished()) rec.feed(n, sample(n)), ++n;
  ASSERT_EQ(rec.phase(), ScopeRecorder::Phase::kDone);
  ASSERT_EQ(rec.rows().size(), 100u);
  EXPECT_EQ(rec.trigger_sample(), 10u);
  EXPECT_EQ(rec.rows()[10].line, 10u);
  EXPECT_EQ(rec.rows()[0].line, 0u);

  // A condition that first holds later: the trigger is there, the 10 samples before it lead.
  ScopeRecorder late(params_with("speed>0.505", 0.05, 0.1), 2000.0);  // speed = n/100
  for (n = 1000; !late.finished(); ++n) late.feed(n - 1000, sample(n - 1000));
  ASSERT_EQ(late.phase(), ScopeRecorder::Phase::kDone);
  EXPECT_EQ(late.trigger_sample(), 51u);
  EXPECT_EQ(late.rows()[10].line, 51u);
  EXPECT_EQ(late.rows()[9].line, 50u) << "the last pre-trigger sample does not hold";
  EXPECT_EQ(late.rows()[0].line, 41u);
  EXPECT_EQ(late.rows().back().line, 140u);
  EXPECT_DOUBLE_EQ(late.armed_t(), sample(10).t);
}

TEST(ScopeRecorder, AGapFailsTheCaptureSayingHowManySamplesWereLost) {
  ScopeRecorder rec(params_with(nullptr, 0.05, 0.0), 2000.0);
  rec.feed(10, sample(10));
  rec.feed(11, sample(11));
  EXPECT_EQ(rec.feed(15, sample(15)), ScopeRecorder::Phase::kFailed);
  EXPECT_NE(rec.failure().find("lost 3 sample(s) from the rt's sample 12"), std::string::npos) << rec.failure();
  ScopeRecorder lapped(params_with(nullptr, 0.05, 0.0), 2000.0);
  lapped.lost(500, 96, "the host read more than 2048 cycles behind the rt");
  EXPECT_EQ(lapped.phase(), ScopeRecorder::Phase::kFailed);
  EXPECT_NE(lapped.failure().find("2048 cycles behind"), std::string::npos);
}

TEST(ScopeFiles, ResultToCsvAndPage) {
  const CaptureParams p = params_with("speed>0.055", 0.005, 0.2);  // 10 rows, 2 before the trigger
  ScopeRecorder rec(p, 2000.0);
  for (std::uint64_t n = 0; !rec.finished(); ++n) rec.feed(n, sample(n));
  const json res = capture_result(rec, p, 2000.0);
  EXPECT_EQ(res["rows"], 10);
  EXPECT_EQ(res["trigger_row"], 2);
  EXPECT_EQ(res["signals"], json({"speed", "line"}));
  const ScopeRecord r = capture_record(res);
  const std::string csv = scope_csv(r);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "t,speed,line");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 11);
  EXPECT_NE(csv.find("\n0.0030,0.06000,6\n"), std::string::npos) << csv;  // the trigger row
  const std::string html = render_scope_html(r);
  EXPECT_NE(html.find("data-name=\"speed\""), std::string::npos);
  EXPECT_NE(html.find("class=\"trigger\""), std::string::npos);
  EXPECT_NE(html.find("class=\"pretrigger\""), std::string::npos);
  EXPECT_EQ(capture_csv_path("/tmp/a/scope.html"), "/tmp/a/scope.csv");

  json broken = res;
  broken["columns"]["line"].erase(0);
  EXPECT_THROW(capture_record(broken), std::runtime_error);
}

// The capture thread's turn: it follows the ring while it keeps up, and a turn that comes
// more than the ring's length late fails the capture naming the samples lost.
TEST(CaptureControl, DrainingFollowsTheRingAndReportsALapAsLostSamples) {
  auto ring = std::make_unique<ScopeRing<kScopeSlots>>();
  for (std::uint64_t n = 0; n < 100; ++n) ring->publish(sample(n));
  ScopeRecorder rec(params_with(nullptr, 0.5, 0.0), 2000.0);  // 1000 rows
  std::uint64_t next = drain_scope(*ring, 40, rec);  // the capture began at sample 40
  EXPECT_EQ(next, 100u);
  EXPECT_EQ(rec.rows().size(), 60u);
  for (std::uint64_t n = 100; n < 600; ++n) ring->publish(sample(n));
  next = drain_scope(*ring, next, rec);
  EXPECT_EQ(next, 600u);
  EXPECT_EQ(rec.rows().size(), 560u);
  EXPECT_EQ(rec.rows().back().line, 599u);
  EXPECT_FALSE(rec.finished());

  // the host sleeps through more than a ring's worth of cycles
  for (std::uint64_t n = 600; n < 600 + kScopeSlots + 25; ++n) ring->publish(sample(n));
  drain_scope(*ring, next, rec);
  ASSERT_EQ(rec.phase(), ScopeRecorder::Phase::kFailed);
  EXPECT_NE(rec.failure().find("lost 25 sample(s) from the rt's sample 600"), std::string::npos) << rec.failure();
  EXPECT_NE(rec.failure().find("2048 cycles behind"), std::string::npos) << rec.failure();
  EXPECT_EQ(rec.rows().size(), 560u) << "nothing after the gap is recorded";
}

// The largest record allowed, with values as long as they get, still fits the socket's reply
// bound (control_server.hpp: a client whose queue passes it is dropped).
TEST(ScopeFiles, TheLargestRecordFitsTheSocketsReplyBound) {
  auto p = check_capture_params(json{{"signals", {"cmd_x", "act_x", "ferr_x", "cmd_y", "act_y", "ferr_y"}}, {"seconds", 4}}, 2000.0);
  ASSERT_TRUE(p.ok()) << p.error.message;
  ScopeRecorder rec(*p.value, 2000.0);
  for (std::uint64_t n = 0; !rec.finished(); ++n) {
    TraceSample s;
    s.t = 123456.7895 + static_cast<double>(n) * 0.0005;  // a day and more of rt uptime
    s.commanded = {-12.3456789 - static_cast<double>(n % 7) * 1e-7, -12.3456781, 0.0};
    s.actual = {-12.3456782, -12.3456783, 0.0};
    s.following_error = {-0.0012345, -0.0054321, 0.0};
    rec.feed(n, s);
  }
  ASSERT_EQ(rec.rows().size(), 8000u);
  const std::string line = rpc::format_result(json(123456), capture_result(rec, *p.value, 2000.0));
  EXPECT_LT(line.size(), ServerLimits{}.max_output_bytes) << line.size() << " bytes";
}

// A capture's thread against a segment in this process, written at the rt's pace by a
// stand-in for the rt (this thread, beating its heartbeat): the reply is the whole record,
// consecutive samples from the request on. Under ThreadSanitizer it checks the thread and the
// ring for races.
TEST(CaptureControl, ACaptureThreadRecordsFromTheSegmentAndReplies) {
  MachineConfig cfg = load_config(test::default_config());
  cfg.process.shm_name = "/pcnc-test-scope-" + std::to_string(getpid());
  RtSegment rt(cfg.process.shm_name);
  auto& shm = rt.shm();
  shm.header.rt_heartbeat_ns.store(monotonic_ns());
  for (std::uint64_t n = 0; n < 7; ++n) shm.scope.publish(sample(n));  // before the request
  auto link = std::make_shared<RtLink>(cfg);

  std::mutex m;
  std::condition_variable cv;
  std::optional<Outcome> got;
  json got_id;
  CaptureControl cc(2000.0, [&](ClientId client, json id, Outcome o) {
    EXPECT_EQ(client, 3u);
    std::lock_guard lock(m);
    got = std::move(o);
    got_id = std::move(id);
    cv.notify_all();
  });
  const Outcome started = cc.start(3, json("cap-1"), link, Status{}, params_with(nullptr, 0.05, 0.0));  // 100 rows
  ASSERT_TRUE(started.is_later());
  EXPECT_EQ(cc.active(), 1u);
  std::uint64_t n = 7;
  for (;;) {
    {
      std::unique_lock lock(m);
      if (cv.wait_for(lock, std::chrono::microseconds(500), [&] { return got.has_value(); })) break;
    }
    shm.scope.publish(sample(n++));
    shm.header.rt_heartbeat_ns.store(monotonic_ns());
    ASSERT_LT(n, 200000u) << "no reply";
  }
  ASSERT_TRUE(got->result) << (got->error ? got->error->message : "");
  EXPECT_EQ(got_id, "cap-1");
  const json& r = *got->result;
  EXPECT_EQ(r["rows"], 100);
  EXPECT_EQ(r["first_sample"], 7);
  EXPECT_FALSE(r["columns"].contains("cmd_x")) << "only the signals asked for";
  EXPECT_TRUE(r["columns"].contains("speed"));
  const auto line = r["columns"]["line"].get<std::vector<double>>();
  ASSERT_EQ(line.size(), 100u);
  for (std::size_t i = 0; i < line.size(); ++i) EXPECT_EQ(line[i], static_cast<double>(7 + i));
}

TEST(CaptureControl, RefusedUnderTheVirtualClock) {
  CaptureControl cc(2000.0, [](ClientId, json, Outcome) {});
  Status st;
  st.clock_virtual = 1;
  const Outcome o = cc.start(1, json(1), nullptr, st, params_with(nullptr, 1.0, 0.0));
  ASSERT_TRUE(o.error);
  EXPECT_EQ(o.error->code, rpc::kRefused);
  EXPECT_NE(o.error->message.find("real clock"), std::string::npos);
}

}  // namespace
}  // namespace pcnc
