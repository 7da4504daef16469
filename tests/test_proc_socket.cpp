// test_proc_socket.cpp — pcnc-host --serve over its real Unix socket with a real pcnc-rt:
// every method, every jog mode with the soft-limit clamp on each axis and direction, the
// refusals (jog or run while running, values out of range), several clients at once, the
// bad clients while a program runs (it must finish without underruns), `pcnc ctl`, and the
// socket's file mode and peer-uid check.
#include <gtest/gtest.h>
#include <grp.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <memory>
#include <thread>

#include "config/config.hpp"
#include "service/rpc.hpp"
#include "service_procs.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

using namespace std::chrono_literals;



// ---------------------------------------------------------------- idle machine

TEST(ServiceSocket, StatusAndRefusalsOnAnIdleMachine) {
  ServicePair p("sock-idle");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  const MachineConfig m = mill_config();
  const json s = p.status();
  EXPECT_EQ(s["state"], "IDLE");
  EXPECT_EQ(s["rt"]["state"], "attached");
  EXPECT_EQ(s["rt"]["pid"], p.rt_pid());
  EXPECT_EQ(s["clock"], "virtual");
  for (int i = 0; i < 3; ++i) {
    EXPECT_DOUBLE_EQ(pos(s, "commanded", i), m.axes[i].home_mm) << "starts at home";
    EXPECT_NEAR(pos(s, "following_error", i), 0.0, 0.01);
  }
  for (const char* key : {"line", "feed_override_percent", "ring_fill", "underruns", "timing", "actual", "work_offsets"}) {
    EXPECT_TRUE(s.contains(key)) << key;
  }

  // Nothing to pause, resume or reset; stop is harmless.
  for (const char* m2 : {"pause", "resume", "reset"}) {
    const json r = p.call(m2);
    EXPECT_EQ(error_code(r), rpc::kRefused) << m2 << ": " << r.dump();
    EXPECT_NE(error_message(r).find("IDLE"), std::string::npos) << r.dump();
  }
  EXPECT_TRUE(p.call("stop").contains("result"));
  EXPECT_EQ(error_code(p.call("jog_keepalive")), rpc::kRefused) << "no continuous jog to keep alive";

  // Override in range is applied by the rt; out of range and wrong types are refused.
  ASSERT_TRUE(p.call("override", {{"percent", 150}}).contains("result"));
  EXPECT_DOUBLE_EQ(p.wait_status([](const json& x) { return x["feed_override_percent"] == 150.0; }, 5)["feed_override_percent"].get<double>(),
                   150.0);
  EXPECT_EQ(error_code(p.call("override", {{"percent", 250}})), rpc::kInvalidParams);
  EXPECT_EQ(error_code(p.call("override", {{"percent", -5}})), rpc::kInvalidParams);
  EXPECT_EQ(error_code(p.call("override", {{"percent", "fast"}})), rpc::kInvalidParams);
  EXPECT_EQ(error_code(p.call("jog", {{"axis", "X"}, {"distance", 1}, {"feed", 1e6}})), rpc::kInvalidParams);
  EXPECT_EQ(error_code(p.call("subscribe", {{"rate_hz", 51}})), rpc::kInvalidParams);
  EXPECT_EQ(error_code(p.call("warp")), rpc::kMethodNotFound);
  ASSERT_TRUE(p.call("override", {{"percent", 100}}).contains("result"));

  // estop then reset.
  ASSERT_TRUE(p.call("estop").contains("result"));
  EXPECT_EQ(p.wait_status([](const json& x) { return x["state"] == "ESTOP"; }, 5)["state"], "ESTOP");
  EXPECT_EQ(error_code(p.call("jog", {{"axis", "X"}, {"distance", 1}})), rpc::kRefused) << "no jog in ESTOP";
  EXPECT_EQ(error_code(p.call("run", {{"file", source_dir() + "/examples/demo.ngc"}})), rpc::kRefused) << "no run in ESTOP";
  ASSERT_TRUE(p.call("reset").contains("result"));
  EXPECT_EQ(p.wait_status(idle, 5)["state"], "IDLE");
}

// ---------------------------------------------------------------- jog

TEST(ServiceSocket, IncrementalJogMovesExactlyAndClampsAtEachSoftLimit) {
  ServicePair p("sock-jog");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  const MachineConfig m = mill_config();

  auto jog = [&](const char* axis, double d, double feed) {
    const json r = p.call("jog", {{"axis", axis}, {"distance", d}, {"feed", feed}});
    EXPECT_TRUE(r.contains("result")) << r.dump();
    return std::make_pair(r, p.wait_status([](const json& s) { return s["state"] == "IDLE"; }, 30));
  };

  auto [r1, s1] = jog("X", 1.0, 300);
  EXPECT_NEAR(pos(s1, "commanded", 0), m.axes[0].home_mm + 1.0, 1e-9);
  EXPECT_FALSE(r1["result"]["clamped"].get<bool>());
  auto [r2, s2] = jog("X", -0.25, 120);
  EXPECT_NEAR(pos(s2, "commanded", 0), m.axes[0].home_mm + 0.75, 1e-9);

  for (int axis = 0; axis < 3; ++axis) {
    const std::string name(1, "XYZ"[axis]);
    const double feed = m.axes[axis].max_velocity_mm_s * 60.0;
    for (double dir : {+1.0, -1.0}) {
      const json before = p.status();
      auto [r, s] = jog(name.c_str(), dir * 100.0, feed);
      const double limit = dir > 0 ? m.axes[axis].travel_max_mm : m.axes[axis].travel_min_mm;
      EXPECT_EQ(s["state"], "IDLE") << name << dir << ": no fault at the limit";
      EXPECT_NEAR(pos(s, "commanded", axis), limit, 1e-9) << name << " jog " << dir << " stops at the soft limit";
      EXPECT_NEAR(pos(s, "actual", axis), limit, 0.01) << name;
      EXPECT_TRUE(r["result"]["clamped"].get<bool>()) << r.dump();
      for (int other = 0; other < 3; ++other) {
        if (other == axis) continue;
        EXPECT_DOUBLE_EQ(pos(s, "commanded", other), pos(before, "commanded", other)) << "only " << name << " moves";
      }
    }
    // Once at the limit, a further jog outward moves nothing and says so.
    const json again = p.call("jog", {{"axis", name}, {"distance", -5.0}});
    ASSERT_TRUE(again.contains("result")) << again.dump();
    EXPECT_FALSE(again["result"]["moved"].get<bool>());
    EXPECT_NEAR(pos(p.status(), "commanded", axis), m.axes[axis].travel_min_mm, 1e-9);
  }
}

TEST(ServiceSocket, ContinuousJogKeepAliveStopDeadmanDisconnectAndLimit) {
  ServicePair p("sock-cjog");
  ASSERT_TRUE(p.start("real")) << p.host_log();
  const MachineConfig m = mill_config();
  const double x0 = m.axes[0].home_mm;

  {  // kept alive, then jog_stop: it moved, it stopped before the limit
    CtlClient c(p.socket());
    ASSERT_TRUE(c.call("jog", {{"axis", "X"}, {"continuous", true}, {"direction", "+"}, {"feed", 120}}).contains("result"));
    for (int i = 0; i < 6; ++i) {
      std::this_thread::sleep_for(100ms);
      ASSERT_TRUE(c.call("jog_keepalive").contains("result")) << "the jog is still ours";
    }
    ASSERT_TRUE(c.call("jog_stop").contains("result"));
    const json s = p.wait_status([](const json& x) { return x["state"] == "IDLE"; }, 10);
    EXPECT_EQ(s["state"], "IDLE");
    EXPECT_GT(pos(s, "commanded", 0), x0 + 0.5) << "moved while kept alive (2 mm/s for 0.6 s)";
    EXPECT_LT(pos(s, "commanded", 0), m.axes[0].travel_max_mm - 5.0) << "and stopped on jog_stop";
  }
  {  // no keep-alive: the deadman stops it
    const double start = pos(p.status(), "commanded", 1);
    CtlClient c(p.socket());
    ASSERT_TRUE(c.call("jog", {{"axis", "Y"}, {"continuous", true}, {"direction", "-"}, {"feed", 60}}).contains("result"));
    const json s = p.wait_status([](const json& x) { return x["state"] == "IDLE" && !x["jog"]["continuous"].get<bool>(); }, 10);
    EXPECT_EQ(s["state"], "IDLE") << "stopped by the deadman while the client stayed connected";
    EXPECT_LT(pos(s, "commanded", 1), start) << "it did move";
    EXPECT_GT(pos(s, "commanded", 1), m.axes[1].travel_min_mm + 5.0) << "but stopped long before the limit";
    EXPECT_EQ(error_code(c.call("jog_keepalive")), rpc::kRefused) << "the jog is over";
  }
  {  // the client disconnects: the jog stops
    const double start = pos(p.status(), "commanded", 2);
    {
      CtlClient c(p.socket());
      ASSERT_TRUE(c.call("jog", {{"axis", "Z"}, {"continuous", true}, {"direction", -1}, {"feed", 60}}).contains("result"));
      std::this_thread::sleep_for(100ms);
    }  // closed here
    const json s = p.wait_status([](const json& x) { return x["state"] == "IDLE"; }, 10);
    EXPECT_EQ(s["state"], "IDLE");
    EXPECT_LT(pos(s, "commanded", 2), start);
    EXPECT_GT(pos(s, "commanded", 2), m.axes[2].travel_min_mm + 5.0);
    EXPECT_NE(p.host_log().find("its client disconnected"), std::string::npos) << p.host_log();
  }
  {  // kept alive all the way: it stops exactly at the soft limit
    CtlClient c(p.socket());
    const double feed = m.axes[0].max_velocity_mm_s * 60.0;
    ASSERT_TRUE(c.call("jog", {{"axis", "X"}, {"continuous", true}, {"direction", "-"}, {"feed", feed}}).contains("result"));
    json s;
    for (int i = 0; i < 400; ++i) {
      std::this_thread::sleep_for(50ms);
      s = c.call("status")["result"];
      if (s["state"] == "IDLE") break;
      c.call("jog_keepalive");
    }
    EXPECT_EQ(s["state"], "IDLE");
    EXPECT_NEAR(pos(s, "commanded", 0), m.axes[0].travel_min_mm, 1e-9) << "continuous jog ends at the soft limit";
  }
}

// ---------------------------------------------------------------- programs

TEST(ServiceSocket, RunCompletesAndPreflightErrorsAreReturned) {
  ServicePair p("sock-run");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  const json r = p.call("run", {{"file", source_dir() + "/examples/demo.ngc"}});
  ASSERT_TRUE(r.contains("result")) << r.dump();
  EXPECT_TRUE(r["result"]["started"].get<bool>());
  const json s = p.wait_status([](const json& x) { return idle(x) && x["last_job"].is_object(); }, 120);
  ASSERT_TRUE(s["last_job"].is_object()) << s.dump();
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_TRUE(s["program_done"].get<bool>());
  const Vec3 expected{12.5, 12.5, 24.0};  // demo.ngc ends at program X0 Y0 Z-1
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(pos(s, "commanded", i), expected[i], 1e-6);

  const std::string bad = write_program(p.dir(), "bad.ngc", "G21 G90 G54\nG01 X1 Y1 F300\nG01 X2 Q7\nG01 X40\nM30\n");
  const json e = p.call("run", {{"file", bad}});
  EXPECT_EQ(error_code(e), rpc::kPreflightFailed) << e.dump();
  ASSERT_TRUE(e["error"]["data"]["errors"].is_array());
  EXPECT_GE(e["error"]["data"]["errors"].size(), 1u);
  EXPECT_NE(e["error"]["data"]["errors"][0].get<std::string>().find("bad.ngc:3:"), std::string::npos) << e.dump();
  EXPECT_EQ(error_code(p.call("run", {{"file", "examples/demo.ngc"}})), rpc::kInvalidParams) << "relative paths are refused";
  EXPECT_EQ(error_code(p.call("run", {{"file", p.dir() + "/missing.ngc"}})), rpc::kPreflightFailed);
  EXPECT_EQ(p.status()["state"], "IDLE") << "nothing moved";
}

TEST(ServiceSocket, SetOffsetIsUsedByLaterRuns) {
  ServicePair p("sock-offset");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  const json o = p.call("set_offset", {{"offset", "G55"}, {"x", 5.0}, {"y", 6.0}, {"z", 20.0}});
  ASSERT_TRUE(o.contains("result")) << o.dump();
  EXPECT_EQ(p.status()["work_offsets"]["G55"]["y"], 6.0);
  const std::string prog = write_program(p.dir(), "g55.ngc", "G21 G90\nG01 X1 Y2 Z-1 F600\nG01 X3\nM30\n");
  ASSERT_TRUE(p.call("run", {{"file", prog}, {"work_offset", "G55"}}).contains("result"));
  const json s = p.wait_status([](const json& x) { return idle(x) && x["last_job"].is_object(); }, 60);
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_NEAR(pos(s, "commanded", 0), 8.0, 1e-6);
  EXPECT_NEAR(pos(s, "commanded", 1), 8.0, 1e-6);
  EXPECT_NEAR(pos(s, "commanded", 2), 19.0, 1e-6);
}

TEST(ServiceSocket, PauseResumeStopEstopAndRefusalsWhileRunning) {
  ServicePair p("sock-ops");
  ASSERT_TRUE(p.start("real")) << p.host_log();
  const std::string prog = zigzag_program(p.dir(), 6, 16.0, 600.0);  // ~20 s at F600
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  json s = p.wait_status([](const json& x) { return x["state"] == "RUNNING" && x["blocks_done"].get<int>() >= 2; }, 20);
  ASSERT_EQ(s["state"], "RUNNING") << s.dump();

  // Refusals while running.
  const json j = p.call("jog", {{"axis", "X"}, {"distance", 1}});
  EXPECT_EQ(error_code(j), rpc::kRefused);
  EXPECT_NE(error_message(j).find("RUNNING"), std::string::npos) << j.dump();
  EXPECT_EQ(error_code(p.call("run", {{"file", prog}})), rpc::kRefused) << "run while running";
  EXPECT_EQ(error_code(p.call("reset")), rpc::kRefused);

  // Override changes the path speed.
  ASSERT_TRUE(p.call("override", {{"percent", 50}}).contains("result"));
  s = p.wait_status([](const json& x) { return x["feed_override_percent"] == 50.0; }, 5);
  EXPECT_EQ(s["feed_override_percent"], 50.0);
  ASSERT_TRUE(p.call("override", {{"percent", 100}}).contains("result"));

  // Pause: at rest on the path; resume: moving again.
  ASSERT_TRUE(p.call("pause").contains("result"));
  s = p.wait_status([](const json& x) { return x["state"] == "PAUSED" && x["path_speed"] == 0.0; }, 10);
  ASSERT_EQ(s["state"], "PAUSED");
  const double held_x = pos(s, "commanded", 0);
  std::this_thread::sleep_for(200ms);
  EXPECT_DOUBLE_EQ(pos(p.status(), "commanded", 0), held_x) << "holds while paused";
  EXPECT_EQ(error_code(p.call("run", {{"file", prog}})), rpc::kRefused) << "run while paused";
  ASSERT_TRUE(p.call("resume").contains("result"));
  s = p.wait_status([](const json& x) { return x["state"] == "RUNNING" && x["path_speed"].get<double>() > 0.0; }, 10);
  EXPECT_EQ(s["state"], "RUNNING");

  // Stop: decelerates, flushes, back to IDLE; the program did not complete.
  ASSERT_TRUE(p.call("stop").contains("result"));
  s = p.wait_status([](const json& x) { return idle(x) && x["last_job"].is_object(); }, 20);
  EXPECT_EQ(s["state"], "IDLE");
  EXPECT_FALSE(s["program_done"].get<bool>());
  EXPECT_NE(s["last_job"]["end"], "completed") << s.dump();
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(pos(s, "following_error", i)), 0.05) << "a controlled stop";

  // E-stop during a run: ESTOP at once, the job ends, reset brings IDLE back.
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  p.wait_status([](const json& x) { return x["state"] == "RUNNING" && x["blocks_done"].get<int>() >= 1; }, 20);
  ASSERT_TRUE(p.call("estop").contains("result"));
  s = p.wait_status([](const json& x) { return x["state"] == "ESTOP" && !x["job"]["active"].get<bool>(); }, 10);
  EXPECT_EQ(s["state"], "ESTOP");
  EXPECT_EQ(s["last_job"]["end"], "fault") << s.dump();
  ASSERT_TRUE(p.call("reset").contains("result"));
  EXPECT_EQ(p.wait_status(idle, 5)["state"], "IDLE");
}

TEST(ServiceSocket, JogWhilePausedIsAllowed) {
  ServicePair p("sock-pjog");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  // M00 leaves the program PAUSED, deterministically.
  const std::string prog = write_program(p.dir(), "m0.ngc", "G21 G90 G54\nG01 X1 F600\nM00\nG01 X2\nM30\n");
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  json s = p.wait_status([](const json& x) { return x["state"] == "PAUSED"; }, 30);
  ASSERT_EQ(s["state"], "PAUSED") << s.dump();
  const json j = p.call("jog", {{"axis", "Z"}, {"distance", -1.0}});
  ASSERT_TRUE(j.contains("result")) << j.dump();
  s = p.wait_status([](const json& x) { return x["state"] == "PAUSED"; }, 30);
  EXPECT_NEAR(pos(s, "commanded", 2), 24.0, 1e-6);
  // Resume: the rt takes Z back up to the pause point, then the program completes.
  ASSERT_TRUE(p.call("resume").contains("result"));
  s = p.wait_status([](const json& x) { return idle(x) && x["last_job"].is_object(); }, 30);
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_NEAR(pos(s, "commanded", 2), 25.0, 1e-6);
}

TEST(ServiceSocket, StopDuringAJogWhilePausedEndsTheProgram) {
  ServicePair p("sock-pjstop");
  // the real clock: under the virtual clock the 10 s jog would be over in milliseconds,
  // before the test could see it move
  ASSERT_TRUE(p.start("real")) << p.host_log();
  const std::string prog = write_program(p.dir(), "m0.ngc", "G21 G90 G54\nG01 X1 F600\nM00\nG01 X2\nM30\n");
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  json s = p.wait_status([](const json& x) { return x["state"] == "PAUSED"; }, 30);
  ASSERT_EQ(s["state"], "PAUSED") << s.dump();
  // A long jog down in Z, stopped while it moves: one stop ends the jog and the program.
  ASSERT_TRUE(p.call("jog", {{"axis", "Z"}, {"distance", -10.0}, {"feed", 60.0}}).contains("result"));
  s = p.wait_status([](const json& x) { return x["state"] == "JOGGING"; }, 10);
  ASSERT_EQ(s["state"], "JOGGING") << s.dump();
  const json r = p.call("stop");
  ASSERT_TRUE(r.contains("result")) << r.dump();
  s = p.wait_status([](const json& x) { return idle(x) && x["last_job"].is_object(); }, 30);
  ASSERT_EQ(s["state"], "IDLE") << s.dump();
  EXPECT_NE(s["last_job"]["end"], "completed") << "the rest of the program was flushed: " << s.dump();
  const double z = pos(s, "commanded", 2);
  EXPECT_LT(z, 25.0) << "the machine stays where the jog stopped";
  EXPECT_GT(z, 15.0);
  EXPECT_NEAR(pos(s, "commanded", 0), 13.5, 1e-6) << "X stayed at the pause point";
}

// ---------------------------------------------------------------- several clients, subscriptions

TEST(ServiceSocket, SeveralClientsAndSubscriptions) {
  ServicePair p("sock-multi");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  std::vector<std::unique_ptr<CtlClient>> clients;
  for (int i = 0; i < 8; ++i) clients.push_back(std::make_unique<CtlClient>(p.socket()));
  // Interleaved requests on all connections: each gets its own reply.
  for (int round = 0; round < 3; ++round) {
    for (auto& c : clients) {
      const json r = c->call("status");
      ASSERT_TRUE(r.contains("result"));
      EXPECT_EQ(r["result"]["state"], "IDLE");
    }
  }
  // A subscriber receives pushed status objects; unsubscribing stops them.
  CtlClient& sub = *clients[0];
  int pushes = 0;
  sub.on_notification = [&](const json& n) {
    if (n["method"] == "status" && n["params"].contains("commanded")) ++pushes;
  };
  const json r = sub.call("subscribe", {{"rate_hz", 50}});
  ASSERT_TRUE(r.contains("result")) << r.dump();
  std::string line;
  for (int i = 0; i < 200 && pushes < 10; ++i) {
    if (sub.read_line(line, 5.0)) {
      const json n = json::parse(line);
      if (!n.contains("id")) sub.on_notification(n);
    }
  }
  EXPECT_GE(pushes, 10);
  ASSERT_TRUE(sub.call("subscribe", {{"rate_hz", 0}}).contains("result"));
  // After unsubscribing (and draining what was in flight), status calls get plain replies.
  EXPECT_TRUE(sub.call("status").contains("result"));
  // Other clients never saw pushes.
  clients[1]->on_notification = [](const json& n) { ADD_FAILURE() << "unexpected push " << n.dump(); };
  EXPECT_TRUE(clients[1]->call("status").contains("result"));
}

// ---------------------------------------------------------------- bad clients

// Raw socket without the client class (a client that misbehaves on purpose).
int raw_connect(const std::string& path) {
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  std::strncpy(a.sun_path, path.c_str(), sizeof a.sun_path - 1);
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0 || connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) return -1;
  return fd;
}

TEST(ServiceSocket, BadClientsDoNotDisturbARunningProgram) {
  ServicePair p("sock-bad");
  ASSERT_TRUE(p.start("real")) << p.host_log();
  // A program of ~8 s of 2 mm blocks at 10 mm/s (about 0.25 s each with the stop at every
  // corner; the 4-block ring holds about 1 s), so a host stalled by a client shows as underruns
  // while the ordinary scheduling noise of a loaded 2-core machine does not.
  std::string text = "G21 G90 G54\nG01 X-5 Y0 F600\n";
  for (int i = 0; i < 32; ++i) text += "G01 X" + std::to_string(-5.0 + 2.0 * ((i + 1) % 6)) + " Y" + std::to_string(i % 2 ? 0.0 : 0.3) + "\n";
  text += "M30\n";
  const std::string prog = write_program(p.dir(), "short.ngc", text);
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  p.wait_status([](const json& x) { return x["state"] == "RUNNING"; }, 10);

  CtlClient bad(p.socket());
  const std::pair<const char*, int> cases[] = {
      {"{not json", rpc::kParseError},
      {"[]", rpc::kInvalidRequest},
      {R"({"id":1,"method":"teleport"})", rpc::kMethodNotFound},
      {R"({"id":2,"method":"override","params":{"percent":"fast"}})", rpc::kInvalidParams},
      {R"({"id":3,"method":"jog","params":{"axis":"X","distance":1e9}})", rpc::kInvalidParams},
      {R"({"id":4,"method":"override","params":{"percent":1000}})", rpc::kInvalidParams},
      {R"({"id":5,"method":"jog","params":{"axis":"X","distance":1}})", rpc::kRefused},
      // issue 19: a number outside double range ended the host; a repeated key let the last win
      {R"({"id":7,"method":"status","x":1e309})", rpc::kParseError},
      {R"({"id":8,"method":"override","params":{"percent":-1e400}})", rpc::kParseError},
      {R"({"id":9,"method":"status","method":"estop"})", rpc::kInvalidRequest},
  };
  for (const auto& [text2, code] : cases) {
    bad.send_raw(std::string(text2) + "\n");
    std::string line;
    ASSERT_TRUE(bad.read_line(line, 10)) << text2;
    const json r = json::parse(line);
    EXPECT_EQ(error_code(r), code) << text2 << " -> " << line;
    EXPECT_FALSE(error_message(r).empty());
  }

  // A 10 MB line: an error reply, then the connection is closed; the writer never blocks the server.
  std::thread big([&] {
    const int fd = raw_connect(p.socket());
    ASSERT_GE(fd, 0);
    const std::string chunk(1 << 20, 'x');
    std::size_t sent = 0;
    for (int i = 0; i < 10; ++i) {
      const ssize_t n = send(fd, chunk.data(), chunk.size(), MSG_NOSIGNAL);
      if (n <= 0) break;  // the server closed on us
      sent += static_cast<std::size_t>(n);
    }
    char buf[4096];
    const ssize_t n = recv(fd, buf, sizeof buf - 1, 0);
    std::string reply = n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : "";
    EXPECT_NE(reply.find(std::to_string(rpc::kLineTooLong)), std::string::npos) << "got: " << reply;
    EXPECT_LT(sent, 10u << 20) << "the server stopped reading long before 10 MB";
    close(fd);
  });

  // A half-open client: floods requests and never reads its replies, until the server drops it.
  bool deaf_dropped = false;
  std::thread deaf([&] {
    const int fd = raw_connect(p.socket());
    ASSERT_GE(fd, 0);
    const std::string req = R"({"id":1,"method":"status"})" "\n";
    std::string burst;
    for (int i = 0; i < 200; ++i) burst += req;
    const auto give_up = std::chrono::steady_clock::now() + 30s;
    while (std::chrono::steady_clock::now() < give_up) {
      if (send(fd, burst.data(), burst.size(), MSG_NOSIGNAL | MSG_DONTWAIT) < 0 && errno != EAGAIN && errno != EINTR) {
        deaf_dropped = errno == EPIPE || errno == ECONNRESET;
        break;
      }
      std::this_thread::sleep_for(1ms);
    }
    close(fd);
  });

  // A flood from a client that does read: every request is answered, in order.
  CtlClient flood(p.socket());
  std::thread writer([&] {
    for (int i = 0; i < 2000; ++i) flood.send_raw("{\"id\":" + std::to_string(i) + ",\"method\":\"status\"}\n");
  });
  int answered = 0;
  std::string line;
  while (answered < 2000 && flood.read_line(line, 20)) {
    const json r = json::parse(line);
    EXPECT_EQ(r["id"], answered);
    ++answered;
  }
  EXPECT_EQ(answered, 2000);
  writer.join();

  big.join();
  deaf.join();
  EXPECT_TRUE(deaf_dropped) << "the client that never reads is disconnected";
  // Meanwhile a well-behaved client is served.
  EXPECT_TRUE(p.call("status").contains("result"));

  const json s = p.wait_status([](const json& x) { return idle(x) && x["last_job"].is_object(); }, 60);
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_EQ(s["underruns"], 0) << "no underrun while the bad clients were served: " << s.dump();
  EXPECT_EQ(s["last_job"]["underruns"], 0);
  EXPECT_NE(p.host_log().find("longer than 65536 bytes"), std::string::npos) << p.host_log();
  EXPECT_NE(p.host_log().find("does not read"), std::string::npos) << "the deaf client was dropped: " << p.host_log();
}

// ---------------------------------------------------------------- pcnc ctl

TEST(ServiceSocket, CtlCommandLine) {
  ServicePair p("sock-ctl");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  auto ctl = [&](const std::vector<std::string>& args) { return p.ctl(args); };
  ProcessResult r = ctl({"status"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("IDLE"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("attached"), std::string::npos) << r.out;

  r = ctl({"jog", "X", "+1.0", "--feed", "300"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("13.5000"), std::string::npos) << "prints where the jog ended: " << r.out;

  r = ctl({"status", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_DOUBLE_EQ(j["result"]["commanded"]["x"].get<double>(), 13.5);

  r = ctl({"override", "300"});
  EXPECT_EQ(r.exit_code, 2) << "the server refuses 300 % as a bad parameter: a bad command line";
  EXPECT_NE(r.err.find("out of range"), std::string::npos) << r.err;

  r = ctl({"set_offset", "G54", "--x", "13.5"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = ctl({"run", source_dir() + "/examples/demo.ngc", "--wait"});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("completed"), std::string::npos) << r.out;

  r = ctl({"reset"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("nothing to reset"), std::string::npos) << r.err;

  const ProcessResult none = run_process({pcnc_exe(), "ctl", "--socket", p.dir() + "/nobody.sock", "status"}, 30);
  EXPECT_EQ(none.exit_code, 3);
  EXPECT_NE(none.err.find("cannot connect"), std::string::npos) << none.err;
}

// `pcnc ctl run --offset X,Y,Z` places the program for this run and prints the placement it
// applied; a malformed value is refused before anything is sent.
TEST(ServiceSocket, CtlRunOffsetAndPlacement) {
  ServicePair p("sock-ctl-offset");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  auto ctl = [&](const std::vector<std::string>& args) { return p.ctl(args); };
  ProcessResult r = ctl({"run", source_dir() + "/examples/demo.ngc", "--offset", "13,12,24", "--wait"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("placement  machine = 1.000000 * program + (13.0000, 12.0000, 24.0000) mm"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("completed"), std::string::npos) << r.out;
  // the demo ends at program X0 Y0: the machine stands at the offset given
  r = ctl({"status", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_NEAR(j["result"]["commanded"]["x"].get<double>(), 13.0, 1e-9) << r.out;
  EXPECT_NEAR(j["result"]["commanded"]["y"].get<double>(), 12.0, 1e-9) << r.out;

  r = ctl({"run", source_dir() + "/examples/demo.ngc", "--fit", "--wait"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("placement  machine = "), std::string::npos) << "--fit prints the scale it applied: " << r.out;

  r = ctl({"run", source_dir() + "/examples/demo.ngc", "--offset", "13,12"});
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("expected X,Y,Z"), std::string::npos) << r.err;
}

// ---------------------------------------------------------------- permissions

mode_t socket_mode(const std::string& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) return 0;
  return st.st_mode & 0777;
}

TEST(ServiceSocket, SocketFileModeIsAsConfigured) {
  {
    ServicePair p("sock-mode600");
    ASSERT_TRUE(p.start_host()) << p.host_log();
    EXPECT_EQ(socket_mode(p.socket()), 0600u);
  }
  {
    ServicePair p("sock-mode660", {{"socket_mode = 0o600", "socket_mode = 0o660"}});
    ASSERT_TRUE(p.start_host()) << p.host_log();
    EXPECT_EQ(socket_mode(p.socket()), 0660u);
  }
}

// In a child: become `uid`, connect, read one line. Exit 0: refused with a permission error;
// 10: connect() itself was denied by the file mode; 20: served (bad); 30: cannot change uid.
int connect_as(uid_t uid, const std::string& path) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (setgroups(0, nullptr) != 0 || setgid(uid) != 0 || setuid(uid) != 0) _exit(30);
    const int fd = raw_connect(path);
    if (fd < 0) _exit(errno == EACCES ? 10 : 11);
    const std::string req = R"({"id":1,"method":"status"})" "\n";
    (void)!send(fd, req.data(), req.size(), MSG_NOSIGNAL);
    std::string got;
    char buf[4096];
    for (;;) {
      const ssize_t n = recv(fd, buf, sizeof buf, 0);
      if (n <= 0) break;
      got.append(buf, static_cast<std::size_t>(n));
    }
    if (got.find("\"result\"") != std::string::npos) _exit(20);
    _exit(got.find("permission denied") != std::string::npos ? 0 : 21);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(ServiceSocket, OtherUidIsRefused) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to run a client as another uid (setuid in a forked child)";
  const uid_t nobody = 65534;
  {
    // Mode 0666 lets the other uid reach the socket; SO_PEERCRED must refuse it.
    ServicePair p("sock-uid", {{"socket_mode = 0o600", "socket_mode = 0o666"}});
    ASSERT_EQ(chmod(p.dir().c_str(), 0755), 0);
    ASSERT_TRUE(p.start_host()) << p.host_log();
    const int r = connect_as(nobody, p.socket());
    if (r == 30) GTEST_SKIP() << "cannot switch to uid 65534 here";
    EXPECT_EQ(r, 0) << "the other uid must get a permission error and be disconnected";
    EXPECT_NE(p.host_log().find("refused connection from uid 65534"), std::string::npos) << p.host_log();
    EXPECT_TRUE(p.call("status").contains("result")) << "our own uid is served";
  }
  {
    // Mode 0600: the kernel already refuses the other uid at connect().
    ServicePair p("sock-uid2");
    ASSERT_EQ(chmod(p.dir().c_str(), 0755), 0);
    ASSERT_TRUE(p.start_host()) << p.host_log();
    EXPECT_EQ(connect_as(nobody, p.socket()), 10);
  }
}

}  // namespace
}  // namespace pcnc::test
