#include "control/control_law.hpp"

#include "core/error.hpp"

namespace narwhal {

ControlLaw::ControlLaw(const std::optional<ControlScheduleSpec>& schedule,
                       const std::optional<AutopilotSettings>& autopilot, const std::optional<ZigzagSettings>& zigzag,
                       const suboff::Deflections& as_built)
    : as_built_(as_built), angles_(as_built), previous_(as_built) {
  if (schedule) schedule_.emplace(*schedule);
  if (autopilot) autopilot_.emplace(*autopilot);
  if (zigzag) zigzag_.emplace(*zigzag);
}

void ControlLaw::start() {
  if (schedule_) angles_ = schedule_->at(0.0, as_built_);
  previous_ = angles_;
}

void ControlLaw::begin_step(Real t_next, Real dt, const VehicleReading& now) {
  previous_ = angles_;
  if (schedule_) angles_ = schedule_->at(t_next, angles_);
  if (autopilot_) angles_ = autopilot_->command(now, dt, angles_);
  if (zigzag_) angles_ = zigzag_->command(t_next, dt, now, angles_);
}

std::vector<Real> ControlLaw::checkpoint() const {
  std::vector<Real> v{previous_.rudder, previous_.stern_planes, previous_.sail_planes,
                      angles_.rudder,   angles_.stern_planes,   angles_.sail_planes};
  if (autopilot_)
    for (Real x : autopilot_->checkpoint()) v.push_back(x);
  if (zigzag_)
    for (Real x : zigzag_->checkpoint()) v.push_back(x);  // last: its length is fixed
  return v;
}

void ControlLaw::restore(const std::vector<Real>& v) {
  if (v.empty())
    fail("restart: it holds no control-surface state (written by a run without [controls], [autopilot] or [zigzag]); "
         "a dual-time run that turns its surfaces continues only from its own restarts");
  const std::size_t zigzag_values = zigzag_ ? zigzag_->checkpoint().size() : 0;
  if (v.size() < 6 + zigzag_values)
    fail("restart: its control-surface state has {} values, at least {} expected", v.size(), 6 + zigzag_values);
  previous_ = {v[0], v[1], v[2]};
  angles_ = {v[3], v[4], v[5]};
  const std::vector<Real> pilot(v.begin() + 6, v.end() - static_cast<std::ptrdiff_t>(zigzag_values));
  if (autopilot_) autopilot_->restore(pilot);
  else if (!pilot.empty()) fail("restart: it holds an autopilot's state; this case has no [autopilot]");
  if (zigzag_) zigzag_->restore(std::vector<Real>(v.end() - static_cast<std::ptrdiff_t>(zigzag_values), v.end()));
}

}  // namespace narwhal
