#pragma once
// A run's control surfaces turned in time (issue 19): their angles for each physical step
// from the case's control law (control/control_law.hpp: schedules, autopilots, zig-zag)
// and, when the angles change, the grids a moving run keeps reshaped to them
// (app/grid_shapes.hpp, MovingGrid::reshape) before they move to the step's pose.
// What else depends on where the walls are (the turbulence model's wall distances, the
// propulsor's disk cells) the caller makes again when a turn says the grids changed.
#include <memory>
#include <optional>

#include "app/grid_shapes.hpp"
#include "app/run_motion.hpp"
#include "control/control_law.hpp"

namespace narwhal {

class ControlSurfaces {
 public:
  // `split_for`, `levels`, `pieces`: the run's grids, as GridShapes takes them.
  ControlSurfaces(const CaseConfig& c, int split_for, int levels, bool pieces);

  // t = 0: the schedules' angles. Returns whether the grids' shapes changed.
  bool start(RunMotion& motion);
  // A step from t^n to t_next = t^n + dt begins with the vehicle at `now`: the angles of
  // t_next (control/control_law.hpp); the grids reshaped when they changed (the step's
  // move carries them there). Returns whether they did.
  bool begin_step(Real t_next, Real dt, const VehicleReading& now, RunMotion& motion);
  const suboff::Deflections& angles() const { return law_.angles(); }
  Real pitch_command() const { return law_.pitch_command(); }

  // Restarts: the law's state (ControlLaw::checkpoint); restore takes it back, then the
  // grids go to level n-1's angles and to level n's.
  std::vector<Real> checkpoint() const { return law_.checkpoint(); }
  void restore(const std::vector<Real>& values) { law_.restore(values); }
  bool to_previous_level(RunMotion& motion) { return reshape(law_.previous(), motion); }
  bool to_present_level(RunMotion& motion) { return reshape(law_.angles(), motion); }

 private:
  bool reshape(const suboff::Deflections& d, RunMotion& motion);  // when the grids' shapes differ

  GridShapes shapes_;
  ControlLaw law_;
  suboff::Deflections shaped_;  // the angles the grids' shapes have
};

}  // namespace narwhal
