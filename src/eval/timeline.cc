#include "eval/timeline.h"

#include <algorithm>

namespace hribench::eval {

TimeSet normalized(TimeSet intervals) {
  std::erase_if(intervals, [](const TimeInterval& i) { return !(i.to > i.from); });
  std::sort(intervals.begin(), intervals.end(),
            [](const TimeInterval& a, const TimeInterval& b) { return a.from < b.from; });
  TimeSet out;
  for (const TimeInterval& i : intervals) {
    if (!out.empty() && i.from <= out.back().to) {
      out.back().to = std::max(out.back().to, i.to);
    } else {
      out.push_back(i);
    }
  }
  return out;
}

TimeSet unite(const TimeSet& a, const TimeSet& b) {
  TimeSet all = a;
  all.insert(all.end(), b.begin(), b.end());
  return normalized(std::move(all));
}

TimeSet intersect(const TimeSet& a, const TimeSet& b) {
  TimeSet out;
  size_t i = 0;
  size_t j = 0;
  // Sweep both sorted sets; emit each overlap.
  while (i < a.size() && j < b.size()) {
    const double from = std::max(a[i].from, b[j].from);
    const double to = std::min(a[i].to, b[j].to);
    if (to > from) out.push_back({from, to});
    if (a[i].to < b[j].to) {
      ++i;
    } else {
      ++j;
    }
  }
  return out;
}

TimeSet subtract(const TimeSet& a, const TimeSet& b) {
  TimeSet out;
  for (const TimeInterval& piece : a) {
    double from = piece.from;
    // Cut every interval of b out of this piece, left to right.
    for (const TimeInterval& cut : b) {
      if (cut.to <= from || cut.from >= piece.to) continue;
      if (cut.from > from) out.push_back({from, cut.from});
      from = std::max(from, cut.to);
    }
    if (piece.to > from) out.push_back({from, piece.to});
  }
  return out;
}

double total_length(const TimeSet& set) {
  double sum = 0;
  for (const TimeInterval& i : set) sum += i.length();
  return sum;
}

bool contains(const TimeSet& set, double t) {
  return std::any_of(set.begin(), set.end(), [t](const TimeInterval& i) { return i.contains(t); });
}

}  // namespace hribench::eval
