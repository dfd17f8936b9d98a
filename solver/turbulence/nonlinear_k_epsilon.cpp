#include "turbulence/nonlinear_k_epsilon.hpp"

#include <algorithm>

namespace narwhal {

Mat3 NonlinearKEpsilon::cell_nonlinear_stress(const TurbState& phi, const CellFlow& c, Real nu_t) const {
  const Real k = std::max(phi[0], 0.0), e = phi[1];
  if (k <= 0.0 || !(e > 0.0)) return Mat3::Zero();
  return realizable_nonlinear_stress(c.grad_u, nu_t, k, e, settings_.nonlinear);
}

Real NonlinearKEpsilon::production(const TurbState& phi, const CellFlow& c, Real nu_t) const {
  // §8.5: P_k = -<u_i u_j> d_j u_i = (2 nu_t S + tau_NL) : S (isotropic part: div u = 0).
  const Mat3 S = 0.5 * (c.grad_u + c.grad_u.transpose());
  const Mat3 stress = 2.0 * nu_t * S + cell_nonlinear_stress(phi, c, nu_t);
  return (stress.array() * S.array()).sum();
}

}  // namespace narwhal
