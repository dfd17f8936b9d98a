#pragma once
// Steady divergence-free manufactured solution of NUMERICS §12.2 on [0,1]^3:
//   u = a1 cos(pi x) sin(pi y) sin(pi z), v = a2 sin cos sin, w = a3 sin sin cos,
//   p = p0 cos cos cos, a1 + a2 + a3 = 0,
// with momentum source S = (u.grad)u + grad p - nu lap u, lap u = -3 pi^2 u.
#include <cmath>

#include "core/types.hpp"

namespace narwhal {

struct ManufacturedSolution {
  Vec3 a{1.0, 1.0, -2.0};
  Real p0 = 1.0;
  Real nu = 0.05;

  State exact(const Vec3& x) const {
    const Real cx = std::cos(M_PI * x[0]), cy = std::cos(M_PI * x[1]), cz = std::cos(M_PI * x[2]);
    const Real sx = std::sin(M_PI * x[0]), sy = std::sin(M_PI * x[1]), sz = std::sin(M_PI * x[2]);
    State q;
    q << p0 * cx * cy * cz, a[0] * cx * sy * sz, a[1] * sx * cy * sz, a[2] * sx * sy * cz;
    return q;
  }

  Vec3 momentum_source(const Vec3& x) const {
    const Real pi = M_PI;
    const Real cx = std::cos(pi * x[0]), cy = std::cos(pi * x[1]), cz = std::cos(pi * x[2]);
    const Real sx = std::sin(pi * x[0]), sy = std::sin(pi * x[1]), sz = std::sin(pi * x[2]);
    const Vec3 u(a[0] * cx * sy * sz, a[1] * sx * cy * sz, a[2] * sx * sy * cz);
    Mat3 G;  // G(i,j) = du_i/dx_j
    G << -a[0] * pi * sx * sy * sz, a[0] * pi * cx * cy * sz, a[0] * pi * cx * sy * cz,  //
        a[1] * pi * cx * cy * sz, -a[1] * pi * sx * sy * sz, a[1] * pi * sx * cy * cz,   //
        a[2] * pi * cx * sy * cz, a[2] * pi * sx * cy * cz, -a[2] * pi * sx * sy * sz;
    const Vec3 gradp(-p0 * pi * sx * cy * cz, -p0 * pi * cx * sy * cz, -p0 * pi * cx * cy * sz);
    return G * u + gradp + nu * 3.0 * pi * pi * u;
  }
};

}  // namespace narwhal
