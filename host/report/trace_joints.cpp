// trace_joints.cpp — the joint columns of a 5-axis trace. See trace_joints.hpp.
#include "report/trace_joints.hpp"

#include <charconv>
#include <string>

#include "ipc/trace_format.hpp"

namespace pcnc {
namespace {

constexpr std::size_t kBaseFields = 13;

bool number(std::string_view s, double& v) {
  if (s.empty()) return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

}  // namespace

bool parse_trace_joint_header(std::string_view header, std::vector<char>& letters) {
  letters.clear();
  while (!header.empty() && (header.back() == '\r' || header.back() == '\n')) header.remove_suffix(1);
  const std::string_view base = kTraceCsvHeader;
  if (header.substr(0, base.size()) != base) return false;
  std::string_view rest = header.substr(base.size());
  while (!rest.empty()) {
    if (rest.size() < 6 || letters.size() == kMaxTraceJoints) return false;
    const char l = rest[5];
    if (l != 'a' && l != 'b' && l != 'c') return false;
    const std::string triple = std::string(",cmd_") + l + ",act_" + l + ",ferr_" + l;
    if (rest.substr(0, triple.size()) != triple) return false;
    for (char seen : letters)
      if (seen == l - 'a' + 'A') return false;
    letters.push_back(static_cast<char>(l - 'a' + 'A'));
    rest.remove_prefix(triple.size());
  }
  return true;
}

bool split_trace_joint_row(std::string_view text, std::size_t joints, std::string_view& base, TraceJointRow& row) {
  if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
  std::size_t pos = 0, commas = 0;
  for (; pos < text.size(); ++pos) {
    if (text[pos] == ',' && ++commas == kBaseFields) break;
  }
  if (joints == 0) {
    base = text;
    row.count = 0;
    return true;
  }
  if (commas != kBaseFields || joints > kMaxTraceJoints) return false;
  base = text.substr(0, pos);
  std::string_view rest = text.substr(pos + 1);
  row.count = joints;
  for (std::size_t j = 0; j < joints; ++j) {
    double* out[3] = {&row.cmd[j], &row.act[j], &row.ferr[j]};
    for (double* v : out) {
      const std::size_t c = rest.find(',');
      const bool last = j + 1 == joints && v == out[2];
      if (last != (c == std::string_view::npos)) return false;
      if (!number(rest.substr(0, c), *v)) return false;
      rest = last ? std::string_view{} : rest.substr(c + 1);
    }
  }
  return true;
}

}  // namespace pcnc
