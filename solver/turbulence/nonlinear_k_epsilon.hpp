#pragma once
// Low-Reynolds-number non-linear k–epsilon model of the paper (NUMERICS §8.5; after
// McDonald & Whitfield 1997, with Speziale's 1987 quadratic stress as the default):
// Myong–Kasagi's k and epsilon equations, damping functions, constants and wall values
// (myong_kasagi.hpp), with the Reynolds stress
//   -<u_i u_j> = -2/3 k delta_ij + 2 nu_t S_ij + tau_NL_ij,
//   tau_NL = -nu_t k/eps [C1 (S S - 1/3 tr(S S) I) + C2 (Omega S - S Omega)
//                         + C3 (Omega Omega^T - 1/3 tr(Omega Omega^T) I)]
// (turbulence/nonlinear_stress.hpp). tau_NL enters the mean flow's viscous face flux
// explicitly (FlowField::tau_nl, face average, not in the Jacobian) and the production
//   P_k = (2 nu_t S + tau_NL) : S,
// which is §8.5's P_k (the C2 term does no work). Realisability: tau_NL is scaled per
// cell so that no normal stress goes negative.
//
// Usage:
//   [turbulence]
//   model = "nonlinear-k-epsilon"
//   nonlinear_c1 = 0.6048   # defaults: C1 = C2 = 4 C_D C_mu, C3 = 0 (§8.5)
//   nonlinear_c2 = 0.6048
//   nonlinear_c3 = 0.0
// C1 = C2 = C3 = 0 is Myong–Kasagi exactly. Needs flow.viscous = "full" (§4.3).
// What it adds over linear models: normal-stress anisotropy, hence the secondary flow
// of the second kind in non-circular ducts and at hull–appendage junctions.
// Limits: UNCLE's own constants and any near-wall damping of the quadratic terms are
// unknown (§8.5 [R]); the quadratic terms lag the mean flow by one iteration.
#include "turbulence/myong_kasagi.hpp"
#include "turbulence/nonlinear_stress.hpp"

namespace narwhal {

class NonlinearKEpsilon : public MyongKasagi {
 public:
  using MyongKasagi::MyongKasagi;
  std::string name() const override { return "nonlinear-k-epsilon"; }

 protected:
  Real production(const TurbState& phi, const CellFlow& c, Real nu_t) const override;
  bool has_nonlinear_stress() const override { return true; }
  Mat3 cell_nonlinear_stress(const TurbState& phi, const CellFlow& c, Real nu_t) const override;
};

}  // namespace narwhal
