// biarc_tool.hpp — `pcnc biarc FILE [--tolerance MM] [--max-tool-radius R] > OUT.ngc`: a CAM
// user's file tool. NURBS groups and smooth runs of short G1 moves become G2/G3 biarcs within
// the tolerance (so that any controller's cutter compensation offsets them exactly); with
// --max-tool-radius the loops that tool would tangle on are removed first (the seed's
// twice-offset step). The program goes to stdout, the figures to stderr (biarc_rewrite.hpp).
#pragma once

#include <iosfwd>
#include <string>

#include "biarc_rewrite.hpp"

namespace CLI {
class App;
}

namespace pcnc {

struct BiarcToolOptions {
  std::string file;
  BiarcRewriteOptions rewrite;
  std::string side = "auto";  // auto | left | right | both
};

/// Exit status: 0 written, 2 unreadable file or bad options.
int run_biarc_tool(const BiarcToolOptions& options, std::ostream& out, std::ostream& err);

/// Registers the `biarc` subcommand on `app`; its callback stores the exit status.
void add_biarc_subcommand(CLI::App& app, int& exit_code);

}  // namespace pcnc
