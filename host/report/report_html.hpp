// report_html.hpp — the run report as one self-contained HTML page (`pcnc run --report`).
//
// Built after both processes have exited, from the run summary pcnc-host wrote (figures)
// and the per-cycle trace pcnc-rt wrote (pictures). Which source lines are rapids comes from
// the summary too (recorded from the blocks the run's check made): no front end runs here. The
// page is one file: inline SVG and CSS, and one script, the interactive 3D view
// (path_view_3d.hpp, three.js inlined); no fonts, nothing fetched from the network, so it opens
// anywhere with nothing but a browser, and without scripts it shows the static views.
//
// Pictures: the tool path as measured, in an interactive 3D view with a time slider and as a
// static isometric SVG (rapids dashed, feed moves coloured by path speed, the final tool
// position as a red dot; the SVG for printing and browsers without scripts) and from above; the path
// speed over time;
// the following error per axis over time (min..max envelopes, so no peak is lost to
// decimation). Figures: one table, each row with a stable id for scripts and tests.
#pragma once

#include <string>

#include "config/config.hpp"
#include "config/fixed_text.hpp"  // fixed(): the page's numbers, shared with the tests
#include "report/path_view_3d.hpp"
#include "report/run_summary.hpp"
#include "report/time_causes.hpp"
#include "report/trace_reader.hpp"

namespace pcnc {

struct ReportPage {
  RunSummary summary;
  bool has_trace = false;
  TraceDigest trace;        // valid when has_trace
  std::string trace_note;   // e.g. why there is no trace
  std::vector<SlowStretch> slowest;  // the lines that lost most time, with their cause
  bool view3d = true;       // the interactive 3D tool path (path_view_3d.hpp) when three.js is there
  PathView3dOptions view3d_options;  // its settings (and three.js, when packed on another thread)
};

/// The whole page.
std::string render_report_html(const ReportPage& page);

/// The isometric tool path alone (an <svg> element), for tests.
std::string render_toolpath_svg(const ReportPage& page);
/// The tool path seen from above (X right, Y up, equal scales).
std::string render_top_view_svg(const ReportPage& page);


}  // namespace pcnc
