// words.cpp — the table of G and M codes (see words.hpp).
#include "gcode/words.hpp"

#include <array>
#include <cstdint>

namespace pcnc {
namespace {

constexpr const char* kTapping =
    "tapping and boring cycles with the spindle (G74, G76, G84, G86-G88) are not supported: the machine has no "
    "spindle; expected G73, G81-G83, G85 or G89";

// One row per meaning: the codes first, first+step, ..., last (G numbers x10, so G54-G59 is
// 540 to 590 in steps of 10 and G38.2-G38.5 is 382 to 385 in steps of 1).
constexpr CodeInfo kGCodes[] = {
    // non-modal
    {40, 40, 1, kGNonModal, nullptr},  // G4 dwell
    {100, 100, 1, kGNonModal, nullptr},  // G10 L1/L2/L10/L11/L20
    {280, 281, 1, kGNonModal, nullptr},  // G28, G28.1
    {300, 301, 1, kGNonModal, nullptr},  // G30, G30.1
    {520, 520, 1, kGNonModal, nullptr},  // G52 local offset
    {530, 530, 1, kGNonModal, nullptr},  // G53 machine coordinates
    {920, 923, 1, kGNonModal, nullptr},  // G92, G92.1, G92.2, G92.3
    // motion
    {0, 30, 10, kGMotion, nullptr},  // G0 rapid, G1 line, G2/G3 arcs
    {50, 51, 1, kGMotion, nullptr},  // G5 cubic, G5.1 quadratic spline (interpreter_spline.cpp)
    {52, 53, 1, kGMotion, nullptr},  // G5.2/G5.3 NURBS (LinuxCNC)
    {62, 62, 1, kGMotion, nullptr},  // G6.2 NURBS (Fanuc)
    {330, 331, 1, kGMotion,
     "spindle-synchronized motion (G33) is not supported: the machine has no spindle; expected G0/G1/G2/G3 moves"},
    {382, 385, 1, kGMotion, nullptr},  // G38.2-G38.5 probing (a machine without [probe] refuses them)
    {730, 730, 1, kGMotion, nullptr},  // G73 chip-break drilling
    {740, 740, 1, kGMotion, kTapping},
    {760, 760, 1, kGMotion, kTapping},
    {800, 800, 1, kGMotion, nullptr},  // G80 cancels the canned cycle
    {810, 830, 10, kGMotion, nullptr},  // G81 G82 G83
    {840, 840, 1, kGMotion, kTapping},
    {850, 850, 1, kGMotion, nullptr},  // G85
    {860, 880, 10, kGMotion, kTapping},
    {890, 890, 1, kGMotion, nullptr},  // G89
    // plane
    {170, 190, 10, kGPlane, nullptr},  // G17 G18 G19
    {171, 191, 10, kGPlane, "the UV/WU/VW planes (G17.1/G18.1/G19.1) are not supported; expected G17, G18 or G19"},
    // distance modes, feed mode, units
    {900, 910, 10, kGDistance, nullptr},
    {901, 901, 1, kGArcDistance, nullptr},  // G90.1: I/J/K absolute
    {911, 911, 1, kGArcDistance, nullptr},
    {930, 930, 1, kGFeedMode, nullptr},  // G93 inverse time (interpreter_feed_mode.cpp)
    {940, 940, 1, kGFeedMode, nullptr},
    {950, 950, 1, kGFeedMode, "feed per revolution (G95) is not supported: the machine has no spindle; expected G94"},
    {200, 210, 10, kGUnits, nullptr},  // G20 G21
    // cutter compensation, tool length
    {400, 400, 1, kGCutterComp, nullptr},  // G40 compensation off
    {410, 411, 1, kGCutterComp, nullptr},  // G41, G41.1 left (host/gcode/cutter_comp.hpp)
    {420, 421, 1, kGCutterComp, nullptr},  // G42, G42.1 right
    {430, 430, 1, kGToolLength, nullptr},  // G43: the offset stays 0 (warned)
    {431, 431, 1, kGToolLength, nullptr},  // G43.1 dynamic tool length
    {432, 432, 1, kGToolLength, nullptr},  // G43.2: add a tool's offset (H) or the axis words to it
    {434, 434, 1, kGToolLength, nullptr},  // G43.4: TCP on (another name for M428), H as G43
    {490, 490, 1, kGToolLength, nullptr},
    {980, 990, 10, kGCannedReturn, nullptr},  // G98 G99
    // work coordinate systems
    {540, 590, 10, kGCoordSystem, nullptr},  // G54-G59
    {591, 593, 1, kGCoordSystem, nullptr},  // G59.1-G59.3
    // path control, spindle mode, lathe
    {610, 611, 1, kGPathControl, nullptr},  // G61 G61.1: contouring off
    {640, 640, 1, kGPathControl, nullptr},  // G64: contouring on
    {960, 960, 1, kGSpindleMode,
     "constant surface speed (G96) is not supported: the machine has no spindle; expected G97 or nothing"},
    {970, 970, 1, kGSpindleMode, nullptr},
    {70, 80, 10, kGLatheDiameter,
     "lathe diameter/radius modes (G7/G8) are not supported on this mill; expected a milling program"},
};

constexpr CodeInfo kMCodes[] = {
    {0, 2, 1, kMStop, nullptr},  // M0 pause, M1 optional pause, M2 end
    {30, 30, 1, kMStop, nullptr},
    {60, 60, 1, kMStop, "pallet change (M60) is not supported; expected M0 to pause the program"},
    {6, 6, 1, kMToolChange, nullptr},  // warned: single-tool machine
    {61, 61, 1, kMToolChange, nullptr},
    {3, 5, 1, kMSpindle, nullptr},  // warned: no spindle
    {19, 19, 1, kMSpindle,
     "spindle orientation (M19) is not supported: the machine has no spindle; expected no spindle words"},
    {7, 9, 1, kMCoolant, nullptr},  // warned: no coolant
    {48, 53, 1, kMOverride, "override switches (M48-M53) are not supported; expected overrides from the control socket"},
    {21, 22, 1, kMContouring, nullptr},
    {62, 68, 1, kMOther, "digital and analog I/O (M62-M68) is not supported; expected a program without I/O words"},
    {70, 73, 1, kMOther, nullptr},  // save, invalidate, restore, autorestore modal state (interpreter_modal_state.cpp)
    {100, 199, 1, kMOther, "user M codes (M100-M199) are not supported; expected M codes listed in docs/gcode.md"},
    {98, 99, 1, kMSubprogram, nullptr},  // M98 call, M99 return (MoveSource)
    {428, 429, 1, kMTcp, nullptr},       // TCP on/off (a machine without kinematics refuses them)
};

// The G table indexed by code (x10) once, at compile time: the parser looks up every G word.
constexpr int kMaxG = 1000;
constexpr std::array<std::int8_t, kMaxG> make_g_index() {
  std::array<std::int8_t, kMaxG> index{};
  for (auto& i : index) i = -1;
  for (std::size_t r = 0; r < std::size(kGCodes); ++r) {
    const CodeInfo& c = kGCodes[r];
    for (int code = c.first; code <= c.last; code += c.step) index[static_cast<std::size_t>(code)] = static_cast<std::int8_t>(r);
  }
  return index;
}
constexpr std::array<std::int8_t, kMaxG> kGIndex = make_g_index();
static_assert(std::size(kGCodes) < 128);

}  // namespace

const CodeInfo* g_code(int code10) {
  if (code10 < 0 || code10 >= kMaxG) return nullptr;
  const int r = kGIndex[static_cast<std::size_t>(code10)];
  return r < 0 ? nullptr : &kGCodes[r];
}

const CodeInfo* m_code(int code) {
  for (const CodeInfo& c : kMCodes) {
    if (code >= c.first && code <= c.last && (code - c.first) % c.step == 0) return &c;
  }
  return nullptr;
}

}  // namespace pcnc
