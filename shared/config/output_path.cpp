// output_path.cpp — checks a file a command will write before anything moves (see output_path.hpp).
#include "config/output_path.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace pcnc {

void check_output_path(const std::string& path, const std::string& what) {
  namespace fs = std::filesystem;
  const std::string head = what + " " + path + ": ";
  if (path.empty()) throw OutputPathError(what + ": the path is empty");
  if (path.back() == '/') throw OutputPathError(head + "names a directory, not a file");
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  struct stat st {};
  if (stat(dir.c_str(), &st) != 0) {
    throw OutputPathError(head + "its directory " + dir.string() + " " +
                          (errno == ENOENT ? std::string("does not exist") : std::string(std::strerror(errno))));
  }
  if (!S_ISDIR(st.st_mode)) throw OutputPathError(head + dir.string() + " is not a directory");
  if (access(dir.c_str(), W_OK | X_OK) != 0) {
    throw OutputPathError(head + "cannot write in its directory " + dir.string() + ": " + std::strerror(errno));
  }
  if (stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw OutputPathError(head + "is a directory");
    if (access(path.c_str(), W_OK) != 0) throw OutputPathError(head + "cannot be written: " + std::strerror(errno));
    return;  // an existing writable file: it is replaced when written
  }
  // A new file: create it (and remove it again) to know the file system takes it.
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) throw OutputPathError(head + "cannot be created: " + std::strerror(errno));
  close(fd);
  unlink(path.c_str());
}

void check_output_paths(const std::vector<std::pair<std::string, std::string>>& outputs) {
  namespace fs = std::filesystem;
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    if (outputs[i].first.empty()) continue;
    check_output_path(outputs[i].first, outputs[i].second);
    for (std::size_t j = 0; j < i; ++j) {
      if (outputs[j].first.empty()) continue;
      std::error_code ec;
      const bool same = fs::weakly_canonical(outputs[i].first, ec) == fs::weakly_canonical(outputs[j].first, ec);
      if (same) {
        throw OutputPathError(outputs[j].second + " and " + outputs[i].second + " name the same file: " + outputs[i].first);
      }
    }
  }
}

}  // namespace pcnc
