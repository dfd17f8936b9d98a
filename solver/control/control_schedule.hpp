#pragma once
// Control surfaces moved on a schedule (issue 19's manoeuvres: a turning circle's rudder
// step, a captive run's oscillating planes): each surface's angle a piecewise-linear
// function of time, held at its first and last values outside the table. The angles are
// suboff_geometry.hpp's (Gertler & Hagen's signs: rudder trailing edges to port, planes'
// trailing edges down), in radians.
#include <optional>
#include <utility>
#include <vector>

#include "core/types.hpp"
#include "mesh/suboff_geometry.hpp"

namespace narwhal {

// (time, angle) points, times strictly increasing.
using AngleTable = std::vector<std::pair<Real, Real>>;

struct ControlScheduleSpec {
  std::optional<AngleTable> rudder, stern_planes, sail_planes;
};

class ControlSchedule {
 public:
  // Throws Error naming the surface when a table is empty or its times do not increase.
  explicit ControlSchedule(ControlScheduleSpec spec);
  // The angles at time t; a surface without a table keeps `as_built`'s.
  suboff::Deflections at(Real t, const suboff::Deflections& as_built) const;

 private:
  ControlScheduleSpec spec_;
};

}  // namespace narwhal
