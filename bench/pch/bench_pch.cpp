// bench_pch.cpp — the one source of the target that builds the benches' precompiled header
// (bench/pch/bench_pch.hpp); the bench executables reuse it (bench/CMakeLists.txt).
int pcnc_bench_pch_anchor() { return 0; }
