#include "turbulence/nonlinear_stress.hpp"

namespace narwhal {

Mat3 nonlinear_stress(const Mat3& grad_u, Real nu_t, Real k, Real eps, const NonlinearCoefficients& c) {
  const Mat3 S = 0.5 * (grad_u + grad_u.transpose());
  const Mat3 W = 0.5 * (grad_u - grad_u.transpose());
  const Mat3 I = Mat3::Identity();
  const Mat3 SS = S * S, WW = W * W.transpose();
  const Real scale = nu_t * k / eps;
  return -scale * (c.c1 * (SS - SS.trace() / 3.0 * I) + c.c2 * (W * S - S * W) + c.c3 * (WW - WW.trace() / 3.0 * I));
}

}  // namespace narwhal
