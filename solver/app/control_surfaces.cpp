#include "app/control_surfaces.hpp"

#include "core/error.hpp"

namespace narwhal {

ControlSurfaces::ControlSurfaces(const CaseConfig& c, int split_for, int levels, bool pieces)
    : shapes_(c, split_for, levels, pieces),
      law_(c.controls, c.autopilot, c.zigzag, shapes_.as_built()),
      shaped_(shapes_.as_built()) {}

bool ControlSurfaces::reshape(const suboff::Deflections& d, RunMotion& motion) {
  if (d == shaped_) return false;
  motion.reshape_all(shapes_.at(d));
  shaped_ = d;
  return true;
}

bool ControlSurfaces::start(RunMotion& motion) {
  law_.start();
  return reshape(law_.angles(), motion);
}

bool ControlSurfaces::begin_step(Real t_next, Real dt, const VehicleReading& now, RunMotion& motion) {
  law_.begin_step(t_next, dt, now);
  return reshape(law_.angles(), motion);
}

}  // namespace narwhal
