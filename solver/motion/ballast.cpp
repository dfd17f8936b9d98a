#include "motion/ballast.hpp"

#include <algorithm>

namespace narwhal {

Real BallastChange::fraction(Real t) const {
  if (t < start) return 0.0;
  if (duration <= 0.0) return 1.0;
  return std::min(1.0, (t - start) / duration);
}

BodyLoads ballast_loads(const std::vector<BallastChange>& changes, const Vec3& down_body, Real t) {
  BodyLoads loads;
  for (const BallastChange& c : changes) {
    // Weight lost: a force against gravity at the tank.
    const Vec3 f = -c.weight * c.fraction(t) * down_body;
    loads.force += f;
    loads.moment += c.tank.cross(f);
  }
  return loads;
}

}  // namespace narwhal
