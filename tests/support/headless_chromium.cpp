// headless_chromium.cpp — see headless_chromium.hpp.
#include "headless_chromium.hpp"

#include <filesystem>
#include <vector>

namespace pcnc::test {

namespace {

// Flags for a machine without network or GPU: no background connections, software GL.
std::vector<std::string> base_args(const std::string& chromium, const std::string& profile_dir) {
  return {chromium,
          "--headless",
          "--no-sandbox",
          "--disable-gpu",
          "--disable-quic",
          "--no-first-run",
          "--disable-background-networking",
          "--disable-component-update",
          "--disable-sync",
          "--user-data-dir=" + profile_dir};
}

}  // namespace

std::string find_chromium() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"}) {
    if (std::filesystem::exists(p)) return p;
  }
  return "";
}

ProcessResult chromium_screenshot(const std::string& chromium, const std::string& url, const std::string& png,
                                  const std::string& profile_dir, int width, int height) {
  std::vector<std::string> argv = base_args(chromium, profile_dir);
  argv.push_back("--virtual-time-budget=10000");
  argv.push_back("--screenshot=" + png);
  argv.push_back("--window-size=" + std::to_string(width) + "," + std::to_string(height));
  argv.push_back(url);
  return run_process(argv, 120);
}

ProcessResult chromium_dump_dom(const std::string& chromium, const std::string& url, const std::string& profile_dir,
                                int budget_ms) {
  std::vector<std::string> argv = base_args(chromium, profile_dir);
  argv.push_back("--virtual-time-budget=" + std::to_string(budget_ms));
  argv.push_back("--window-size=1200,1000");
  argv.push_back("--dump-dom");
  argv.push_back(url);
  return run_process(argv, 120);
}

}  // namespace pcnc::test
