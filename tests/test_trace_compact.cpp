// test_trace_compact.cpp — the compact trace (ipc/trace_compact, report/trace_compact_reader):
// the report's digest made from it equals the digest made from the full CSV of the same rows
// (buckets, causes, per-line times, counts, the last row; the path keeps its ends), each
// slice's min and max against the rows themselves, and the file as the rt's writer thread
// writes it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "ipc/trace_compact.hpp"
#include "loop/trace_writer.hpp"
#include "report/trace_compact_reader.hpp"
#include "report/trace_reader.hpp"

namespace pcnc {
namespace {

// A made-up run with what the digest must survive: idle before the start, a long program with
// ramps and cruises over many lines (rapids among them), a pause, a short idle gap inside
// the window, a fault, and a long idle tail that closes the window.
std::vector<TraceSample> synthetic_rows(std::size_t program_rows, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<TraceSample> rows;
  TraceSample s;
  std::uint64_t cycle = 0;
  auto push = [&](MachineState st) {
    s.t = static_cast<double>(cycle++) * 0.0005;
    s.state = st;
    rows.push_back(s);
  };
  s.actual = s.commanded = {12.5, 12.5, 25.0};
  for (int i = 0; i < 300; ++i) push(MachineState::kIdle);
  double v = 0.0;
  std::uint32_t line = 10;
  for (std::size_t i = 0; i < program_rows; ++i) {
    if (i % 700 == 0) line += 1 + static_cast<std::uint32_t>(rng() % 3);
    const std::size_t phase = i % 700;
    if (phase < 150) v += 0.2;        // ramp up
    else if (phase < 500) { }         // cruise: many rows of one speed
    else if (phase < 650) v = std::max(0.0, v - 0.2);
    else v = 0.0;                     // at rest between blocks
    s.speed = v;
    for (std::size_t a = 0; a < 3; ++a) {
      s.commanded[a] += v * 0.0005 * (a == 0 ? 0.8 : a == 1 ? 0.6 : 0.0) + 1e-5 * u(rng);
      s.following_error[a] = 2e-3 * u(rng);
      s.actual[a] = s.commanded[a] - s.following_error[a];
    }
    s.line = line;
    MachineState st = MachineState::kRunning;
    if (i > program_rows / 3 && i < program_rows / 3 + 400) st = MachineState::kPaused;
    if (i > program_rows / 2 && i < program_rows / 2 + 50) st = MachineState::kIdle;  // a gap inside the window
    if (i + 20 >= program_rows) st = MachineState::kFault;
    push(st);
  }
  s.speed = 0.0;
  for (int i = 0; i < 21000; ++i) push(MachineState::kIdle);  // closes the window
  return rows;
}

// Through the CSV text and back: what the report reads from a --trace file.
std::vector<TraceSample> through_csv(const std::vector<TraceSample>& rows) {
  std::vector<TraceSample> out;
  out.reserve(rows.size());
  for (const TraceSample& r : rows) {
    TraceSample p;
    EXPECT_TRUE(parse_trace_row(trace_csv_row(r), p));
    out.push_back(p);
  }
  return out;
}

struct Fixture {
  std::string path;
  CompactTotals totals;
  std::vector<CompactSlice> slices;
  std::vector<CompactPoint> points;
  std::vector<CompactRun> runs;
};

// Builds the compact trace in memory and writes it as the writer thread does.
Fixture build(const std::vector<TraceSample>& rows, const std::string& name) {
  Fixture f;
  f.path = ::testing::TempDir() + name;
  TraceWriter w(TraceFiles{"", f.path});
  CompactTraceBuilder b([&f](const CompactRun& r) { f.runs.push_back(r); });
  for (const TraceSample& r : rows) {
    w.push_wait(r);
    b.add(r);
  }
  w.close();
  EXPECT_FALSE(w.failed()) << w.failure();
  f.totals = b.finish();
  f.slices = b.slices();
  f.points = b.points();
  return f;
}

// A plan-like classifier and rapid lines that depend on line and speed the way the real
// ones do (bands around per-line speeds, the previous row's speed).
DigestOptions options_for_test() {
  DigestOptions o;
  o.max_buckets = 920;
  o.path_tolerance_mm = 0.02;
  o.max_path_points = 40000;
  o.is_rapid_line = [](std::uint32_t line) { return line % 5 == 0; };
  o.cause_of = [](const TraceSample& row, double prev) {
    RowCause rc;
    if (row.state == MachineState::kPaused) return RowCause{TimeCause::kPaused, 0.0};
    if (row.state != MachineState::kRunning) return rc;
    rc.planned_speed = 10.0 + row.line % 7;
    if (std::fabs(row.speed - 30.0) <= 0.02 * 30.0) rc.cause = TimeCause::kFeed;
    else if (std::fabs(row.speed - prev) <= 1e-9) rc.cause = TimeCause::kOverride;
    else rc.cause = row.speed < prev ? TimeCause::kJunctionStop : TimeCause::kAccelX;
    return rc;
  };
  return o;
}

void expect_same_digest(const TraceDigest& a, const TraceDigest& b) {
  EXPECT_EQ(a.rows, b.rows);
  EXPECT_EQ(a.program_rows, b.program_rows);
  EXPECT_EQ(a.duration_s, b.duration_s);
  EXPECT_EQ(a.speed_max, b.speed_max);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(a.ferr_abs_max[i], b.ferr_abs_max[i]);
  EXPECT_EQ(a.saw_fault, b.saw_fault);
  EXPECT_EQ(a.classified, b.classified);
  EXPECT_EQ(a.last.t, b.last.t);
  EXPECT_EQ(a.last.line, b.last.line);
  EXPECT_EQ(a.last.actual[0], b.last.actual[0]);
  EXPECT_EQ(a.cause_rows, b.cause_rows);
  ASSERT_EQ(a.line_time.size(), b.line_time.size());
  for (const auto& [line, lt] : a.line_time) {
    ASSERT_EQ(b.line_time.count(line), 1u) << line;
    EXPECT_EQ(lt.rows, b.line_time.at(line).rows) << line;
    EXPECT_EQ(lt.cause_rows, b.line_time.at(line).cause_rows) << line;
  }
  ASSERT_EQ(a.buckets.size(), b.buckets.size());
  for (std::size_t i = 0; i < a.buckets.size(); ++i) {
    const TraceBucket &x = a.buckets[i], &y = b.buckets[i];
    SCOPED_TRACE("bucket " + std::to_string(i));
    EXPECT_EQ(x.t0, y.t0);
    EXPECT_EQ(x.t1, y.t1);
    EXPECT_EQ(x.rows, y.rows);
    EXPECT_EQ(x.speed_min, y.speed_min);
    EXPECT_EQ(x.speed_max, y.speed_max);
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(x.ferr_min[k], y.ferr_min[k]);
      EXPECT_EQ(x.ferr_max[k], y.ferr_max[k]);
    }
    EXPECT_EQ(x.feed_rows, y.feed_rows);
    EXPECT_EQ(x.rapid_rows, y.rapid_rows);
    EXPECT_EQ(x.feed_speed_min, y.feed_speed_min);
    EXPECT_EQ(x.feed_speed_max, y.feed_speed_max);
    EXPECT_EQ(x.planned_max, y.planned_max);
    EXPECT_EQ(x.line_min, y.line_min);
    EXPECT_EQ(x.line_max, y.line_max);
    EXPECT_EQ(x.cause_rows, y.cause_rows);
    if (::testing::Test::HasFailure()) return;
  }
}

TraceDigest digest_rows(const std::vector<TraceSample>& rows, const DigestOptions& o) {
  TraceDigester d(o);
  for (const TraceSample& r : rows) d.add(r);
  return d.finish();
}

TEST(CompactTrace, DigestEqualsTheFullCsvsDigest) {
  for (const std::size_t n : {3000u, 40000u, 600000u}) {  // buckets of 0.5 ms; doubled; doubled many times
    SCOPED_TRACE("program rows " + std::to_string(n));
    const auto rows = synthetic_rows(n, static_cast<unsigned>(n));
    const Fixture f = build(rows, "compact_eq.pcct");
    const DigestOptions o = options_for_test();
    const TraceDigest full = digest_rows(through_csv(rows), o);
    const TraceDigest compact = digest_compact_trace(f.path, o);
    ASSERT_GT(full.program_rows, n / 2);
    expect_same_digest(full, compact);
    // the path: decimated twice, but from the same rows: same ends, same tolerance rule
    ASSERT_FALSE(compact.path.empty());
    EXPECT_NEAR(compact.path.front().p[0], full.path.front().p[0], 1e-5);  // single precision
    EXPECT_EQ(compact.path.back().p[0], full.path.back().p[0]);
    EXPECT_EQ(compact.path.back().t, full.path.back().t);
    EXPECT_LE(compact.path.size(), o.max_path_points + 1);
    std::remove(f.path.c_str());
  }
}

TEST(CompactTrace, WithoutPlanOrRapidsToo) {
  const auto rows = synthetic_rows(20000, 7);
  const Fixture f = build(rows, "compact_plain.pcct");
  DigestOptions o;  // the defaults: 1200 buckets, no classifier
  expect_same_digest(digest_rows(through_csv(rows), o), digest_compact_trace(f.path, o));
  std::remove(f.path.c_str());
}

// Each slice against the rows it covers, computed here from the rows alone.
TEST(CompactTrace, SliceMinMaxAgainstTheRows) {
  const auto rows = synthetic_rows(120000, 3);
  const Fixture f = build(rows, "compact_slices.pcct");
  const auto csv = through_csv(rows);
  ASSERT_GT(f.slices.size(), 100u);
  ASSERT_LE(f.slices.size(), CompactTraceBuilder::kMaxSlices);
  const double w = f.totals.slice_width_s;
  EXPECT_GT(w, 0.0005);  // 120,000 rows of 0.5 ms are more than 4096 slices: the width doubled
  // window: first RUNNING row to the last busy one
  std::size_t first = 0;
  while (csv[first].state != MachineState::kRunning) ++first;
  std::size_t last = csv.size() - 1;
  while (csv[last].state == MachineState::kIdle) --last;
  const double t0 = csv[first].t;
  std::size_t k = first, rows_seen = 0;
  for (const CompactSlice& s : f.slices) {
    double vmin = 1e300, vmax = -1e300, emin = 1e300, emax = -1e300;
    std::uint32_t n = 0;
    double tfirst = -1, tlast = -1;
    while (k <= last && static_cast<std::size_t>((csv[k].t - t0) / w) == static_cast<std::size_t>(s.t0 / w)) {
      vmin = std::min(vmin, csv[k].speed);
      vmax = std::max(vmax, csv[k].speed);
      emin = std::min(emin, csv[k].following_error[1]);
      emax = std::max(emax, csv[k].following_error[1]);
      if (tfirst < 0) tfirst = csv[k].t - t0;
      tlast = csv[k].t - t0;
      ++n;
      ++k;
    }
    ASSERT_EQ(s.rows, n) << "slice at " << s.t0;
    EXPECT_EQ(s.speed_min, vmin);
    EXPECT_EQ(s.speed_max, vmax);
    EXPECT_EQ(s.ferr_min[1], emin);
    EXPECT_EQ(s.ferr_max[1], emax);
    EXPECT_EQ(s.t0, tfirst);
    EXPECT_EQ(s.t1, tlast);
    rows_seen += n;
  }
  EXPECT_EQ(rows_seen, f.totals.program_rows);
  EXPECT_EQ(rows_seen, last - first + 1);
  // the runs cover the same rows, each inside one slice
  std::uint64_t run_rows = 0;
  for (const CompactRun& r : f.runs) run_rows += r.count();
  EXPECT_EQ(run_rows, f.totals.program_rows);
  EXPECT_EQ(f.runs.size(), f.totals.runs);
  EXPECT_LT(f.runs.size(), f.totals.program_rows / 2);  // cruises and rests are runs of many rows
}

TEST(CompactTrace, FileCutShortOrForeignIsRefusedWithItsName) {
  const auto rows = synthetic_rows(5000, 11);
  const Fixture f = build(rows, "compact_cut.pcct");
  EXPECT_TRUE(is_compact_trace_file(f.path));
  // a file without its footer: pcnc-rt did not close it
  std::FILE* in = std::fopen(f.path.c_str(), "rb");
  ASSERT_NE(in, nullptr);
  std::vector<char> bytes(1 << 20);
  bytes.resize(std::fread(bytes.data(), 1, bytes.size(), in));
  std::fclose(in);
  const std::string cut = ::testing::TempDir() + "compact_cut2.pcct";
  std::FILE* out = std::fopen(cut.c_str(), "wb");
  std::fwrite(bytes.data(), 1, bytes.size() / 2, out);
  std::fclose(out);
  try {
    digest_compact_trace(cut, {});
    ADD_FAILURE() << "a cut file was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("incomplete"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(cut), std::string::npos) << e.what();
  }
  const std::string csv = ::testing::TempDir() + "compact_cut.csv";
  out = std::fopen(csv.c_str(), "w");
  std::fputs("t,line,state\n", out);
  std::fclose(out);
  EXPECT_FALSE(is_compact_trace_file(csv));
  EXPECT_THROW(digest_compact_trace(csv, {}), std::runtime_error);
  std::remove(f.path.c_str());
  std::remove(cut.c_str());
  std::remove(csv.c_str());
}

// A trace with no RUNNING row (a run refused or stopped before it started): an empty window.
TEST(CompactTrace, NoProgramWindow) {
  std::vector<TraceSample> rows(500);
  for (std::size_t i = 0; i < rows.size(); ++i) rows[i].t = static_cast<double>(i) * 0.0005;
  const Fixture f = build(rows, "compact_empty.pcct");
  const TraceDigest d = digest_compact_trace(f.path, options_for_test());
  EXPECT_EQ(d.rows, 500u);
  EXPECT_EQ(d.program_rows, 0u);
  EXPECT_TRUE(d.buckets.empty());
  EXPECT_TRUE(d.path.empty());
  std::remove(f.path.c_str());
}

// Debugging aid: PCNC_COMPACT_CSV=trace.csv compares both digests over a real trace.
TEST(CompactTrace, RealTraceFromTheEnvironment) {
  const char* p = std::getenv("PCNC_COMPACT_CSV");
  if (!p) GTEST_SKIP() << "set PCNC_COMPACT_CSV to a trace CSV";
  std::vector<TraceSample> rows;
  TraceReader r(p);
  for (TraceSample s; r.next(s);) rows.push_back(s);
  const Fixture f = build(rows, "compact_env.pcct");
  DigestOptions o = options_for_test();
  expect_same_digest(digest_rows(rows, o), digest_compact_trace(f.path, o));
}

// A rotary machine's joint section: every busy window row's joint error in the slices (its
// min and max per joint as the rows give them, rounded as the CSV), the points thinned past
// their budget and ending on the last busy row; a 3-axis builder keeps no joint section.
TEST(CompactTrace, JointSectionKeepsTheJointErrorsAndThinsItsPoints) {
  const std::vector<TraceSample> rows = synthetic_rows(150000, 11);
  constexpr RotaryMask kAC = 0b101;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  CompactTraceBuilder five(nullptr, kAC), three(nullptr, 0);
  double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
  std::uint64_t busy_rows = 0;
  double t_start = -1.0, t_last_busy = 0.0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const TraceSample& r = rows[i];
    TraceJoints j;
    j.mask = kAC;
    for (std::size_t k : {0u, 2u}) {
      j.commanded[k] = 1e-5 * static_cast<double>(i) * (k == 0 ? 1.0 : -2.0);  // rad: 0.0006° and 0.0011° a row
      j.actual[k] = j.commanded[k] - 1e-6 * u(rng);
    }
    five.add(r, j);
    three.add(r, j);
    if (t_start < 0.0 && r.state == MachineState::kRunning) t_start = round_like_csv(r.t, 1e4);
    const bool busy = t_start >= 0.0 && r.state != MachineState::kIdle && r.state != MachineState::kStarting;
    if (!busy) continue;
    ++busy_rows;
    t_last_busy = round_like_csv(r.t, 1e4) - t_start;
    for (std::size_t k : {0u, 2u}) {
      const double e = round_like_csv((j.commanded[k] - j.actual[k]) * 180.0 / 3.14159265358979323846, 1e7);
      lo[k] = std::min(lo[k], e);
      hi[k] = std::max(hi[k], e);
    }
  }
  const CompactTotals t5 = five.finish(), t3 = three.finish();
  EXPECT_EQ(t3.rotary_mask, 0u);
  EXPECT_TRUE(three.joint_slices().empty() && three.joint_points().empty());
  EXPECT_EQ(t5.rotary_mask, kAC);
  ASSERT_EQ(five.joint_slices().size(), five.slices().size());
  std::uint64_t n = 0;
  double jlo[3] = {1e9, 1e9, 1e9}, jhi[3] = {-1e9, -1e9, -1e9};
  for (std::size_t i = 0; i < five.slices().size(); ++i) {
    const CompactJointSlice& s = five.joint_slices()[i];
    EXPECT_LE(s.rows, five.slices()[i].rows) << i;
    if (s.rows == 0) continue;
    n += s.rows;
    EXPECT_GE(s.t0, five.slices()[i].t0) << i;
    EXPECT_LE(s.t1, five.slices()[i].t1) << i;
    for (std::size_t k : {0u, 2u}) {
      jlo[k] = std::min(jlo[k], s.ferr_min[k]);
      jhi[k] = std::max(jhi[k], s.ferr_max[k]);
    }
  }
  EXPECT_EQ(n, busy_rows);
  for (std::size_t k : {0u, 2u}) {
    EXPECT_EQ(jlo[k], lo[k]) << k;
    EXPECT_EQ(jhi[k], hi[k]) << k;
    EXPECT_EQ(five.joint_totals().ferr_abs_max[k], std::max(-lo[k], hi[k])) << k;
  }
  ASSERT_GT(busy_rows, CompactTraceBuilder::kMaxPoints);
  EXPECT_LE(five.joint_points().size(), CompactTraceBuilder::kMaxPoints + 1);
  EXPECT_GT(five.joint_totals().angle_tolerance_deg, CompactTraceBuilder::kAngleToleranceDeg);  // thinned
  EXPECT_EQ(five.joint_totals().points, five.joint_points().size());
  ASSERT_FALSE(five.joint_points().empty());
  EXPECT_EQ(five.joint_points().front().t, 0.0);
  EXPECT_EQ(five.joint_points().back().t, t_last_busy);
}

}  // namespace
}  // namespace pcnc
