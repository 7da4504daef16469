// path_view_3d.hpp — the run report's interactive 3D tool path: rotate, zoom, and a time slider
// that moves the red dot along the path and reads out the program line, speed and following
// error at that moment (the seed's red dot, in a browser).
//
// The page stays one file: three.js (r111, from Debian's libjs-three, read when the report is
// written) and its OrbitControls are inlined gzip+base64 and unpacked by the browser; the path
// goes in as a compact binary record (below), packed the same way. Packing three.js (0.9 MB,
// gzip level 6: about 40 ms, level 4 about 17 ms) was the largest single cost of writing a report, the same bytes
// every time: `pcnc run --report` packs it on a second thread (pack_three_js, given to the
// view through PathView3dOptions::library) while the trace is read and the rest of the page
// drawn; both processes have ended by then, so the run's cores are free. Both blobs are
// packed at zlib level 4 (inline_blob.cpp): half of level 6's time for 17-21 kB more page. The static isometric SVG
// stays in the page for printing and for browsers without scripts; CSS shows one or the other.
//
// The binary record (little-endian), in planar arrays so that gzip finds the repeats:
//   "PV3D" u32 version(1) u32 n f64 x0 y0 z0 (origin, mm) f64 quantum_mm f64 tick_s
//   i32 dx[n] i32 dy[n] i32 dz[n]   position steps in quantum_mm from the previous point
//                                   (the first from the origin)
//   u32 dt[n]                       time steps in ticks (program time)
//   i32 dline[n]                    source line steps
//   u16 speed[n]                    commanded path speed, 0.01 mm/s (saturating)
//   i16 ferr_x[n] ferr_y[n] ferr_z[n] following error, 0.1 µm (saturating)
//   u8  rapid[n]                    1: the block was a rapid
#pragma once

#include <cstddef>
#include <cstdint>
#include <future>
#include <string>
#include <vector>

#include "report/trace_reader.hpp"

namespace pcnc {

/// three.js and its OrbitControls as the page inlines them (gzip + base64), or an empty
/// `base64` and `why_not` when they cannot be read.
struct PackedLibrary {
  std::string base64;
  std::string why_not;
};

/// Reads and packs three.js from `three_dir` (empty: the libjs-three directory pcnc was built
/// with). The same for every report: it may run on another thread while the page is drawn.
PackedLibrary pack_three_js(const std::string& three_dir);

struct PathView3dOptions {
  std::size_t max_points = 20000;   // the path is thinned (by distance, doubling) to at most this
  double quantum_mm = 0.0005;       // position resolution of the record
  double tick_s = 0.0005;           // time resolution (one rt cycle)
  std::string three_dir = "";       // empty: the libjs-three directory pcnc was built with
  /// three.js already being packed (pack_three_js, on another thread); not valid: the view
  /// packs it from three_dir itself
  std::shared_future<PackedLibrary> library = {};
};

/// The points the view draws: `path` thinned to at most `max_points` (a point is dropped when
/// closer than a growing distance to the last kept one in the same class; rapid/feed changes
/// and the last point are kept).
std::vector<ToolPathPoint> thin_for_view(const std::vector<ToolPathPoint>& path, std::size_t max_points);

/// The binary record above, for `points` (already thinned).
std::string encode_path_record(const std::vector<ToolPathPoint>& points, const PathView3dOptions& options);

/// A path decoded from the record (tests): positions rebuilt from the quantised steps.
std::vector<ToolPathPoint> decode_path_record(const std::string& record);

/// The view's HTML (container, slider, readout, inlined scripts), or an empty string and
/// `*why_not` set when three.js cannot be read (the report then keeps its static views).
std::string render_path_view_3d(const std::vector<ToolPathPoint>& path, const PathView3dOptions& options,
                                std::string* why_not);

/// The CSS the view needs (part of the report's style sheet).
const char* path_view_3d_css();

}  // namespace pcnc
