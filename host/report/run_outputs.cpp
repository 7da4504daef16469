// run_outputs.cpp — summary + trace -> time by cause and the HTML report (see run_outputs.hpp).
#include "report/run_outputs.hpp"

#include "config/joint_map.hpp"
#include "report/trace_compact_reader.hpp"

#include <algorithm>
#include <fstream>
#include <future>
#include <iterator>
#include <stdexcept>

#include <pthread.h>
#include <signal.h>

namespace pcnc {

ReportPage load_report_page(const std::string& summary_path, const std::string& trace_path) {
  ReportPage page;
  page.summary = read_run_summary(summary_path);
  if (trace_path.empty()) {
    page.trace_note = "the run was made without a trace";
    return page;
  }
  // which source lines hold rapids, and what capped each block: recorded from the blocks the
  // run's check made (the blocks that were sent), so the report runs no front end of its own
  const std::vector<LineRange>& rapid = page.summary.rapid_lines;
  const CauseClassifier classifier(page.summary.plan);
  DigestOptions d;
  const Vec3 size = page.summary.max_point - page.summary.min_point;
  // the views are ~700 px across: a point every ~1/1000 of the part's size is under a pixel
  d.path_tolerance_mm = std::max(1e-4, std::max({size[0], size[1], size[2]}) / 1000.0);
  d.max_path_points = 40000;
  d.max_buckets = 920;  // the time plots' width in pixels: one bucket (min..max) per column
  d.is_rapid_line = [&rapid](std::uint32_t line) {
    const auto it = std::upper_bound(rapid.begin(), rapid.end(), line,
                                     [](std::uint32_t l, const LineRange& r) { return l < r.first; });
    return it != rapid.begin() && line <= std::prev(it)->last;
  };
  if (!page.summary.plan.empty()) {
    d.cause_of = [&classifier](const TraceSample& row, double prev) { return classifier.classify(row, prev); };
  }
  // a 5-axis trace's tool axis: the forward kinematics of the machine the run used (its config
  // file as the summary names it) with the tool length its TCP blocks ran with (the summary's)
  try {
    if (!page.summary.config_path.empty()) {
      const MachineConfig config = load_config(page.summary.config_path);
      d.joints.kinematics = kinematics_with_tool(config, page.summary.tcp_tool_length_mm);
      d.joints.has_kinematics = config.kinematics.kind != KinematicsKind::kTrivial;
    }
  } catch (const std::exception&) {
    d.joints.has_kinematics = false;  // the joint plots are still drawn; the view says why there is no axis
  }
  const double part = std::max({size[0], size[1], size[2], 1.0});
  d.joints.axis_every_mm = part / 60.0;
  d.joints.axis_length_mm = part / 8.0;
  d.joints.tip_tolerance_mm = d.path_tolerance_mm;
  d.joints.max_buckets = d.max_buckets;
  // the compact trace pcnc-rt keeps for the report (--trace-digest), or the full CSV (--trace)
  page.trace = is_compact_trace_file(trace_path) ? digest_compact_trace(trace_path, d) : digest_trace(trace_path, d);
  page.has_trace = true;
  const double program_time = page.summary.final_status.program_time_s;
  if (page.trace.classified && page.trace.program_rows > 0) {
    page.summary.time_by_cause = time_by_cause(page.trace.cause_rows, program_time);
    page.slowest = slowest_stretches(page.trace, classifier, program_time / static_cast<double>(page.trace.program_rows), 12);
  }
  return page;
}

std::shared_future<PackedLibrary> start_packing_three_js() {
  // The thread takes no signals (it inherits the mask it is started with): a Ctrl-C or SIGTERM
  // goes to the thread that handles them (pcnc run's launcher), as without it.
  sigset_t all, old;
  sigfillset(&all);
  pthread_sigmask(SIG_BLOCK, &all, &old);
  std::shared_future<PackedLibrary> f = std::async(std::launch::async, pack_three_js, std::string()).share();
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
  return f;
}

void finish_run_outputs(const std::string& summary_path, const std::string& trace_path, const std::string& html_path,
                        bool rewrite_summary, std::shared_future<PackedLibrary> three) {
  // three.js, the same in every report and the largest cost of packing the page, is packed on
  // a second thread while the trace is read and the page drawn (path_view_3d.hpp), if the caller
  // has not started it already
  if (!three.valid() && !html_path.empty() && !trace_path.empty()) three = start_packing_three_js();
  ReportPage page = load_report_page(summary_path, trace_path);
  page.view3d_options.library = three;
  if (!html_path.empty()) {
    const std::string html = render_report_html(page);
    std::ofstream f(html_path);
    if (!f) throw std::runtime_error("cannot write the report '" + html_path + "'");
    f << html;
    if (!f.flush()) throw std::runtime_error("cannot write the report '" + html_path + "'");
  }
  if (rewrite_summary) write_run_summary(page.summary, summary_path);
}

void build_report_file(const std::string& summary_path, const std::string& trace_path, const std::string& html_path) {
  finish_run_outputs(summary_path, trace_path, html_path, false);
}

}  // namespace pcnc
