#pragma once
// Body axes (NUMERICS §0.1: x_B forward, y_B starboard, z_B down) of a body whose nose
// points to -x of the grid, as the body-of-revolution grids are built and as imported
// hull grids are expected: x_B = -x, y_B = -y, z_B = z. The map is its own inverse.
// One place for it, so that the free stream set from the angles and the forces
// reported in body axes cannot disagree.
#include <cmath>

#include "core/types.hpp"

namespace narwhal {

inline Vec3 grid_to_body_axes(const Vec3& v) { return {-v[0], -v[1], v[2]}; }
inline Vec3 body_to_grid_axes(const Vec3& v) { return grid_to_body_axes(v); }

// The unit velocity of the body through the fluid, in its own axes, at angle of attack
// alpha = atan(w / u) and drift angle beta = -asin(v / U) (radians):
// (cos a cos b, -sin b, sin a cos b).
inline Vec3 body_velocity_direction(Real alpha, Real beta) {
  return {std::cos(alpha) * std::cos(beta), -std::sin(beta), std::sin(alpha) * std::cos(beta)};
}

// The free stream the body sees, in grid axes: minus its own velocity.
inline Vec3 free_stream_in_grid_axes(Real alpha, Real beta) {
  return body_to_grid_axes(-body_velocity_direction(alpha, beta));
}

}  // namespace narwhal
