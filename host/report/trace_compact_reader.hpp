// trace_compact_reader.hpp — reads the compact trace that pcnc-rt's trace writer thread keeps
// for the report (pcnc-rt --trace-digest, format in ipc/trace_compact.hpp) and finishes it
// into the same TraceDigest the full CSV gives (report/trace_reader.hpp), with what only the
// host knows: which lines are rapids, each row's cause from the check's plan, the part's size
// for the path tolerance.
//
// Exact where the CSV's digest is exact: rows, program rows, every bucket (its time span, rows,
// min and max of speed and following error, feed/rapid rows and speeds, planned speed, rows
// per cause), the rows per cause and per line, the last row. The tool path is decimated
// twice (by the rt at 1 µm or more, then here by the report's rule), so its points may differ
// from the CSV's digest within the rt's tolerance; its end point is the same. A rotary
// machine's joints (TraceDigest::joints): the joints' following-error buckets and their
// maxima are exact; the tip path and tool-axis marks come from the rt's kept points (1 µm or
// 0.001° apart, or more past its point budget), so they may differ from the CSV's within that.
#pragma once

#include <string>

#include "report/trace_reader.hpp"

namespace pcnc {

/// True when the file starts with the compact trace's magic (false for a CSV or a missing file).
bool is_compact_trace_file(const std::string& path);

/// Reads and digests a compact trace. Throws std::runtime_error naming the file when it
/// cannot be read, is not a compact trace of this build's layout, or was cut short (pcnc-rt
/// did not close it).
TraceDigest digest_compact_trace(const std::string& path, const DigestOptions& options = {});

}  // namespace pcnc
