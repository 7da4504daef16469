// subprocess.hpp — starting the real executables from tests: run to completion with output
// captured, or start in the background and signal/wait later. Also writes per-test configs
// so that concurrent tests never share a segment or socket name.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace pcnc::test {

struct ProcessResult {
  int exit_code = -1;  // exit status, or 128+signal when killed
  bool timed_out = false;
  std::string out;
  std::string err;
};

/// Runs argv[0] with arguments, capturing stdout and stderr; kills it after timeout_s.
ProcessResult run_process(const std::vector<std::string>& argv, double timeout_s = 120.0);

/// A process running in the background with stdout/stderr going to files.
struct BackgroundProcess {
  pid_t pid = -1;
  std::string out_path, err_path;
  /// Waits up to timeout_s; returns exit code (128+signal if killed) or -1 on timeout.
  int wait(double timeout_s);
  std::string out() const;
  std::string err() const;
};
BackgroundProcess start_process(const std::vector<std::string>& argv, const std::string& scratch_prefix);

/// Ends a background process the test did not end itself (a failed assertion), never one it
/// reaped: wait_for() forgets the pid once it has the exit status.
struct Reaped {
  BackgroundProcess& p;
  ~Reaped();
};
/// BackgroundProcess::wait, forgetting the pid once the exit status is in.
int wait_for(BackgroundProcess& p, double timeout_s);

/// Writes a copy of configs/desktop-mill.toml into `dir` with a shared-memory name and socket
/// path unique to this test process, plus `extra_replacements` (pairs of exact text, new text).
/// Returns the file path.
std::string write_test_config(const std::string& dir, const std::string& tag,
                              const std::vector<std::pair<std::string, std::string>>& extra_replacements = {});
/// The shm name write_test_config used for `tag`.
std::string test_shm_name(const std::string& tag);

/// A fresh temporary directory, removed with everything in it when the test process exits
/// (PCNC_KEEP_TEST_FILES=1 keeps it). The same holds for the segment named by test_shm_name.
std::string make_temp_dir(const std::string& tag);

std::string read_file(const std::string& path);

}  // namespace pcnc::test
