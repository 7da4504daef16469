// test_pch.cpp — the one source of the target that builds the tests' precompiled header
// (tests/pch/test_pch.hpp); the test executables reuse it (tests/CMakeLists.txt).
int pcnc_test_pch_anchor() { return 0; }
