// interpreter_modal_state.cpp — LinuxCNC's M70-M73: saving and restoring the modal state.
//
// M70 saves the modal state at the current call level (the main program, or this invocation
// of a subroutine: a level is a call running, as MoveSource follows the control flow), M71
// forgets it, M72 restores it (an error when nothing was saved at this level), and M73 saves it
// to be restored when the subroutine returns (endsub, return, M99). The state, as LinuxCNC's
// M-code reference lists what pcnc has of it: units (restored first, so that F keeps its
// meaning), plane, distance mode, arc distance mode, feed mode, feed, work coordinate system,
// tool length offset, retract mode, path control (contouring and path tolerance). The motion
// mode is not restored (LinuxCNC). Spindle, coolant and override state do not exist here.
// Cutter compensation is part of LinuxCNC's state; pcnc refuses a restore that would turn it
// on, off or into another plane (the entry and exit moves belong to G41/G42/G40).
#include <string>

#include "gcode/interpreter.hpp"
#include "gcode/interpreter_text.hpp"

namespace pcnc {

using namespace interp;

Interpreter::SavedModal Interpreter::save_modal() const {
  SavedModal s;
  s.inches = inches_;
  s.incremental = incremental_;
  s.inverse_time = inverse_time_;
  s.arc_absolute = arc_absolute_;
  s.retract_r = retract_r_;
  s.contouring = contouring_;
  s.tool_offset_on = tool_offset_on_;
  s.normal_axis = normal_axis_;
  s.work_index = work_index_;
  s.feed = feed_;
  s.path_tolerance = path_tolerance_;
  s.tlo = tlo_;
  s.comp_side = comp_.side;
  s.comp_plane = comp_.normal_axis;
  return s;
}

bool Interpreter::restore_modal(const SavedModal& s, int line, int column, const char* by) {
  if (s.comp_side != comp_.side || (s.comp_side != 0 && s.comp_plane != comp_.normal_axis)) {
    sink_.error(line, column,
                std::string(by) + " would change cutter radius compensation (" + (comp_.side == 0 ? "G40" : "G41/G42") +
                    " now, " + (s.comp_side == 0 ? "G40" : "G41/G42") +
                    " when the state was saved); expected the compensation in effect at M70/M73 (G40, G41 or G42 "
                    "before the restore)");
    return false;
  }
  inches_ = s.inches;  // first: the feed below is in the saved units
  incremental_ = s.incremental;
  inverse_time_ = s.inverse_time;
  arc_absolute_ = s.arc_absolute;
  retract_r_ = s.retract_r;
  contouring_ = s.contouring;
  path_tolerance_ = s.path_tolerance;
  normal_axis_ = s.normal_axis;
  feed_ = s.feed;
  feed_cleared_line_ = 0;
  tool_offset_on_ = s.tool_offset_on;
  tlo_ = s.tlo;
  select_system(s.work_index);  // and the origin, with the tool length offset
  return true;
}

bool Interpreter::modal_state_words(const ParsedLine& l) {
  const int m = l.m[kMOther];
  if (m < 70 || m > 73) return true;
  const int column = l.m_col[kMOther];
  ModalLevel& level = modal_levels_.back();
  switch (m) {
    case 70:
      level.saved = save_modal();
      return true;
    case 71:
      level.saved.reset();
      level.autorestore = false;
      return true;
    case 72:
      if (!level.saved) {
        return fail(l, column,
                    std::string("M72 with no modal state saved at this ") +
                        (call_level() == 0 ? "level (the main program)" : "call level (this subroutine call)") +
                        "; expected M70 (or M73 in a subroutine) before it");
      }
      return restore_modal(*level.saved, l.line, column, "M72");
    default:  // 73
      level.saved = save_modal();
      level.autorestore = call_level() > 0;  // the main program's M2 restores nothing (LinuxCNC)
      return true;
  }
}

void Interpreter::enter_call() { modal_levels_.emplace_back(); }

void Interpreter::leave_call(int line) {
  if (modal_levels_.size() <= 1) return;
  const ModalLevel level = modal_levels_.back();
  modal_levels_.pop_back();
  if (level.autorestore && level.saved) (void)restore_modal(*level.saved, line, 0, "the return to M73's saved state");
}

}  // namespace pcnc
