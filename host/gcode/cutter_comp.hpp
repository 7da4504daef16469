// cutter_comp.hpp — cutter radius compensation, the first geometry stage of the pipeline
// (gcode/pipeline.hpp): the programmed contour in, the tool centre's path out, offset by the
// tool radius to the left (G41) or right (G42) in the plane compensation went on in (G17,
// G18 or G19).
//
// The moves are those LinuxCNC's interpreter makes (its comp1/comp2 rules), so that a program
// gives LinuxCNC's end points:
//   * the entry move (the first move after G41/G42) goes straight from where the tool is to
//     the end point offset along the normal of that move (an arc entry keeps its center);
//     it must be longer than the tool radius;
//   * each later move ends at its end point offset along its own normal; it is held back one
//     move (a queue), because the next move decides where it really ends:
//       - convex corner: an arc about the programmed corner joins the two offset moves;
//       - concave corner: the held move is cut back to where the two offset moves meet (line
//         and arc intersections), and an error names the move when one would reverse;
//       - within 0.05 rad: tangent, nothing inserted;
//   * a move with no motion in the plane (Z under G17) keeps the tool's place in the plane;
//   * G40 ends the held move where it is; the next move goes from there to its programmed end
//     point and must be straight (an arc there is an error, as in LinuxCNC).
// Beyond LinuxCNC: a NURBS move (G5.2/G6.2), and a run of at least 8 G1 moves each shorter than
// cutter_comp.fit_segment_max_mm turning less than the contouring angle at each junction, are
// replaced by tangent biarcs within cutter_comp.fit_tolerance_mm (geometry/biarc.hpp) whose
// offsets are exact; those arcs then go through the rules above (cutter_comp_fit.cpp).
// Besides LinuxCNC's local tests, every tool move is measured against every programmed move
// within kGougeWindow moves on either side (exact distances, geometry/intersect.hpp): a tool
// path that comes closer to the contour than the tool radius is a gouge, reported with the
// line and column of the move and its depth. All in machine mm: under --fit the programmed path
// is scaled and offset by the real radius.
// Inverse time (G93): the tool's move takes the programmed move's time, as in LinuxCNC (its feed
// is the offset move's length over that time); a corner arc inserted before it runs at the
// programmed move's feed; G93 moves are never fitted into biarc runs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include "gcode/cutter_gouge.hpp"
#include "gcode/diagnostics.hpp"
#include "gcode/move.hpp"
#include "geometry/offset.hpp"

namespace pcnc {

/// What compensation did over a program, for `pcnc check` and the run report.
struct CompFigures {
  std::uint64_t sessions = 0;          // G41/G42 entries that moved the tool
  std::uint64_t moves_in = 0;          // moves offset (a fitted curve counts its arcs)
  std::uint64_t moves_out = 0;         // tool moves made for them (corner arcs included)
  std::uint64_t corner_arcs = 0;       // convex corners rounded
  std::uint64_t concave_corners = 0;   // offset moves cut back at a concave corner
  double max_radius_mm = 0.0;          // the largest tool radius used
  // Biarc fits under G41/G42 (cutter_comp_fit.cpp): NURBS curves and runs of short G1 moves
  // replaced by tangent arcs, then offset exactly.
  std::uint64_t fitted_nurbs = 0;      // NURBS moves fitted
  std::uint64_t fitted_runs = 0;       // G1 runs fitted
  std::uint64_t moves_replaced = 0;    // programmed moves they held (a NURBS counts 1)
  std::uint64_t biarcs = 0;            // biarcs that replaced them
  std::uint64_t gouges = 0;            // exact look-ahead gouges reported (errors; the moves go on)
  std::uint64_t fit_arcs = 0;          // arcs (and straight pieces) those biarcs are made of
  double max_fit_deviation_mm = 0.0;   // the largest deviation measured between a curve and its arcs
  // The programmed contour of each session (machine mm, arcs as chords of at most 3 degrees),
  // for the run report's top view; at most kMaxContourPoints in all (contour_truncated then).
  static constexpr std::size_t kMaxContourPoints = 20000;
  std::vector<std::vector<Vec3>> contour;
  bool contour_truncated = false;
};

/// The config's [cutter_comp] and the contouring angle, as the stage uses them.
struct CompOptions {
  bool gouge_check = true;             // false: LinuxCNC's local tests alone
  double fit_segment_max_mm = 0.5;     // G1 runs: each move shorter than this
  double fit_tolerance_mm = 0.001;     // biarcs within this of the curve
  double contouring_angle_rad = 0.17453292519943295;  // G1 runs: each junction turning less
  double max_feed_mm_s = 1e300;        // G93: an offset move's feed (its length / its time) is capped here
  static constexpr std::size_t kMinRun = 8;           // G1 runs: at least this many moves
};

class CutterComp {
 public:
  CutterComp(DiagnosticSink& sink, const CompOptions& options) : sink_(sink), options_(options) {}

  /// The next move of the compensated stream (see SegmentMerger::next for the shape).
  bool next(const std::function<bool(Move&)>& pull, Move& out);

  const CompFigures& figures() const { return figures_; }

  /// The tool moves a program was offset into (their source lines), for the run report.
  bool active() const { return active_; }

 private:
  // One move held back (LinuxCNC's queue): what to emit, with what its end may still become.
  struct Held {
    Move m;               // template: line, feed, kind; start is filled in at emission
    Vec2 end{};           // in the plane
    double out_of_plane = 0.0;
    Vec2 dir{};           // straight: the direction it was programmed in (for the reversal test)
    Vec2 center{};        // arc
    int turn = 0;         // arc: +1 ccw, -1 cw
    double original_turn = 0.0;  // arc: its sweep as made (0: never tested)
    bool motion = true;   // false: a dwell or pause riding in the queue
    bool entry = false;   // the entry move (not measured for gouges)
    bool corner = false;  // an arc inserted at a convex corner (G93: runs at the next move's feed)
    int index = -1;       // the programmed move of the session it belongs to
  };

  void process(Move& m);
  void dispatch(Move& m);  // one programmed move of an active session
  // cutter_comp_fit.cpp: biarcs for NURBS curves and short G1 runs
  bool run_candidate(const Move& m) const;
  void flush_run();
  void fit_nurbs(const Move& m);
  bool comp_on(const Move& m);
  void comp_off();
  void straight_entry(const Move& m);
  void straight_next(const Move& m);
  void arc_entry(const Move& m);
  void arc_next(const Move& m);
  bool move_endpoint_and_flush(const Move& m, Vec2 p);
  void dequeue();
  void emit(const Held& h);
  void report_gouge(const Gouge& g);
  Held held(const Move& m, Vec2 end, double oop) const;  // a held move of this session
  void enqueue_line(const Move& m, Vec2 dir, Vec2 end, double oop);
  void enqueue_arc(const Move& m, double original_turn, Vec2 end, Vec2 center, int turn, double oop);
  void set_endpoint(Vec2 p) {
    endpoint_ = p;
    endpoint_valid_ = true;
  }
  bool fail(const Move& m, const std::string& message);
  Vec2 in_plane(const Vec3& p) const;
  double oop(const Vec3& p) const { return p[static_cast<std::size_t>(normal_)]; }
  Vec3 to_space(Vec2 p, double oop) const;
  Vec2 cur() const { return in_plane(cur_); }
  Vec2 prog() const { return in_plane(prog_); }
  void programmed_piece(const Move& m);
  void note_crossings();  // the warning for gouge pairs skipped at self-crossings
  void record_contour(const Move& m);  // the programmed move, for CompFigures::contour
  std::size_t contour_points_ = 0;

  DiagnosticSink& sink_;
  CompOptions options_;
  std::vector<Move> run_;  // short G1 moves held back: a smooth run to fit, if long enough
  std::deque<Move> ready_;   // moves to hand on, in order
  std::vector<Held> queue_;  // held back
  bool ended_ = false;
  bool have_pos_ = false;
  Vec3 emitted_{};  // where the last move handed on ends (the tool's position)

  // The session (LinuxCNC's cutter_comp_* state), in the plane's coordinates.
  bool active_ = false;
  bool first_move_ = false;
  bool arc_not_allowed_ = false;  // the move after a G40 must be straight
  bool resume_from_tool_ = false;
  std::uint32_t serial_ = 0;
  std::uint32_t broken_serial_ = 0;  // a session that failed: its moves pass unchanged
  CompSide side_ = CompSide::kOff;
  double radius_ = 0.0;
  double arc_tolerance_ = 0.0254;  // LinuxCNC's sweep growth allowed when an arc end moves
  int normal_ = 2;
  Vec3 cur_{};   // the tool
  Vec3 prog_{};  // the programmed point
  Vec2 endpoint_{};
  bool endpoint_valid_ = false;
  int index_ = 0;  // programmed moves in the session
  int session_line_ = 0;
  GougeCheck gouge_;
  CompFigures figures_;
};

}  // namespace pcnc
