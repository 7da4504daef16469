// test_paths.hpp — where tests find the shared G-code corpus, the project sources and the
// built executables, independent of the working directory ctest runs them in.
#pragma once

#include <string>

namespace pcnc::test {

inline std::string shared_dir() { return PCNC_SHARED_DIR; }
inline std::string source_dir() { return PCNC_SOURCE_DIR; }
inline std::string bin_dir() { return PCNC_BIN_DIR; }
inline std::string default_config() { return std::string(PCNC_SOURCE_DIR) + "/configs/desktop-mill.toml"; }

// True in the sanitizer builds (tools/test.sh's ASan+UBSan and TSan steps). The few tests that
// sweep the whole corpus under every config (minutes under ASan) sweep a sample there: every
// program and every config still run, not every pair. The normal build runs the full sweep;
// the sanitizers look for memory errors and undefined behaviour on the same code paths.
inline constexpr bool sanitizer_build() {
#ifdef PCNC_SANITIZED_BUILD
  return true;
#else
  return false;
#endif
}

}  // namespace pcnc::test
