#include "patlab/calib/field.h"

#include <algorithm>

namespace patlab::calib {

namespace {

template <typename T>
const T* FindByName(const std::vector<T>& items, std::string_view name) {
  const auto it =
      std::find_if(items.begin(), items.end(), [&](const T& t) { return t.name == name; });
  return it == items.end() ? nullptr : &*it;
}

template <typename T>
std::string JoinNames(const std::vector<T>& items) {
  std::string out;
  for (const T& t : items) out += (out.empty() ? "" : ", ") + t.name;
  return out.empty() ? "(none)" : out;
}

}  // namespace

const FieldLine* Field::FindLine(std::string_view n) const { return FindByName(lines, n); }
const FieldCircle* Field::FindCircle(std::string_view n) const { return FindByName(circles, n); }
const FieldPoint* Field::FindPoint(std::string_view n) const { return FindByName(points, n); }
std::string Field::LineNames() const { return JoinNames(lines); }
std::string Field::CircleNames() const { return JoinNames(circles); }
std::string Field::PointNames() const { return JoinNames(points); }

}  // namespace patlab::calib
