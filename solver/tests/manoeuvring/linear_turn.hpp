#pragma once
// A linear sway-yaw manoeuvring model and the steady turn its linear equations give: the
// fixture of the model's own test and of `narwhal simulate`'s.
#include <Eigen/LU>

#include "manoeuvring/manoeuvring_model.hpp"

namespace narwhal::test {

inline ManoeuvringCoefficients linear_turning_coefficients() {
  ManoeuvringCoefficients c;
  c.Yv = -0.03;
  c.Yr = 0.008;
  c.Nv = -0.01;
  c.Nr = -0.005;
  c.Ydr = 0.012;
  c.Ndr = -0.006;
  c.Yvdot = -0.016;
  c.Nrdot = -0.0009;
  return c;
}

// (v, r) of the steady turn at surge u = 1 under rudder `rudder` (radians), no gravity:
// m u r = Y and 0 = N, so [Y'v / 2, Y'r / 2 - m; N'v / 2, N'r / 2] (v, r) = -(Y'dr, N'dr) dr / 2.
inline Eigen::Vector2d linear_steady_turn(const ManoeuvringCoefficients& c, Real mass, Real rudder) {
  Eigen::Matrix2d a;
  a << 0.5 * c.Yv, 0.5 * c.Yr - mass, 0.5 * c.Nv, 0.5 * c.Nr;
  return a.inverse() * Eigen::Vector2d(-0.5 * c.Ydr * rudder, -0.5 * c.Ndr * rudder);
}

}  // namespace narwhal::test
