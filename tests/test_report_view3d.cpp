// The run report's interactive 3D tool path (host/report/path_view_3d, inline_blob): the
// packing round trips, the thinning keeps what it promises, and in headless Chromium the view
// draws the path and the red dot, and its time slider reads out the point the test computes;
// three.js packed on another thread gives the same page.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>
#include <regex>

#include "headless_chromium.hpp"
#include "report/inline_blob.hpp"
#include "report/path_view_3d.hpp"
#include "report/report_html.hpp"
#include "subprocess.hpp"

namespace pcnc {
namespace {

namespace fs = std::filesystem;

// A rapid down to the start, then a helix of three turns (radius 5 mm, 1 mm per turn) at
// 10 mm/s traced at 2 kHz, a source line per quarter turn; a following-error bump mid-way.
TraceDigest helix_digest(std::size_t max_points = 200000) {
  DigestOptions o;
  o.path_tolerance_mm = 0.01;
  o.max_path_points = max_points;
  o.is_rapid_line = [](std::uint32_t line) { return line == 1; };
  TraceDigester d(o);
  auto add = [&](double t, std::uint32_t line, Vec3 p, Vec3 ferr, double speed) {
    TraceSample r;
    r.t = t;
    r.line = line;
    r.state = MachineState::kRunning;
    r.actual = p;
    r.commanded = p + ferr;
    r.following_error = ferr;
    r.speed = speed;
    d.add(r);
  };
  double t = 0.0;
  for (int i = 0; i <= 400; ++i) add(t += 0.0005, 1, {5.0, 0.0, 8.0 - 5.0 * i / 400.0}, {}, 50.0);
  const double dphi = 10.0 * 0.0005 / 5.0;  // 10 mm/s on a 5 mm radius
  for (double phi = 0.0; phi < 3 * 2 * M_PI; phi += dphi) {
    const auto line = static_cast<std::uint32_t>(2 + phi / (M_PI / 2));
    const Vec3 ferr = std::fabs(phi - 3 * M_PI) < 0.05 ? Vec3{0.0021, -0.0012, 0.0003} : Vec3{0.0001, 0, 0};
    add(t += 0.0005, line, {5.0 * std::cos(phi), 5.0 * std::sin(phi), 3.0 - phi / (2 * M_PI)}, ferr, 10.0);
  }
  return d.finish();
}

TEST(InlineBlob, Base64KnownAnswersAndGzipRoundTrip) {
  // RFC 4648, section 10
  const char* plain[] = {"", "f", "fo", "foo", "foob", "fooba", "foobar"};
  const char* coded[] = {"", "Zg==", "Zm8=", "Zm9v", "Zm9vYg==", "Zm9vYmE=", "Zm9vYmFy"};
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(base64_encode(plain[i]), coded[i]);
    EXPECT_EQ(base64_decode(coded[i]), plain[i]);
  }
  EXPECT_THROW(base64_decode("Zm9v!"), std::runtime_error);
  std::string data;
  for (int i = 0; i < 100000; ++i) data += static_cast<char>((i * 7919) % 251);
  const std::string gz = gzip_bytes(data);
  EXPECT_EQ(static_cast<unsigned char>(gz[0]), 0x1f) << "a gzip stream, as DecompressionStream('gzip') wants";
  EXPECT_EQ(static_cast<unsigned char>(gz[1]), 0x8b);
  EXPECT_EQ(gunzip_bytes(gz), data);
  EXPECT_THROW(gunzip_bytes(gz.substr(0, gz.size() / 2)), std::runtime_error);
}

TEST(PathView3d, RecordRoundTripsWithinItsQuanta) {
  const TraceDigest d = helix_digest();
  ASSERT_GT(d.path.size(), 1000u);
  const PathView3dOptions opt;
  const std::vector<ToolPathPoint> back = decode_path_record(encode_path_record(d.path, opt));
  ASSERT_EQ(back.size(), d.path.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    const ToolPathPoint &a = d.path[i], &b = back[i];
    for (std::size_t k = 0; k < 3; ++k) {
      ASSERT_NEAR(a.p[k], b.p[k], opt.quantum_mm / 2 + 1e-12) << i;  // steps are exact integers: no drift
      ASSERT_NEAR(a.ferr[k], b.ferr[k], 0.5e-4 + 1e-12) << i;
    }
    ASSERT_NEAR(a.t, b.t, opt.tick_s / 2 + 1e-12) << i;
    ASSERT_EQ(a.line, b.line) << i;
    ASSERT_NEAR(a.speed, b.speed, 0.005 + 1e-12) << i;
    ASSERT_EQ(a.rapid, b.rapid) << i;
  }
  EXPECT_THROW(decode_path_record("PV3D"), std::runtime_error);
  std::string bad = encode_path_record(d.path, opt);
  bad.push_back('x');
  EXPECT_THROW(decode_path_record(bad), std::runtime_error) << "trailing bytes are refused";
}

TEST(PathView3d, ThinningKeepsEndsAndRapidChanges) {
  const TraceDigest d = helix_digest();
  const std::vector<ToolPathPoint> thin = thin_for_view(d.path, 500);
  ASSERT_LE(thin.size(), 500u);
  ASSERT_GE(thin.size(), 100u) << "thinned by doubling a distance: at least a quarter of the budget is used";
  EXPECT_EQ(norm(thin.front().p - d.path.front().p), 0.0);
  EXPECT_EQ(norm(thin.back().p - d.path.back().p), 0.0);
  const auto changes = [](const std::vector<ToolPathPoint>& v) {
    int n = 0;
    for (std::size_t i = 1; i < v.size(); ++i) n += v[i].rapid != v[i - 1].rapid;
    return n;
  };
  EXPECT_EQ(changes(thin), changes(d.path));
  for (std::size_t i = 1; i < thin.size(); ++i) ASSERT_GE(thin[i].t, thin[i - 1].t) << "in time order";
  EXPECT_EQ(thin_for_view(d.path, 1000000).size(), d.path.size()) << "under the budget nothing is dropped";
}

TEST(PathView3d, WithoutThreeJsThereIsNoViewAndAReason) {
  std::string why;
  EXPECT_EQ(render_path_view_3d(helix_digest().path, PathView3dOptions{.three_dir = "/nonexistent/three"}, &why), "");
  EXPECT_NE(why.find("/nonexistent/three"), std::string::npos) << why;
  EXPECT_NE(why.find("libjs-three"), std::string::npos) << why;
}

// ---- in a browser ----

std::string attr(const std::string& dom, const std::string& name) {
  const std::regex re("<div class=\"view3d\"[^>]* " + name + "=\"([^\"]*)\"");
  std::smatch m;
  return std::regex_search(dom, m, re) ? m[1].str() : "";
}

std::string bold(const std::string& dom, const std::string& id) {
  const std::regex re("<b id=\"" + id + "\">([^<]*)</b>");
  std::smatch m;
  return std::regex_search(dom, m, re) ? m[1].str() : "";
}

TEST(PathView3dChromium, DrawsThePathAndTheSliderReadsOutThePointAtThatTime) {
  const std::string chromium = test::find_chromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (tools/install-deps.sh installs it): the 3D view test did not run";
  const TraceDigest d = helix_digest();
  std::string why;
  const std::string view = render_path_view_3d(d.path, PathView3dOptions{}, &why);
  if (view.empty()) GTEST_SKIP() << why;
  const std::string dir = test::make_temp_dir("view3d");
  const std::string html = dir + "/view.html";
  std::ofstream(html) << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><style>" << path_view_3d_css()
                      << "</style></head><body style=\"background:#161a24\"><div class=\"toolpath-static\">static</div>" << view
                      << "</body></html>";
  // What the page should show: the record's own points (quantised), found by time.
  const std::vector<ToolPathPoint> pts = decode_path_record(encode_path_record(thin_for_view(d.path, 20000), PathView3dOptions{}));
  const double t_end = pts.back().t;
  auto expected_index = [&](double t) {
    std::size_t i = 0;
    while (i + 1 < pts.size() && pts[i + 1].t <= t) ++i;
    return i;
  };

  int run = 0;
  for (const double f : {-1.0, 0.25, 0.75}) {  // -1: no hash, the dot at the end
    const std::string url = "file://" + html + (f < 0 ? std::string() : "#t=" + std::to_string(f));
    const test::ProcessResult r = test::chromium_dump_dom(chromium, url, dir + "/profile" + std::to_string(run++));
    ASSERT_EQ(attr(r.out, "data-state"), "ready") << "exit " << r.exit_code << "\n" << r.err << "\n" << r.out.substr(0, 2000);
    EXPECT_EQ(attr(r.out, "data-points"), std::to_string(pts.size()));
    EXPECT_GT(std::stoi(attr(r.out, "data-lit")), 2000) << "the path and its box are drawn";
    EXPECT_GT(std::stoi(attr(r.out, "data-red")), 10) << "the red dot is drawn";
    const double t = f < 0 ? t_end : std::round(f * 2000) / 2000 * t_end;
    const std::size_t i = expected_index(t);
    EXPECT_EQ(attr(r.out, "data-index"), std::to_string(i)) << "t " << t;
    EXPECT_EQ(bold(r.out, "v3-line"), std::to_string(pts[i].line));
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3f s", t);
    EXPECT_EQ(bold(r.out, "v3-time"), buf);
    std::snprintf(buf, sizeof buf, "%.2f mm/s", pts[i].speed);
    EXPECT_EQ(bold(r.out, "v3-speed").rfind(buf, 0), 0u) << bold(r.out, "v3-speed");
    EXPECT_NE(r.out.find("class=\"js has3d\""), std::string::npos) << "the static view is hidden on screen";
  }
  fs::remove_all(dir);
}

// A page of the helix, with the part's box around it.
ReportPage helix_page() {
  ReportPage page;
  page.has_trace = true;
  page.trace = helix_digest();
  page.summary.max_point = {5, 5, 8};
  page.summary.min_point = {-5, -5, 0};
  return page;
}

TEST(ReportHtml, CarriesTheInteractiveViewAndKeepsTheStaticOne) {
  ReportPage page = helix_page();
  const std::string html = render_report_html(page);
  std::string why;
  if (render_path_view_3d(page.trace.path, PathView3dOptions{}, &why).empty()) {
    EXPECT_NE(html.find("No interactive view"), std::string::npos) << "the reason is on the page";
  } else {
    EXPECT_NE(html.find("id=\"view3d\""), std::string::npos);
  }
  EXPECT_NE(html.find("<div class=\"toolpath-static\"><svg class=\"toolpath\""), std::string::npos);
  page.view3d = false;
  EXPECT_EQ(render_report_html(page).find("id=\"view3d\""), std::string::npos);
}

// three.js packed beforehand on another thread (as `pcnc run --report` does) gives the page the
// view packs itself: the same bytes, the library unpacking to three.min.js and OrbitControls;
// and a library that could not be read gives the same reason and no view.
TEST(ReportHtml, ThreeJsPackedOnAnotherThreadGivesTheSamePage) {
  ReportPage page = helix_page();
  const std::string in_place = render_report_html(page);
  page.view3d_options.library = std::async(std::launch::async, pack_three_js, std::string()).share();
  EXPECT_EQ(render_report_html(page), in_place);
  const PackedLibrary& lib = page.view3d_options.library.get();
  if (!lib.base64.empty()) {
    const std::string js = gunzip_bytes(base64_decode(lib.base64));
    EXPECT_NE(js.find("OrbitControls"), std::string::npos);
    EXPECT_NE(in_place.find(lib.base64), std::string::npos) << "the page inlines the packed library";
  }
  page.view3d_options = PathView3dOptions{.three_dir = "/nonexistent/three"};
  const std::string without = render_report_html(page);
  page.view3d_options.library = std::async(std::launch::async, pack_three_js, std::string("/nonexistent/three")).share();
  EXPECT_EQ(render_report_html(page), without);
  EXPECT_NE(without.find("No interactive view: three.js was not found in /nonexistent/three"), std::string::npos);
  EXPECT_EQ(without.find("id=\"view3d\""), std::string::npos);
}

}  // namespace
}  // namespace pcnc
