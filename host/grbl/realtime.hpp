// realtime.hpp — grbl 1.1's real-time command bytes: acted on the moment they arrive, never
// part of a line and never counted in the 128-byte receive buffer (docs/grbl-protocol.md).
#pragma once

#include <cstdint>

namespace pcnc::grbl {

enum Realtime : std::uint8_t {
  kSoftReset = 0x18,  // Ctrl-X
  kStatusQuery = '?',
  kCycleStart = '~',
  kFeedHold = '!',
  kSafetyDoor = 0x84,
  kJogCancel = 0x85,
  kFeedOv100 = 0x90,
  kFeedOvPlus10 = 0x91,
  kFeedOvMinus10 = 0x92,
  kFeedOvPlus1 = 0x93,
  kFeedOvMinus1 = 0x94,
  kRapidOv100 = 0x95,
  kRapidOv50 = 0x96,
  kRapidOv25 = 0x97,
  kSpindleOv100 = 0x99,
  kSpindleOvPlus10 = 0x9A,
  kSpindleOvMinus10 = 0x9B,
  kSpindleOvPlus1 = 0x9C,
  kSpindleOvMinus1 = 0x9D,
  kSpindleStop = 0x9E,
  kFloodToggle = 0xA0,
  kMistToggle = 0xA1,
};

/// Whether byte `b` is a real-time command (the four ASCII ones, Ctrl-X, and 0x80..0xFF,
/// which grbl reserves for them: an unknown one is ignored, as grbl does).
constexpr bool is_realtime(std::uint8_t b) {
  return b == kSoftReset || b == kStatusQuery || b == kCycleStart || b == kFeedHold || b >= 0x80;
}

/// An override after one of its five bytes (`first` = 0x90 for the feed, 0x99 for the
/// spindle; `b` - `first`: 100 %, +10, -10, +1, -1), from `percent`: grbl's steps, within 10..200.
constexpr int next_override(std::uint8_t b, std::uint8_t first, int percent) {
  constexpr int kStep[5] = {0, 10, -10, 1, -1};
  const int k = b - first;
  if (k < 0 || k > 4) return percent;
  const int p = k == 0 ? 100 : percent + kStep[k];
  return p < 10 ? 10 : (p > 200 ? 200 : p);
}
constexpr int next_feed_override(std::uint8_t b, int percent) { return next_override(b, kFeedOv100, percent); }
constexpr int next_spindle_override(std::uint8_t b, int percent) { return next_override(b, kSpindleOv100, percent); }

}  // namespace pcnc::grbl
