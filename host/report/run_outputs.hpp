// run_outputs.hpp — what `pcnc run` does with a run's files once both processes have ended:
// reads the host's summary and the rt's trace (the full CSV or the compact trace,
// report/trace_compact_reader.hpp) in one pass, attributes the program time to its
// causes (report/time_causes.hpp) into the summary's `time_by_cause`, and writes the HTML
// report (report/report_html.hpp).
#pragma once

#include <future>
#include <string>

#include "report/report_html.hpp"

namespace pcnc {

/// The page's data from a summary and a trace, CSV or compact, told apart by the file's first
/// bytes (empty `trace_path`: no pictures, no causes).
/// Fills page.summary.time_by_cause when the trace is there. Throws std::runtime_error.
ReportPage load_report_page(const std::string& summary_path, const std::string& trace_path);

/// three.js packed for the page (pack_three_js) on another thread. It is the same for every
/// report and the page's largest single cost, so `pcnc run --report` starts it with the
/// processes, while the front process only waits for them.
std::shared_future<PackedLibrary> start_packing_three_js();

/// load_report_page, then: writes `html_path` when it is not empty, and the summary back to
/// `summary_path` with its time_by_cause when `rewrite_summary`. `three`: three.js already
/// being packed (start_packing_three_js); not valid: packed here, on a second thread while the
/// trace is read. Throws std::runtime_error naming what failed.
void finish_run_outputs(const std::string& summary_path, const std::string& trace_path, const std::string& html_path,
                        bool rewrite_summary, std::shared_future<PackedLibrary> three = {});

/// The report alone (finish_run_outputs without touching the summary).
void build_report_file(const std::string& summary_path, const std::string& trace_path, const std::string& html_path);

}  // namespace pcnc
