// test_proc_grbl_cncjs.cpp — end to end with a real sender: CNCjs (from npm, test-only:
// tests/e2e/README.md) runs headless against `pcnc grbl`'s pseudo-terminal; a node script
// drives it through its HTTP and socket.io API (load a program, start it) and takes a headless
// Chromium screenshot of its page; the run is verified in pcnc's own status. Skips with a
// message when CNCjs, node or Chromium is missing (tools/install-deps.sh installs them).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "ctl.hpp"
#include "grbl_sender.hpp"
#include "ipc/segment.hpp"
#include "subprocess.hpp"

namespace pcnc::test {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::string e2e_dir() {
  if (const char* d = std::getenv("PCNC_E2E_DIR")) return d;
  return std::string(PCNC_SOURCE_DIR) + "/.cache/e2e";
}

int free_tcp_port() {
  const int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
  getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
  close(s);
  return ntohs(a.sin_port);
}

bool listening(int port) {
  const int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool ok = connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  close(s);
  return ok;
}

TEST(ProcGrblCncjs, CncjsRunsAProgramOnThePort) {
  const std::string npm = e2e_dir() + "/node_modules";
  const std::string cncjs = npm + "/.bin/cncjs";
  if (access(cncjs.c_str(), X_OK) != 0 || !fs::exists(npm + "/socket.io-client") || !fs::exists(npm + "/playwright-core")) {
    GTEST_SKIP() << "CNCjs test packages not installed in " << e2e_dir() << " (tools/install-deps.sh installs them)";
  }
  if (access("/usr/bin/node", X_OK) != 0) GTEST_SKIP() << "node is not installed (Debian package nodejs)";
  if (access("/usr/bin/chromium", X_OK) != 0) GTEST_SKIP() << "chromium is not installed (Debian package chromium)";

  const std::string tag = "grbl-cncjs";
  const std::string dir = make_temp_dir(tag);
  // Chromium's start-up may starve pcnc-host on a loaded 2-core machine for more than 100 ms.
  const std::string config = write_test_config(dir, tag, {{"host_timeout_s = 0.1", "host_timeout_s = 2.0"}});
  auto grbl = start_grbl(config, dir);
  for (int i = 0; i < 600 && !fs::exists(grbl->link); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(fs::exists(grbl->link)) << grbl->proc.err();

  // CNCjs's configuration in a temporary HOME; a udevadm that lists nothing (the container
  // has no udev: without it CNCjs lists no port at all, not even the configured one).
  const std::string home = dir + "/home", bin = dir + "/bin";
  fs::create_directories(home);
  fs::create_directories(bin);
  std::ofstream(bin + "/udevadm") << "#!/bin/sh\nexit 0\n";
  fs::permissions(bin + "/udevadm", fs::perms::owner_all);
  std::ofstream(home + "/.cncrc") << json{{"ports", json::array({json{{"path", grbl->link}, {"manufacturer", "pcnc"}}})},
                                          {"allowRemoteAccess", true}}
                                         .dump();
  const int port = free_tcp_port();
  BackgroundProcess server = start_process({"/usr/bin/env", "HOME=" + home, "PATH=" + bin + ":/usr/bin:/bin", cncjs, "--port",
                                            std::to_string(port), "--host", "127.0.0.1", "--allow-remote-access", "-c",
                                            home + "/.cncrc"},
                                           dir + "/cncjs");
  Reaped reap_server{server};
  for (int i = 0; i < 1200 && !listening(port); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(listening(port)) << server.err();

  // A square 5 mm, ending at program X5 Y5 (machine 17.5, 17.5 with the default G54).
  const std::string program = dir + "/square.nc";
  std::ofstream(program) << "G21 G90\nG0 X0 Y0\nG1 X5 Y0 F1200\nG1 X5 Y5\nG1 X0 Y5\nG1 X0 Y0\nG1 X5 Y5\nM30\n";
  const std::string shot = dir + "/cncjs.png";
  const auto r = run_process({"/usr/bin/env", "NODE_PATH=" + npm, "/usr/bin/node", std::string(PCNC_SOURCE_DIR) + "/tests/e2e/cncjs_run.js",
                              std::to_string(port), grbl->link, program, shot},
                             300.0);
  kill(server.pid, SIGTERM);
  ASSERT_FALSE(r.out.empty()) << r.err;
  const json result = json::parse(r.out.substr(0, r.out.find('\n')), nullptr, false);
  ASSERT_TRUE(result.is_object()) << r.out << r.err;
  EXPECT_TRUE(result.value("ok", false)) << result.dump() << "\n" << r.err;
  EXPECT_EQ(result.value("received", -1), result.value("lines", -2)) << "CNCjs had every line acknowledged";
  EXPECT_TRUE(result.value("page_mentions_port", false)) << "the page shows the connected port";

  // The run, as pcnc saw it: the machine at the program's end point, no fault.
  CtlClient c(dir + "/pcnc.sock");
  const json st = c.call("status")["result"];
  EXPECT_NEAR(st["actual"]["x"].get<double>(), 17.5, 0.01) << st.dump();
  EXPECT_NEAR(st["actual"]["y"].get<double>(), 17.5, 0.01);
  EXPECT_EQ(st["fault"], "none");
  ASSERT_TRUE(fs::exists(shot));
  EXPECT_GT(fs::file_size(shot), 20000u) << "a rendered page, not a blank one";
  std::printf("CNCjs screenshot: %s (%ju bytes)\n", shot.c_str(), static_cast<std::uintmax_t>(fs::file_size(shot)));
  if (std::getenv("PCNC_E2E_SCREENSHOT")) fs::copy_file(shot, std::getenv("PCNC_E2E_SCREENSHOT"), fs::copy_options::overwrite_existing);
  remove_segment(test_shm_name(tag));
}

}  // namespace
}  // namespace pcnc::test
