#include "patlab/core/timeprofile.h"

namespace patlab {

void TimeProfile::Add(std::string_view stage, double seconds, long count) {
  for (Entry& e : entries_) {
    if (e.stage == stage) {
      e.seconds += seconds;
      e.count += count;
      return;
    }
  }
  entries_.push_back({stage, seconds, count});
}

TimeProfile& TimeProfile::operator+=(const TimeProfile& other) {
  for (const Entry& e : other.entries_) Add(e.stage, e.seconds, e.count);
  return *this;
}

double TimeProfile::total_seconds() const {
  double total = 0.0;
  for (const Entry& e : entries_) total += e.seconds;
  return total;
}

}  // namespace patlab
