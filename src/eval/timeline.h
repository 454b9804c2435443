#pragma once
// Time intervals and sets of them, for the metrics' bookkeeping ("the time in which the robot
// is still", "the allowed time minus the waits"). Pure functions; seconds.

#include <vector>

namespace hribench::eval {

// The closed interval [from, to]; empty when to <= from.
struct TimeInterval {
  double from = 0;
  double to = 0;
  double length() const { return to > from ? to - from : 0.0; }
  bool contains(double t) const { return from <= t && t <= to; }
  bool operator==(const TimeInterval&) const = default;
};

// A set of disjoint, sorted, non-empty intervals.
using TimeSet = std::vector<TimeInterval>;

// Sorts, drops empty intervals and merges overlapping or touching ones.
TimeSet normalized(TimeSet intervals);
// Set operations on normalized sets.
TimeSet unite(const TimeSet& a, const TimeSet& b);
TimeSet intersect(const TimeSet& a, const TimeSet& b);
TimeSet subtract(const TimeSet& a, const TimeSet& b);
// Total length of a normalized set.
double total_length(const TimeSet& set);
// True if t lies in one of the intervals.
bool contains(const TimeSet& set, double t);

}  // namespace hribench::eval
