// point_grid_csv.cpp — the measured grid's CSV reader and writer (see point_grid_csv.hpp).
#include "config/point_grid_csv.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <vector>

namespace pcnc {
namespace {

[[noreturn]] void refuse(const std::string& origin, std::size_t line, std::size_t col, const std::string& why) {
  throw PointGridError(origin + ":" + std::to_string(line) + ":" + std::to_string(col) + ": " + why);
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

}  // namespace

PointGrid parse_point_grid_csv(std::string_view text, const std::string& origin) {
  std::vector<std::vector<Vec3>> rows;
  std::vector<std::size_t> row_line;  // the line each row starts on
  std::size_t line_no = 0, pos = 0;
  bool header = false;
  while (pos < text.size()) {
    const std::size_t nl = text.find('\n', pos);
    const std::string_view raw = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? text.size() : nl + 1;
    ++line_no;
    if (trim(raw).empty()) continue;  // blank lines (a trailing newline) are no rows
    if (!header) {
      std::string h;
      for (char c : raw)
        if (c != ' ' && c != '\t' && c != '\r') h += c;
      if (h != "x,y,z") refuse(origin, line_no, 1, "expected the header line 'x,y,z'");
      header = true;
      continue;
    }
    Vec3 p{};
    std::size_t start = 0;
    for (int k = 0; k < 3; ++k) {
      const std::size_t comma = raw.find(',', start);
      if (k < 2 && comma == std::string_view::npos)
        refuse(origin, line_no, raw.size() + 1, "expected 3 numbers x,y,z, found " + std::to_string(k + 1));
      const std::size_t end = k < 2 ? comma : raw.size();
      if (k == 2 && raw.find(',', start) != std::string_view::npos)
        refuse(origin, line_no, raw.find(',', start) + 1, "more than 3 values on the line");
      const std::string_view field = trim(raw.substr(start, end - start));
      const std::size_t lead = raw.substr(start, end - start).find_first_not_of(" \t");
      const std::size_t col = start + 1 + (lead == std::string_view::npos ? 0 : lead);
      double v = 0.0;
      const char* b = field.data();
      const char* e = field.data() + field.size();
      if (b < e && *b == '+') ++b;
      const auto r = std::from_chars(b, e, v);
      if (field.empty() || r.ec != std::errc() || r.ptr != e || !std::isfinite(v))
        refuse(origin, line_no, col, std::string("'") + std::string(field) + "' is not a finite number (" + "xyz"[k] + ")");
      p[static_cast<std::size_t>(k)] = v;
      start = end + 1;
    }
    if (!rows.empty() && !rows.back().empty() && p[0] > rows.back().back()[0]) {
      rows.back().push_back(p);
    } else {
      if (!rows.empty() && !rows.back().empty() && p[0] == rows.back().back()[0])
        refuse(origin, line_no, 1, "x does not increase within the row (a repeated point?)");
      rows.push_back({p});
      row_line.push_back(line_no);
    }
  }
  if (!header) refuse(origin, line_no + 1, 1, "empty file: expected the header line 'x,y,z'");
  if (rows.empty()) refuse(origin, line_no + 1, 1, "no points after the header");
  PointGrid g;
  g.cols = static_cast<int>(rows.front().size());
  g.rows = static_cast<int>(rows.size());
  double last_y = -INFINITY;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (rows[r].size() != rows.front().size())
      refuse(origin, row_line[r], 1,
             "row " + std::to_string(r + 1) + " has " + std::to_string(rows[r].size()) + " points, the first row " +
                 std::to_string(rows.front().size()) + " (rows end where x stops increasing)");
    double y = 0.0;
    for (const Vec3& p : rows[r]) y += p[1] / static_cast<double>(rows[r].size());
    if (!(y > last_y)) refuse(origin, row_line[r], 1, "row " + std::to_string(r + 1) + ": y does not increase from row to row");
    last_y = y;
    g.points.insert(g.points.end(), rows[r].begin(), rows[r].end());
  }
  return g;
}

PointGrid load_point_grid_csv(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw PointGridError(path + ": cannot be opened");
  if (!S_ISREG(st.st_mode)) throw PointGridError(path + ": is not a regular file");
  if (st.st_size > (64 << 20)) throw PointGridError(path + ": is larger than 64 MB");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw PointGridError(path + ": cannot be opened");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_point_grid_csv(text.str(), path);
}

std::string point_grid_csv(const PointGrid& g) {
  std::ostringstream out;
  out.precision(17);
  out << "x,y,z\n";
  for (const Vec3& p : g.points) out << p[0] << "," << p[1] << "," << p[2] << "\n";
  return out.str();
}

}  // namespace pcnc
