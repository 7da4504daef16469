// test_proc_hardening.cpp — pcnc-host --serve against bad input and bad neighbours (issue 19),
// on real processes and real sockets: program files that are not regular files, runtime
// directories and files another user could tamper with, connection limits and idle clients,
// group membership through supplementary groups, and the journal under write failures.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <grp.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include "config/config.hpp"
#include "config/runtime_paths.hpp"
#include "gcode/program.hpp"
#include "ipc/segment.hpp"
#include "service/job_journal.hpp"
#include "service/sha256.hpp"
#include "service/rpc.hpp"
#include "service_procs.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

using namespace std::chrono_literals;
using steady = std::chrono::steady_clock;

double seconds_since(steady::time_point t0) { return std::chrono::duration<double>(steady::now() - t0).count(); }


// ---------------------------------------------------------------- 1. runtime files

bool is_root() { return geteuid() == 0; }
constexpr uid_t kNobody = 65534;

// pcnc-host --serve with this config is refused at start with a message containing `what`.
void expect_host_refuses(const std::string& config, const std::string& what) {
  const ProcessResult r = run_process({host_exe(), "--config", config, "--serve"}, 10.0);
  EXPECT_FALSE(r.timed_out) << "the service started instead of refusing: " << r.err;
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
}

TEST(RuntimeFiles, ASymlinkPlantedAtTheJournalTempFileIsNotFollowed) {
  const std::string dir = make_temp_dir("hard-jsym");
  const std::string target = dir + "/precious";
  std::ofstream(target) << "do not touch\n";
  const std::string journal = journal_path(dir);
  ASSERT_EQ(symlink(target.c_str(), (journal + ".tmp").c_str()), 0);
  JobJournal j;
  j.file = "/some/program.ngc";
  std::string err;
  ASSERT_TRUE(write_journal(journal, j, &err)) << err;
  EXPECT_EQ(read_file(target), "do not touch\n") << "the symlink's target is untouched";
  struct stat st {};
  ASSERT_EQ(lstat(journal.c_str(), &st), 0);
  EXPECT_TRUE(S_ISREG(st.st_mode));
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  auto back = read_journal(journal, &err);
  ASSERT_TRUE(back) << err;
  EXPECT_EQ(back->file, j.file);
  EXPECT_NE(lstat((journal + ".tmp").c_str(), &st), 0) << "no temporary file left";
  // A symlink at the journal's own name is neither read through nor written through.
  ASSERT_EQ(unlink(journal.c_str()), 0);
  ASSERT_EQ(symlink(target.c_str(), journal.c_str()), 0);
  EXPECT_FALSE(read_journal(journal, &err));
  ASSERT_TRUE(write_journal(journal, j, &err)) << err;
  EXPECT_EQ(read_file(target), "do not touch\n");
}

TEST(RuntimeFiles, SocketDirectoryWritableByOthersIsRefused) {
  const std::string dir = make_temp_dir("hard-ww");
  const std::string ww = dir + "/open";
  ASSERT_EQ(mkdir(ww.c_str(), 0700), 0);
  ASSERT_EQ(chmod(ww.c_str(), 0777), 0);
  const std::string cfg =
      write_test_config(dir, "hard-ww", {{"socket_path = \"" + dir + "/pcnc.sock\"", "socket_path = \"" + ww + "/pcnc.sock\""}});
  expect_host_refuses(cfg, "writable by group or others without the sticky bit");
  struct stat st {};
  EXPECT_NE(lstat((ww + "/pcnc.sock").c_str(), &st), 0) << "no socket was created";
}

TEST(RuntimeFiles, SocketDirectoryOwnedByAnotherUidIsRefused) {
  if (!is_root()) GTEST_SKIP() << "needs root to give a directory to another uid (65534)";
  const std::string dir = make_temp_dir("hard-other");
  const std::string theirs = dir + "/theirs";
  ASSERT_EQ(mkdir(theirs.c_str(), 0755), 0);
  ASSERT_EQ(chown(theirs.c_str(), kNobody, kNobody), 0);
  const std::string cfg = write_test_config(
      dir, "hard-other", {{"socket_path = \"" + dir + "/pcnc.sock\"", "socket_path = \"" + theirs + "/pcnc.sock\""}});
  expect_host_refuses(cfg, "owned by uid 65534");
}

TEST(RuntimeFiles, SocketSquattedInTmpByAnotherUidIsRefused) {
  if (!is_root()) GTEST_SKIP() << "needs root to create a file as another uid (65534)";
  const std::string dir = make_temp_dir("hard-squat");
  const std::string squat = "/tmp/pcnc-test-squat-" + std::to_string(getpid()) + ".sock";
  std::ofstream(squat) << "";
  ASSERT_EQ(chown(squat.c_str(), kNobody, kNobody), 0);
  const std::string cfg =
      write_test_config(dir, "hard-squat", {{"socket_path = \"" + dir + "/pcnc.sock\"", "socket_path = \"" + squat + "\""}});
  expect_host_refuses(cfg, "belongs to uid 65534");
  unlink(squat.c_str());
}

TEST(RuntimeFiles, StateDirectoryWritableByGroupOrAnotherUsersIsRefused) {
  const std::string dir = make_temp_dir("hard-state");
  const std::string state = dir + "/shared-state";
  ASSERT_EQ(mkdir(state.c_str(), 0700), 0);
  ASSERT_EQ(chmod(state.c_str(), 0770), 0);
  const std::string cfg = write_test_config(dir, "hard-state", {{"state_dir = \"" + dir + "/state\"", "state_dir = \"" + state + "\""}});
  expect_host_refuses(cfg, "writable by group or others");
  // A symlink in place of the state directory is refused too.
  ASSERT_EQ(chmod(state.c_str(), 0700), 0);
  const std::string link = dir + "/linked-state";
  ASSERT_EQ(symlink(state.c_str(), link.c_str()), 0);
  const std::string cfg2 = write_test_config(dir, "hard-state", {{"state_dir = \"" + dir + "/state\"", "state_dir = \"" + link + "\""}});
  expect_host_refuses(cfg2, "symbolic link");
}

TEST(RuntimeFiles, DefaultSocketInTheRuntimeDirectoryFoundByCtl) {
  const std::string dir = make_temp_dir("hard-rtdir");
  const std::string name = "pcnc-test-rtdir-" + std::to_string(getpid());
  const std::string cfg = write_test_config(dir, "hard-rtdir", {{"socket_path = \"" + dir + "/pcnc.sock\"", "# socket_path unset"},
                                                                {"name = \"desktop-mill\"", "name = \"" + name + "\""}});
  const MachineConfig m = load_config(cfg);
  const std::string runtime = default_runtime_dir(m);
  EXPECT_EQ(control_socket_path(m), runtime + "/control.sock");
  EXPECT_EQ(runtime.rfind("/tmp/pcnc-test", 0), std::string::npos);
  BackgroundProcess host = start_process({host_exe(), "--config", cfg, "--serve"}, dir + "/host");
  bool up = false;
  for (int i = 0; i < 200 && !up; ++i) {
    std::this_thread::sleep_for(50ms);
    up = run_process({pcnc_exe(), "ctl", "--config", cfg, "--json", "status"}, 10.0).exit_code == 0;
  }
  EXPECT_TRUE(up) << host.err();
  struct stat st {};
  ASSERT_EQ(lstat(runtime.c_str(), &st), 0);
  EXPECT_TRUE(S_ISDIR(st.st_mode));
  EXPECT_EQ(st.st_mode & 07777, 0750u);
  EXPECT_EQ(st.st_uid, geteuid());
  EXPECT_EQ(st.st_gid, getegid()) << "no socket_group: our group";
  kill(host.pid, SIGTERM);
  EXPECT_EQ(host.wait(10.0), 0) << host.err();
  rmdir(runtime.c_str());
}

TEST(RuntimeFiles, CtlOfAGroupMemberFindsARootServicesSocket) {
  if (!is_root()) GTEST_SKIP() << "needs root to create /run/pcnc/<machine> and to run a client as uid 65534";
  const std::string name = "pcnc-test-find-" + std::to_string(getpid());
  MachineConfig m = load_config(default_config());
  m.name = name;
  m.process.socket_path.clear();
  const std::string runtime = "/run/pcnc/" + name;
  const gid_t group = 4242;  // the socket group; the client below is a member
  ensure_private_dir(runtime, 0750, group);
  const std::string sock = runtime + "/control.sock";
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, sock.c_str(), sizeof addr.sun_path - 1);
  ASSERT_EQ(bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
  EXPECT_EQ(find_control_socket(m), sock) << "root: its own default";
  const pid_t pid = fork();
  if (pid == 0) {
    unsetenv("XDG_RUNTIME_DIR");
    if (setgroups(1, &group) != 0 || setgid(kNobody) != 0 || setuid(kNobody) != 0) _exit(3);
    _exit(find_control_socket(m) == sock ? 0 : 1);
  }
  int st = 0;
  waitpid(pid, &st, 0);
  EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << "a group member falls back to the root service's socket";
  close(fd);
  unlink(sock.c_str());
  rmdir(runtime.c_str());
}

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

// ---------------------------------------------------------------- raw sockets

int connect_raw(const std::string& path) {
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
  if (fd < 0 || connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    if (fd >= 0) close(fd);
    return -1;
  }
  return fd;
}

// ---------------------------------------------------------------- 3. connection limits

TEST(ConnectionLimits, AFullTableStillServesEstopAndStatus) {
  ServicePair p("hard-full");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  // 64 idle connections, all in the normal table. One accepted while the service had not yet
  // reaped an earlier (closed) status connection becomes a reserve connection and is closed
  // after 2 s of silence: such ones are replaced until all 64 stay open past that timeout.
  std::vector<int> idle;
  for (int i = 0; i < 64; ++i) {
    const int fd = connect_raw(p.socket());
    ASSERT_GE(fd, 0) << i;
    idle.push_back(fd);
  }
  for (int round = 0;; ++round) {
    ASSERT_LT(round, 5) << "idle connections keep being closed";
    std::this_thread::sleep_for(2500ms);
    int replaced = 0;
    for (int& fd : idle) {
      pollfd pfd{fd, POLLIN, 0};
      if (poll(&pfd, 1, 0) == 0) continue;  // still open and silent: a normal connection
      close(fd);
      fd = connect_raw(p.socket());
      ASSERT_GE(fd, 0);
      ++replaced;
    }
    if (replaced == 0) break;
  }
  const auto t0 = steady::now();
  const json e = p.call("estop", json::object(), 5.0);
  ASSERT_TRUE(e.contains("result")) << e.dump() << p.host_log();
  EXPECT_EQ(e["result"]["state"], "ESTOP");
  // The rt applies the e-stop on its next cycle: status shows it within moments.
  json s;
  for (int i = 0; i < 100; ++i) {
    s = p.call("status", json::object(), 5.0);
    ASSERT_TRUE(s.contains("result")) << s.dump();
    if (s["result"]["state"] == "ESTOP") break;
    std::this_thread::sleep_for(10ms);
  }
  EXPECT_EQ(s["result"]["state"], "ESTOP");
  EXPECT_TRUE(p.call("stop", json::object(), 5.0).contains("result"));
  EXPECT_LT(seconds_since(t0), 2.0);
  // Anything else is refused with a clear error while the table is full.
  const json r = p.call("reset", json::object(), 5.0);
  EXPECT_EQ(error_code(r), rpc::kServerFull) << r.dump();
  EXPECT_NE(error_message(r).find("only stop, estop and status"), std::string::npos) << r.dump();
  // A slot freed: every request is served again.
  close(idle.back());
  idle.pop_back();
  std::this_thread::sleep_for(200ms);
  EXPECT_TRUE(p.call("reset", json::object(), 5.0).contains("result"));
  for (int fd : idle) close(fd);
  std::cout << "[ figures  ] 64 idle connections: estop, status and stop answered in " << seconds_since(t0) << " s\n";
}

TEST(ConnectionLimits, AnIdleConnectionIsClosedAfterTheTimeout) {
  ServicePair p("hard-idle", {{"client_idle_timeout_s = 60.0", "client_idle_timeout_s = 0.5"}});
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  const int silent = connect_raw(p.socket());
  ASSERT_GE(silent, 0);
  // A subscriber is not idle, and neither is a client that keeps asking.
  CtlClient sub(p.socket());
  ASSERT_TRUE(sub.call("subscribe", {{"rate_hz", 0.5}}).contains("result"));
  CtlClient chatty(p.socket());
  const auto t0 = steady::now();
  bool closed = false;
  double closed_after = 0.0;
  std::string got;
  while (!closed && seconds_since(t0) < 3.0) {
    ASSERT_TRUE(chatty.call("status").contains("result")) << "a client that keeps asking stays connected";
    char buf[4096];
    const ssize_t n = recv(silent, buf, sizeof buf, MSG_DONTWAIT);
    if (n > 0) got.append(buf, static_cast<std::size_t>(n));
    if (n == 0) {
      closed = true;
      closed_after = seconds_since(t0);
    }
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_TRUE(closed) << "the silent connection is closed";
  EXPECT_GT(closed_after, 0.3);
  EXPECT_LT(closed_after, 2.0);
  EXPECT_NE(got.find("\"code\":8"), std::string::npos) << got;
  EXPECT_NE(got.find("client_idle_timeout_s"), std::string::npos) << got;
  close(silent);
  std::this_thread::sleep_for(1000ms);  // twice the timeout without a request from the subscriber
  EXPECT_TRUE(sub.call("status").contains("result")) << "the subscriber was not closed";
}

// ---------------------------------------------------------------- 4. supplementary groups

// In a forked child: drop to uid/gid 65534 with `groups` as the supplementary groups, send a
// status request on `path`. Exit 0 on a result, 5 on permission denied, 1 otherwise.
int status_as_nobody(const std::string& path, const std::vector<gid_t>& groups) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (setgroups(groups.size(), groups.data()) != 0 || setgid(kNobody) != 0 || setuid(kNobody) != 0) _exit(3);
    const int fd = connect_raw(path);
    if (fd < 0) _exit(4);
    const char req[] = "{\"id\":1,\"method\":\"status\"}\n";
    // A refused peer's send may fail (the server has already written its refusal and closed):
    // the refusal is still in this socket's receive queue, so read it whatever send said.
    (void)send(fd, req, sizeof req - 1, MSG_NOSIGNAL);
    const timeval limit{5, 0};  // a server that never answers fails the test, never hangs it
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &limit, sizeof limit);
    std::string got;
    char buf[4096];
    for (;;) {  // up to the end of the first line (a status reply is longer than one read)
      const ssize_t n = recv(fd, buf, sizeof buf, 0);
      if (n <= 0) break;
      got.append(buf, static_cast<std::size_t>(n));
      if (got.find('\n') != std::string::npos) break;
    }
    if (got.find("\"result\"") != std::string::npos) _exit(0);
    if (got.find("\"code\":5") != std::string::npos) _exit(5);
    _exit(1);
  }
  int st = 0;
  waitpid(pid, &st, 0);
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

TEST(SocketGroup, ASupplementaryGroupMemberMayConnect) {
  if (!is_root()) GTEST_SKIP() << "needs root to start a client as another uid (65534) with chosen groups";
  const gid_t group = 4242;  // a gid no one has as primary group
  // Mode 0666 and a traversable directory let any uid reach the socket, so that the service's
  // own check (SO_PEERCRED, then the peer's groups) decides, not the file mode.
  ServicePair p("hard-group", {{"socket_mode = 0o600", "socket_mode = 0o666\nsocket_group = \"4242\""}});
  ASSERT_EQ(chmod(p.dir().c_str(), 0755), 0);
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  struct stat st {};
  ASSERT_EQ(stat(p.socket().c_str(), &st), 0);
  EXPECT_EQ(st.st_gid, group) << "the socket belongs to the socket group";
  EXPECT_EQ(st.st_mode & 0777, 0666u);
  EXPECT_EQ(status_as_nobody(p.socket(), {group}), 0) << "a member through a supplementary group is admitted\n" << p.host_log();
  EXPECT_EQ(status_as_nobody(p.socket(), {100, group}), 0) << "anywhere in the list";
  EXPECT_EQ(status_as_nobody(p.socket(), {100}), 5) << "a non-member is refused";
  EXPECT_EQ(status_as_nobody(p.socket(), {}), 5);
  EXPECT_EQ(p.status()["state"], "IDLE");
}

// ---------------------------------------------------------------- 5. the journal

TEST(Journal, AFailedWriteLeavesTheOldJournalIntact) {
  const std::string dir = make_temp_dir("hard-jfail");
  const std::string journal = journal_path(dir);
  JobJournal good;
  good.file = "/the/good/program.ngc";
  good.seq_base = 42;
  std::string err;
  ASSERT_TRUE(write_journal(journal, good, &err)) << err;
  const std::string before = read_file(journal);
  // Something the writer cannot remove sits at the temporary name (as a full or read-only
  // file system would make the write fail): a directory with a file in it.
  ASSERT_EQ(mkdir((journal + ".tmp").c_str(), 0700), 0);
  std::ofstream(journal + ".tmp/x") << "x";
  JobJournal next;
  next.file = "/another.ngc";
  EXPECT_FALSE(write_journal(journal, next, &err));
  EXPECT_NE(err.find("left as it was"), std::string::npos) << err;
  EXPECT_EQ(read_file(journal), before) << "the old journal is intact";
  auto back = read_journal(journal, &err);
  ASSERT_TRUE(back) << err;
  EXPECT_EQ(back->seq_base, 42u);
  if (!is_root()) {
    // A state directory without write permission.
    ASSERT_EQ(std::filesystem::remove_all(journal + ".tmp"), 2u);
    ASSERT_EQ(chmod(dir.c_str(), 0500), 0);
    EXPECT_FALSE(write_journal(journal, next, &err));
    EXPECT_EQ(read_file(journal), before);
    chmod(dir.c_str(), 0700);
  }
}

// A disk that fills up in the middle of the write: RLIMIT_FSIZE makes write() fail (EFBIG)
// past a few bytes, as ENOSPC would. The old journal must survive, not be replaced by the
// part that was written.
TEST(Journal, ADiskFullInTheMiddleOfTheWriteLeavesTheOldJournalIntact) {
  const std::string dir = make_temp_dir("hard-jfull");
  const std::string journal = journal_path(dir);
  JobJournal good;
  good.file = "/the/good/program.ngc";
  good.seq_base = 7;
  std::string err;
  ASSERT_TRUE(write_journal(journal, good, &err)) << err;
  const std::string before = read_file(journal);
  ASSERT_GT(before.size(), 200u);
  const pid_t pid = fork();
  if (pid == 0) {
    signal(SIGXFSZ, SIG_IGN);
    const rlimit lim{100, 100};
    if (setrlimit(RLIMIT_FSIZE, &lim) != 0) _exit(3);
    JobJournal next;
    next.file = "/a/much/longer/path/to/another/program/that/does/not/fit.ngc";
    std::string e;
    _exit(write_journal(journal, next, &e) ? 1 : (e.find("cannot write") != std::string::npos ? 0 : 2));
  }
  int st = 0;
  waitpid(pid, &st, 0);
  ASSERT_TRUE(WIFEXITED(st));
  EXPECT_EQ(WEXITSTATUS(st), 0) << "the write must fail and say so";
  EXPECT_EQ(read_file(journal), before) << "the old journal is intact";
  struct stat sb {};
  EXPECT_NE(lstat((journal + ".tmp").c_str(), &sb), 0) << "the partial temporary file is removed";
}

TEST(Journal, RecordsTheProgramsHashAndOptions) {
  const std::string dir = make_temp_dir("hard-jrec");
  const std::string journal = journal_path(dir);
  JobJournal j;
  j.file = "/p.ngc";
  j.file_sha256 = std::string(64, 'a');
  j.transform_offset = {1, 2, 3};
  j.transform_scale = 0.5;
  j.path_tolerance_mm = 0.01;
  j.contouring = 1;
  j.fit = true;
  j.work_offset = 2;
  std::string err;
  ASSERT_TRUE(write_journal(journal, j, &err)) << err;
  auto b = read_journal(journal, &err);
  ASSERT_TRUE(b) << err;
  EXPECT_EQ(b->file_sha256, j.file_sha256);
  EXPECT_EQ(b->transform_offset, j.transform_offset);
  EXPECT_EQ(b->transform_scale, 0.5);
  EXPECT_EQ(b->path_tolerance_mm, 0.01);
  EXPECT_EQ(b->contouring, 1);
  EXPECT_TRUE(b->fit);
  EXPECT_EQ(b->work_offset, 2);
}

TEST(Journal, Sha256KnownAnswers) {
  Sha256 a;
  a.update("abc");
  EXPECT_EQ(a.hex(), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  Sha256 e;
  EXPECT_EQ(e.hex(), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  Sha256 l;
  l.update("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq");
  EXPECT_EQ(l.hex(), "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  Sha256 m;
  const std::string million(1000000, 'a');
  m.update(million);
  EXPECT_EQ(m.hex(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}


TEST(Journal, ResumeAfterTheProgramChangedIsRefused) {
  ServicePair p("hard-jchg");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  // A long program (virtual clock: minutes of machine time) with a comment to change later.
  const std::string base = read_file(zigzag_program(p.dir(), 40, 16.0, 60.0));
  const std::string prog = write_program(p.dir(), "changing.ngc", base + "(revision A)\n");
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  ASSERT_EQ(p.wait_status([](const json& s) { return s["blocks_done"].get<int>() >= 3; }, 30)["state"], "RUNNING");
  const json running = p.status();
  EXPECT_TRUE(running["journal_error"].is_null()) << running.dump();
  p.kill_host(SIGKILL);
  Status st{};
  for (int i = 0; i < 1000; ++i) {
    try {
      HostSegment seg(test_shm_name("hard-jchg"));
      seg.shm().status.load(st);
    } catch (const SegmentError&) {
    }
    if (st.state == MachineState::kHostLost) break;
    std::this_thread::sleep_for(5ms);
  }
  ASSERT_EQ(st.state, MachineState::kHostLost);
  // Same size, same modification time, different content.
  struct stat before {};
  ASSERT_EQ(stat(prog.c_str(), &before), 0);
  std::ofstream(prog, std::ios::trunc) << base + "(revision B)\n";
  const timespec times[2] = {before.st_atim, before.st_mtim};
  ASSERT_EQ(utimensat(AT_FDCWD, prog.c_str(), times, 0), 0);

  ASSERT_TRUE(p.start_host()) << p.host_log();
  json s = p.wait_status([](const json& x) { return x["rt"]["state"] == "attached"; }, 10);
  ASSERT_EQ(s["state"], "HOST_LOST");
  const json r = p.call("resume", json::object(), 60);
  EXPECT_EQ(error_code(r), rpc::kRefused) << r.dump();
  EXPECT_NE(error_message(r).find("changed since the program started"), std::string::npos) << r.dump();
  EXPECT_NE(error_message(r).find("SHA-256"), std::string::npos) << r.dump();
  s = p.status();
  EXPECT_EQ(s["state"], "HOST_LOST") << "nothing moved";
  // Restoring the content makes it resumable again.
  std::ofstream(prog, std::ios::trunc) << base + "(revision A)\n";
  const json r2 = p.call("resume", json::object(), 60);
  ASSERT_TRUE(r2.contains("result")) << r2.dump() << p.host_log();
  EXPECT_TRUE(p.call("stop").contains("result"));
}

TEST(Journal, AJournalThatCannotBeWrittenIsReportedAndTheProgramRuns) {
  ServicePair p("hard-jrep");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  const std::string tmp = p.dir() + "/state/job.json.tmp";
  ASSERT_EQ(mkdir(tmp.c_str(), 0700), 0);
  std::ofstream(tmp + "/in-the-way") << "x";
  CtlClient sub(p.socket());
  std::vector<json> events;
  sub.on_notification = [&](const json& n) {
    if (n["method"] == "event") events.push_back(n["params"]);
  };
  ASSERT_TRUE(sub.call("subscribe", {{"rate_hz", 1}}).contains("result"));
  ASSERT_TRUE(p.call("run", {{"file", source_dir() + "/examples/demo.ngc"}}).contains("result"));
  const json s = p.status();
  ASSERT_TRUE(s["journal_error"].is_string()) << s.dump();
  EXPECT_NE(s["journal_error"].get<std::string>().find("job.json.tmp"), std::string::npos) << s.dump();
  EXPECT_NE(p.host_log().find("journal:"), std::string::npos) << p.host_log();
  const json end = p.wait_status(idle_after_job, 120);
  EXPECT_EQ(end["last_job"]["end"], "completed") << end.dump();
  sub.call("status");  // collects the notifications that came meanwhile
  bool seen = false;
  for (const auto& e : events) seen = seen || e["event"] == "journal_error";
  EXPECT_TRUE(seen) << "a journal_error event";
}

}  // namespace
}  // namespace pcnc::test
