// headless_chromium.hpp — Debian's Chromium run headless on a local page, for the tests that
// check what a browser makes of pcnc's HTML (the run report, its 3D view): a screenshot, or
// the page's DOM after its scripts ran. Skipped by the callers where Chromium is missing.
#pragma once

#include <string>

#include "subprocess.hpp"

namespace pcnc::test {

/// The Chromium executable, or "" when none is installed.
std::string find_chromium();

/// Loads `url` (file://...) headless in a fresh profile under `profile_dir` and writes a
/// screenshot of `width`x`height` pixels to `png`.
ProcessResult chromium_screenshot(const std::string& chromium, const std::string& url, const std::string& png,
                                  const std::string& profile_dir, int width = 1200, int height = 1600);

/// Loads `url` headless, lets its scripts run for up to `budget_ms` of virtual time, and
/// returns the DOM as serialised HTML in `out`.
ProcessResult chromium_dump_dom(const std::string& chromium, const std::string& url, const std::string& profile_dir,
                                int budget_ms = 10000);

}  // namespace pcnc::test
