// measure_program.cpp — the probing programs of `pcnc measure` and their log (see
// measure_program.hpp).
#include "measure_program.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pcnc {
namespace {

std::string xyz(const char* fmt, const Vec3& p) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, p[0], p[1], p[2]);
  return buf;
}

}  // namespace

std::vector<PlannedTouch> sphere_touches(const Vec3& centre, double sphere_radius, double ball_radius,
                                         const std::vector<Vec3>& approaches, double clearance, double distance) {
  std::vector<PlannedTouch> out;
  for (const Vec3& a : approaches) {
    const Vec3 d = normalized(a);
    const Vec3 contact = centre - sphere_radius * d;
    out.push_back({contact - (ball_radius + clearance) * d, contact - (ball_radius - distance) * d, d});
  }
  return out;
}

std::string probing_program(const std::vector<PlannedTouch>& touches, double safe_z, double feed,
                            const std::string& log_path, const std::string& title) {
  std::ostringstream g;
  g << "(pcnc measure: " << title << ", " << touches.size() << " touches, machine coordinates)\n";
  g << "G21 G90 G17 G40 G49 G94\nG92.1\n";
  g << "(PROBEOPEN " << log_path << ")\n";
  char z[64];
  std::snprintf(z, sizeof z, "G0 Z%.6f\n", safe_z);
  g << z;
  char f[32];
  std::snprintf(f, sizeof f, " F%.3f\n", feed);
  char z_start[64];
  for (const PlannedTouch& t : touches) {
    g << xyz("G0 X%.6f Y%.6f\n", t.start);
    std::snprintf(z_start, sizeof z_start, "G0 Z%.6f\n", t.start[2]);
    g << z_start;
    g << xyz("G38.2 X%.6f Y%.6f Z%.6f", t.end) << f;
    g << xyz("G0 X%.6f Y%.6f Z%.6f\n", t.start);
    g << z;
  }
  g << "(PROBECLOSE)\nM2\n";
  return g.str();
}

std::vector<Vec3> read_probe_log(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": the probe log cannot be read (did the program run its probing moves?)");
  std::vector<Vec3> out;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    std::istringstream s(line);
    Vec3 p{};
    if (!(s >> p[0] >> p[1] >> p[2])) throw std::runtime_error(path + ":" + std::to_string(n) + ": expected X Y Z ...");
    out.push_back(p);
  }
  return out;
}

}  // namespace pcnc
