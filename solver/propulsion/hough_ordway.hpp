#pragma once
// The Hough-Ordway radial distribution of a body-force propeller's loads (NUMERICS §9.3):
// force per unit volume over a disk between the hub radius R_H and the tip radius R_P,
// zero at both, peaking at r* = 2/3. Templated on the scalar so that its derivatives can
// be complex-step tested like the flux kernels.
#include <cmath>
#include <complex>
#include <numbers>

#include "core/types.hpp"

namespace narwhal::hough_ordway {

using std::sqrt;

struct Disk {
  Real hub_radius = 0.0;  // R_H
  Real tip_radius = 0.0;  // R_P = D_p / 2
  Real thickness = 0.0;   // Delta, along the axis
};

// r* = (r - R_H) / (R_P - R_H): 0 at the hub, 1 at the tip.
template <class T>
T r_star(const T& r, const Disk& d) {
  return (r - d.hub_radius) / (d.tip_radius - d.hub_radius);
}

// The axial shape r* sqrt(1 - r*) (zero outside the disk's radii).
template <class T>
T axial_shape(const T& r, const Disk& d) {
  const T s = r_star(r, d);
  if (std::real(s) <= 0.0 || std::real(s) >= 1.0) return T(0.0);
  return s * sqrt(1.0 - s);
}

// The tangential shape r* sqrt(1 - r*) R_P / r.
template <class T>
T tangential_shape(const T& r, const Disk& d) {
  return axial_shape(r, d) * d.tip_radius / r;
}

// The constants that make the continuous distribution carry thrust T and torque Q:
// int f_a dV = T and int f_theta r dV = Q over the disk (§9.3).
inline Real axial_constant(Real thrust, const Disk& d) {
  return 105.0 / 8.0 * thrust /
         (std::numbers::pi * d.thickness * (3.0 * d.hub_radius + 4.0 * d.tip_radius) * (d.tip_radius - d.hub_radius));
}
inline Real tangential_constant(Real torque, const Disk& d) {
  return 105.0 / 8.0 * torque /
         (std::numbers::pi * d.thickness * d.tip_radius * (3.0 * d.hub_radius + 4.0 * d.tip_radius) * (d.tip_radius - d.hub_radius));
}

}  // namespace narwhal::hough_ordway
