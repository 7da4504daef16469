// job_journal.hpp — the small file in which `pcnc-host --serve` records the program it is
// feeding (path, options, work offsets, start position, file size and time), so that a host
// started after a crash of the previous one can re-stream the same program and resume it
// where pcnc-rt held it (HOST_LOST). Written when a program starts, removed when it ends.
//
// May include: shared/geometry only (the file format is private to job_journal.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "geometry/vec3.hpp"

namespace pcnc {

struct JobJournal {
  std::string file;                // absolute path of the G-code program
  int work_offset = 0;             // 0..5 = G54..G59 at program start
  std::array<Vec3, 6> work_offsets{};  // G54..G59 values in effect (set_offset may change later)
  bool fit = false;
  int contouring = -1;             // -1: the config's default, 0 off, 1 on
  Vec3 start_position{};           // the machine position the program was checked from
  std::uint64_t file_size = 0;
  std::int64_t file_mtime_ns = 0;  // to notice a file changed since
  int host_pid = 0;
  // Program blocks before the current run's first block: a resumed run numbers its blocks
  // from 1 again, so program block = rt block_seq + seq_base.
  std::uint64_t seq_base = 0;
};

/// Where the journal lives for a given control socket path.
std::string journal_path(const std::string& socket_path);
/// Writes atomically (temporary file + rename). Returns false with `error` set on failure.
bool write_journal(const std::string& path, const JobJournal& journal, std::string* error);
/// Reads a journal; nullopt (with `error` set) when absent or unreadable.
std::optional<JobJournal> read_journal(const std::string& path, std::string* error);
void remove_journal(const std::string& path);
/// Size and modification time of a file (false if it cannot be read).
bool file_identity(const std::string& path, std::uint64_t& size, std::int64_t& mtime_ns);

}  // namespace pcnc
