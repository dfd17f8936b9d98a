#pragma once
// Cell velocity gradients for the turbulence models (NUMERICS §8.1): Green–Gauss with
// face values averaged from the two cells; the invariant direction's faces cancel.
#include "mesh/block.hpp"
#include "physics/flow.hpp"

namespace narwhal {

// G(i, j) = d u_i / d x_j of cell c (flow ghosts filled).
inline Mat3 velocity_gradient(const Block& b, const GhostArray<State>& Q, const Index3& c) {
  Mat3 G = Mat3::Zero();
  for (int d = 0; d < 3; ++d) {
    if (d == b.invariant_dir) continue;
    const Index3 e = unit(d);
    const Index3 up = add(c, e), dn = add(c, e, -1);
    G += 0.5 * (Q(c).tail<3>() + Q(up).tail<3>()) * b.S[d](up).transpose() -
         0.5 * (Q(c).tail<3>() + Q(dn).tail<3>()) * b.S[d](c).transpose();
  }
  return G / b.vol(c);
}

// |omega| = sqrt(2 Omega_ij Omega_ij), the magnitude of the curl.
inline Real vorticity_magnitude(const Mat3& G) {
  return Vec3(G(2, 1) - G(1, 2), G(0, 2) - G(2, 0), G(1, 0) - G(0, 1)).norm();
}

}  // namespace narwhal
