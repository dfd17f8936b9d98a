#pragma once
// Quadratic (nonlinear) part of the Reynolds stress of the low-Re nonlinear k–epsilon
// model (NUMERICS §8.5):
//   tau_NL = - C1 nu_t k/eps (S S - 1/3 tr(S S) I)
//            - C2 nu_t k/eps (Omega S - S Omega)
//            - C3 nu_t k/eps (Omega Omega^T - 1/3 tr(Omega Omega^T) I),
// with S = (G + G^T)/2, Omega = (G - G^T)/2 and G(i, j) = du_i/dx_j (§8.1's sign of
// Omega: Omega_ij = (d_j u_i - d_i u_j)/2). The full stress is
//   -<u_i u_j> = -2/3 k delta_ij + 2 nu_t S_ij + tau_NL_ij.
// Defaults C1 = C2 = 4 C_D C_mu = 0.6048, C3 = 0 (Speziale 1987 without the material
// derivative); they give <u^2> = 1.02 k, <w^2> = 0.57 k, <v^2> = 0.42 k in simple
// shear at equilibrium (unit test).
#include "core/types.hpp"

namespace narwhal {

struct NonlinearCoefficients {
  Real c1 = 0.6048, c2 = 0.6048, c3 = 0.0;
};

Mat3 nonlinear_stress(const Mat3& grad_u, Real nu_t, Real k, Real eps, const NonlinearCoefficients& c);

// §8.5's realisability guard: tau_NL scaled by the largest s in [0, 1] that keeps
// every normal stress <u_a^2> = 2/3 k - 2 nu_t S_aa - s tau_NL_aa >= 0 (s = 0 where
// the linear part alone is already unrealisable).
Mat3 realizable_nonlinear_stress(const Mat3& grad_u, Real nu_t, Real k, Real eps, const NonlinearCoefficients& c);

}  // namespace narwhal
