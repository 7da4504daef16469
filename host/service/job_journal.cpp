// job_journal.cpp — JSON form of the program journal (see job_journal.hpp).
#include "service/job_journal.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace pcnc {

using json = nlohmann::json;

std::string journal_path(const std::string& socket_path) { return socket_path + ".job"; }

bool file_identity(const std::string& path, std::uint64_t& size, std::int64_t& mtime_ns) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) return false;
  size = static_cast<std::uint64_t>(st.st_size);
  mtime_ns = static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
  return true;
}

bool write_journal(const std::string& path, const JobJournal& j, std::string* error) {
  json offsets = json::array();
  for (const auto& o : j.work_offsets) offsets.push_back({o[0], o[1], o[2]});
  const json doc = {{"file", j.file},
                    {"work_offset", j.work_offset},
                    {"work_offsets", offsets},
                    {"fit", j.fit},
                    {"contouring", j.contouring},
                    {"start_position", {j.start_position[0], j.start_position[1], j.start_position[2]}},
                    {"file_size", j.file_size},
                    {"file_mtime_ns", j.file_mtime_ns},
                    {"host_pid", j.host_pid},
                    {"seq_base", j.seq_base}};
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << doc.dump(2) << "\n";
    if (!out) {
      if (error) *error = "cannot write " + tmp;
      return false;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    if (error) *error = "cannot rename " + tmp + " to " + path;
    return false;
  }
  return true;
}

std::optional<JobJournal> read_journal(const std::string& path, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    if (error) *error = "no program journal at " + path;
    return std::nullopt;
  }
  std::stringstream ss;
  ss << in.rdbuf();
  try {
    const json doc = json::parse(ss.str());
    JobJournal j;
    j.file = doc.at("file").get<std::string>();
    j.work_offset = doc.at("work_offset").get<int>();
    const auto& offs = doc.at("work_offsets");
    for (std::size_t i = 0; i < j.work_offsets.size() && i < offs.size(); ++i) {
      for (std::size_t k = 0; k < 3; ++k) j.work_offsets[i][k] = offs[i].at(k).get<double>();
    }
    j.fit = doc.at("fit").get<bool>();
    j.contouring = doc.at("contouring").get<int>();
    for (std::size_t k = 0; k < 3; ++k) j.start_position[k] = doc.at("start_position").at(k).get<double>();
    j.file_size = doc.at("file_size").get<std::uint64_t>();
    j.file_mtime_ns = doc.at("file_mtime_ns").get<std::int64_t>();
    j.host_pid = doc.at("host_pid").get<int>();
    j.seq_base = doc.value("seq_base", std::uint64_t{0});
    if (j.work_offset < 0 || j.work_offset > 5) throw std::runtime_error("work_offset out of range");
    return j;
  } catch (const std::exception& e) {
    if (error) *error = "program journal " + path + " is unreadable: " + e.what();
    return std::nullopt;
  }
}

void remove_journal(const std::string& path) { unlink(path.c_str()); }

}  // namespace pcnc
