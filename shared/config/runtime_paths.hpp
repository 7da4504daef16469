// runtime_paths.hpp — where a machine's runtime files live, and the checks that keep another
// user from tampering with them (issue 19).
//
//   control socket  process.socket_path when the config sets it, else
//                   <runtime dir>/control.sock with the runtime directory
//                   /run/pcnc/<machine> (root), $XDG_RUNTIME_DIR/pcnc/<machine>, or
//                   /tmp/pcnc-<uid>/<machine>; mode 0750, group = process.socket_group.
//   state (journal) process.state_dir when set, else /var/lib/pcnc/<machine> (root),
//                   $XDG_STATE_HOME/pcnc/<machine> or ~/.local/state/pcnc/<machine>; mode 0700.
//
// One function computes each default (pcnc-host and pcnc ctl both call control_socket_path).
// The checks throw RuntimePathError with a message naming the path and what is wrong.
//
// May include: the standard library, POSIX, config.hpp.
#pragma once

#include <sys/types.h>

#include <stdexcept>
#include <string>

#include "config/config.hpp"

namespace pcnc {

struct RuntimePathError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The runtime directory for the default socket (see above); not created.
std::string default_runtime_dir(const MachineConfig& config);
/// process.socket_path when set, else default_runtime_dir()/control.sock.
std::string control_socket_path(const MachineConfig& config);
/// The socket a client should connect to: control_socket_path(), except that when the config
/// sets no socket_path and this user's default does not exist while the system one
/// (/run/pcnc/<machine>/control.sock, a service running as root) does, that one: so a member
/// of the socket group finds a root service without --socket.
std::string find_control_socket(const MachineConfig& config);
/// process.state_dir when set, else the default state directory (see above); not created.
std::string state_dir(const MachineConfig& config);

/// The gid of process.socket_group (a group name or a number); -1 when it is not set. Throws
/// RuntimePathError for an unknown group.
gid_t socket_group_gid(const MachineConfig& config);

/// Creates `path` (and missing parents, 0755) unless it exists, then checks it: a directory,
/// not a symlink, owned by the effective uid, not writable by group or others; and its parent
/// not writable by others unless sticky. Sets its mode to `mode` and, when `gid` is not -1,
/// its group. Throws RuntimePathError saying what is wrong.
void ensure_private_dir(const std::string& path, mode_t mode, gid_t gid = static_cast<gid_t>(-1));

/// Checks a directory the service is given: a directory, not a symlink, owned by the
/// effective uid, not writable by group or others. Throws RuntimePathError.
void check_private_dir(const std::string& path);

/// Checks the directory of a socket path the config sets: refused when it is owned by
/// another uid (other than root), or writable by group or others without the sticky bit; in
/// a sticky shared directory (such as /tmp) an existing file at `socket_path` owned by another
/// uid is refused too. Throws RuntimePathError.
void check_socket_dir(const std::string& socket_path);

}  // namespace pcnc
