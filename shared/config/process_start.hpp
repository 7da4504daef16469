// process_start.hpp — what pcnc-host and pcnc-rt both do first: log to stderr under their own
// name (stdout stays for what the user asked for) at the level given on the command line, and
// turn SIGINT and SIGTERM into a stop request.
#pragma once

#include <string>

namespace pcnc {

/// The default logger writes "[time] [name] [level] message" to stderr from now on.
void start_logging(const char* process_name, const std::string& level);

/// SIGINT and SIGTERM call `handler` (which should only set a flag).
void on_stop_signals(void (*handler)(int));

}  // namespace pcnc
