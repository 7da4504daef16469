// job_journal.hpp — the small file in which `pcnc-host --serve` records the program it is
// feeding (path and SHA-256 of its content, options, work offsets, the transform and the path
// tolerance the blocks were made with, start position, file size and time), so that a host
// started after a crash of the previous one can re-stream the same program and resume it
// where pcnc-rt held it (HOST_LOST). Written when a program starts, removed when it ends.
//
// May include: shared/geometry, config/atomic_file.hpp, config/work_state.hpp (the file format is private to job_journal.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "config/atomic_file.hpp"  // write_file_atomically
#include "config/work_state.hpp"   // WorkOffsets
#include "geometry/vec3.hpp"

namespace pcnc {

/// One probing move's result as the rt reported it (docs/probe.md): ProbeOutcome as a number,
/// machine mm.
struct JournalProbe {
  int outcome = 1;
  Vec3 latched{};
  Vec3 stop{};
};

struct JobJournal {
  std::string file;                // absolute path of the G-code program
  int work_offset = 0;             // 0..5 = G54..G59 at program start
  // G54..G59.3 in effect at the start (set_offset may change them later). A journal of an
  // older pcnc-host holds only G54..G59: G59.1..G59.3 then read as 0 (a job used none of them).
  WorkOffsets work_offsets{};
  bool fit = false;
  int contouring = -1;             // -1: the config's default, 0 off, 1 on
  Vec3 start_position{};           // the machine position the program was checked from
  std::uint64_t file_size = 0;
  std::int64_t file_mtime_ns = 0;  // to notice a file changed since
  std::string file_sha256;         // the program's content: a resumed run is the same program
  Vec3 transform_offset{};         // machine = scale * program + offset, as checked at the start
  double transform_scale = 1.0;
  double path_tolerance_mm = 0.0;  // the config's path tolerance the blocks were made with
  std::string config_path;         // the machine config the service ran with (for the record)
  int host_pid = 0;
  // Program blocks before the current run's first block: a resumed run numbers its blocks
  // from 1 again, so program block = rt block_seq + seq_base.
  std::uint64_t seq_base = 0;
  // The results of the program's probing moves so far, in order: a resumed run interprets the
  // program with them (docs/probe.md).
  std::vector<JournalProbe> probes;
};

/// Where the journal lives in the service's private state directory (runtime_paths.hpp).
std::string journal_path(const std::string& state_dir);
/// Writes atomically (write_file_atomically). Returns false with `error` set on failure; the
/// journal already there is then left as it was.
bool write_journal(const std::string& path, const JobJournal& journal, std::string* error);
/// Reads a journal; nullopt (with `error` set) when absent or unreadable.
std::optional<JobJournal> read_journal(const std::string& path, std::string* error);
void remove_journal(const std::string& path);
/// Size and modification time of a file (false if it cannot be read).
bool file_identity(const std::string& path, std::uint64_t& size, std::int64_t& mtime_ns);

}  // namespace pcnc
