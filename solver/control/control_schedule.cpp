#include "control/control_schedule.hpp"

#include <algorithm>

#include "core/error.hpp"

namespace narwhal {

namespace {

void check(const std::optional<AngleTable>& table, const char* surface) {
  if (!table) return;
  if (table->empty()) fail("control schedule: the {} table has no points", surface);
  for (std::size_t i = 1; i < table->size(); ++i)
    if (!((*table)[i].first > (*table)[i - 1].first))
      fail("control schedule: the {} table's times must increase (point {} at {} follows {})", surface, i + 1,
           (*table)[i].first, (*table)[i - 1].first);
}

Real interpolate(const AngleTable& t, Real time) {
  if (time <= t.front().first) return t.front().second;
  if (time >= t.back().first) return t.back().second;
  const auto hi = std::upper_bound(t.begin(), t.end(), time, [](Real x, const auto& p) { return x < p.first; });
  const auto lo = hi - 1;
  const Real w = (time - lo->first) / (hi->first - lo->first);
  return lo->second + w * (hi->second - lo->second);
}

}  // namespace

ControlSchedule::ControlSchedule(ControlScheduleSpec spec) : spec_(std::move(spec)) {
  check(spec_.rudder, "rudder");
  check(spec_.stern_planes, "stern planes'");
  check(spec_.sail_planes, "sail planes'");
}

suboff::Deflections ControlSchedule::at(Real t, const suboff::Deflections& as_built) const {
  suboff::Deflections d = as_built;
  if (spec_.rudder) d.rudder = interpolate(*spec_.rudder, t);
  if (spec_.stern_planes) d.stern_planes = interpolate(*spec_.stern_planes, t);
  if (spec_.sail_planes) d.sail_planes = interpolate(*spec_.sail_planes, t);
  return d;
}

}  // namespace narwhal
