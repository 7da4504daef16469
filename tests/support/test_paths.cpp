// test_paths.cpp — anchors the test-support library (its helpers are header-only).
#include "test_paths.hpp"
