// ctl_capture.cpp — a capture's reply to its two files (see ctl_capture.hpp).
#include "ctl_capture.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace pcnc {

std::string capture_csv_path(const std::string& html_path) {
  return std::filesystem::path(html_path).replace_extension(".csv").string();
}

ScopeRecord capture_record(const nlohmann::json& res) {
  ScopeRecord r;
  try {
    r.signals = res.at("signals").get<std::vector<std::string>>();
    const auto& cols = res.at("columns");
    r.t = cols.at("t").get<std::vector<double>>();
    for (const auto& s : r.signals) {
      r.columns.push_back(cols.at(s).get<std::vector<double>>());
      if (r.columns.back().size() != r.t.size()) throw std::runtime_error("column " + s + " has a different length than t");
    }
    if (res.value("rows", std::size_t{0}) != r.t.size()) throw std::runtime_error("'rows' disagrees with the columns");
    if (res.at("trigger").is_string()) r.trigger = res["trigger"].get<std::string>();
    r.trigger_row = res.value("trigger_row", std::size_t{0});
    r.period_s = res.value("period_s", 0.0005);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("malformed capture reply: ") + e.what());
  }
  return r;
}

namespace {
void write_file(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot create " + path + ": " + std::strerror(errno));
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  const int e = errno;
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error("cannot write " + path + ": " + std::strerror(ok ? errno : e));
}
}  // namespace

void write_capture_files(const ScopeRecord& record, const std::string& html_path) {
  write_file(capture_csv_path(html_path), scope_csv(record));
  write_file(html_path, render_scope_html(record));
}

}  // namespace pcnc
