// ctl_capture.hpp — `pcnc ctl capture`'s files: the `capture` reply (docs/protocol.md) turned
// into a ScopeRecord and written as the HTML page the user named and the CSV beside it (same
// stem). The client writes them, never the service: a file is written with the rights of the
// user who asked for it.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "report/scope_page.hpp"

namespace pcnc {

/// The CSV path beside an HTML path: scope.html -> scope.csv.
std::string capture_csv_path(const std::string& html_path);
/// The record in a `capture` result. Throws std::runtime_error when the result is malformed
/// (a column missing or of the wrong length).
ScopeRecord capture_record(const nlohmann::json& result);
/// Writes both files; throws std::runtime_error naming the file that failed.
void write_capture_files(const ScopeRecord& record, const std::string& html_path);

}  // namespace pcnc
