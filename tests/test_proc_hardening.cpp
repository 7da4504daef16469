// test_proc_hardening.cpp — pcnc-host --serve against bad input and bad neighbours (issue 19),
// on real processes and real sockets: program files that are not regular files.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "gcode/program.hpp"
#include "service/rpc.hpp"
#include "service_procs.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

using namespace std::chrono_literals;
using steady = std::chrono::steady_clock;

int error_code(const json& reply) { return reply.contains("error") ? reply["error"]["code"].get<int>() : 0; }
std::string error_message(const json& reply) { return reply.contains("error") ? reply["error"]["message"].get<std::string>() : ""; }
double seconds_since(steady::time_point t0) { return std::chrono::duration<double>(steady::now() - t0).count(); }

// ---------------------------------------------------------------- 2. run: regular files only

TEST(RunFile, CheckRefusesAFifoWithoutBlocking) {
  const std::string dir = make_temp_dir("hard-fifo-check");
  const std::string fifo = dir + "/prog.ngc";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const auto t0 = steady::now();
  const CheckResult c = check_program(fifo, load_config(default_config()), JobOptions{});
  EXPECT_LT(seconds_since(t0), 1.0) << "opening a FIFO with no writer must not wait";
  EXPECT_FALSE(c.ok);
  EXPECT_NE(program_file_problem(fifo).find("FIFO"), std::string::npos) << program_file_problem(fifo);
  EXPECT_NE(program_file_problem("/dev/zero").find("character device"), std::string::npos);
  EXPECT_NE(program_file_problem(dir).find("directory"), std::string::npos);
  EXPECT_EQ(program_file_problem(source_dir() + "/examples/demo.ngc"), "");
}

TEST(RunFile, FifoDevZeroAndDirectoryAreRefusedAndTheServiceAnswersAtOnce) {
  ServicePair p("hard-fifo");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  const std::string fifo = p.dir() + "/prog.ngc";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  for (const auto& [file, what] : std::vector<std::pair<std::string, std::string>>{
           {fifo, "FIFO"}, {"/dev/zero", "character device"}, {p.dir(), "directory"}}) {
    const auto t0 = steady::now();
    const json r = p.call("run", {{"file", file}}, 5.0);
    EXPECT_LT(seconds_since(t0), 1.0) << file;
    EXPECT_EQ(error_code(r), rpc::kInvalidParams) << r.dump();
    EXPECT_NE(error_message(r).find(what), std::string::npos) << r.dump();
    EXPECT_NE(error_message(r).find("regular file"), std::string::npos) << r.dump();
    const auto t1 = steady::now();
    const json s = p.status();
    EXPECT_EQ(s["state"], "IDLE");
    EXPECT_FALSE(s["job"]["active"].get<bool>()) << "no job was started for " << file;
    EXPECT_TRUE(p.call("stop").contains("result"));
    EXPECT_LT(seconds_since(t1), 1.0) << "status and stop answered at once after " << file;
  }
  // The service still runs programs.
  ASSERT_TRUE(p.call("run", {{"file", source_dir() + "/examples/demo.ngc"}}).contains("result"));
}

}  // namespace
}  // namespace pcnc::test
