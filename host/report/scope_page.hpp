// scope_page.hpp — a scope capture (`pcnc ctl capture`) as files: the CSV (a header of `t`
// and the signal names, one row per cycle, values written as the trace writes them) and one
// self-contained HTML page of plots against time, in the run report's style (inline SVG, no
// script): one plot per kind of signal (positions, following errors, speed, line, state),
// time in ms from the trigger, the pre-trigger shaded, each plot column drawn as the min..max
// of the rows under it so no peak is lost.
//
// May include: shared/ (ipc/status for state names), report_html.hpp (fixed()).
#pragma once

#include <string>
#include <vector>

namespace pcnc {

struct ScopeRecord {
  std::vector<std::string> signals;           // trace column names, as captured
  std::vector<double> t;                      // machine time per row, s
  std::vector<std::vector<double>> columns;   // one per signal, t.size() values each (state: its number)
  std::string trigger;                        // the condition, "" without one
  std::size_t trigger_row = 0;                // the row the trigger held at (0 without one)
  double period_s = 0.0005;
  std::string source;                         // what was captured from (socket, machine), for the page title
};

/// The CSV text: "t,<signals>\n" and one line per row.
std::string scope_csv(const ScopeRecord& r);
/// The HTML page.
std::string render_scope_html(const ScopeRecord& r);

}  // namespace pcnc
