// error_codes.hpp — grbl 1.1's error and alarm numbers, pure: a pcnc diagnostic (the
// pipeline's message for a line) becomes the `error:N` a sender looks up, and the rt's fault
// the `ALARM:N`. The table is docs/grbl-protocol.md's; grbl's own texts are kept for [MSG:].
#pragma once

#include <string>
#include <string_view>

namespace pcnc::grbl {

enum Error : int {
  kExpectedCommandLetter = 1,
  kBadNumberFormat = 2,
  kInvalidStatement = 3,
  kNegativeValue = 4,
  kSettingDisabled = 5,
  kIdleError = 8,
  kSystemGcLock = 9,
  kOverflow = 11,
  kTravelExceeded = 15,
  kInvalidJogCommand = 16,
  kUnsupportedCommand = 20,
  kModalGroupViolation = 21,
  kUndefinedFeedRate = 22,
  kCommandValueNotInteger = 23,
  kAxisCommandConflict = 24,
  kWordRepeated = 25,
  kNoAxisWords = 26,
  kInvalidLineNumber = 27,
  kValueWordMissing = 28,
  kG53InvalidMotionMode = 30,
  kAxisWordsExist = 31,
  kNoAxisWordsInPlane = 32,
  kInvalidTarget = 33,
  kArcRadiusError = 34,
  kNoOffsetsInPlane = 35,
  kUnusedWords = 36,
};

enum Alarm : int {
  kHardLimit = 1,
  kSoftLimit = 2,
  kAbortCycle = 3,  // reset while in motion; pcnc also uses it for an e-stop and a lost host
};

/// The grbl error number for a pcnc front-end message (a G-code line the pipeline refused).
int error_for_message(std::string_view message);

/// grbl's short text for an error number ("Invalid target", ...).
const char* error_text(int code);

/// The alarm for the service's status `state` and `fault` ("FAULT"/"soft limit", "ESTOP"...);
/// 0 when the machine is not in an alarm state.
int alarm_for(std::string_view state, std::string_view fault);

/// "[MSG:text]" with the characters a sender's parser would stop at replaced (']' -> ')').
std::string msg_line(std::string_view text);

}  // namespace pcnc::grbl
