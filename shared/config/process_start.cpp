// process_start.cpp — the processes' common start (see process_start.hpp).
#include "config/process_start.hpp"

#include <signal.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace pcnc {

void start_logging(const char* process_name, const std::string& level) {
  spdlog::set_default_logger(spdlog::stderr_color_mt(process_name));
  spdlog::set_pattern(std::string("[%H:%M:%S.%e] [") + process_name + "] [%^%l%$] %v");
  spdlog::set_level(spdlog::level::from_str(level));
}

void on_stop_signals(void (*handler)(int)) {
  struct sigaction sa {};
  sa.sa_handler = handler;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

}  // namespace pcnc
