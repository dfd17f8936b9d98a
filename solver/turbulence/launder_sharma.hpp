#pragma once
// Launder–Sharma low-Reynolds-number k–epsilon model (NUMERICS §8.3; Launder &
// Sharma, Lett. Heat Mass Transfer 1, 1974), one of the three models of McDonald &
// Whitfield (1997).
//
// Equations (nondimensional: nu = 1/Re), eps~ the isotropic dissipation:
//   Dk/Dt    = div((nu + nu_t/sigma_k) grad k) + P - eps~ - D
//   Deps~/Dt = div((nu + nu_t/sigma_e) grad eps~) + C1 f1 eps~/k P - C2 f2 eps~^2/k + E
//   nu_t = C_mu f_mu k^2/eps~,  P = nu_t S^2 (S = sqrt(2 S_ij S_ij)),
//   D = 2 nu |grad sqrt(k)|^2 = nu |grad k|^2 / (2 k),
//   E = 2 nu nu_t sum_ijl (d2 u_i/dx_j dx_l)^2 (Green-Gauss applied twice),
//   R_t = k^2/(nu eps~), f_mu = exp(-3.4/(1 + R_t/50)^2), f1 = 1, f2 = 1 - 0.3 exp(-min(R_t^2, 50)).
// Constants: C_mu 0.09, C1 1.44, C2 1.92, sigma_k 1.0, sigma_e 1.3.
// Wall: k = 0, eps~ = 0. Free stream: k = 1.5 Tu^2 (turbulence.intensity),
// eps~ = C_mu k^2/(ratio nu) (turbulence.freestream_nut_ratio, the f_mu -> 1 limit, §8.7).
// Discretization as transport_model.hpp; D and E are explicit point sources, the
// implicit diagonal has (eps~ + D)/k for k and 2 C2 f2 eps~/k for eps~ (§8.6) or the
// numerical source derivative where larger; updates keep k and eps~ positive.
// Limits: no wall functions (y+ of the first cell ~1 needed); stagnation-point
// overproduction of k as in every linear k-epsilon model.
#include "turbulence/transport_model.hpp"

namespace narwhal {

class LaunderSharma final : public TransportModel {
 public:
  using TransportModel::TransportModel;
  std::string name() const override { return "launder-sharma"; }
  int num_variables() const override { return 2; }
  std::string variable_name(int m) const override { return m == 0 ? "k" : "epsilon_tilde"; }
  std::string cgns_name(int m) const override { return m == 0 ? "TurbulentEnergyKinetic" : "TurbulentDissipation"; }
  PointSource source(const TurbState& phi, const CellFlow& c) const override;

 protected:
  TurbState freestream(Real nu) const override;
  TurbState wall_value(Real, Real, const TurbState&) const override { return TurbState::Zero(); }
  TurbState cell_aux(const TurbState& phi, const CellFlow& c) const override;
  TurbState diffusivity(const TurbState& phi, Real nu, const TurbState& aux) const override;
  Real nut(const TurbState& phi, const CellFlow& c) const override;
  TurbState limit_update(const TurbState& phi, const TurbState& dphi) const override { return keep_positive(phi, dphi); }
  bool needs_velocity_hessian() const override { return true; }
  bool needs_root_gradient() const override { return true; }
  bool coupled_sources() const override { return true; }
};

}  // namespace narwhal
