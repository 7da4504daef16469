// test_dispatch.cpp — the service's request dispatch without processes or a socket: the
// method table names every protocol method once; the order of the checks (request, no
// parameters, a live rt, then the method's own parameters); methods that need no rt
// answered while none is attached; a handler's exception becomes an internal-error reply.
#include <gtest/gtest.h>

#include <stdexcept>

#include "config/config.hpp"
#include "service/dispatch.hpp"
#include "service/methods.hpp"
#include "service/subscriptions.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

using rpc::json;

// The service's parts with no rt attached (the monitor is never started) and no socket.
struct Parts {
  MachineConfig config = load_config(test::default_config());
  WorkStore work{"", default_work_state(config)};  // in memory only
  RtMonitor rt{config, 0.005, 0.1, {}};
  Subscriptions subs{[](ClientId, std::string_view) {}};
  JobControl jobs{"/nonexistent/pcnc-test-dispatch.job", JobNotices{[](ClientId, json, Outcome) {}, [](json) {}, {}}};
  JogControl jogs{config, rt, [](ClientId, const json&, const Outcome&) {}, [](const json&) {}};
  ServiceParts parts{config, work, rt, jobs, jogs, subs};
  Dispatcher dispatcher{method_table(parts), rt};

  json call(const std::string& line) { return json::parse(dispatcher.handle(1, line)); }
};

int code(const json& reply) { return reply.contains("error") ? reply["error"]["code"].get<int>() : 0; }

TEST(Dispatch, TheTableHasEveryProtocolMethodOnceInOrder) {
  Parts p;
  const auto table = method_table(p.parts);
  ASSERT_EQ(table.size(), rpc::method_names().size());
  for (std::size_t i = 0; i < table.size(); ++i) EXPECT_EQ(table[i].name, rpc::method_names()[i]);
}

TEST(Dispatch, ATableThatMissesOrRepeatsAMethodIsRefused) {
  Parts p;
  auto table = method_table(p.parts);
  auto missing = table;
  missing.pop_back();
  EXPECT_THROW(Dispatcher(missing, p.rt), std::logic_error);
  auto repeated = table;
  repeated.push_back(table.front());
  EXPECT_THROW(Dispatcher(repeated, p.rt), std::logic_error);
}

TEST(Dispatch, ChecksComeInOrderRequestNoParamsRtThenParams) {
  Parts p;
  EXPECT_EQ(code(p.call("{nope")), rpc::kParseError);
  EXPECT_EQ(code(p.call(R"({"id":1,"method":"teleport"})")), rpc::kMethodNotFound);
  // pause takes no parameters: refused for them before the missing rt is noticed
  EXPECT_EQ(code(p.call(R"({"id":2,"method":"pause","params":{"x":1}})")), rpc::kInvalidParams);
  const json r = p.call(R"({"id":3,"method":"pause"})");
  EXPECT_EQ(code(r), rpc::kRtUnavailable);
  EXPECT_EQ(r["id"], 3);
  EXPECT_EQ(r["error"]["message"], "pcnc-rt is not available (waiting): no pcnc-rt attached yet");
  // a method that needs the rt: the rt is checked before its own parameters
  EXPECT_EQ(code(p.call(R"({"id":4,"method":"override","params":{"percent":"fast"}})")), rpc::kRtUnavailable);
  // mdi and touch_off read the machine's position: they need the rt
  EXPECT_EQ(code(p.call(R"({"id":5,"method":"mdi","params":{"text":"G0 X1"}})")), rpc::kRtUnavailable);
  EXPECT_EQ(code(p.call(R"({"id":6,"method":"touch_off","params":{"axis":"Z","value":0}})")), rpc::kRtUnavailable);
}

TEST(Dispatch, MethodsThatNeedNoRtAreAnsweredWithoutOne) {
  Parts p;
  json r = p.call(R"({"id":"a","method":"status"})");
  ASSERT_TRUE(r.contains("result")) << r.dump();
  EXPECT_EQ(r["result"]["state"], "NO_RT");
  EXPECT_EQ(r["result"]["rt"]["state"], "waiting");
  EXPECT_EQ(r["result"]["job"]["active"], false);
  EXPECT_EQ(r["result"]["jog"]["continuous"], false);

  r = p.call(R"({"id":1,"method":"set_offset","params":{"offset":"G55","x":3.5}})");
  ASSERT_TRUE(r.contains("result")) << r.dump();
  EXPECT_EQ(r["result"]["offset"], "G55");
  EXPECT_EQ(p.call(R"({"id":2,"method":"status"})")["result"]["work_offsets"]["G55"]["x"], 3.5);
  EXPECT_EQ(code(p.call(R"({"id":3,"method":"set_offset","params":{"offset":"G60"}})")), rpc::kInvalidParams);

  EXPECT_EQ(p.call(R"({"id":4,"method":"subscribe","params":{"rate_hz":0}})")["result"]["rate_hz"], 0);
  EXPECT_EQ(code(p.call(R"({"id":5,"method":"jog_keepalive"})")), rpc::kRefused);
}

TEST(Dispatch, SetOffsetReachesG59_3AndStatusListsTheWorkState) {
  Parts p;
  const json r = p.call(R"({"id":1,"method":"set_offset","params":{"offset":"g59.3","z":-4}})");
  ASSERT_TRUE(r.contains("result")) << r.dump();
  EXPECT_EQ(r["result"]["offset"], "G59.3");
  EXPECT_EQ(p.work.state().g5x[8], (Vec3{0, 0, -4}));
  EXPECT_EQ(p.config.gcode.work_offsets, load_config(test::default_config()).gcode.work_offsets) << "the config is not changed";
  const json s = p.call(R"({"id":2,"method":"status"})")["result"];
  ASSERT_EQ(s["work_offsets"].size(), 9u) << s["work_offsets"].dump();
  EXPECT_EQ(s["work_offsets"]["G59.3"]["z"], -4.0);
  EXPECT_EQ(s["work_offsets"]["G54"]["x"], 12.5);
  EXPECT_EQ(s["work_state"]["active"], "G54");
  EXPECT_EQ(s["work_state"]["G92_applied"], false);
  EXPECT_EQ(s["work_state"]["G28"]["z"], 25.0);
  EXPECT_TRUE(s["work_state"]["file"].is_null()) << "this one is in memory only";
}

TEST(Dispatch, SetOffsetThatCannotBeSavedChangesNothing) {
  Parts p;
  p.work = WorkStore("/proc/pcnc-no-such-dir/work_state.json", default_work_state(p.config));
  const json r = p.call(R"({"id":1,"method":"set_offset","params":{"offset":"G55","x":1}})");
  EXPECT_EQ(code(r), rpc::kInternalError) << r.dump();
  const std::string m = r["error"]["message"].get<std::string>();
  EXPECT_NE(m.find("the work offset was not changed"), std::string::npos) << m;
  EXPECT_NE(m.find("/proc/pcnc-no-such-dir/work_state.json"), std::string::npos) << m;
  EXPECT_EQ(p.work.state().g5x[1], p.config.gcode.work_offsets[1]);
  EXPECT_EQ(p.call(R"({"id":2,"method":"status"})")["result"]["work_offsets"]["G55"]["x"], 0.0);
}

TEST(Dispatch, AHandlerExceptionIsAnInternalErrorReply) {
  Parts p;
  auto table = method_table(p.parts);
  table.front().handler = [](Call&) -> Outcome { throw std::runtime_error("boom"); };
  Dispatcher d(table, p.rt);
  const json r = json::parse(d.handle(1, R"({"id":9,"method":"status"})"));
  EXPECT_EQ(code(r), rpc::kInternalError);
  EXPECT_EQ(r["id"], 9);
  EXPECT_NE(r["error"]["message"].get<std::string>().find("boom"), std::string::npos);
}

// A rate the protocol accepts can be so small that its period overflows the clock (5e-324 Hz:
// 1/rate is infinite); found by clang's UBSan in the live protocol fuzz test. Such a client
// gets one push now and none for a day, not a push every tick.
TEST(Subscriptions, ATinyRateGetsOnePushNotOneEveryTick) {
  for (const double rate : {5e-324, 1e-300, 1e-9}) {
    int pushes = 0;
    Subscriptions subs{[&](ClientId, std::string_view line) {
      if (line.find("\"status\"") != std::string_view::npos) ++pushes;
    }};
    subs.subscribe(7, rate);
    for (int i = 0; i < 5; ++i) subs.tick([] { return json{{"state", "IDLE"}}; });
    EXPECT_EQ(pushes, 1) << "rate " << rate;
  }
  int pushes = 0;
  Subscriptions fast{[&](ClientId, std::string_view) { ++pushes; }};
  fast.subscribe(7, 50.0);
  fast.tick([] { return json{{"state", "IDLE"}}; });
  EXPECT_EQ(pushes, 1);
}

}  // namespace
}  // namespace pcnc
