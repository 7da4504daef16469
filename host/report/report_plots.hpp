// report_plots.hpp — the run report's plots over program time as inline SVG: min..max
// envelopes per time bucket (one bucket per pixel column, so no peak is lost), and for the
// path speed the extras that explain it: feed moves on their own scale with rapids marked
// apart, the planned speed (F, or what caps it) as a reference line, a band coloured by the
// cause the time went to, and a program-line axis under the time axis.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "report/trace_reader.hpp"

namespace pcnc {

struct PlotSeries {
  std::string name, colour;
  std::vector<double> lo, hi;  // per bucket
  std::vector<bool> valid;     // per bucket; empty: all (a gap where false)
};

struct TimePlot {
  std::string css_class, label, unit;
  std::vector<double> t;              // per bucket: its middle, program time s
  std::vector<PlotSeries> series;
  bool symmetric = false;             // y range symmetric about 0
  // extras (empty: none)
  std::vector<double> reference;      // a step line per bucket (<= 0: none there), e.g. the planned speed
  std::string reference_name;
  std::vector<bool> marked;           // buckets shaded (e.g. rapids), named `marked_name`
  std::string marked_name;
  std::vector<std::string> band;      // a colour per bucket under the plot ("" none)
  std::vector<std::uint32_t> line_lo; // program lines per bucket, for the line axis
};

std::string render_time_plot(const TimePlot& p);

/// The speed plot's data from the digest (feed speeds, rapids, planned speed, cause band, lines).
TimePlot speed_plot(const TraceDigest& d);
/// The following error per axis (µm).
TimePlot ferr_plot(const TraceDigest& d);
/// The following error per rotary joint of a 5-axis trace (millidegrees), like ferr_plot.
TimePlot joint_ferr_plot(const JointDigest& d);

}  // namespace pcnc
