#include "turbulence/nonlinear_stress.hpp"

#include <algorithm>

namespace narwhal {

Mat3 nonlinear_stress(const Mat3& grad_u, Real nu_t, Real k, Real eps, const NonlinearCoefficients& c) {
  const Mat3 S = 0.5 * (grad_u + grad_u.transpose());
  const Mat3 W = 0.5 * (grad_u - grad_u.transpose());
  const Mat3 I = Mat3::Identity();
  const Mat3 SS = S * S, WW = W * W.transpose();
  const Real scale = nu_t * k / eps;
  return -scale * (c.c1 * (SS - SS.trace() / 3.0 * I) + c.c2 * (W * S - S * W) + c.c3 * (WW - WW.trace() / 3.0 * I));
}

Mat3 realizable_nonlinear_stress(const Mat3& grad_u, Real nu_t, Real k, Real eps, const NonlinearCoefficients& c) {
  const Mat3 T = nonlinear_stress(grad_u, nu_t, k, eps, c);
  Real s = 1.0;
  for (int a = 0; a < 3; ++a) {
    const Real linear = 2.0 / 3.0 * k - nu_t * 2.0 * grad_u(a, a);  // <u_a^2> without tau_NL
    if (T(a, a) > 0.0) s = std::min(s, std::max(linear, 0.0) / T(a, a));
  }
  return s * T;
}

}  // namespace narwhal
