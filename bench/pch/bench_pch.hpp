// bench_pch.hpp — CLI11 (header-only in Debian, about 15 s of compile time in each file that
// includes it at -O2) and the standard headers the benches use, precompiled once and reused by
// each bench when PCNC_TEST_PCH is on (tools/test.sh; bench/CMakeLists.txt).
#pragma once
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>
