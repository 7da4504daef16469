// job_journal.cpp — JSON form of the program journal (see job_journal.hpp).
#include "service/job_journal.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>

namespace pcnc {

using json = nlohmann::json;

std::string journal_path(const std::string& state_dir) { return state_dir + "/job.json"; }

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
                    {"file_sha256", j.file_sha256},
                    {"transform", {{"offset", {j.transform_offset[0], j.transform_offset[1], j.transform_offset[2]}},
                                   {"scale", j.transform_scale}}},
                    {"path_tolerance_mm", j.path_tolerance_mm},
                    {"config", j.config_path},
                    {"host_pid", j.host_pid},
                    {"seq_base", j.seq_base},
                    {"probes", [&] {
                       json a = json::array();
                       for (const JournalProbe& p : j.probes) {
                         a.push_back({{"outcome", p.outcome},
                                      {"latched", {p.latched[0], p.latched[1], p.latched[2]}},
                                      {"stop", {p.stop[0], p.stop[1], p.stop[2]}}});
                       }
                       return a;
                     }()}};
  return write_file_atomically(path, doc.dump(2) + "\n", error);
}

std::optional<JobJournal> read_journal(const std::string& path, std::string* error) {
  // O_NOFOLLOW: a symlink planted at the journal's name is not read through.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) {
    if (error) *error = "no program journal at " + path + " (" + std::strerror(errno) + ")";
    return std::nullopt;
  }
  std::string text;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0 || text.size() > (1u << 20)) break;
    text.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  try {
    const json doc = json::parse(text);
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
    // Absent in a journal of an older pcnc-host: a resume then refuses (no content hash).
    j.file_sha256 = doc.value("file_sha256", std::string());
    if (doc.contains("transform")) {
      for (std::size_t k = 0; k < 3; ++k) j.transform_offset[k] = doc.at("transform").at("offset").at(k).get<double>();
      j.transform_scale = doc.at("transform").at("scale").get<double>();
    }
    j.path_tolerance_mm = doc.value("path_tolerance_mm", 0.0);
    j.config_path = doc.value("config", std::string());
    j.seq_base = doc.value("seq_base", std::uint64_t{0});
    if (doc.contains("probes")) {
      for (const json& p : doc.at("probes")) {
        JournalProbe r;
        r.outcome = p.at("outcome").get<int>();
        for (std::size_t k = 0; k < 3; ++k) {
          r.latched[k] = p.at("latched").at(k).get<double>();
          r.stop[k] = p.at("stop").at(k).get<double>();
        }
        j.probes.push_back(r);
      }
    }
    if (j.work_offset < 0 || j.work_offset > 5) throw std::runtime_error("work_offset out of range");
    return j;
  } catch (const std::exception& e) {
    if (error) *error = "program journal " + path + " is unreadable: " + e.what();
    return std::nullopt;
  }
}

void remove_journal(const std::string& path) { unlink(path.c_str()); }

}  // namespace pcnc
