#pragma once
// A run's control surfaces turned in time ([controls], issue 19): the angles the schedule
// gives at each time level, and, when they change, the grids a moving run keeps
// reshaped to them (app/grid_shapes.hpp, MovingGrid::reshape) before they move to the
// level's pose. What else depends on where the walls are (the turbulence model's wall
// distances, the propulsor's disk cells) the caller makes again when turn_to says so.
#include <memory>

#include "app/grid_shapes.hpp"
#include "app/run_motion.hpp"
#include "control/control_schedule.hpp"

namespace narwhal {

class ControlSurfaces {
 public:
  // `split_for`, `levels`, `pieces`: the run's grids, as GridShapes takes them.
  ControlSurfaces(const CaseConfig& c, int split_for, int levels, bool pieces);

  // The surfaces to their angles at time t, every grid of `motion` reshaped when they
  // changed (the next move carries the grids there); returns whether they changed.
  bool turn_to(Real t, RunMotion& motion);
  const suboff::Deflections& angles() const { return angles_; }

 private:
  ControlSchedule schedule_;
  GridShapes shapes_;
  suboff::Deflections angles_;  // those the grids' shapes have
};

}  // namespace narwhal
