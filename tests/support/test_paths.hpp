// test_paths.hpp — where tests find the shared G-code corpus, the project sources and the
// built executables, independent of the working directory ctest runs them in.
#pragma once

#include <string>

namespace pcnc::test {

inline std::string shared_dir() { return PCNC_SHARED_DIR; }
inline std::string source_dir() { return PCNC_SOURCE_DIR; }
inline std::string bin_dir() { return PCNC_BIN_DIR; }
inline std::string default_config() { return std::string(PCNC_SOURCE_DIR) + "/configs/desktop-mill.toml"; }

}  // namespace pcnc::test
