// serve.hpp — `pcnc serve`: starts pcnc-rt and `pcnc-host --serve` as a pair (launcher.hpp),
// so a user can then run programs and jog from other terminals with `pcnc ctl`.
#pragma once

namespace CLI {
class App;
}

namespace pcnc {

/// Registers `serve` on `app`; its callback stores the exit status in `exit_code`.
void add_serve_subcommand(CLI::App& app, int& exit_code);

}  // namespace pcnc
