#include "app/control_surfaces.hpp"

namespace narwhal {

ControlSurfaces::ControlSurfaces(const CaseConfig& c, int split_for, int levels, bool pieces)
    : schedule_(*c.controls), shapes_(c, split_for, levels, pieces), angles_(shapes_.as_built()) {}

bool ControlSurfaces::turn_to(Real t, RunMotion& motion) {
  const suboff::Deflections next = schedule_.at(t, shapes_.as_built());
  if (next.rudder == angles_.rudder && next.stern_planes == angles_.stern_planes &&
      next.sail_planes == angles_.sail_planes)
    return false;
  motion.reshape_all(shapes_.at(next));
  angles_ = next;
  return true;
}

}  // namespace narwhal
