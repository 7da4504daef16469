// atomic_file.cpp — write_file_atomically (see atomic_file.hpp).
#include "config/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace pcnc {

bool write_file_atomically(const std::string& path, const std::string& text, std::string* error) {
  auto failed = [&](const std::string& what, int fd, const std::string& tmp) {
    const std::string why = what + ": " + std::strerror(errno);
    if (fd >= 0) ::close(fd);
    if (!tmp.empty()) ::unlink(tmp.c_str());
    if (error) *error = why + "; the previous " + path + " is left as it was";
    return false;
  };
  const std::string tmp = path + ".tmp";
  // O_EXCL|O_NOFOLLOW: never write through a file or symlink planted at the temporary name.
  // Whatever is there is removed first (unlink removes a symlink, never its target).
  const int flags = O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC;
  int fd = ::open(tmp.c_str(), flags, 0600);
  if (fd < 0 && errno == EEXIST) {
    if (::unlink(tmp.c_str()) != 0) return failed("cannot remove the stale " + tmp, -1, "");
    fd = ::open(tmp.c_str(), flags, 0600);
  }
  if (fd < 0) return failed("cannot create " + tmp, -1, "");
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = ENOSPC;
      return failed("cannot write " + tmp, fd, tmp);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) return failed("cannot fsync " + tmp, fd, tmp);
  if (::close(fd) != 0) return failed("cannot close " + tmp, -1, tmp);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) return failed("cannot rename " + tmp + " to " + path, -1, tmp);
  // The rename itself reaches the disk with the directory.
  const auto slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
  if (const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
    (void)::fsync(dfd);
    ::close(dfd);
  }
  return true;
}

}  // namespace pcnc
