// fixed_text.hpp — numbers as fixed-decimal text: the one formatter of the report pages'
// figures and SVG coordinates (host/report: report_html, report_plots, the tool-axis view, the
// scope and surface pages) and of the grbl status report (host/grbl), which both may include
// shared/config.
//
// The digits are printf's "%.*f" in the C locale (the exact binary value, ties to even), made
// without printf's format parsing and locale: a report writes some 190 000 coordinates, and
// snprintf was a third of the report's time (docs/replay.md, "Replay speed with a report").
// Small values far from a tie are rounded as integers (v times 10^decimals, under 1e9: its
// rounding error cannot cross a rounding step); the rest goes through std::to_chars
// (chars_format::fixed, precision), which gives printf's digits. test_fixed_text compares
// both paths with snprintf over a broad sweep.
// One difference from printf: a value that prints as zero has no minus sign ("-0.000" is
// written "0.000"), so a tiny negative error does not show as "-0.00". NaN and infinities
// read as printf writes them: "nan", "-nan", "inf", "-inf".
#pragma once

#include <string>

namespace pcnc {

/// Appends `v` with `decimals` digits after the point (none and no point for 0; a negative
/// count is printf's default, 6) to `out`.
void append_fixed(std::string& out, double v, int decimals);

/// The same as a string.
std::string fixed(double v, int decimals);

}  // namespace pcnc
