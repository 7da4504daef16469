// cutter_gouge.hpp — the exact gouge test of cutter compensation (cutter_comp.hpp): every tool
// move of a compensation session is measured against every programmed move from 2 to
// kGougeWindow moves before or after it (a move and its neighbours meet at corners that
// LinuxCNC's rules decide, with their own errors), with the exact minimum distance between a segment or
// arc and another (geometry/intersect.hpp). A tool centre closer to the contour than the tool
// radius cuts into it: a notch narrower than the tool, a concave arc of smaller radius than the
// tool, an offset move that reversed. Each pair is measured once, when the later of the two
// arrives, so the test streams over programs of any length with O(window) memory.
// Two kinds of pair are not gouges and are skipped: a contour that winds a full turn (its
// signed turning, arcs and corners, reaches 2 pi either way) from one move to the other is on
// another lap (roughing passes, repositioning loops: LinuxCNC's cam-nisley), and one that
// crosses itself between them has no material side there (crazy-paths); the latter is counted
// for a warning. The walls of a notch or a bottle neck are about half a turn apart.
#pragma once

#include <deque>
#include <string>

#include "geometry/offset.hpp"

namespace pcnc {

inline constexpr int kGougeWindow = 32;  // programmed moves looked at before and after each tool move

struct Gouge {
  int line = 0;      // the move whose tool path cuts in
  int column = 0;
  int into_line = 0; // the programmed move it cuts into
  double depth_mm = 0.0;
  Vec2 at{};         // where on the tool path (plane coordinates)
};

class GougeCheck {
 public:
  /// A new session with this tool radius: forgets the last one.
  void start(double radius_mm);
  /// A programmed move (index counts the session's moves); false and `g` when a tool move
  /// already made comes too close to it.
  bool programmed(const Piece& p, int index, int line, Gouge& g);
  /// A tool move made for programmed move `index`; false and `g` when it comes too close to a
  /// programmed move within the window.
  bool tool(const Piece& t, int index, int line, int column, Gouge& g);

  /// The depth accepted as no gouge: 1 um, plus twice what LinuxCNC's 0.05 rad corner
  /// tolerance lets a nearly straight concave corner take (r (1 - cos 0.05) each).
  double tolerance() const { return tolerance_; }
  /// Tool moves too close to a contour that crosses itself between them: not gouges (neither
  /// side of such a contour is the material's), counted for a warning.
  int crossings() const { return crossings_; }

 private:
  struct Item {
    Piece p;
    int index;
    int line;
    int column;
    double turned = 0.0;  // programmed: the contour's signed turning up to its end (radians)
  };
  bool measure(const Item& tool, const Item& prog, Gouge& g) const;
  void trim(int index);
  bool crosses_itself(int from, int to) const;  // two programmed moves of [from, to] cross
  bool laps(int from, int to) const;            // the contour over [from, to] winds a full turn

  double radius_ = 0.0;
  double tolerance_ = 1e-6;
  mutable int crossings_ = 0;
  std::deque<Item> programmed_;
  std::deque<Item> tools_;
};

/// The error text for a gouge: the move, how deep, into which line, the tool radius.
std::string describe_gouge(const Gouge& g, double radius_mm);

}  // namespace pcnc
