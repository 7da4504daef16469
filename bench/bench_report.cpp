// bench_report.cpp — where the time of `pcnc run --report` goes after the replay itself, from
// a real run's files: per trace row, what the rt's trace writer thread spends on the CSV text
// (format_trace_row) against the compact trace (CompactTraceBuilder::add); then what the
// report step spends reading the full CSV against the compact trace (load_report_page), and
// drawing the page (render_report_html). CPU time of this thread, fastest of N. Prints
// figures; never fails.
//   pcnc run P --fit --clock virtual --trace T.csv --summary S.json
//   bench_report --trace T.csv --summary S.json [--repeat N]
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "ipc/trace_compact.hpp"
#include "loop/trace_writer.hpp"
#include "report/inline_blob.hpp"
#include "report/path_view_3d.hpp"
#include "report/report_html.hpp"
#include "report/run_outputs.hpp"
#include "report/trace_reader.hpp"

using namespace pcnc;

namespace {

double cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

double fastest(int repeat, const std::function<void()>& f) {
  double best = 1e300;
  for (int i = 0; i < repeat; ++i) {
    const double t0 = cpu_s();
    f();
    best = std::min(best, cpu_s() - t0);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"bench_report: the costs of a run report, from a real run's trace and summary"};
  std::string trace, summary;
  int repeat = 3;
  app.add_option("--trace", trace, "the run's full trace (CSV)")->required();
  app.add_option("--summary", summary, "the run's summary (JSON)")->required();
  app.add_option("--repeat", repeat, "runs of each step (the fastest is shown)");
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;

  std::vector<TraceSample> rows;
  {
    TraceReader r(trace);
    for (TraceSample s; r.next(s);) rows.push_back(s);
  }
  const std::string compact = trace + ".pcct";
  {
    TraceWriter w(TraceFiles{"", compact});
    for (const TraceSample& s : rows) w.push_wait(s);
    w.close();
  }
  const double n = static_cast<double>(rows.size());
  std::printf("bench_report: %s, %zu rows\n", trace.c_str(), rows.size());
  {
    CompactTraceBuilder b(nullptr);
    for (const TraceSample& s : rows) b.add(s);
    const CompactTotals t = b.finish();
    std::FILE* f = std::fopen(compact.c_str(), "rb");
    long size = -1;
    if (f && std::fseek(f, 0, SEEK_END) == 0) size = std::ftell(f);
    if (f) std::fclose(f);
    std::printf("  compact trace: %.2f MB: %llu runs for %llu window rows, %llu slices of %.1f ms, %llu path points %.0f um apart\n",
                static_cast<double>(size) / 1e6, static_cast<unsigned long long>(t.runs),
                static_cast<unsigned long long>(t.program_rows), static_cast<unsigned long long>(t.slices),
                t.slice_width_s * 1e3, static_cast<unsigned long long>(t.points), t.path_tolerance_mm * 1e3);
  }

  std::size_t sink = 0;
  const double t_csv = fastest(repeat, [&] {
    char buf[512];
    for (const TraceSample& s : rows) sink += static_cast<std::size_t>(format_trace_row(buf, sizeof buf, s));
  });
  const double t_compact = fastest(repeat, [&] {
    CompactTraceBuilder b([&sink](const CompactRun& r) { sink += r.count(); });
    for (const TraceSample& s : rows) b.add(s);
    sink += b.finish().runs;
  });
  std::printf("  rt writer thread, per row:  CSV text %.0f ns   compact trace %.0f ns   (%.1f ms and %.1f ms in all)\n",
              t_csv / n * 1e9, t_compact / n * 1e9, t_csv * 1e3, t_compact * 1e3);

  // the run's summary: pcnc-host writes it after the run, the front process reads it back
  const RunSummary parsed = read_run_summary(summary);
  const std::string summary_copy = trace + ".summary.json";
  const double t_write_summary = fastest(repeat, [&] { write_run_summary(parsed, summary_copy); });
  const double t_read_summary = fastest(repeat, [&] { sink += read_run_summary(summary_copy).plan.size(); });
  std::printf("  summary (%zu plan entries): write %.1f ms, read %.1f ms\n", parsed.plan.size(), t_write_summary * 1e3,
              t_read_summary * 1e3);
  std::remove(summary_copy.c_str());

  ReportPage page;
  const double t_read_csv = fastest(repeat, [&] { page = load_report_page(summary, trace); });
  const double t_read_compact = fastest(repeat, [&] { page = load_report_page(summary, compact); });
  std::string html;
  const double t_render = fastest(repeat, [&] { html = render_report_html(page); });
  std::printf("  report: read + digest the CSV %.1f ms, the compact trace %.1f ms; draw the page %.1f ms (%.2f MB)\n",
              t_read_csv * 1e3, t_read_compact * 1e3, t_render * 1e3, static_cast<double>(html.size()) / 1e6);
  // the page's two packed blobs: three.js (the same every time) and the 3D view's path record
  std::string three;
  if (std::FILE* f = std::fopen("/usr/share/javascript/three/three.min.js", "rb")) {
    char b[65536];
    for (std::size_t k; (k = std::fread(b, 1, sizeof b, f)) > 0;) three.append(b, k);
    std::fclose(f);
  }
  const PathView3dOptions vo;
  const std::string record = encode_path_record(thin_for_view(page.trace.path, vo.max_points), vo);
  if (const char* dump = std::getenv("PCNC_BENCH_DUMP_RECORD")) {
    if (std::FILE* f = std::fopen(dump, "wb")) {
      std::fwrite(record.data(), 1, record.size(), f);
      std::fclose(f);
    }
  }
  const double t_three = fastest(repeat, [&] { sink += gzip_bytes(three).size(); });
  const double t_record = fastest(repeat, [&] { sink += gzip_bytes(record).size(); });
  std::printf("  of which gzip: three.min.js (%.0f kB) %.1f ms, the path record (%.0f kB) %.1f ms\n",
              static_cast<double>(three.size()) / 1e3, t_three * 1e3, static_cast<double>(record.size()) / 1e3,
              t_record * 1e3);
  std::remove(compact.c_str());
  return sink == 0 ? 1 : 0;
}
