#include "motion/trim.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace narwhal {

BodyLoads TrimWeights::loads(const Vec3& down_body) const {
  return {weight * down_body, Vec3(first_moment, 0.0, 0.0).cross(down_body)};
}

TrimWeights trim_at_release(const TrimSpec& spec, const RigidBodyEquations& body, const RigidBodyState& at_release,
                            const BodyLoads& loads) {
  // With gravity along d (body axes), a weight dW at O adds dW d_z to Z and a first moment
  // s along x_B adds (s e_x x d)_y = -s d_z to M: each cancels its own component.
  TrimWeights t;
  const Vec3 d = rotation_matrix(at_release.attitude()).transpose() * body.mass_properties().down;
  if (std::abs(d.z()) < 0.5)
    fail("trim: weights trim only with gravity within 60 degrees of z_B at release, it is {} degrees off",
         std::acos(std::clamp(std::abs(d.z()), 0.0, 1.0)) * 180.0 / std::numbers::pi);
  const BodyLoads total = loads + body.hydrostatic_loads(at_release);
  if (spec.heave) t.weight = -total.force.z() / d.z();
  if (spec.pitch) t.first_moment = total.moment.y() / d.z();
  return t;
}

}  // namespace narwhal
