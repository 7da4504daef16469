// words.hpp — the G-code dialect in one table: every G and M code that some RS274 dialect
// defines, its modal group, and whether this machine executes it (or accepts it with a
// logged warning, the interpreter's decision) or rejects it, with why and what to write
// instead. The parser asks it for the group (an unknown code is an error there), the
// interpreter for the rejection; docs/gcode.md lists the same codes for users.
#pragma once

namespace pcnc {

/// G and M numbers are kept as ten times their value: G1 -> 10, G5.2 -> 52, G91.1 -> 911.
enum GGroup : int {
  kGNonModal = 0,        // G4 G10 G28 G28.1 G30 G30.1 G52 G53 G92 G92.x
  kGMotion = 1,          // G0 G1 G2 G3 G5.x G6.2 G33 G38.x G73 G76 G80-G89
  kGPlane = 2,           // G17 G18 G19 (and .1)
  kGDistance = 3,        // G90 G91
  kGArcDistance = 4,     // G90.1 G91.1
  kGFeedMode = 5,        // G93 G94 G95
  kGUnits = 6,           // G20 G21
  kGCutterComp = 7,      // G40 G41 G42 (and .1)
  kGToolLength = 8,      // G43 G43.1 G43.2 G49
  kGCannedReturn = 10,   // G98 G99
  kGCoordSystem = 12,    // G54-G59, G59.1-G59.3
  kGPathControl = 13,    // G61 G61.1 G64
  kGSpindleMode = 14,    // G96 G97
  kGLatheDiameter = 15,  // G7 G8
  kGGroupCount = 16
};

enum MGroup : int {
  kMStop = 0,        // M0 M1 M2 M30 M60
  kMToolChange = 1,  // M6 M61
  kMSpindle = 2,     // M3 M4 M5 M19
  kMCoolant = 3,     // M7 M8 M9
  kMOverride = 4,    // M48-M53
  kMContouring = 5,  // M21 M22 (pcnc: contouring on/off)
  kMOther = 6,       // M62-M68, M100-M199 (known, refused), M70-M73 (modal state)
  kMSubprogram = 7,  // M98 M99 (Fanuc subprograms)
  kMTcp = 8,         // M428 M429: tool-centre-point control on/off (LinuxCNC's XYZAC demos)
  kMGroupCount = 9
};

/// One row of the table: the codes first, first + step, ..., last (G: x10), their group, and
/// why this machine rejects them (nullptr: executed, or accepted with a warning).
struct CodeInfo {
  int first;
  int last;
  int step;
  int group;
  const char* rejected;
};

/// The row of a G number (x10) or an M number; nullptr when no dialect defines it.
const CodeInfo* g_code(int code10);
const CodeInfo* m_code(int code);

/// Modal group of a G number (x10), or -1 when no RS274 dialect defines it.
inline int g_group(int code10) {
  const CodeInfo* c = g_code(code10);
  return c ? c->group : -1;
}
/// Modal group of an M number, or -1 when undefined.
inline int m_group(int code) {
  const CodeInfo* c = m_code(code);
  return c ? c->group : -1;
}
/// nullptr when the code is executed or warned about (or unknown); else why it is rejected.
inline const char* g_rejected(int code10) {
  const CodeInfo* c = g_code(code10);
  return c ? c->rejected : nullptr;
}
inline const char* m_rejected(int code) {
  const CodeInfo* c = m_code(code);
  return c ? c->rejected : nullptr;
}

}  // namespace pcnc
