// test_pch.hpp — the headers nearly every test file includes, precompiled once and reused by
// each test executable when PCNC_TEST_PCH is on (tools/test.sh turns it on; README command 1
// leaves it off, so that a test file missing an #include still fails to compile there).
// Only third-party and standard headers: a change to pcnc's own headers rebuilds what uses them,
// not every test.
#pragma once
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>
