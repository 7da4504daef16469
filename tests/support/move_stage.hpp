// move_stage.hpp — runs one of the pipeline's geometry stages (a class with
// `bool next(const MovePull&, Move&)`, gcode/pipeline.hpp) over a list of moves in a test.
#pragma once

#include <vector>

#include "gcode/move.hpp"

namespace pcnc::test {

/// Every move `stage` hands on when it is fed `in`, in order.
template <class Stage>
std::vector<Move> run_move_stage(Stage& stage, const std::vector<Move>& in) {
  std::size_t next = 0;
  auto pull = [&](Move& m) {
    if (next >= in.size()) return false;
    m = in[next++];
    return true;
  };
  std::vector<Move> out;
  Move m;
  while (stage.next(pull, m)) out.push_back(m);
  return out;
}

}  // namespace pcnc::test
