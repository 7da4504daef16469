// atomic_file.hpp — writing a small state file so that a crash or a planted link never leaves
// a half-written or redirected file: the text goes to `path`.tmp, created with
// O_EXCL|O_NOFOLLOW (whatever is at the temporary name, a symlink included, is unlinked
// first, never followed), every write checked, fsync'ed, then renamed over `path` and the
// directory fsync'ed. Used by the service's program journal and the work-coordinate state.
//
// May include: the standard library, POSIX.
#pragma once

#include <string>

namespace pcnc {

/// Writes `text` to `path` as above. On any failure `path` is untouched, false is returned
/// and `error` (when not null) says what failed.
bool write_file_atomically(const std::string& path, const std::string& text, std::string* error);

}  // namespace pcnc
