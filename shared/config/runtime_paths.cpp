// runtime_paths.cpp — default runtime and state directories and their checks (see
// runtime_paths.hpp).
#include "config/runtime_paths.hpp"

#include <grp.h>
#include <pwd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace pcnc {
namespace {

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v && v[0] == '/' ? std::string(v) : std::string();
}

std::string machine_name(const MachineConfig& c) {
  const std::string& n = c.name;
  if (n.empty() || n == "." || n == ".." || n.find('/') != std::string::npos) {
    throw RuntimePathError("machine name '" + n + "' cannot name a directory (empty, '.', '..' or with a '/')");
  }
  return n;
}

std::string home_dir() {
  std::string h = env("HOME");
  if (!h.empty()) return h;
  if (const passwd* pw = getpwuid(geteuid()); pw && pw->pw_dir) return pw->pw_dir;
  throw RuntimePathError("no home directory for uid " + std::to_string(geteuid()) + "; set process.state_dir");
}

std::string parent_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string octal(mode_t m) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "%04o", static_cast<unsigned>(m & 07777));
  return buf;
}

[[noreturn]] void fail(const std::string& path, const std::string& why) {
  throw RuntimePathError("refusing runtime directory '" + path + "': " + why);
}

void check_dir_stat(const std::string& path, const struct stat& st) {
  if (S_ISLNK(st.st_mode)) fail(path, "it is a symbolic link");
  if (!S_ISDIR(st.st_mode)) fail(path, "it is not a directory");
  if (st.st_uid != geteuid()) {
    fail(path, "it is owned by uid " + std::to_string(st.st_uid) + ", not by this process's uid " + std::to_string(geteuid()));
  }
  if (st.st_mode & 0022) fail(path, "it is writable by group or others (mode " + octal(st.st_mode) + ")");
}

// A parent that others may write to lets them rename our directory away and plant their own.
void check_parent(const std::string& path) {
  const std::string parent = parent_of(path);
  struct stat st {};
  if (stat(parent.c_str(), &st) != 0) fail(path, "cannot stat its parent " + parent + ": " + std::strerror(errno));
  if (st.st_uid != geteuid() && st.st_uid != 0) {
    fail(path, "its parent " + parent + " is owned by uid " + std::to_string(st.st_uid));
  }
  if ((st.st_mode & 0022) && !(st.st_mode & S_ISVTX)) {
    fail(path, "its parent " + parent + " is writable by group or others without the sticky bit (mode " + octal(st.st_mode) + ")");
  }
}

}  // namespace

std::string default_runtime_dir(const MachineConfig& c) {
  const std::string name = machine_name(c);
  if (geteuid() == 0) return "/run/pcnc/" + name;
  if (const std::string xdg = env("XDG_RUNTIME_DIR"); !xdg.empty()) return xdg + "/pcnc/" + name;
  return "/tmp/pcnc-" + std::to_string(geteuid()) + "/" + name;  // a private directory, checked like the others
}

std::string control_socket_path(const MachineConfig& c) {
  if (!c.process.socket_path.empty()) return c.process.socket_path;
  return default_runtime_dir(c) + "/control.sock";
}

std::string find_control_socket(const MachineConfig& c) {
  const std::string own = control_socket_path(c);
  if (!c.process.socket_path.empty()) return own;
  struct stat st {};
  if (lstat(own.c_str(), &st) == 0) return own;
  const std::string system = "/run/pcnc/" + machine_name(c) + "/control.sock";
  if (lstat(system.c_str(), &st) == 0 && S_ISSOCK(st.st_mode)) return system;
  return own;
}

std::string state_dir(const MachineConfig& c) {
  if (!c.process.state_dir.empty()) return c.process.state_dir;
  const std::string name = machine_name(c);
  if (geteuid() == 0) return "/var/lib/pcnc/" + name;
  if (const std::string xdg = env("XDG_STATE_HOME"); !xdg.empty()) return xdg + "/pcnc/" + name;
  return home_dir() + "/.local/state/pcnc/" + name;
}

gid_t socket_group_gid(const MachineConfig& c) {
  const std::string& g = c.process.socket_group;
  if (g.empty()) return static_cast<gid_t>(-1);
  if (g.find_first_not_of("0123456789") == std::string::npos && g.size() < 10) return static_cast<gid_t>(std::stoul(g));
  if (const group* gr = getgrnam(g.c_str())) return gr->gr_gid;
  throw RuntimePathError("process.socket_group: no group named '" + g + "'");
}

void ensure_private_dir(const std::string& path, mode_t mode, gid_t gid) {
  if (path.empty() || path[0] != '/') fail(path, "not an absolute path");
  // Create the missing components, parents first.
  for (std::size_t at = 1; at <= path.size(); ++at) {
    if (at != path.size() && path[at] != '/') continue;
    const std::string prefix = path.substr(0, at);
    const bool leaf = at == path.size();
    if (mkdir(prefix.c_str(), leaf ? 0700 : 0755) != 0 && errno != EEXIST) {
      fail(path, "cannot create " + prefix + ": " + std::strerror(errno));
    }
  }
  struct stat st {};
  if (lstat(path.c_str(), &st) != 0) fail(path, std::strerror(errno));
  check_dir_stat(path, st);
  check_parent(path);
  if (gid != static_cast<gid_t>(-1) && st.st_gid != gid && lchown(path.c_str(), static_cast<uid_t>(-1), gid) != 0) {
    fail(path, "cannot give it group " + std::to_string(gid) + ": " + std::strerror(errno));
  }
  if ((st.st_mode & 07777) != mode && chmod(path.c_str(), mode) != 0) {
    fail(path, "cannot set its mode " + octal(mode) + ": " + std::strerror(errno));
  }
}

void check_private_dir(const std::string& path) {
  struct stat st {};
  if (lstat(path.c_str(), &st) != 0) fail(path, std::strerror(errno));
  check_dir_stat(path, st);
}

void check_socket_dir(const std::string& socket_path) {
  const std::string dir = parent_of(socket_path);
  struct stat st {};
  if (stat(dir.c_str(), &st) != 0) fail(dir, std::string("cannot stat it: ") + std::strerror(errno));
  if (!S_ISDIR(st.st_mode)) fail(dir, "it is not a directory");
  if (st.st_uid != geteuid() && st.st_uid != 0) {
    fail(dir, "it is owned by uid " + std::to_string(st.st_uid) + ", who could replace the socket (this process runs as uid " +
                  std::to_string(geteuid()) + ")");
  }
  const bool shared = (st.st_mode & 0022) != 0;
  if (shared && !(st.st_mode & S_ISVTX)) {
    fail(dir, "it is writable by group or others without the sticky bit (mode " + octal(st.st_mode) +
                  "): anyone could replace the socket; use the default runtime directory (leave process.socket_path unset)");
  }
  struct stat sock {};
  if (shared && lstat(socket_path.c_str(), &sock) == 0 && sock.st_uid != geteuid()) {
    throw RuntimePathError("refusing socket path '" + socket_path + "': it already exists in the shared directory " + dir +
                           " and belongs to uid " + std::to_string(sock.st_uid));
  }
}

}  // namespace pcnc
