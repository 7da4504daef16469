// error_codes.cpp — pcnc's diagnostics and faults as grbl's numbers (see error_codes.hpp).
// The pipeline's messages name what is wrong in words; the first rule whose key appears in
// the message decides, in the order of the table (the more specific first).
#include "grbl/error_codes.hpp"

#include <array>
#include <utility>

namespace pcnc::grbl {

int error_for_message(std::string_view m) {
  static constexpr std::array<std::pair<std::string_view, int>, 24> kRules{{
      {"travel", kInvalidTarget},
      {"soft limit", kInvalidTarget},
      {"refused by the rt's block check", kInvalidTarget},
      {"no feed rate", kUndefinedFeedRate},
      {"negative F", kNegativeValue},
      {"negative", kNegativeValue},
      {"G53 needs", kG53InvalidMotionMode},
      {"without axis words", kNoAxisWords},
      {"radius", kArcRadiusError},
      {"I, J, K and R words all missing", kNoOffsetsInPlane},
      {"plane of this arc", kNoAxisWordsInPlane},
      {"with no motion mode", kAxisWordsExist},
      {"modal group", kModalGroupViolation},
      {"same modal", kModalGroupViolation},
      {"twice", kWordRepeated},
      {"repeated", kWordRepeated},
      {"whole number", kCommandValueNotInteger},
      {"with no G code that uses it", kUnusedWords},
      {"is not supported", kUnsupportedCommand},
      {"unknown", kUnsupportedCommand},
      {"not part of this G-code dialect", kExpectedCommandLetter},
      {"bad number", kBadNumberFormat},
      {"number", kBadNumberFormat},
      {"expected", kInvalidStatement},
  }};
  for (const auto& [key, code] : kRules) {
    if (m.find(key) != std::string_view::npos) return code;
  }
  return kUnsupportedCommand;
}

const char* error_text(int code) {
  switch (code) {
    case kExpectedCommandLetter: return "Expected command letter";
    case kBadNumberFormat: return "Bad number format";
    case kInvalidStatement: return "Invalid statement";
    case kNegativeValue: return "Value < 0";
    case kSettingDisabled: return "Setting disabled";
    case kIdleError: return "Not idle";
    case kSystemGcLock: return "G-code lock";
    case kOverflow: return "Line overflow";
    case kTravelExceeded: return "Travel exceeded";
    case kInvalidJogCommand: return "Invalid jog command";
    case kUnsupportedCommand: return "Unsupported command";
    case kModalGroupViolation: return "Modal group violation";
    case kUndefinedFeedRate: return "Undefined feed rate";
    case kCommandValueNotInteger: return "Invalid gcode ID:23";
    case kAxisCommandConflict: return "Invalid gcode ID:24";
    case kWordRepeated: return "Invalid gcode ID:25";
    case kNoAxisWords: return "Invalid gcode ID:26";
    case kInvalidLineNumber: return "Invalid gcode ID:27";
    case kValueWordMissing: return "Invalid gcode ID:28";
    case kG53InvalidMotionMode: return "Invalid gcode ID:30";
    case kAxisWordsExist: return "Invalid gcode ID:31";
    case kNoAxisWordsInPlane: return "Invalid gcode ID:32";
    case kInvalidTarget: return "Invalid gcode ID:33";
    case kArcRadiusError: return "Invalid gcode ID:34";
    case kNoOffsetsInPlane: return "Invalid gcode ID:35";
    case kUnusedWords: return "Invalid gcode ID:36";
    default: return "Error";
  }
}

int alarm_for(std::string_view state, std::string_view fault) {
  if (state == "FAULT") return fault == "soft limit" ? kSoftLimit : kHardLimit;
  if (state == "ESTOP" || state == "HOST_LOST") return kAbortCycle;
  return 0;
}

std::string msg_line(std::string_view text) {
  std::string out = "[MSG:";
  for (char c : text) out.push_back(c == ']' ? ')' : (c == '\n' || c == '\r' ? ' ' : c));
  return out + "]";
}

}  // namespace pcnc::grbl
