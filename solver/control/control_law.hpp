#pragma once
// What turns a vehicle's control surfaces during a manoeuvre (issue 19): the case's
// schedules ([controls], control/control_schedule.hpp), autopilots ([autopilot],
// control/autopilot.hpp) and zig-zag ([zigzag], control/zigzag.hpp), in that order, each
// surface driven by one of them; sampled once per step from the vehicle at the step's
// start. The CFD run (app/control_surfaces.hpp, which reshapes the grids to the angles)
// and the manoeuvring simulator (app/simulate.hpp) fly the same law.
#include <optional>
#include <vector>

#include "control/autopilot.hpp"
#include "control/control_schedule.hpp"
#include "control/zigzag.hpp"

namespace narwhal {

class ControlLaw {
 public:
  // `as_built`: the angles the surfaces have before anything turns them.
  ControlLaw(const std::optional<ControlScheduleSpec>& schedule, const std::optional<AutopilotSettings>& autopilot,
             const std::optional<ZigzagSettings>& zigzag, const suboff::Deflections& as_built);

  // t = 0: the schedules' angles.
  void start();
  // The step to t_next = t^n + dt begins with the vehicle at `now`: the angles of t_next.
  void begin_step(Real t_next, Real dt, const VehicleReading& now);

  const suboff::Deflections& angles() const { return angles_; }      // of t^{n+1} once a step began
  const suboff::Deflections& previous() const { return previous_; }  // of the level before
  Real pitch_command() const { return autopilot_ ? autopilot_->pitch_command() : 0.0; }

  // The angles of the last two levels, the autopilots' and the zig-zag's state, as one list.
  std::vector<Real> checkpoint() const;
  void restore(const std::vector<Real>& values);  // throws Error naming what does not match

 private:
  std::optional<ControlSchedule> schedule_;
  std::optional<Autopilot> autopilot_;
  std::optional<Zigzag> zigzag_;
  suboff::Deflections as_built_, angles_, previous_;
};

}  // namespace narwhal
