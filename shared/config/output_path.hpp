// output_path.hpp — the check every command makes, before anything moves, on each file it
// will write (run report, summary, trace, soak figures): the directory exists and is
// writable and the file can be created, so a bad path fails at once (exit 2) and never after
// a long run.
//
// May include: the standard library, POSIX.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace pcnc {

struct OutputPathError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Checks that `path` can be written: not a directory; its directory exists and is a
/// directory; an existing file is writable; a new file can be created there (it is created
/// and removed again). `what` names it in the message ("--report"). Throws OutputPathError
/// saying which part fails and why.
void check_output_path(const std::string& path, const std::string& what);

/// check_output_path for each (path, what) whose path is not empty, and no two the same file.
void check_output_paths(const std::vector<std::pair<std::string, std::string>>& outputs);

}  // namespace pcnc
