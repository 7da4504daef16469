// time_causes.cpp — each trace row's cause from the check's plan, their seconds, and the
// slowest stretches (see time_causes.hpp).
#include "report/time_causes.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {
namespace {

constexpr double kCruiseBand = 0.02;  // within 2 % of the block's limit counts as cruising at it

bool is_stop(JunctionKind j) {
  return j == JunctionKind::kAngleStop || j == JunctionKind::kContouringOff || j == JunctionKind::kTurnStop;
}

TimeCause junction_cause(JunctionKind j, TimeCause accel) {
  switch (j) {
    case JunctionKind::kAngleStop:
    case JunctionKind::kContouringOff:
    case JunctionKind::kTurnStop: return TimeCause::kJunctionStop;
    case JunctionKind::kCorner: return TimeCause::kJunctionCorner;
    case JunctionKind::kStartEnd: return TimeCause::kStartEndStop;
    case JunctionKind::kStraight: return accel;
  }
  return accel;
}

}  // namespace

CauseClassifier::CauseClassifier(std::vector<LinePlan> plan) : plan_(std::move(plan)) {
  for (std::uint32_t i = 0; i < plan_.size(); ++i) {
    for (std::uint32_t l = plan_[i].first; l <= plan_[i].last && l >= plan_[i].first; ++l) index_.push_back({l, i});
  }
  std::sort(index_.begin(), index_.end());
  index_.erase(std::unique(index_.begin(), index_.end()), index_.end());
}

std::vector<const LinePlan*> CauseClassifier::entries(std::uint32_t line) const {
  std::vector<const LinePlan*> out;
  auto it = std::lower_bound(index_.begin(), index_.end(), std::pair<std::uint32_t, std::uint32_t>{line, 0});
  for (; it != index_.end() && it->first == line; ++it) out.push_back(&plan_[it->second]);
  return out;
}

RowCause CauseClassifier::classify(const TraceSample& row, double prev_speed) const {
  RowCause r;
  if (row.state == MachineState::kPaused) return {TimeCause::kPaused, 0.0};
  if (row.state != MachineState::kRunning) return {TimeCause::kOther, 0.0};
  auto it = std::lower_bound(index_.begin(), index_.end(), std::pair<std::uint32_t, std::uint32_t>{row.line, 0});
  if (it == index_.end() || it->first != row.line) return {TimeCause::kOther, 0.0};
  const LinePlan* first = &plan_[it->second];
  const LinePlan* last = first;
  const double v = row.speed;
  bool dwell = false;
  double top = 0.0;  // the fastest limit of the line's blocks
  for (; it != index_.end() && it->first == row.line; ++it) {
    const LinePlan& p = plan_[it->second];
    last = &p;
    if (p.cruise == TimeCause::kDwell) dwell = true;
    if (p.cruise == TimeCause::kPaused || p.cruise == TimeCause::kDwell || p.cruise == TimeCause::kOther) continue;
    if (r.planned_speed == 0.0 && p.cruise != TimeCause::kRapid) r.planned_speed = p.speed;
    top = std::max(top, p.speed);
    if (p.speed > 0.0 && std::fabs(v - p.speed) <= kCruiseBand * p.speed) {
      r.cause = p.cruise;
      if (p.cruise != TimeCause::kRapid) r.planned_speed = p.speed;
      return r;
    }
  }
  if (dwell && v <= 0.0) return {TimeCause::kDwell, 0.0};
  if (top > 0.0 && v > top * (1.0 + kCruiseBand)) {
    r.cause = TimeCause::kOverride;  // above every limit of the line: an override over 100 %
    return r;
  }
  if (v > 0.0 && first->cruise == TimeCause::kCurveSchedule && last->cruise == TimeCause::kCurveSchedule) {
    // a curve's speed follows its feed schedule (curvature, chord error, axis limits) along
    // the whole curve: below its top speed is the schedule, not a junction (smoothed runs:
    // most of a surfacing program's time)
    r.cause = TimeCause::kCurveSchedule;
    return r;
  }
  const double dv = v - prev_speed;
  if (v > 0.0 && std::fabs(dv) <= 1e-9 * std::max(1.0, v)) {
    r.cause = TimeCause::kOverride;  // steady below every limit of the line: the override holds it there
    return r;
  }
  if (dv < 0.0 || v <= 0.0) {
    r.cause = junction_cause(last->after, last->accel);  // slowing toward the end of the line's block
  } else {
    r.cause = junction_cause(first->before, first->accel);  // speeding up from its start
  }
  return r;
}

std::map<std::string, double> time_by_cause(const std::array<std::uint64_t, kTimeCauseCount>& rows, double program_time_s) {
  std::map<std::string, double> out;
  std::uint64_t total = 0;
  for (std::uint64_t n : rows) total += n;
  if (total == 0) return out;
  // the rt's program time shared by rows; the largest share takes the rounding rest, so the
  // values add up to program_time_s
  int largest = 0;
  double assigned = 0.0;
  for (int c = 0; c < kTimeCauseCount; ++c) {
    if (rows[static_cast<std::size_t>(c)] > rows[static_cast<std::size_t>(largest)]) largest = c;
  }
  for (int c = 0; c < kTimeCauseCount; ++c) {
    const std::uint64_t n = rows[static_cast<std::size_t>(c)];
    if (n == 0 || c == largest) continue;
    const double s = program_time_s * static_cast<double>(n) / static_cast<double>(total);
    out[time_cause_key(static_cast<TimeCause>(c))] = s;
    assigned += s;
  }
  out[time_cause_key(static_cast<TimeCause>(largest))] = program_time_s - assigned;
  return out;
}

std::vector<SlowStretch> slowest_stretches(const TraceDigest& d, const CauseClassifier& plan, double seconds_per_row,
                                           std::size_t n) {
  std::vector<SlowStretch> all;
  for (const auto& [line, lt] : d.line_time) {
    SlowStretch s;
    s.line = line;
    s.time_s = static_cast<double>(lt.rows) * seconds_per_row;
    std::uint32_t best = 0, lost = 0;
    for (int c = 0; c < kTimeCauseCount; ++c) {
      const auto cause = static_cast<TimeCause>(c);
      if (cause == TimeCause::kFeed || cause == TimeCause::kRapid) continue;
      const std::uint32_t k = lt.cause_rows[static_cast<std::size_t>(c)];
      lost += k;
      if (k > best) best = k, s.cause = cause;
    }
    if (lost == 0) continue;
    s.lost_s = lost * seconds_per_row;
    s.cause_s = best * seconds_per_row;
    if (s.cause == TimeCause::kJunctionStop || s.cause == TimeCause::kJunctionCorner) {
      for (const LinePlan* p : plan.entries(line)) {
        if (is_stop(p->after) || p->after == JunctionKind::kCorner) s.angle_deg = std::max(s.angle_deg, p->angle_after_deg);
        if (is_stop(p->before) || p->before == JunctionKind::kCorner) s.angle_deg = std::max(s.angle_deg, p->angle_before_deg);
      }
    }
    all.push_back(s);
  }
  std::sort(all.begin(), all.end(), [](const SlowStretch& a, const SlowStretch& b) {
    return a.lost_s != b.lost_s ? a.lost_s > b.lost_s : a.line < b.line;
  });
  if (all.size() > n) all.resize(n);
  return all;
}

const char* time_cause_colour(TimeCause c) {
  switch (c) {
    case TimeCause::kFeed: return "#2a9d58";
    case TimeCause::kFeedClamp: return "#8fbf3f";
    case TimeCause::kRapid: return "#aab3c5";
    case TimeCause::kAxisVelocityX:
    case TimeCause::kAxisVelocityY:
    case TimeCause::kAxisVelocityZ: return "#e9a23b";
    case TimeCause::kArcCentripetal: return "#c77dff";
    case TimeCause::kCurveSchedule: return "#9b5de5";
    case TimeCause::kAccelX:
    case TimeCause::kAccelY:
    case TimeCause::kAccelZ:
    case TimeCause::kAccelArcCurve: return "#4ea8de";
    case TimeCause::kJunctionStop: return "#d1495b";
    case TimeCause::kJunctionCorner: return "#f28482";
    case TimeCause::kStartEndStop: return "#6c757d";
    case TimeCause::kOverride: return "#ffb703";
    case TimeCause::kDwell: return "#3d405b";
    case TimeCause::kPaused: return "#222222";
    default: return "#bbbbbb";
  }
}

}  // namespace pcnc
